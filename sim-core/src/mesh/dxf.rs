//! Pattern pieces from a DXF file in the AAMA / ASTM D6673 layout that pattern tools
//! exchange (Seamly2D, Valentina, CLO, and our own `pattern.dxf`): one block per piece,
//! its boundary a closed polyline on layer 1 (the cut line) and, with a seam allowance,
//! its sewing line on layer 14, which is taken over the cut line (a piece is sewn on its
//! sewing line); its name from the text "Piece Name: ..."; our seams from layer 8 lines
//! labelled by a "Seam: X" text on them. Each block is placed where its INSERT puts it
//! (move, scale, turn). A file without blocks gives its closed polylines as pieces.
//!
//! ASCII DXF only; POLYLINE (with VERTEX, bulges as arcs), LWPOLYLINE, LINE, TEXT. Units
//! from `$INSUNITS` (inches, feet, mm, cm, m), millimetres when it is absent.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use glam::{DVec2, Vec2};

use super::mesher::{Outline, contains, signed_area2};
use super::sets::Sets;
use super::svg::{NamedOutline, SeamMark};

#[derive(Debug, thiserror::Error)]
pub enum DxfError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
    #[error("not an ASCII DXF file: {0}")]
    Format(String),
    #[error(
        "no piece boundary: an AAMA piece is a closed polyline on layer 1 (or any closed polyline in a plain DXF), and this file has none"
    )]
    NoBoundary,
}

/// One entity: its type and its group codes in order.
#[derive(Debug, Default)]
struct Entity {
    kind: String,
    codes: Vec<(i32, String)>,
    /// A POLYLINE's vertices (each a VERTEX entity).
    vertices: Vec<Entity>,
}

impl Entity {
    fn get(&self, code: i32) -> Option<&str> {
        self.codes
            .iter()
            .find(|(c, _)| *c == code)
            .map(|(_, v)| v.as_str())
    }

    fn num(&self, code: i32) -> f64 {
        self.get(code)
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .unwrap_or(0.0)
    }

    fn layer(&self) -> &str {
        self.get(8).map_or("0", str::trim)
    }

    fn flags(&self) -> i64 {
        self.get(70)
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or(0)
    }

    /// A polyline's points with their bulges, and whether it is closed.
    fn polyline(&self) -> Option<(Vec<(DVec2, f64)>, bool)> {
        match self.kind.as_str() {
            "POLYLINE" => Some((
                self.vertices
                    .iter()
                    .map(|v| (DVec2::new(v.num(10), v.num(20)), v.num(42)))
                    .collect(),
                self.flags() & 1 == 1,
            )),
            "LWPOLYLINE" => {
                let mut pts: Vec<(DVec2, f64)> = Vec::new();
                for (c, v) in &self.codes {
                    let x = v.trim().parse::<f64>().unwrap_or(0.0);
                    match c {
                        10 => pts.push((DVec2::new(x, 0.0), 0.0)),
                        20 => {
                            if let Some(p) = pts.last_mut() {
                                p.0.y = x;
                            }
                        }
                        42 => {
                            if let Some(p) = pts.last_mut() {
                                p.1 = x;
                            }
                        }
                        _ => {}
                    }
                }
                Some((pts, self.flags() & 1 == 1))
            }
            _ => None,
        }
    }
}

/// The group code and value pairs of the file.
fn pairs(text: &str) -> Result<Vec<(i32, String)>, DxfError> {
    let mut lines = text.lines();
    let mut out = Vec::new();
    while let Some(code) = lines.next() {
        let code = code.trim();
        if code.is_empty() && out.is_empty() {
            continue;
        }
        let c: i32 = code.parse().map_err(|_| {
            DxfError::Format(format!(
                "line {}: expected a group code, found {code:?}",
                2 * out.len() + 1
            ))
        })?;
        let v = lines
            .next()
            .ok_or_else(|| DxfError::Format("the file ends inside a group".into()))?;
        out.push((c, v.trim_end_matches('\r').to_string()));
    }
    if !out.iter().any(|(c, v)| *c == 0 && v.trim() == "EOF") {
        return Err(DxfError::Format("no EOF marker (truncated?)".into()));
    }
    Ok(out)
}

