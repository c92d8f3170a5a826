//! Pattern files in: SVG and DXF pieces (with our seam marks read back as seams, and
//! pieces arranged by name), or a GarmentCode specification (with its stitches and its
//! placement), as a [`PatternSpec`] ready to assemble.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec2;

use super::conform::{arc, point_at, project};
use super::garmentcode::read_garmentcode;
use super::place::Landmarks;
use super::spec::{DEFAULT_FABRIC, EdgeRef, PatternSpec, PieceSpec, SeamSpec, SpecError};
use super::start::PieceStart;
use crate::collision::BodyKind;
use crate::design::MAX_NAME;
use crate::mesh::dxf::{DxfError, load_dxf};
use crate::mesh::sets::Sets;
use crate::mesh::svg::{NamedOutline, Saved, SeamMark, SvgError, load_svg};

#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{path}: {source}")]
    Svg { path: PathBuf, source: SvgError },
    #[error("{path}: {source}")]
    Dxf { path: PathBuf, source: DxfError },
    #[error("{path}: GarmentCode specification: {reason}")]
    GarmentCode { path: PathBuf, reason: String },
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: a pattern is an .svg, a .dxf or a GarmentCode .json file")]
    Kind { path: PathBuf },
    #[error("{path}: {source}")]
    Spec { path: PathBuf, source: SpecError },
}

/// The body a pattern file is cut for, where its format says: GarmentCode's (a `.json`
/// specification) is cut and placed for GarmentCode's average body, ours as `human`;
/// an SVG whose root names one of our bodies (`data-body`, as the sleeved dress we
/// ship does), that body; an SVG of ours whose pieces' saved starts all name one of our
/// bodies, that body. `None`: a pattern from elsewhere, for whatever body it is draped
/// on.
pub fn own_body(path: &Path) -> Option<BodyKind> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    // Ours only: a file naming an OBJ path does not choose what is loaded.
    let ours = |name: &str| {
        BodyKind::parse(name)
            .ok()
            .filter(|b| !matches!(b, BodyKind::Obj(_)))
    };
    match ext.as_str() {
        "json" => Some(BodyKind::Human),
        "svg" => {
            let text = std::fs::read_to_string(path).ok()?;
            if let Some(body) = crate::mesh::svg::cut_for(&text) {
                return ours(&body);
            }
            let pieces = crate::mesh::svg::read_svg(&text).ok()?;
            let mut names = (pieces.iter())
                .map(|p| PieceStart::parse(p.saved.start.as_deref()?).ok()?.body_name);
            let first = names.next()??;
            let body = ours(&first)?;
            names
                .all(|n| n.as_deref() == Some(first.as_str()))
                .then_some(body)
        }
        _ => None,
    }
}

/// Reads the pattern in `path` for a body with `marks`: normalised, every piece placed.
/// Returns what a designer should know (seam marks that make no seam).
pub fn load_pattern(
    path: &Path,
    marks: &Landmarks,
) -> Result<(PatternSpec, Vec<String>), ImportError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let (mut spec, notices) = match ext.as_str() {
        "svg" => pattern_from_outlines(load_svg(path).map_err(|source| ImportError::Svg {
            path: path.into(),
            source,
        })?),
        "dxf" => pattern_from_outlines(load_dxf(path).map_err(|source| ImportError::Dxf {
            path: path.into(),
            source,
        })?),
        "json" => {
            let text = std::fs::read_to_string(path).map_err(|source| ImportError::Io {
                path: path.into(),
                source,
            })?;
            let spec =
                read_garmentcode(&text, marks).map_err(|reason| ImportError::GarmentCode {
                    path: path.into(),
                    reason,
                })?;
            (spec, Vec::new())
        }
        _ => return Err(ImportError::Kind { path: path.into() }),
    };
    spec.normalise().map_err(|source| ImportError::Spec {
        path: path.into(),
        source,
    })?;
    let mut notices = notices;
    notices.extend(spec.start_where_saved(marks));
    notices.extend(spec.arrange(marks));
    Ok((spec, notices))
}

