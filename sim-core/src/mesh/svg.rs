//! Pattern pieces from an SVG file: every closed shape (a path's closed subpaths with
//! lines, arcs and Béziers, a polygon, a rect, a circle or an ellipse), under its groups'
//! transforms, flattened to within 0.1 mm (kurbo), in millimetres as the document's size
//! says (`width="...mm"` over its `viewBox`; without units, a user unit is a millimetre,
//! as in our own `pattern.svg`). Loops inside loops are holes, loops inside holes pieces
//! again. In a group that has a sewing line (`class="sew"`, ours), the cut line around it
//! (`class="cut"`) is left out, so our patterns read back as their sewn shape; a drill
//! hole's circle (`class="drill"`) is a mark, not a hole.

use std::path::Path;

use glam::Vec2;
use kurbo::{Affine, BezPath, PathEl, Shape};
use quick_xml::events::{BytesStart, Event};

use super::mesher::{Outline, contains, signed_area2 as area2};

/// How closely curves are followed, mm.
const TOLERANCE_MM: f64 = 0.1;

/// A piece read from a file: its name (the group's title or id) and its outline, metres,
/// pattern y up; with the seam marks on its outline (a label and a segment), where the
/// file has them (ours do).
#[derive(Clone, Debug, PartialEq)]
pub struct NamedOutline {
    pub name: String,
    pub outline: Outline,
    pub marks: Vec<SeamMark>,
    /// What a pattern of ours says of the piece beyond its shape ([`Saved`]).
    pub saved: Saved,
}

/// What our own SVG writes on a piece's group for Saiho to read back: its fabric's name,
/// its grain's angle (radians from the pattern's x, y up) and its start on the body (as
/// written: the design layer reads it). A piece with a start has its outline and marks
/// in its own coordinates (the origin the file gives it), not the page's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Saved {
    pub fabric: Option<String>,
    pub grain: Option<f32>,
    pub start: Option<String>,
}

/// A segment of an outline marked as part of the seam `label`, metres, pattern y up.
#[derive(Clone, Debug, PartialEq)]
pub struct SeamMark {
    pub label: String,
    pub a: Vec2,
    pub b: Vec2,
    /// Ours: the first segment of a side drawn from the end that meets the start of
    /// the seam's other side (`data-seam-pairs="from-start"`): `a` is that end.
    pub start: bool,
}

impl NamedOutline {
    /// Gives each mark to the piece whose outer loop it lies on (within `tol` m);
    /// returns how many lay on none.
    pub fn take_marks(pieces: &mut [NamedOutline], marks: Vec<SeamMark>, tol: f32) -> usize {
        let mut lost = 0;
        for m in marks {
            let mid = (m.a + m.b) * 0.5;
            let near = pieces
                .iter()
                .enumerate()
                .map(|(i, p)| (i, loop_distance(&p.outline.loops[0], mid)))
                .min_by(|x, y| x.1.total_cmp(&y.1));
            match near {
                Some((i, d)) if d <= tol => pieces[i].marks.push(m),
                _ => lost += 1,
            }
        }
        lost
    }
}

/// The distance from `p` to closed loop `l`.
pub fn loop_distance(l: &[Vec2], p: Vec2) -> f32 {
    (0..l.len())
        .map(|i| {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared().max(1e-20)).clamp(0.0, 1.0);
            (a + ab * t - p).length()
        })
        .fold(f32::INFINITY, f32::min)
}

#[derive(Debug, thiserror::Error)]
pub enum SvgError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("not an SVG document: {0}")]
    Xml(String),
    #[error(
        "no closed shape: a piece is a closed path (ending in Z), a polygon, a rect, a circle or an ellipse"
    )]
    NoClosedShape,
    #[error("a path's d is not SVG path data ({0})")]
    PathData(String),
    #[error(
        "a shape reaches {0} mm from the origin, beyond the {max} mm a pattern may span (another unit, or a damaged file?)",
        max = crate::mesh::MAX_COORD * 1000.0
    )]
    TooFar(f64),
}