/// The header variables, blocks (name to entities) and top-level entities.
type Parsed = (
    HashMap<String, String>,
    Vec<(String, Vec<Entity>)>,
    Vec<Entity>,
);

fn parse(pairs: &[(i32, String)]) -> Parsed {
    let mut header = HashMap::new();
    let mut blocks: Vec<(String, Vec<Entity>)> = Vec::new();
    let mut entities: Vec<Entity> = Vec::new();
    let mut section = String::new();
    let mut i = 0;
    let mut open_poly: Option<Entity> = None;
    while i < pairs.len() {
        let (c, v) = (&pairs[i].0, pairs[i].1.trim());
        i += 1;
        if *c == 9 && section == "HEADER" {
            if let Some((_, val)) = pairs.get(i) {
                header.insert(v.to_string(), val.trim().to_string());
            }
            continue;
        }
        if *c != 0 {
            continue;
        }
        // An entity or marker: collect its codes up to the next 0.
        let mut e = Entity {
            kind: v.to_string(),
            ..Entity::default()
        };
        while i < pairs.len() && pairs[i].0 != 0 {
            e.codes.push(pairs[i].clone());
            i += 1;
        }
        match e.kind.as_str() {
            "SECTION" => section = e.get(2).unwrap_or("").trim().to_string(),
            "ENDSEC" => section.clear(),
            "BLOCK" => blocks.push((e.get(2).unwrap_or("").trim().to_string(), Vec::new())),
            "ENDBLK" => {}
            "VERTEX" => {
                if let Some(p) = &mut open_poly {
                    p.vertices.push(e);
                }
            }
            "SEQEND" => {
                if let Some(p) = open_poly.take() {
                    push(&section, &mut blocks, &mut entities, p);
                }
            }
            "POLYLINE" => open_poly = Some(e),
            _ => push(&section, &mut blocks, &mut entities, e),
        }
    }
    (header, blocks, entities)
}

fn push(section: &str, blocks: &mut [(String, Vec<Entity>)], top: &mut Vec<Entity>, e: Entity) {
    match section {
        "BLOCKS" => {
            if let Some(b) = blocks.last_mut() {
                b.1.push(e);
            }
        }
        "ENTITIES" => top.push(e),
        _ => {}
    }
}

/// Points of a polyline with its bulges as arcs (within about 0.1 mm).
fn flatten(pts: &[(DVec2, f64)], closed: bool) -> Vec<DVec2> {
    let n = pts.len();
    let mut out = Vec::with_capacity(n);
    let segs = if closed { n } else { n.saturating_sub(1) };
    for i in 0..n {
        out.push(pts[i].0);
        let b = pts[i].1;
        if i < segs && b.abs() > 1e-9 {
            let (p, q) = (pts[i].0, pts[(i + 1) % n].0);
            let theta = 4.0 * b.atan();
            let chord = (q - p).length();
            if chord < 1e-12 {
                continue;
            }
            let r = chord / (2.0 * (theta / 2.0).sin()).abs();
            // The centre: off the chord's middle, to the left for a positive bulge.
            let mid = (p + q) * 0.5;
            let left = DVec2::new(-(q - p).y, (q - p).x) / chord;
            let h = r * (theta / 2.0).cos().abs();
            let side = if (theta.abs() < std::f64::consts::PI) == (b > 0.0) {
                1.0
            } else {
                -1.0
            };
            let c = mid + left * h * side;
            let a0 = (p - c).y.atan2((p - c).x);
            // Steps whose sagitta r (1 - cos(step / 2)) stays under 0.1 mm.
            let k = ((theta.abs() * (r / 0.8).sqrt()).ceil() as usize).clamp(2, 256);
            for j in 1..k {
                let a = a0 + theta * j as f64 / k as f64;
                out.push(c + DVec2::new(a.cos(), a.sin()) * r);
            }
        }
    }
    out
}