/// What our SVG saved of piece `name` (`saved`): its start, when it reads (else why not,
/// as a notice), and its fabric (the default where it names none, or the design's own
/// material, "cloth").
fn saved_of(name: &str, saved: &Saved) -> (Option<PieceStart>, String, Option<String>) {
    let (start, why) = match saved.start.as_deref().map(PieceStart::parse) {
        Some(Ok(start)) => (Some(start), None),
        Some(Err(why)) => (
            None,
            Some(format!(
                "piece {name}: its start on the body could not be read ({why}); it is placed by its name"
            )),
        ),
        None => (None, None),
    };
    let fabric = (saved.fabric.clone())
        .filter(|f| !f.trim().is_empty() && f.len() <= MAX_NAME && f != "cloth")
        .unwrap_or_else(|| DEFAULT_FABRIC.into());
    (start, fabric, why)
}

/// Pieces read from SVG or DXF as a pattern: each piece in the fabric, grain and start our
/// SVG saved (else the default fabric, its grain along its x, placed by its name); each
/// seam label marked on exactly two stretches of outline is a seam, sewn the way round
/// our SVG says where it does.
pub fn pattern_from_outlines(pieces: Vec<NamedOutline>) -> (PatternSpec, Vec<String>) {
    let mut spec = PatternSpec::default();
    let mut unread: Vec<String> = Vec::new();
    let mut seam_starts: Vec<(String, usize, Vec2)> = Vec::new();
    let mut runs: Vec<(String, EdgeRef)> = Vec::new();
    let mut apexes: HashMap<String, Vec2> = HashMap::new();
    for (k, p) in pieces.into_iter().enumerate() {
        let mut outline = p.outline;
        if crate::mesh::mesher::signed_area2(&outline.loops[0]) < 0.0 {
            outline.loops[0].reverse();
        }
        // Ours: where a side starts that meets the start of its seam's other side.
        (seam_starts).extend(
            (p.marks.iter())
                .filter(|m| m.start)
                .map(|m| (m.label.clone(), k, m.a)),
        );
        for (label, from, to, apex) in stretches(&outline.loops[0], &p.marks) {
            if let Some(apex) = apex {
                apexes.insert(label.clone(), apex);
            }
            runs.push((label, EdgeRef { piece: k, from, to }));
        }
        let (start, fabric, unreadable) = saved_of(&p.name, &p.saved);
        unread.extend(unreadable);
        spec.pieces.push(PieceSpec {
            name: p.name,
            outline,
            fabric,
            grain: p.saved.grain.unwrap_or(0.0),
            placement: None,
            start,
            fallback: None,
        });
    }
    let mut notices = unread;
    // Each label's stretches, in label order (a map: thousands of labels cost no more
    // than sorting them).
    let mut by_label: std::collections::BTreeMap<String, Vec<EdgeRef>> = Default::default();
    for (label, side) in runs {
        by_label.entry(label).or_default().push(side);
    }
    let loops: Vec<&[Vec2]> = spec
        .pieces
        .iter()
        .map(|p| &p.outline.loops[0][..])
        .collect();
    // The darts, each as the points that mark it: its point, where it is marked as one
    // stretch round it; its legs' ends, where it is marked as two legs on one piece.
    let darts: Vec<Vec<Vec2>> = (by_label.iter())
        .filter_map(|(label, sides)| match sides[..] {
            [_] => apexes.get(label).map(|&p| vec![p]),
            [a, b] if a.piece == b.piece => Some(vec![a.from, a.to, b.from, b.to]),
            _ => None,
        })
        .collect();
    for (label, mut sides) in by_label {
        // A dart, marked as one stretch round its point (as our export marks a dart's
        // welded legs): its legs, each counter-clockwise, sewn mouth to mouth.
        if let ([one], Some(&apex)) = (&sides[..], apexes.get(&label)) {
            let (piece, from, to) = (one.piece, one.from, one.to);
            spec.seams.push(SeamSpec {
                label,
                a: EdgeRef {
                    piece,
                    from,
                    to: apex,
                },
                b: EdgeRef {
                    piece,
                    from: apex,
                    to,
                },
                reversed: Some(true),
            });
            continue;
        }
        let bridged = bridge_gaps(&mut sides, &loops);
        if let [a, b] = sides[..] {
            for (piece, gap) in bridged {
                notices.push(format!(
                    "seam {label}: its marks on {} stop for {:.0} mm of outline (a notch in \
                     the seam line, such as a dart) and go on; sewn as one stretch across it",
                    spec.pieces[piece].name,
                    gap * 1000.0
                ));
            }
            let reversed = match (
                at_from(&seam_starts, &label, &a),
                at_from(&seam_starts, &label, &b),
            ) {
                (Some(x), Some(y)) => Some(x != y),
                _ => None,
            };
            spec.seams.push(SeamSpec {
                label,
                a,
                b,
                reversed,
            });
        } else if let Some((halves, gap)) = split_across(&label, &sides, &loops, &darts) {
            notices.push(format!(
                "seam {label}: its side on {} stops for {:.0} mm of outline (a dart's mouth) \
                 and goes on; sewn as two seams that meet where the dart closes",
                spec.pieces[halves[0].a.piece].name,
                gap * 1000.0
            ));
            spec.seams.extend(halves);
        } else {
            notices.push(format!(
                "seam {label} is marked on {} stretches of outline, and a seam joins two: left unsewn",
                sides.len()
            ));
        }
    }
    (spec, notices)
}