/// `path` under `affine` (in mm), refused when it reaches farther than a scene spans:
/// flattening a curve kilometres long to 0.1 mm would take all the memory there is.
fn placed(path: &BezPath, affine: Affine) -> Result<BezPath, SvgError> {
    use kurbo::Shape;
    let mut p = path.clone();
    p.apply_affine(affine);
    let b = p.bounding_box();
    let reach = [b.x0, b.y0, b.x1, b.y1].iter().fold(0.0f64, |m, v| {
        if v.is_finite() {
            m.max(v.abs())
        } else {
            f64::INFINITY
        }
    });
    if reach > crate::mesh::MAX_COORD as f64 * 1000.0 {
        return Err(SvgError::TooFar(reach));
    }
    Ok(p)
}

/// One closed loop found, in mm (SVG axes), with the group it belongs to and its class.
struct Found {
    points: Vec<Vec2>,
    group: usize,
    class: String,
}

/// An attribute's value.
fn attr(e: &BytesStart<'_>, name: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == name.as_bytes())
        .map(|a| {
            let raw = String::from_utf8_lossy(&a.value).into_owned();
            quick_xml::escape::unescape(&raw)
                .map(|v| v.into_owned())
                .unwrap_or(raw)
        })
}

/// Largest number a shape's geometry may hold, in user units: a km in µm, and more.
const MAX_RAW: f64 = 1e9;

/// The first number in `s` (SVG's number syntax: sign, digits, point, exponent) whose
/// size is over [`MAX_RAW`] or that is not finite.
fn first_huge(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            || (b[i] == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
            || (matches!(b[i], b'+' | b'-')
                && b.get(i + 1)
                    .is_some_and(|c| c.is_ascii_digit() || *c == b'.'));
        if !starts {
            i += 1;
            continue;
        }
        let start = i;
        if matches!(b[i], b'+' | b'-') {
            i += 1;
        }
        let mut point = false;
        while i < b.len() && (b[i].is_ascii_digit() || (b[i] == b'.' && !point)) {
            point |= b[i] == b'.';
            i += 1;
        }
        if i < b.len() && matches!(b[i], b'e' | b'E') {
            let mut j = i + 1;
            if j < b.len() && matches!(b[j], b'+' | b'-') {
                j += 1;
            }
            if j < b.len() && b[j].is_ascii_digit() {
                while j < b.len() && b[j].is_ascii_digit() {
                    j += 1;
                }
                i = j;
            }
        }
        if let Ok(v) = s[start..i].parse::<f64>()
            && (v.abs() > MAX_RAW || !v.is_finite())
        {
            return Some(v);
        }
    }
    None
}

fn num(e: &BytesStart<'_>, name: &str) -> f64 {
    attr(e, name)
        .and_then(|v| {
            v.trim()
                .trim_end_matches(|c: char| c.is_ascii_alphabetic() || c == '%')
                .parse()
                .ok()
        })
        .unwrap_or(0.0)
}

/// A length with its unit, in mm (`None` without a unit or for %).
fn length_mm(v: &str) -> Option<f64> {
    let v = v.trim();
    let split = v
        .find(|c: char| c.is_ascii_alphabetic() || c == '%')
        .unwrap_or(v.len());
    let (n, unit) = v.split_at(split);
    let n: f64 = n.trim().parse().ok()?;
    let per = match unit {
        "mm" => 1.0,
        "cm" => 10.0,
        "in" => 25.4,
        "pt" => 25.4 / 72.0,
        "pc" => 25.4 / 6.0,
        "px" => 25.4 / 96.0,
        _ => return None,
    };
    Some(n * per)
}