/// A block's content as pieces' loops, seam marks and texts (mm, the block's frame).
#[derive(Default)]
struct Drawn {
    cut: Vec<Vec<DVec2>>,
    sew: Vec<Vec<DVec2>>,
    other: Vec<Vec<DVec2>>,
    seam_lines: Vec<(DVec2, DVec2)>,
    texts: Vec<(DVec2, String)>,
}

fn draw(entities: &[Entity], xf: &dyn Fn(DVec2) -> DVec2, d: &mut Drawn) {
    for e in entities {
        if let Some((pts, closed)) = e.polyline() {
            let mut l: Vec<DVec2> = flatten(&pts, closed).into_iter().map(xf).collect();
            let ends_meet = l.len() > 2 && (l[0] - l[l.len() - 1]).length() < 1e-6;
            if ends_meet {
                l.pop();
            }
            if !(closed || ends_meet) || l.len() < 3 {
                continue;
            }
            match e.layer() {
                "1" => d.cut.push(l),
                "14" => d.sew.push(l),
                _ => d.other.push(l),
            }
        } else if e.kind == "LINE" && e.layer() == "8" {
            d.seam_lines.push((
                xf(DVec2::new(e.num(10), e.num(20))),
                xf(DVec2::new(e.num(11), e.num(21))),
            ));
        } else if (e.kind == "TEXT" || e.kind == "MTEXT")
            && let Some(t) = e.get(1)
        {
            d.texts
                .push((xf(DVec2::new(e.num(10), e.num(20))), t.trim().to_string()));
        }
    }
}

/// mm per drawing unit from `$INSUNITS`.
fn unit_mm(header: &HashMap<String, String>) -> f64 {
    match header.get("$INSUNITS").and_then(|v| v.parse::<i32>().ok()) {
        Some(1) => 25.4,
        Some(2) => 304.8,
        Some(5) => 10.0,
        Some(6) => 1000.0,
        _ => 1.0,
    }
}

/// The pieces of a DXF document (see the module doc).
pub fn read_dxf(text: &str) -> Result<Vec<NamedOutline>, DxfError> {
    let (header, blocks, top) = parse(&pairs(text)?);
    let unit = unit_mm(&header);
    let mut drawn: Vec<Drawn> = Vec::new();
    let mut inserted: Vec<&str> = Vec::new();
    for e in top.iter().filter(|e| e.kind == "INSERT") {
        let name = e.get(2).unwrap_or("").trim();
        let Some((_, content)) = blocks.iter().find(|(n, _)| n == name) else {
            continue;
        };
        inserted.push(name);
        let at = DVec2::new(e.num(10), e.num(20));
        let sx = if e.get(41).is_some() { e.num(41) } else { 1.0 };
        let sy = if e.get(42).is_some() { e.num(42) } else { 1.0 };
        let rot = e.num(50).to_radians();
        let (s, c) = rot.sin_cos();
        let xf = move |p: DVec2| {
            let q = DVec2::new(p.x * sx, p.y * sy);
            (at + DVec2::new(c * q.x - s * q.y, s * q.x + c * q.y)) * unit
        };
        let mut d = Drawn::default();
        draw(content, &xf, &mut d);
        drawn.push(d);
    }
    // Blocks never inserted are drawn where they are; so are loose entities.
    let plain = move |p: DVec2| p * unit;
    for (name, content) in &blocks {
        if !inserted.contains(&name.as_str()) && !name.starts_with('*') {
            let mut d = Drawn::default();
            draw(content, &plain, &mut d);
            drawn.push(d);
        }
    }
    let mut loose = Drawn::default();
    draw(&top, &plain, &mut loose);
    drawn.push(loose);
    let any_cut = drawn.iter().any(|d| !d.cut.is_empty());
    let mut pieces = Vec::new();
    let mut marks = Vec::new();
    for d in drawn {
        let loops = if !d.sew.is_empty() {
            d.sew.clone()
        } else if any_cut {
            d.cut.clone()
        } else {
            d.other.clone()
        };
        if loops.is_empty() {
            continue;
        }
        let name = d
            .texts
            .iter()
            .find_map(|(_, t)| t.strip_prefix("Piece Name:").map(|n| n.trim().to_string()));
        // Ours and AAMA's annotation name the fabric: "Material: ...".
        let fabric = (d.texts.iter())
            .find_map(|(_, t)| t.strip_prefix("Material:").map(|n| n.trim().to_string()));
        pieces.extend(nest(loops, name, pieces.len()).into_iter().map(|mut p| {
            p.saved.fabric = fabric.clone();
            p
        }));
        marks.extend(seam_marks(&d));
    }
    if pieces.is_empty() {
        return Err(DxfError::NoBoundary);
    }
    NamedOutline::take_marks(&mut pieces, marks, 1e-4);
    Ok(pieces)
}