/// Whether side `e` of seam `label` starts, as our file drew it to meet its other side's
/// start, at its `from` end (`Some(false)`: at its `to`); `None` where the file does not
/// say (or its mark lies more than 1 mm from both ends). `starts`: each such mark's
/// label, piece and point.
fn at_from(starts: &[(String, usize, Vec2)], label: &str, e: &EdgeRef) -> Option<bool> {
    let near = |q: Vec2| q.distance(e.from).min(q.distance(e.to));
    let q = (starts.iter())
        .filter(|(l, k, _)| l == label && *k == e.piece)
        .map(|s| s.2)
        .min_by(|p, q| near(*p).total_cmp(&near(*q)))?;
    (near(q) < 1e-3).then(|| q.distance(e.from) <= q.distance(e.to))
}

/// A seam marked on three stretches, two of them on one piece either side of a gap too
/// long to bridge that is a dart's mouth (it holds one of `darts`, each the points that
/// mark one, or runs into the piece and back as a dart's legs do: a side seam over a
/// bust dart) and one on another: the lone side split where the two meet once the dart
/// is closed, at the share of the two's lengths, and sewn as two seams. Which ends meet
/// is read from where they lie in their pieces' bounds (a pattern's pieces stand the
/// same way up); the two seams say it. Returns them and the gap (m).
fn split_across(
    label: &str,
    sides: &[EdgeRef],
    loops: &[&[Vec2]],
    darts: &[Vec<Vec2>],
) -> Option<([SeamSpec; 2], f32)> {
    let [x, y, z] = sides else { return None };
    let (pair, lone) = match (x.piece == y.piece, x.piece == z.piece, y.piece == z.piece) {
        (true, false, false) => ([*x, *y], *z),
        (false, true, false) => ([*x, *z], *y),
        (false, false, true) => ([*y, *z], *x),
        _ => return None,
    };
    let l = loops.get(pair[0].piece).filter(|l| l.len() >= 3)?;
    let lb = loops.get(lone.piece).filter(|l| l.len() >= 3)?;
    let (cum, cum_b) = (arc(l), arc(lb));
    let (per, per_b) = (cum[l.len()], cum_b[lb.len()]);
    let at = |p: Vec2| project(l, &cum, p).0;
    // The two in order round their piece: the first ends where the gap starts.
    let span = |e: &EdgeRef| (at(e.to) - at(e.from)).rem_euclid(per);
    let gap = |a: &EdgeRef, b: &EdgeRef| (at(b.from) - at(a.to)).rem_euclid(per);
    let [s1, s2] = if gap(&pair[0], &pair[1]) <= gap(&pair[1], &pair[0]) {
        pair
    } else {
        [pair[1], pair[0]]
    };
    let (l1, l2, g) = (span(&s1), span(&s2), gap(&s1, &s2));
    let in_gap = |p: Vec2| {
        let (t, off) = project(l, &cum, p);
        // (The gap's own ends, where the legs start, within 0.1 mm.)
        off < 1e-4 && (t - at(s1.to) + 1e-4).rem_euclid(per) <= g + 2e-4
    };
    // A dart's mouth: a marked dart in the gap, or a gap that runs in and comes back
    // (its ends within a quarter of its length, as an unmarked dart's legs).
    let mouth = s1.to.distance(s2.from) < 0.25 * g;
    if l1 + g + l2 >= per
        || l1 <= 0.0
        || l2 <= 0.0
        || !(mouth || darts.iter().any(|d| d.iter().all(|&p| in_gap(p))))
    {
        return None;
    }
    // Which ends meet: the pairing whose ends lie nearer alike in their pieces' bounds.
    let rel = |l: &[Vec2], p: Vec2| {
        let (lo, hi) = crate::mesh::bounds2(l);
        (p - lo) / (hi - lo).max(Vec2::splat(1e-9))
    };
    let (a0, a1) = (rel(l, s1.from), rel(l, s2.to));
    let (b0, b1) = (rel(lb, lone.from), rel(lb, lone.to));
    let reversed = a0.distance(b1) + a1.distance(b0) < a0.distance(b0) + a1.distance(b1);
    // The lone side's point that meets the dart's closed mouth.
    let t0 = project(lb, &cum_b, lone.from).0;
    let len = (project(lb, &cum_b, lone.to).0 - t0).rem_euclid(per_b);
    let share = l1 / (l1 + l2);
    let mid = point_at(
        lb,
        &cum_b,
        t0 + len * if reversed { 1.0 - share } else { share },
    );
    let (first, second) = if reversed {
        ((mid, lone.to), (lone.from, mid))
    } else {
        ((lone.from, mid), (mid, lone.to))
    };
    let seam = |a: EdgeRef, (from, to): (Vec2, Vec2)| SeamSpec {
        label: label.to_string(),
        a,
        b: EdgeRef {
            piece: lone.piece,
            from,
            to,
        },
        reversed: Some(reversed),
    };
    Some(([seam(s1, first), seam(s2, second)], g))
}