/// Parses a `transform` attribute (matrix, translate, scale, rotate, skewX, skewY).
fn transform(v: &str) -> Affine {
    let mut out = Affine::IDENTITY;
    let mut rest = v;
    while let Some(open) = rest.find('(') {
        let name = rest[..open].trim().trim_start_matches(',').trim();
        let Some(close) = rest[open..].find(')') else {
            break;
        };
        let args: Vec<f64> = rest[open + 1..open + close]
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .filter_map(|s| s.parse().ok())
            .collect();
        let a = |i: usize| args.get(i).copied().unwrap_or(0.0);
        let t = match name {
            "matrix" if args.len() == 6 => Affine::new([a(0), a(1), a(2), a(3), a(4), a(5)]),
            "translate" => Affine::translate((a(0), a(1))),
            "scale" => Affine::scale_non_uniform(a(0), if args.len() > 1 { a(1) } else { a(0) }),
            "rotate" => {
                let r = Affine::rotate(a(0).to_radians());
                if args.len() == 3 {
                    Affine::translate((a(1), a(2))) * r * Affine::translate((-a(1), -a(2)))
                } else {
                    r
                }
            }
            "skewX" => Affine::skew(a(0).to_radians().tan(), 0.0),
            "skewY" => Affine::skew(0.0, a(0).to_radians().tan()),
            _ => Affine::IDENTITY,
        };
        out *= t;
        rest = &rest[open + close + 1..];
    }
    out
}

/// The closed subpaths of `p` (in mm, [`placed`]), flattened.
fn closed_loops(p: BezPath) -> Vec<Vec<Vec2>> {
    let tol = TOLERANCE_MM;
    let mut loops = Vec::new();
    let mut cur: Vec<Vec2> = Vec::new();
    let mut closed = false;
    let finish = |cur: &mut Vec<Vec2>, closed: bool, loops: &mut Vec<Vec<Vec2>>| {
        let first_last = cur.len() > 2 && (cur[0] - cur[cur.len() - 1]).length() < 1e-6;
        if first_last {
            cur.pop();
        }
        if (closed || first_last) && cur.len() >= 3 {
            loops.push(std::mem::take(cur));
        }
        cur.clear();
    };
    kurbo::flatten(p, tol, |el| match el {
        PathEl::MoveTo(q) => {
            finish(&mut cur, closed, &mut loops);
            closed = false;
            cur.push(Vec2::new(q.x as f32, q.y as f32));
        }
        PathEl::LineTo(q) => {
            let q = Vec2::new(q.x as f32, q.y as f32);
            if cur.last().is_none_or(|l| (*l - q).length() > 1e-6) {
                cur.push(q);
            }
        }
        PathEl::ClosePath => closed = true,
        _ => {}
    });
    finish(&mut cur, closed, &mut loops);
    loops
}

/// The shape an element draws, as a path (`None`: not a shape).
fn shape_of(e: &BytesStart<'_>) -> Result<Option<BezPath>, SvgError> {
    let name = e.local_name();
    // Before any curve is made: an arc or a circle of radius 1e40 is cut into millions
    // of Béziers (minutes, found by the svg fuzz target).
    for a in [
        "d", "points", "x", "y", "width", "height", "cx", "cy", "r", "rx", "ry",
    ] {
        if let Some(v) = attr(e, a).as_deref().and_then(first_huge) {
            return Err(SvgError::TooFar(v));
        }
    }
    Ok(match name.as_ref() {
        b"path" => match attr(e, "d") {
            Some(d) => {
                Some(BezPath::from_svg(&d).map_err(|err| SvgError::PathData(format!("{err:?}")))?)
            }
            None => None,
        },
        b"polygon" => attr(e, "points").map(|pts| {
            let v: Vec<f64> = pts
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .filter_map(|s| s.parse().ok())
                .collect();
            let mut p = BezPath::new();
            for (i, xy) in v.chunks_exact(2).enumerate() {
                if i == 0 {
                    p.move_to((xy[0], xy[1]));
                } else {
                    p.line_to((xy[0], xy[1]));
                }
            }
            p.close_path();
            p
        }),
        b"rect" => Some(
            kurbo::Rect::new(
                num(e, "x"),
                num(e, "y"),
                num(e, "x") + num(e, "width"),
                num(e, "y") + num(e, "height"),
            )
            .to_path(TOLERANCE_MM),
        ),
        b"circle" => Some(
            kurbo::Circle::new((num(e, "cx"), num(e, "cy")), num(e, "r")).to_path(TOLERANCE_MM),
        ),
        b"ellipse" => Some(
            kurbo::Ellipse::new(
                (num(e, "cx"), num(e, "cy")),
                (num(e, "rx"), num(e, "ry")),
                0.0,
            )
            .to_path(TOLERANCE_MM),
        ),
        _ => None,
    })
}