/// Loops in mm as pieces in metres: the larger loops hold the smaller ones inside them
/// as holes.
fn nest(mut loops: Vec<Vec<DVec2>>, name: Option<String>, before: usize) -> Vec<NamedOutline> {
    let to_m = |l: &[DVec2]| -> Vec<Vec2> { l.iter().map(|p| (*p * 0.001).as_vec2()).collect() };
    loops.sort_by(|a, b| {
        let area = |l: &[DVec2]| signed_area2(&to_m(l)).abs();
        area(b).total_cmp(&area(a))
    });
    let mut out: Vec<NamedOutline> = Vec::new();
    for l in loops {
        let mut m = to_m(&l);
        if let Some(holder) = out.iter_mut().find(|p| contains(&p.outline.loops[0], m[0])) {
            if signed_area2(&m) > 0.0 {
                m.reverse();
            }
            holder.outline.loops.push(m);
        } else {
            if signed_area2(&m) < 0.0 {
                m.reverse();
            }
            let k = before + out.len() + 1;
            out.push(NamedOutline {
                name: match (&name, out.is_empty()) {
                    (Some(n), true) => n.clone(),
                    (Some(n), false) => format!("{n} ({})", out.len() + 1),
                    (None, _) => format!("piece {k}"),
                },
                outline: Outline { loops: vec![m] },
                marks: Vec::new(),
                saved: Default::default(),
            });
        }
    }
    out
}

/// Layer 8 lines chained into runs, each labelled by the "Seam: X" text on one of its
/// segments' middles; unlabelled runs are an internal line, not a seam. A run that two
/// labels' texts lie on (a seam ending where a dart's leg starts, as our export draws
/// a side seam over a dart's mouth) is chained again, joined only where it runs on
/// within 45 degrees, so that each label keeps its own stretch.
fn seam_marks(d: &Drawn) -> Vec<SeamMark> {
    let labels: Vec<(DVec2, &str)> = d
        .texts
        .iter()
        .filter_map(|(p, t)| Some((*p, t.strip_prefix("Seam:")?.trim())))
        .collect();
    let runs = |straight_in: &HashSet<usize>| -> (Sets, HashMap<usize, String>, HashSet<usize>) {
        let n = d.seam_lines.len();
        // Runs: lines joined at shared ends (union-find).
        let mut sets = Sets::new(n);
        for i in 0..n {
            for j in i + 1..n {
                if let Some(p) = meeting(d.seam_lines[i], d.seam_lines[j])
                    && (!straight_in.contains(&i) || runs_on(d.seam_lines[i], d.seam_lines[j], p))
                {
                    sets.join(i, j);
                }
            }
        }
        let mut label_of: HashMap<usize, String> = HashMap::new();
        let mut torn = HashSet::new();
        for (i, &(a, b)) in d.seam_lines.iter().enumerate() {
            let mid = (a + b) * 0.5;
            if let Some((_, l)) = labels.iter().find(|(p, _)| (*p - mid).length() < 0.05) {
                let r = sets.find(i);
                if label_of.get(&r).is_some_and(|had| had != l) {
                    torn.insert(r);
                }
                label_of.insert(r, (*l).to_string());
            }
        }
        (sets, label_of, torn)
    };
    let (mut sets, mut label_of, mut torn) = runs(&HashSet::new());
    if !torn.is_empty() {
        let lines: HashSet<usize> = (0..d.seam_lines.len())
            .filter(|&i| torn.contains(&sets.find(i)))
            .collect();
        (sets, label_of, torn) = runs(&lines);
    }
    let mut label: Vec<Option<String>> = (0..d.seam_lines.len())
        .map(|i| label_of.get(&sets.find(i)).cloned())
        .collect();
    if !torn.is_empty() {
        let lines: Vec<usize> = (0..d.seam_lines.len())
            .filter(|&i| torn.contains(&sets.find(i)))
            .collect();
        for (i, l) in walk_labels(d, &labels, &lines) {
            label[i] = Some(l);
        }
    }
    (0..d.seam_lines.len())
        .filter_map(|i| {
            let (a, b) = d.seam_lines[i];
            Some(SeamMark {
                label: label[i].clone()?,
                a: (a * 0.001).as_vec2(),
                b: (b * 0.001).as_vec2(),
                start: false,
            })
        })
        .collect()
}