/// The most a gap in a seam's marks on one piece may be, as a share of the two marked
/// stretches either side of it, for them to be sewn as one. Our own export leaves such a
/// gap where a weld took the eased side's extra length in as a dart (the collapsing
/// weld, docs/garments.md): the notch it cuts into the seam line is not marked.
const BRIDGE: f32 = 0.25;
/// Most stretches of one label [`bridge_gaps`] tries to join.
const BRIDGE_MOST: usize = 8;

/// Joins a label's stretches on one piece across the gap between them, the shortest
/// first, while the label has more than the two stretches a seam joins and the gap is at
/// most [`BRIDGE`] of the stretches' length. Returns each join's piece and gap (m). A
/// label on more than [`BRIDGE_MOST`] stretches is not a broken seam and is left as it is
/// (each try is a pass over every pair of its stretches).
fn bridge_gaps(sides: &mut Vec<EdgeRef>, loops: &[&[Vec2]]) -> Vec<(usize, f32)> {
    let mut bridged = Vec::new();
    if sides.len() > BRIDGE_MOST {
        return bridged;
    }
    while sides.len() > 2 {
        let mut best: Option<(f32, usize, usize)> = None;
        for (i, a) in sides.iter().enumerate() {
            for (j, b) in sides.iter().enumerate() {
                let Some(l) = loops
                    .get(a.piece)
                    .filter(|l| i != j && a.piece == b.piece && l.len() >= 3)
                else {
                    continue;
                };
                let cum = arc(l);
                let per = cum[l.len()];
                let at = |p: Vec2| project(l, &cum, p).0;
                let (a0, a1, b0, b1) = (at(a.from), at(a.to), at(b.from), at(b.to));
                let (len_a, len_b) = ((a1 - a0).rem_euclid(per), (b1 - b0).rem_euclid(per));
                let gap = (b0 - a1).rem_euclid(per);
                let fits = len_a + gap + len_b < per && gap <= BRIDGE * (len_a + len_b);
                if fits && best.is_none_or(|(g, ..)| gap < g) {
                    best = Some((gap, i, j));
                }
            }
        }
        let Some((gap, i, j)) = best else {
            break;
        };
        sides[i].to = sides[j].to;
        bridged.push((sides[i].piece, gap));
        sides.remove(j);
    }
    bridged
}