/// The pieces of an SVG document (see the module doc), with our seam marks
/// (`class="seam"` lines or paths labelled by `data-seam`).
pub fn read_svg(text: &str) -> Result<Vec<NamedOutline>, SvgError> {
    let (found, names, marks) = walk(text)?;
    let (mut pieces, origins): (Vec<NamedOutline>, Vec<Option<Vec2>>) =
        nest(found, &names)?.into_iter().unzip();
    let to_m = |p: Vec2| Vec2::new(p.x, -p.y) * 0.001;
    let marks = marks
        .into_iter()
        .map(|m| SeamMark {
            label: m.label,
            a: to_m(m.a),
            b: to_m(m.b),
            start: m.start,
        })
        .collect();
    NamedOutline::take_marks(&mut pieces, marks, 1e-4);
    // A piece of ours with a start: in its own coordinates, as its start measures them.
    for (p, o) in pieces.iter_mut().zip(origins) {
        let Some(o) = o.map(to_m) else { continue };
        for q in p.outline.loops.iter_mut().flatten() {
            *q -= o;
        }
        for m in &mut p.marks {
            m.a -= o;
            m.b -= o;
        }
    }
    Ok(pieces)
}

/// The segments of an open or closed path `p` (in mm, [`placed`]), flattened; a segment
/// of no length marks nothing and is left out (a `Z` on a closed path, or a run of them:
/// the svg fuzz target's 34 kB of `ZZZ...` made 30,000 marks and 0.3 s an input).
fn segments(p: BezPath) -> Vec<(Vec2, Vec2)> {
    let mut out = Vec::new();
    let mut push = |a: Vec2, b: Vec2| {
        if (b - a).length() > 1e-6 {
            out.push((a, b));
        }
    };
    let (mut start, mut at): (Option<Vec2>, Option<Vec2>) = (None, None);
    kurbo::flatten(p, TOLERANCE_MM, |el| match el {
        PathEl::MoveTo(q) => {
            let q = Vec2::new(q.x as f32, q.y as f32);
            start = Some(q);
            at = Some(q);
        }
        PathEl::LineTo(q) => {
            let q = Vec2::new(q.x as f32, q.y as f32);
            if let Some(a) = at {
                push(a, q);
            }
            at = Some(q);
        }
        PathEl::ClosePath => {
            if let (Some(a), Some(s)) = (at, start) {
                push(a, s);
            }
            at = start;
        }
        _ => {}
    });
    out
}

/// Every closed loop of the document, in mm, with its group and class; and each group's
/// name (index 0: the document).
/// What `walk` finds: the loops, the groups, the seam marks (mm, SVG axes).
type Walked = (Vec<Found>, Vec<Group>, Vec<SeamMark>);

/// A group: its name (title or id), what ours saves on it, and where the origin of its
/// piece's own coordinates lies (mm, SVG axes).
#[derive(Default)]
struct Group {
    name: String,
    saved: Saved,
    origin: Option<Vec2>,
}

/// A group's `data-` attributes of ours (see [`Saved`]), its origin placed by `affine`.
fn group_of(e: &BytesStart<'_>, affine: Affine) -> Group {
    let origin = attr(e, "data-origin").and_then(|v| {
        let n: Vec<f64> = (v.split(|c: char| c == ',' || c.is_whitespace()))
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().unwrap_or(f64::NAN))
            .collect();
        let p = affine * kurbo::Point::new(*n.first()?, *n.get(1)?);
        (n.len() == 2 && p.x.abs() < MAX_RAW && p.y.abs() < MAX_RAW)
            .then(|| Vec2::new(p.x as f32, p.y as f32))
    });
    Group {
        name: attr(e, "id").unwrap_or_default(),
        saved: Saved {
            fabric: attr(e, "data-fabric"),
            grain: attr(e, "data-grain")
                .and_then(|g| g.trim().parse::<f32>().ok())
                .filter(|g| g.is_finite()),
            start: attr(e, "data-start"),
        },
        origin,
    }
}