/// Labels of `lines` (a run two labels' texts still lie on once re-chained: an armhole
/// running straight on into the side seam below it), each label walked on from the line
/// its text lies on, end to start, up to the next line with a text: our writer draws a
/// stretch's lines from start to end and puts its text on the first.
fn walk_labels(d: &Drawn, labels: &[(DVec2, &str)], lines: &[usize]) -> HashMap<usize, String> {
    let text_on = |i: usize| {
        let (a, b) = d.seam_lines[i];
        let mid = (a + b) * 0.5;
        labels
            .iter()
            .find(|(p, _)| (*p - mid).length() < 0.05)
            .map(|(_, l)| l.to_string())
    };
    let mut walked: HashMap<usize, String> = HashMap::new();
    for &first in lines {
        let Some(l) = text_on(first) else { continue };
        let mut at = first;
        walked.insert(at, l.clone());
        loop {
            let end = d.seam_lines[at].1;
            let next = (lines.iter().copied())
                .find(|&j| j != at && (d.seam_lines[j].0 - end).length() < 1e-3);
            match next {
                Some(j) if !walked.contains_key(&j) && text_on(j).is_none() => {
                    walked.insert(j, l.clone());
                    at = j;
                }
                _ => break,
            }
        }
    }
    walked
}

/// Where two lines share an end (within 0.001 of the file's millimetres).
fn meeting((a, b): (DVec2, DVec2), (c, e): (DVec2, DVec2)) -> Option<DVec2> {
    [a, b]
        .into_iter()
        .find(|p| (*p - c).length() < 1e-3 || (*p - e).length() < 1e-3)
}

/// Whether line `j` runs on from line `i` at their shared end `p` within 45 degrees.
fn runs_on((a, b): (DVec2, DVec2), (c, e): (DVec2, DVec2), p: DVec2) -> bool {
    let far = |x: DVec2, y: DVec2| if (x - p).length() < 1e-3 { y } else { x };
    let (u, v) = (far(a, b) - p, far(c, e) - p);
    let lens = u.length() * v.length();
    // Straight on, the two point away from each other: cos of their angle near -1.
    lens > 0.0 && u.dot(v) / lens < -std::f64::consts::FRAC_1_SQRT_2
}