/// The marked stretches of outer loop `l`: per label, its marks chained where they meet,
/// each chain as the points it starts and ends at going counter-clockwise, and the point
/// of the dart it marks, if it turns back as one does ([`dart_point`]).
fn stretches(l: &[Vec2], marks: &[SeamMark]) -> Vec<(String, Vec2, Vec2, Option<Vec2>)> {
    let n = marks.len();
    let mut sets = Sets::new(n);
    // Marks of one label meet where their ends lie within `MEET` of each other: the ends
    // hashed on a grid of that size, each joined with the first mark whose end lies in
    // its cell or (within `MEET`) in a cell beside it. Pair by pair, ten thousand marks
    // took a minute (found by the svg fuzz target).
    const MEET: f32 = 1e-5;
    let cell = |p: Vec2| ((p.x / MEET).floor() as i64, (p.y / MEET).floor() as i64);
    let mut first: HashMap<(&str, i64, i64), usize> = HashMap::new();
    for (i, m) in marks.iter().enumerate() {
        for p in [m.a, m.b] {
            let (cx, cy) = cell(p);
            let j = *first.entry((m.label.as_str(), cx, cy)).or_insert(i);
            sets.join(i, j);
        }
    }
    for (i, m) in marks.iter().enumerate() {
        for p in [m.a, m.b] {
            let (cx, cy) = cell(p);
            for (dx, dy) in [
                (-1, -1),
                (-1, 0),
                (-1, 1),
                (0, -1),
                (0, 1),
                (1, -1),
                (1, 0),
                (1, 1),
            ] {
                if let Some(&j) = first.get(&(m.label.as_str(), cx + dx, cy + dy))
                    && [marks[j].a, marks[j].b]
                        .iter()
                        .any(|q| (*q - p).length() < MEET)
                {
                    sets.join(i, j);
                }
            }
        }
    }
    let mut cum = vec![0.0f32];
    for i in 0..l.len() {
        cum.push(cum[i] + (l[(i + 1) % l.len()] - l[i]).length());
    }
    let per = cum[l.len()];
    // Each chain's marks, chains in the order of their first mark.
    let mut chains: Vec<Vec<usize>> = Vec::new();
    let mut chain_of: HashMap<usize, usize> = HashMap::new();
    for i in 0..n {
        let root = sets.find(i);
        let k = *chain_of.entry(root).or_insert_with(|| {
            chains.push(Vec::new());
            chains.len() - 1
        });
        chains[k].push(i);
    }
    let mut out = Vec::new();
    for chain in chains {
        // Every point of the chain by its place along the loop; the chain is the loop
        // less the widest gap between them.
        let mut pts: Vec<(f32, Vec2)> = chain
            .iter()
            .flat_map(|&i| [marks[i].a, marks[i].b])
            .map(|p| (project(l, &cum, p).0, p))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        if pts.len() < 2 {
            continue;
        }
        let k = pts.len();
        let gap = |i: usize| (pts[(i + 1) % k].0 - pts[i].0).rem_euclid(per);
        let widest = (0..k)
            .max_by(|&a, &b| gap(a).total_cmp(&gap(b)))
            .unwrap_or(0);
        let from = pts[(widest + 1) % k].1;
        let to = pts[widest].1;
        let along = (1..k).map(|i| pts[(widest + 1 + i) % k].1);
        let apex = dart_point(from, to, along);
        out.push((marks[chain[0]].label.clone(), from, to, apex));
    }
    out
}

/// The point of a dart marked as one stretch from `from` to `to` through `along`: the
/// point farthest from the line between its ends, where the stretch turns back within
/// 60 degrees, its legs within 1.25x of each other (as the pattern out finds a dart).
fn dart_point(from: Vec2, to: Vec2, along: impl Iterator<Item = Vec2>) -> Option<Vec2> {
    let chord = (to - from).normalize_or_zero();
    let apex = along.max_by(|a, b| {
        let off = |q: Vec2| chord.perp_dot(q - from).abs();
        off(*a).total_cmp(&off(*b))
    })?;
    let (ta, tb) = (from - apex, to - apex);
    let (la, lb) = (ta.length(), tb.length());
    // The pattern out's rule for a dart, so that what it marks reads back as one.
    use crate::design::sewing_pattern::dart::{LEGS_RATIO, WIDEST};
    let alike = la > 0.0 && lb > 0.0 && la.max(lb) <= LEGS_RATIO as f32 * la.min(lb);
    let theta = ta.angle_to(tb).abs();
    (alike && theta <= WIDEST as f32 && from.distance(to) > 0.0).then_some(apex)
}

#[cfg(test)]
mod tests;