fn walk(text: &str) -> Result<Walked, SvgError> {
    let mut reader = quick_xml::Reader::from_str(text);
    // (transform, group index) of the open groups; the root's transform scales to mm.
    let mut stack: Vec<(Affine, usize)> = Vec::new();
    let mut names: Vec<Group> = vec![Group::default()];
    let mut found: Vec<Found> = Vec::new();
    let mut marks: Vec<SeamMark> = Vec::new();
    let mut in_title = false;
    let mut saw_svg = false;
    loop {
        let ev = reader
            .read_event()
            .map_err(|e| SvgError::Xml(e.to_string()))?;
        let (e, empty) = match &ev {
            Event::Start(e) => (Some(e.clone()), false),
            Event::Empty(e) => (Some(e.clone()), true),
            Event::End(e) => {
                let n = e.local_name();
                if n.as_ref() == b"g" || n.as_ref() == b"svg" {
                    stack.pop();
                }
                if n.as_ref() == b"title" {
                    in_title = false;
                }
                continue;
            }
            Event::Text(t) if in_title => {
                // A group's title names it (over its id); the document's does not.
                if let (Some(&(_, g)), Ok(s)) = (stack.last(), t.decode())
                    && g > 0
                {
                    names[g].name = s.trim().to_string();
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let Some(e) = e else { continue };
        let parent = stack.last().map_or(Affine::IDENTITY, |s| s.0);
        let own = attr(&e, "transform").map_or(Affine::IDENTITY, |t| transform(&t));
        match e.local_name().as_ref() {
            b"svg" => {
                saw_svg = true;
                // User units to mm: the width's unit over the viewBox's width.
                let vb: Vec<f64> = attr(&e, "viewBox")
                    .map(|v| {
                        v.split(|c: char| c == ',' || c.is_whitespace())
                            .filter(|s| !s.is_empty())
                            .filter_map(|s| s.parse().ok())
                            .collect()
                    })
                    .unwrap_or_default();
                let w = attr(&e, "width").and_then(|w| length_mm(&w));
                let scale = match (w, vb.get(2)) {
                    (Some(w), Some(&vw)) if vw > 0.0 => w / vw,
                    _ => 1.0,
                };
                let origin =
                    Affine::translate((-vb.first().unwrap_or(&0.0), -vb.get(1).unwrap_or(&0.0)));
                if !empty {
                    stack.push((parent * Affine::scale(scale) * origin, 0));
                }
            }
            b"g" => {
                names.push(group_of(&e, parent * own));
                let g = names.len() - 1;
                if !empty {
                    stack.push((parent * own, g));
                }
            }
            b"title" => in_title = !empty,
            _ if attr(&e, "class").as_deref() == Some("seam") => {
                let label = attr(&e, "data-seam").unwrap_or_default();
                let path = if e.local_name().as_ref() == b"line" {
                    let mut p = BezPath::new();
                    p.move_to((num(&e, "x1"), num(&e, "y1")));
                    p.line_to((num(&e, "x2"), num(&e, "y2")));
                    Some(p)
                } else {
                    shape_of(&e)?
                };
                let paired = attr(&e, "data-seam-pairs").as_deref() == Some("from-start");
                if let Some(path) = path {
                    for (k, (a, b)) in segments(placed(&path, parent * own)?)
                        .into_iter()
                        .enumerate()
                    {
                        marks.push(SeamMark {
                            label: label.clone(),
                            a,
                            b,
                            start: paired && k == 0,
                        });
                    }
                }
            }
            // Ours: a drill hole's mark (a dart's point) is no outline.
            _ if attr(&e, "class").as_deref() == Some("drill") => {}
            _ => {
                if let Some(path) = shape_of(&e)? {
                    let group = stack.last().map_or(0, |s| s.1);
                    let class = attr(&e, "class").unwrap_or_default();
                    for points in closed_loops(placed(&path, parent * own)?) {
                        found.push(Found {
                            points,
                            group,
                            class: class.clone(),
                        });
                    }
                }
            }
        }
    }
    if !saw_svg {
        return Err(SvgError::Xml("no <svg> element".into()));
    }
    Ok((found, names, marks))
}

/// The loops as pieces: outer loops (counter-clockwise) with the holes inside them
/// (clockwise), in metres with the pattern's y up, in the file's order.
/// Each piece with its group's origin (mm, SVG axes), where it has one.
fn nest(
    mut found: Vec<Found>,
    names: &[Group],
) -> Result<Vec<(NamedOutline, Option<Vec2>)>, SvgError> {
    // Ours: a group's cut line is dropped when it has a sewing line.
    let sewn: Vec<usize> = found
        .iter()
        .filter(|f| f.class == "sew")
        .map(|f| f.group)
        .collect();
    found.retain(|f| !(f.class == "cut" && sewn.contains(&f.group)));
    // Metres, pattern y up.
    let loops: Vec<(Vec<Vec2>, usize)> = found
        .into_iter()
        .map(|f| {
            (
                f.points
                    .iter()
                    .map(|p| Vec2::new(p.x, -p.y) * 0.001)
                    .collect(),
                f.group,
            )
        })
        .filter(|(l, _): &(Vec<Vec2>, usize)| area2(l).abs() > 1e-12)
        .collect();
    if loops.is_empty() {
        return Err(SvgError::NoClosedShape);
    }
    // Largest first; each loop's depth is the number of larger loops holding it.
    let mut by_size: Vec<usize> = (0..loops.len()).collect();
    by_size.sort_by(|&a, &b| {
        area2(&loops[b].0)
            .abs()
            .total_cmp(&area2(&loops[a].0).abs())
    });
    let mut pieces: Vec<(NamedOutline, usize)> = Vec::new();
    for (r, &i) in by_size.iter().enumerate() {
        let p = loops[i].0[0];
        let holders: Vec<usize> = (by_size[..r].iter().copied())
            .filter(|&j| contains(&loops[j].0, p))
            .collect();
        let depth = holders.len();
        // The innermost holder is the last (smallest) of them.
        let holder = holders.last().copied();
        let mut l = loops[i].0.clone();
        if depth.is_multiple_of(2) {
            if area2(&l) < 0.0 {
                l.reverse();
            }
            let group = names.get(loops[i].1);
            pieces.push((
                NamedOutline {
                    name: group.map(|g| g.name.clone()).unwrap_or_default(),
                    outline: Outline { loops: vec![l] },
                    marks: Vec::new(),
                    saved: group.map(|g| g.saved.clone()).unwrap_or_default(),
                },
                i,
            ));
        } else if let Some(h) = holder
            && let Some(piece) = pieces.iter_mut().find(|(_, k)| *k == h)
        {
            if area2(&l) > 0.0 {
                l.reverse();
            }
            piece.0.outline.loops.push(l);
        }
    }
    // In the file's order (by size only to nest them): the first drawn first.
    pieces.sort_by_key(|(_, i)| *i);
    for (k, p) in (1..).zip(&mut pieces).filter(|(_, p)| p.0.name.is_empty()) {
        p.0.name = format!("piece {k}");
    }
    Ok(pieces
        .into_iter()
        .map(|(p, i)| {
            let origin = names.get(loops[i].1).and_then(|g| g.origin);
            (p, origin)
        })
        .collect())
}

/// The body a pattern says it is cut for: its root element's `data-body` (a name such
/// as `mannequin`, as the sleeved dress we ship says). `None` when it says none, or the
/// file cannot be read as XML up to its root.
pub fn cut_for(text: &str) -> Option<String> {
    let mut reader = quick_xml::Reader::from_str(text);
    loop {
        match reader.read_event().ok()? {
            Event::Start(e) | Event::Empty(e) => {
                return (e.local_name().as_ref() == b"svg")
                    .then(|| attr(&e, "data-body"))
                    .flatten();
            }
            Event::Eof => return None,
            _ => {}
        }
    }
}

/// Reads the pieces of an SVG file.
pub fn load_svg(path: &Path) -> Result<Vec<NamedOutline>, SvgError> {
    let text = std::fs::read_to_string(path).map_err(|source| SvgError::Io {
        path: path.to_owned(),
        source,
    })?;
    read_svg(&text)
}

#[cfg(test)]
mod tests;