/// Reads the pieces of a DXF file.
pub fn load_dxf(path: &Path) -> Result<Vec<NamedOutline>, DxfError> {
    let bytes = std::fs::read(path).map_err(|source| DxfError::Io {
        path: path.to_owned(),
        source,
    })?;
    let text = String::from_utf8(bytes)
        .map_err(|_| DxfError::Format("not text (binary DXF is not read)".into()))?;
    read_dxf(&text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dxf(body: &str) -> String {
        format!("0\nSECTION\n2\nENTITIES\n{body}0\nENDSEC\n0\nEOF\n")
    }

    #[test]
    fn a_plain_closed_polyline_with_a_bulge_is_a_piece() {
        // A 100 x 50 mm rectangle whose top side is a half circle (bulge 1).
        let body = "0\nLWPOLYLINE\n8\nCUT\n90\n4\n70\n1\n10\n0\n20\n0\n10\n100\n20\n0\n10\n100\n20\n50\n42\n1\n10\n0\n20\n50\n";
        let p = read_dxf(&dxf(body)).unwrap();
        assert_eq!(p.len(), 1);
        let l = &p[0].outline.loops[0];
        let per: f32 = (0..l.len())
            .map(|i| (l[(i + 1) % l.len()] - l[i]).length())
            .sum();
        let want = 0.1 + 0.05 + 0.05 + std::f32::consts::PI * 0.05;
        assert!((per - want).abs() < 5e-4, "{per} {want}");
        // The arc bulges up, away from the rectangle.
        assert!(l.iter().any(|q| q.y > 0.09));
        assert!(signed_area2(l) > 0.0);
    }

    /// A side seam over a dart's mouth, as our export draws it: seam E's lines below and
    /// above the mouth, each run on into one of dart D's legs at the mouth's corners,
    /// every stretch with its own text. Each line keeps its own label (the runs that
    /// chained E into D took one label for both).
    #[test]
    fn a_seam_that_runs_into_a_darts_leg_keeps_its_own_label() {
        let square = "0\nLWPOLYLINE\n8\n1\n90\n7\n70\n1\n10\n0\n20\n0\n10\n100\n20\n0\n\
                      10\n100\n20\n30\n10\n60\n20\n40\n10\n100\n20\n50\n10\n100\n20\n100\n\
                      10\n0\n20\n100\n";
        let line = |a: (f64, f64), b: (f64, f64)| {
            format!(
                "0\nLINE\n8\n8\n10\n{}\n20\n{}\n11\n{}\n21\n{}\n",
                a.0, a.1, b.0, b.1
            )
        };
        let text = |at: (f64, f64), t: &str| {
            format!(
                "0\nTEXT\n8\n15\n10\n{}\n20\n{}\n40\n6\n1\nSeam: {t}\n",
                at.0, at.1
            )
        };
        let stretches = [
            ((100.0, 0.0), (100.0, 30.0), "E"),
            ((100.0, 30.0), (64.0, 39.0), "D"),
            ((64.0, 41.0), (100.0, 50.0), "D"),
            ((100.0, 50.0), (100.0, 100.0), "E"),
        ];
        let mut body = square.to_string();
        for (a, b, l) in stretches {
            body += &line(a, b);
            body += &text(((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0), l);
        }
        let p = read_dxf(&dxf(&body)).unwrap();
        assert_eq!(p.len(), 1);
        let marks = &p[0].marks;
        assert_eq!(marks.len(), 4, "{marks:?}");
        for (a, _, l) in stretches {
            let at = Vec2::new(a.0 as f32, a.1 as f32) * 0.001;
            let m = marks.iter().find(|m| m.a.distance(at) < 1e-6).unwrap();
            assert_eq!(m.label, l, "{marks:?}");
        }
    }

    #[test]
    fn no_boundary_or_not_dxf_is_a_clear_error() {
        assert!(matches!(
            read_dxf(&dxf("0\nLINE\n8\n1\n10\n0\n20\n0\n11\n1\n21\n1\n")),
            Err(DxfError::NoBoundary)
        ));
        assert!(matches!(
            read_dxf("hello\nworld\n"),
            Err(DxfError::Format(_))
        ));
        assert!(matches!(
            read_dxf("0\nSECTION\n2\nENTITIES\n"),
            Err(DxfError::Format(_))
        ));
    }
}
