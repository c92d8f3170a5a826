//! The sewing pattern out: every piece of the design's cloth as it lies in its pattern
//! plane now, after cuts, tears and welds, as outlines to cut real fabric from (the point
//! of draping).
//!
//! A piece is a connected part of the cloth in the pattern: two triangles belong to the
//! same piece when they share an edge there (the same two vertices at the same two
//! pattern places). Welding two vertices in 3D does not join their pattern places, so a
//! seam stays an edge of the outline on both sides and a dart sewn shut stays a notch
//! cut into it, as a pattern maker draws them. Each piece's outline is the chain of its
//! boundary edges: the outer loop counter-clockwise, holes clockwise.
//!
//! `svg.rs` and `dxf.rs` write the pieces, laid out side by side without overlap, in
//! millimetres.

mod dxf;
mod svg;

use rustc_hash::{FxHashMap as HashMap, FxHashSet};
use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3, Vec3};

use super::document::Design;
use super::export::ExportError;
use crate::mesh::sets::Sets;

pub use dxf::dxf_string;
pub use svg::svg_string;

/// One piece of the pattern, in millimetres in its pattern plane (x right, y up).
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    pub name: String,
    /// The sewing line: the outer loop (counter-clockwise) first, then holes (clockwise).
    pub loops: Vec<Vec<DVec2>>,
    /// With a seam allowance: the cut line, each loop offset away from the material by
    /// it (mitred corners); otherwise equal to `loops`.
    pub cut: Vec<Vec<DVec2>>,
    /// Outline segments that are sewn to another (or the same) piece, with the seam's
    /// label: the same label marks both sides of one seam.
    pub seams: Vec<(String, DVec2, DVec2)>,
    /// The designer's names of the seams here that have one: (label, name).
    pub seam_names: Vec<(String, String)>,
    /// The grain line (warp direction: the pattern's first axis), through the piece.
    pub grain: (DVec2, DVec2),
    /// The piece's fabric, by its library name ("cloth" for the design's own material).
    pub fabric: String,
    /// Balance notches (`finish`): slits cut into the edge, each from the cut line into
    /// the piece, where a seam's side is matched to its other side: at its middle, and
    /// at its quarters when it is longer than [`QUARTER_NOTCHES_MM`]. Sewn notch to
    /// notch, the two sides meet as the simulation paired them (by arc length).
    pub notches: Vec<(DVec2, DVec2)>,
}

impl Piece {
    /// What a seam's mark says: its label, and its name after it when it has one.
    pub fn seam_text(&self, label: &str) -> String {
        match self.seam_names.iter().find(|(l, _)| l == label) {
            Some((_, name)) => format!("{label} {name}"),
            None => label.to_string(),
        }
    }
}

impl Piece {
    /// Length of each sewing-line loop, mm.
    pub fn perimeters(&self) -> Vec<f64> {
        self.loops.iter().map(|l| perimeter(l)).collect()
    }
}

/// The length of closed loop `l`.
pub fn perimeter(l: &[DVec2]) -> f64 {
    (0..l.len())
        .map(|i| (l[(i + 1) % l.len()] - l[i]).length())
        .sum()
}

/// Twice the signed area of closed loop `l` (positive counter-clockwise).
fn area2(l: &[DVec2]) -> f64 {
    (0..l.len())
        .map(|i| l[i].perp_dot(l[(i + 1) % l.len()]))
        .sum()
}

/// A corner's pattern place as a key: the vertex and its place, to a micrometre.
type Key = (u32, [i64; 3]);

fn key(v: u32, p: Vec3) -> Key {
    let q = |x: f32| (x as f64 * 1e6).round() as i64;
    (v, [q(p.x), q(p.y), q(p.z)])
}

/// The pattern plane of the cloth: an origin and two unit axes `u`, `v` with `u x v` the
/// cloth's front normal (its triangles' winding), so the pattern is drawn as seen from
/// the front, the face a designer sees. A square cloth lies in X and Z; any flat
/// pattern's plane comes from its triangles' summed normals.
fn plane(design: &Design) -> (DVec3, DVec3, DVec3) {
    let mut n = DVec3::ZERO;
    let mut o = DVec3::ZERO;
    let mut k = 0.0f64;
    for (_, t) in design.sim.cloth.live.iter() {
        let [a, b, c] = t.rest.map(|p| p.as_dvec3());
        n += (b - a).cross(c - a);
        o += a + b + c;
        k += 3.0;
    }
    let n = n.try_normalize().unwrap_or(DVec3::Y);
    // The first axis: world X projected into the plane (the grid's warp), else Z.
    let u = (DVec3::X - n * n.dot(DVec3::X))
        .try_normalize()
        .or_else(|| (DVec3::Z - n * n.dot(DVec3::Z)).try_normalize())
        .unwrap_or(DVec3::X);
    let v = n.cross(u);
    (o / k.max(1.0), u, v)
}

/// The triangles of each part of the cloth connected in the pattern (see the module
/// doc): slots, each part's in order, the parts in the order of their first triangle.
pub fn pattern_parts(design: &Design) -> Vec<Vec<u32>> {
    let live = &design.sim.cloth.live;
    let slots: Vec<u32> = live.iter().map(|(s, _)| s).collect();
    let tris: Vec<[Key; 3]> = live
        .iter()
        .map(|(_, t)| [0, 1, 2].map(|k| key(t.v[k], t.rest[k])))
        .collect();
    let mut edge_tri: HashMap<(Key, Key), usize> = HashMap::default();
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            edge_tri.insert((t[k], t[(k + 1) % 3]), i);
        }
    }
    // Triangles joined across shared pattern edges (union-find).
    let mut sets = Sets::new(tris.len());
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            if let Some(&j) = edge_tri.get(&(t[(k + 1) % 3], t[k])) {
                sets.join(i, j);
            }
        }
    }
    let mut part_of: HashMap<usize, usize> = HashMap::default();
    let mut parts: Vec<Vec<u32>> = Vec::new();
    for i in 0..tris.len() {
        let root = sets.find(i);
        let k = *part_of.entry(root).or_insert_with(|| {
            parts.push(Vec::new());
            parts.len() - 1
        });
        parts[k].push(slots[i]);
    }
    parts
}

/// The pieces of the design's pattern (no allowance, not laid out), in millimetres,
/// named as [`Design::piece_list`] names them.
pub fn pieces(design: &Design) -> Vec<Piece> {
    let (origin, u, v) = plane(design);
    pieces_in(design, |p: Vec3| {
        let d = p.as_dvec3() - origin;
        DVec2::new(d.dot(u), d.dot(v)) * 1000.0
    })
}

/// Every listed seam's outline edges where the studio's pattern view draws them: in the
/// design's pattern plane (rest x and -z), metres, each with its seam's index.
pub fn seam_lines(design: &Design) -> Vec<(usize, DVec2, DVec2)> {
    if design.seams.is_empty() {
        return Vec::new();
    }
    let index: HashMap<String, usize> = (0..design.seams.len())
        .map(|i| (seam_label(i), i))
        .collect();
    pieces_in(design, |p: Vec3| DVec2::new(p.x as f64, -p.z as f64))
        .into_iter()
        .flat_map(|piece| piece.seams)
        .filter_map(|(label, a, b)| Some((*index.get(&label)?, a, b)))
        .collect()
}

/// [`pieces`] with each rest position mapped into the plane by `to2`.
fn pieces_in(design: &Design, to2: impl Fn(Vec3) -> DVec2 + Copy) -> Vec<Piece> {
    // The designer's names of the seams that have one, by label.
    let seam_names_of: HashMap<String, String> = design
        .seams
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.name.is_empty())
        .map(|(i, s)| (seam_label(i), s.name.clone()))
        .collect();
    let live = &design.sim.cloth.live;
    let parts = pattern_parts(design);
    let names = design.describe(&parts);
    let seam_of = seam_labels(design);
    let eased: Vec<[Vec3; 3]> = design
        .seams
        .iter()
        .flat_map(|s| &s.eased)
        .copied()
        .collect();
    let mut out = Vec::new();
    for (part, info) in parts.iter().zip(names) {
        let mut corners: Vec<[Key; 3]> = part
            .iter()
            .filter_map(|&s| live.tri(s))
            .map(|t| [0, 1, 2].map(|k| key(t.v[k], t.rest[k])))
            .collect();
        let mut places: HashMap<Key, DVec2> = part
            .iter()
            .filter_map(|&s| live.tri(s))
            .flat_map(|t| (0..3).map(move |k| (key(t.v[k], t.rest[k]), to2(t.rest[k]))))
            .collect();
        add_eased(&mut corners, &mut places, &eased, to2);
        let boundary = boundary_of(&corners);
        let key_loops = chain(&boundary);
        let mut loops = key_loops
            .iter()
            .map(|l| l.iter().map(|k| places[k]).collect::<Vec<DVec2>>())
            .filter(|l| l.len() >= 3)
            .collect::<Vec<_>>();
        if loops.is_empty() {
            continue;
        }
        // The outer loop: the largest; counter-clockwise, holes clockwise.
        loops.sort_by(|a, b| area2(b).abs().total_cmp(&area2(a).abs()));
        for (i, l) in loops.iter_mut().enumerate() {
            if (area2(l) > 0.0) != (i == 0) {
                l.reverse();
            }
        }
        let seams: Vec<(String, DVec2, DVec2)> = key_loops
            .iter()
            .flat_map(|l| seam_segments(l, &places, &seam_of))
            .map(|(label, a, b)| (label, places[&a], places[&b]))
            .collect();
        // The grain line through the middle, along the piece's warp, 60% of its extent.
        let (lo, hi) = bounds(&loops[0]);
        let angle = info.record.map_or(0.0, |r| design.pieces[r].grain as f64);
        let dir = DVec2::new(angle.cos(), angle.sin());
        let half = 0.3 * ((hi.x - lo.x) * dir.x.abs() + (hi.y - lo.y) * dir.y.abs());
        let mid = (lo + hi) * 0.5;
        let grain = (mid - dir * half, mid + dir * half);
        let mut seam_names: Vec<(String, String)> = Vec::new();
        for (label, _, _) in &seams {
            if let Some(name) = seam_names_of.get(label)
                && !seam_names.iter().any(|(l, _)| l == label)
            {
                seam_names.push((label.clone(), name.clone()));
            }
        }
        out.push(Piece {
            name: info.name,
            cut: loops.clone(),
            loops,
            seams,
            seam_names,
            grain,
            fabric: info.fabric,
            notches: Vec::new(),
        });
    }
    out
}

/// The directed pattern edges of `corners` without their twin: the part's outline.
fn boundary_of(corners: &[[Key; 3]]) -> Vec<(Key, Key)> {
    let edges = || {
        corners
            .iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
    };
    let directed: FxHashSet<(Key, Key)> = edges().collect();
    edges()
        .filter(|&(a, b)| !directed.contains(&(b, a)))
        .collect()
}

/// Puts back into a part (its triangles' corner keys and their places) the triangles the
/// seams' welds folded away (`Seam::eased`, rest corners). A seam whose side has more
/// vertices than its partner welds two neighbours of that side to one partner vertex in
/// turn, and the second weld collapses the triangle between them (the extra length eased
/// into the seam in 3D). That cloth is still part of the piece, but its outline went round
/// the missing triangle: a notch a triangle deep, or a corner cut off, and a spike in
/// the cut line with an allowance (the dress's back had six). Each such triangle is
/// joined to the part along an outline edge it shares (the edge's twin is one of its
/// sides), its third corner the outline's key at that place next to the edge, or a place
/// of its own where the weld merged that corner away; a triangle it shares no outline
/// edge with yet may join after another (a run of them), one not of this part never
/// does. A dart's tip, whose cloth was cut away, is never in the record and stays.
fn add_eased(
    corners: &mut Vec<[Key; 3]>,
    places: &mut HashMap<Key, DVec2>,
    eased: &[[Vec3; 3]],
    to2: impl Fn(Vec3) -> DVec2,
) {
    let mut left: Vec<usize> = (0..eased.len()).collect();
    loop {
        let boundary = boundary_of(corners);
        let next_of: HashMap<Key, Key> = boundary.iter().map(|&(a, b)| (a, b)).collect();
        let prev_of: HashMap<Key, Key> = boundary.iter().map(|&(a, b)| (b, a)).collect();
        let before = left.len();
        left.retain(|&n| {
            let t = eased[n];
            let q = t.map(|p| key(0, p).1);
            for i in 0..3 {
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                // The triangle's side i -> j is the twin of outline edge (u, v).
                let Some(&(u, v)) = boundary.iter().find(|(u, v)| u.1 == q[j] && v.1 == q[i])
                else {
                    continue;
                };
                // Its third corner: next to the edge on the outline, or its own place.
                let third = [next_of.get(&v), prev_of.get(&u)]
                    .into_iter()
                    .flatten()
                    .copied()
                    .find(|w| w.1 == q[k])
                    .unwrap_or((u32::MAX - n as u32, q[k]));
                places.entry(third).or_insert_with(|| to2(t[k]));
                let mut tri = [v, u, third];
                // In the triangle's own winding: i, j, k.
                tri.rotate_right(i);
                corners.push(tri);
                return false;
            }
            true
        });
        if left.is_empty() || left.len() == before {
            return;
        }
    }
}

/// Most outline edges in a row a seam may skip (see `seam_segments`).
const SEAM_GAP: usize = 8;

/// The outline edges of loop `l` (keys, with their pattern places) that belong to a
/// seam, with its label: both ends in the seam, or in a short straight run of edges
/// between two of the same seam going on in the same direction (a seam path resampled to
/// its partner's count pairs only some of its vertices). A run that turns, as between a
/// dart's two sides, is not a seam.
fn seam_segments(
    l: &[Key],
    places: &HashMap<Key, DVec2>,
    seam_of: &HashMap<u32, Vec<String>>,
) -> Vec<(String, Key, Key)> {
    let n = l.len();
    let label = |i: usize| -> Option<&String> {
        let (a, b) = (l[i % n], l[(i + 1) % n]);
        let (sa, sb) = (seam_of.get(&a.0)?, seam_of.get(&b.0)?);
        sa.iter().find(|s| sb.contains(s))
    };
    let own: Vec<Option<&String>> = (0..n).map(label).collect();
    let mut out: Vec<Option<&String>> = own.clone();
    for i in 0..n {
        if own[i].is_some() || own[(i + n - 1) % n].is_none() {
            continue;
        }
        // A run of unlabelled edges starts at i: fill it if the same seam resumes soon.
        let before = own[(i + n - 1) % n];
        let dir = |e: usize| (places[&l[(e + 1) % n]] - places[&l[e % n]]).normalize_or_zero();
        let d0 = dir(i + n - 1);
        // The run ends at the first vertex of the same seam (a side's last vertex can
        // follow one the pairing skipped, with no labelled edge after it).
        let in_before = |k: usize| {
            seam_of
                .get(&l[(i + k) % n].0)
                .is_some_and(|labels| before.is_some_and(|b| labels.contains(b)))
        };
        if let Some(len) = (1..=SEAM_GAP.min(n - 1)).find(|&k| in_before(k))
            && (0..len).all(|k| dir(i + k).dot(d0) > 0.95)
        {
            for k in 0..len {
                out[(i + k) % n] = before;
            }
        }
    }
    (0..n)
        .filter_map(|i| Some((out[i]?.clone(), l[i], l[(i + 1) % n])))
        .collect()
}

/// The seams' labels ("A", "B", ...) of each vertex in them.
fn seam_labels(design: &Design) -> HashMap<u32, Vec<String>> {
    let mut m: HashMap<u32, Vec<String>> = HashMap::default();
    for (i, s) in design.seams.iter().enumerate() {
        let label = label(i);
        for &(a, b) in &s.pairs {
            for v in [a, b] {
                let e = m.entry(v).or_default();
                if !e.contains(&label) {
                    e.push(label.clone());
                }
            }
        }
    }
    m
}

/// Seam `i`'s label in the pattern out: "A".."Z", then "AA", "AB", ...
pub fn seam_label(i: usize) -> String {
    label(i)
}

/// "A".."Z", then "AA", "AB", ...
pub(crate) fn label(i: usize) -> String {
    let letter = |k: usize| char::from(b'A' + (k % 26) as u8);
    if i < 26 {
        letter(i).to_string()
    } else {
        format!("{}{}", letter(i / 26 - 1), letter(i))
    }
}

/// Chains directed boundary edges into closed loops of keys.
fn chain(edges: &[(Key, Key)]) -> Vec<Vec<Key>> {
    let mut next: HashMap<Key, Vec<Key>> = HashMap::default();
    for &(a, b) in edges {
        next.entry(a).or_default().push(b);
    }
    let mut loops = Vec::new();
    let mut starts: Vec<Key> = edges.iter().map(|e| e.0).collect();
    starts.sort_unstable();
    for s in starts {
        while next.get(&s).is_some_and(|n| !n.is_empty()) {
            let mut l = vec![s];
            let mut at = s;
            while let Some(b) = next.get_mut(&at).and_then(|n| n.pop()) {
                if b == s {
                    break;
                }
                l.push(b);
                at = b;
            }
            loops.push(l);
        }
    }
    loops
}

fn bounds(l: &[DVec2]) -> (DVec2, DVec2) {
    l.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

/// Loop `l` offset by `d` to the right of its direction (away from the material, for
/// an outer loop counter-clockwise and a hole clockwise), with mitred corners; a corner
/// sharper than the mitre limit (4 d) is bevelled.
pub fn offset(l: &[DVec2], d: f64) -> Vec<DVec2> {
    let n = l.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (p, c, q) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
        let right = |a: DVec2, b: DVec2| {
            let t = (b - a).normalize_or_zero();
            DVec2::new(t.y, -t.x)
        };
        let (n1, n2) = (right(p, c), right(c, q));
        let m = n1 + n2;
        let cos_half = (m.length() * 0.5).max(1e-9);
        let miter = d / cos_half;
        if miter <= 4.0 * d && m.length() > 1e-9 {
            out.push(c + m.normalize() * miter);
        } else {
            out.push(c + n1 * d);
            out.push(c + n2 * d);
        }
    }
    out
}

/// A seam side longer than this gets notches at its quarters too, mm.
pub const QUARTER_NOTCHES_MM: f64 = 250.0;
/// How far a notch reaches into a piece without an allowance, mm.
const NOTCH_DEPTH_MM: f64 = 5.0;

/// Each seam side of `p` as a chain of outline points (its segments joined end to end).
fn seam_sides(p: &Piece) -> Vec<Vec<DVec2>> {
    let mut labels: Vec<&str> = p.seams.iter().map(|(l, _, _)| l.as_str()).collect();
    labels.sort_unstable();
    labels.dedup();
    let mut sides = Vec::new();
    for label in labels {
        let mut segs: Vec<(DVec2, DVec2)> = (p.seams.iter())
            .filter(|(l, _, _)| l == label)
            .map(|&(_, a, b)| (a, b))
            .collect();
        let mut chains: Vec<Vec<DVec2>> = Vec::new();
        while let Some((a, b)) = segs.pop() {
            let mut c = vec![a, b];
            // Grow the chain at both ends while a segment continues it.
            loop {
                let end = c[c.len() - 1];
                let start = c[0];
                if let Some(k) = segs.iter().position(|s| s.0 == end) {
                    c.push(segs.swap_remove(k).1);
                } else if let Some(k) = segs.iter().position(|s| s.1 == start) {
                    c.insert(0, segs.swap_remove(k).0);
                } else {
                    break;
                }
            }
            chains.push(c);
        }
        sides.extend(chains);
    }
    sides
}

/// Whether `q` lies in the piece's material (inside its outer loop and no hole; even-odd
/// over the loops).
fn in_material(loops: &[Vec<DVec2>], q: DVec2) -> bool {
    let mut inside = false;
    for l in loops {
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                inside = !inside;
            }
        }
    }
    inside
}

/// The point at `t` of the way along chain `c` by length, and the chain's direction there.
fn along(c: &[DVec2], t: f64) -> (DVec2, DVec2) {
    let total: f64 = c.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    let mut left = t * total;
    for w in c.windows(2) {
        let len = (w[1] - w[0]).length();
        if len > 0.0 && (left <= len || w[1] == c[c.len() - 1]) {
            let d = (w[1] - w[0]) / len;
            return (w[0] + d * left.min(len), d);
        }
        left -= len;
    }
    (c[0], DVec2::X)
}

/// The balance notches of piece `p` (see [`Piece::notches`]) for an allowance of
/// `allowance_mm`: each a slit square to its seam's side, from the cut line half way to
/// the sewing line (or [`NOTCH_DEPTH_MM`] into a piece cut on its sewing line).
fn notches(p: &Piece, allowance_mm: f64) -> Vec<(DVec2, DVec2)> {
    let mut out = Vec::new();
    for side in seam_sides(p) {
        let len: f64 = side.windows(2).map(|w| (w[1] - w[0]).length()).sum();
        if len <= 0.0 {
            continue;
        }
        let at: &[f64] = if len > QUARTER_NOTCHES_MM {
            &[0.25, 0.5, 0.75]
        } else {
            &[0.5]
        };
        for &t in at {
            let (q, d) = along(&side, t);
            let mut n = DVec2::new(-d.y, d.x);
            if !in_material(&p.loops, q + n * 0.5) {
                n = -n;
            }
            let (from, depth) = if allowance_mm > 0.0 {
                (q - n * allowance_mm, 0.5 * allowance_mm)
            } else {
                (q, NOTCH_DEPTH_MM)
            };
            out.push((from, from + n * depth));
        }
    }
    out
}

/// The width the pattern's layout keeps to, mm: a wide fabric's (150 cm), so the pattern
/// prints and lays on the cloth in rows instead of one strip (a jumpsuit's was 5 m long).
pub const LAYOUT_WIDTH_MM: f64 = 1500.0;
/// The gap between pieces in the layout, mm.
const LAYOUT_GAP_MM: f64 = 20.0;

/// Adds a seam allowance of `mm` to every piece (the cut line) and its notches, then lays
/// the pieces out left to right in rows [`LAYOUT_WIDTH_MM`] wide (a piece wider than that
/// has a row of its own), 20 mm apart, the first row's lowest points on y = 0 and each
/// next row above.
pub fn finish(mut pieces: Vec<Piece>, allowance_mm: f64) -> Vec<Piece> {
    let (mut x, mut row_y, mut row_top) = (0.0, 0.0, 0.0f64);
    for p in &mut pieces {
        if allowance_mm > 0.0 {
            p.cut = p.loops.iter().map(|l| offset(l, allowance_mm)).collect();
        }
        p.notches = notches(p, allowance_mm);
        let (lo, hi) = p.cut.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), l| {
                let (a, b) = bounds(l);
                (lo.min(a), hi.max(b))
            },
        );
        if x > 0.0 && x + (hi.x - lo.x) > LAYOUT_WIDTH_MM {
            x = 0.0;
            row_y = row_top + LAYOUT_GAP_MM;
        }
        row_top = row_top.max(row_y + hi.y - lo.y);
        let shift = DVec2::new(x - lo.x, row_y - lo.y);
        for l in p.loops.iter_mut().chain(p.cut.iter_mut()) {
            for q in l.iter_mut() {
                *q += shift;
            }
        }
        for s in &mut p.seams {
            s.1 += shift;
            s.2 += shift;
        }
        for n in &mut p.notches {
            n.0 += shift;
            n.1 += shift;
        }
        p.grain.0 += shift;
        p.grain.1 += shift;
        x += hi.x - lo.x + LAYOUT_GAP_MM;
    }
    pieces
}

/// Largest seam allowance, mm.
pub const MAX_ALLOWANCE_MM: f64 = 100.0;

/// Writes `dir/pattern.svg` and `dir/pattern.dxf` (AAMA): the design's pieces with a seam
/// allowance of `allowance_mm` (0: none). Returns the two paths.
pub fn export_pattern(
    design: &Design,
    dir: &Path,
    allowance_mm: f64,
) -> Result<Vec<PathBuf>, ExportError> {
    if !(0.0..=MAX_ALLOWANCE_MM).contains(&allowance_mm) {
        return Err(ExportError::BadAllowance(allowance_mm));
    }
    write_pattern(&finish(pieces(design), allowance_mm), dir)
}

/// Writes laid-out pieces (`finish`) as `dir/pattern.svg` and `dir/pattern.dxf`.
pub fn write_pattern(pieces: &[Piece], dir: &Path) -> Result<Vec<PathBuf>, ExportError> {
    if pieces.is_empty() {
        return Err(ExportError::Empty);
    }
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| ExportError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let svg = dir.join("pattern.svg");
    std::fs::write(&svg, svg_string(pieces)).map_err(io(&svg))?;
    let dxf = dir.join("pattern.dxf");
    std::fs::write(&dxf, dxf_string(pieces)).map_err(io(&dxf))?;
    Ok(vec![svg, dxf])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::{Cloth, Environment, Material, ModelKind, Simulation};
    use glam::Vec2;

    /// A flat `size` m square cloth of `n` x `n` cells on the floor.
    fn square(size: f32, n: usize) -> Design {
        let m = Material::default();
        let cloth = Cloth::new(ClothMesh::grid(size, size, n, n, 0.0).unwrap(), &m).unwrap();
        let sim = Simulation::new(
            cloth,
            None,
            ModelKind::Xpbd,
            m,
            Environment::default(),
            None,
        )
        .unwrap();
        Design::new(sim)
    }

    #[test]
    fn a_square_cloth_is_one_piece_with_its_perimeter() {
        let d = square(1.0, 8);
        let p = pieces(&d);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].loops.len(), 1);
        assert!(
            (p[0].perimeters()[0] - 4000.0).abs() < 0.01,
            "{:?}",
            p[0].perimeters()
        );
        assert!(area2(&p[0].loops[0]) > 0.0, "outer loop counter-clockwise");
        // A 10 mm allowance: the cut line is the square grown by 10 mm each side.
        let f = finish(p, 10.0);
        assert!((perimeter(&f[0].cut[0]) - 4080.0).abs() < 0.01);
        let (lo, _) = bounds(&f[0].cut[0]);
        assert!(
            lo.x.abs() < 1e-9 && lo.y.abs() < 1e-9,
            "laid out at the origin"
        );
    }

    #[test]
    fn a_band_cut_out_makes_two_pieces_and_a_hole_makes_two_loops() {
        let mut d = square(1.0, 8);
        // The two middle rows of cells (triangle centres in the band), across the cloth.
        d.remove_region(Vec2::new(-0.1, 0.37), Vec2::new(1.1, 0.63))
            .unwrap();
        let p = pieces(&d);
        assert_eq!(p.len(), 2);
        for q in &p {
            // Each half: 1000 x 375 mm.
            assert!(
                (q.perimeters()[0] - 2750.0).abs() < 0.01,
                "{:?}",
                q.perimeters()
            );
        }
        let laid = finish(p, 0.0);
        let (lo0, hi0) = bounds(&laid[0].cut[0]);
        let (lo1, hi1) = bounds(&laid[1].cut[0]);
        // Two 1000 mm pieces: one row each, the second above, 20 mm apart.
        assert!(
            lo1.y >= hi0.y + 19.999 && lo0.x.abs() < 1e-9 && lo1.x.abs() < 1e-9,
            "laid out in rows without overlap: {lo0} {hi0} {lo1} {hi1}"
        );
        // Narrow pieces share a row, within the layout's width.
        let narrow: Vec<Piece> = (0..7)
            .map(|i| {
                let mut q = laid[i % 2].clone();
                let sq = vec![
                    DVec2::ZERO,
                    DVec2::new(300.0, 0.0),
                    DVec2::new(300.0, 200.0),
                    DVec2::new(0.0, 200.0),
                ];
                (q.loops, q.cut, q.seams, q.notches) = (vec![sq.clone()], vec![sq], vec![], vec![]);
                q
            })
            .collect();
        let laid = finish(narrow, 0.0);
        let boxes: Vec<(DVec2, DVec2)> = laid.iter().map(|q| bounds(&q.cut[0])).collect();
        // Four of 300 mm and three gaps in a row (1260 mm), then the other three.
        assert!(boxes.iter().all(|(_, hi)| hi.x <= LAYOUT_WIDTH_MM));
        assert_eq!(boxes.iter().filter(|(lo, _)| lo.y == 0.0).count(), 4);
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[i + 1..] {
                let apart = a.1.x + 19.999 <= b.0.x
                    || b.1.x + 19.999 <= a.0.x
                    || a.1.y + 19.999 <= b.0.y
                    || b.1.y + 19.999 <= a.0.y;
                assert!(apart, "{a:?} {b:?}");
            }
        }

        let mut d = square(1.0, 8);
        d.remove_region(Vec2::new(0.24, 0.24), Vec2::new(0.76, 0.76))
            .unwrap();
        let p = pieces(&d);
        assert_eq!(p.len(), 1);
        assert_eq!(p[0].loops.len(), 2, "an outline and a hole");
        assert!(
            (p[0].perimeters()[1] - 2000.0).abs() < 0.01,
            "{:?}",
            p[0].perimeters()
        );
        assert!(area2(&p[0].loops[1]) < 0.0, "the hole clockwise");
        // The hole's allowance goes into the hole: its cut line is shorter.
        let f = finish(p, 10.0);
        assert!(perimeter(&f[0].cut[1]) < perimeter(&f[0].loops[1]));
        assert!(perimeter(&f[0].cut[0]) > perimeter(&f[0].loops[0]));
    }

    #[test]
    fn both_sides_of_a_seam_carry_its_label_and_a_welded_seam_stays_an_edge() {
        let mut d = square(1.0, 8);
        // Cut a notch: remove two columns of cells from the bottom edge to the middle,
        // then sew the notch's two sides (a dart).
        d.remove_region(Vec2::new(0.37, -0.1), Vec2::new(0.63, 0.5))
            .unwrap();
        let side = |x: f32| -> Vec<u32> {
            let mut v: Vec<(f32, u32)> = (0..d.sim.cloth.len() as u32)
                .filter(|&i| d.sim.cloth.live.vertex_alive(i))
                .filter_map(|i| {
                    let uv = d.vertex_uv(i)?;
                    ((uv.x - x).abs() < 1e-4 && uv.y < 0.5 - 1e-4).then_some((uv.y, i))
                })
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.into_iter().map(|(_, i)| i).collect()
        };
        let (a, b) = (side(0.375), side(0.625));
        assert_eq!(a.len(), 4);
        d.add_seam(&a, &b, 0.05).unwrap();
        let p = pieces(&d);
        assert_eq!(p.len(), 1);
        let labelled = |p: &Piece| p.seams.iter().filter(|s| s.0 == "A").count();
        assert_eq!(
            labelled(&p[0]),
            6,
            "three segments each side: {:?}",
            p[0].seams
        );
        // Welding the pairs in 3D keeps the dart open in the pattern.
        for &(x, y) in &d.seams[0].pairs.clone() {
            d.sew(x, y).unwrap();
        }
        let p = pieces(&d);
        assert_eq!(p.len(), 1);
        assert!(
            (p[0].perimeters()[0] - 5000.0).abs() < 0.01,
            "{:?}",
            p[0].perimeters()
        );
    }

    #[test]
    fn a_paths_pattern_length_is_its_rest_length_however_it_hangs() {
        let mut d = square(1.0, 8);
        let row: Vec<u32> = (0..=8).collect();
        assert!((d.pattern_length(&row) - 1.0).abs() < 1e-5);
        // Stretched in 3D, the pattern length stays.
        for v in &row {
            d.sim.cloth.x[*v as usize].x *= 2.0;
        }
        assert!((d.pattern_length(&row) - 1.0).abs() < 1e-5);
        assert!((d.pattern_length(&row[..3]) - 0.25).abs() < 1e-5);
        // A vertex skipped (as a seam's shorter side is paired): the pattern's distance
        // between the two, not the 3D one (0.5 m, stretched).
        assert!((d.pattern_length(&[0, 2, 3]) - 0.375).abs() < 1e-5);
    }

    #[test]
    fn a_seam_skipping_vertices_on_a_straight_side_is_still_one_seam() {
        // A loop whose bottom side runs 0..4; the seam holds 0, 1, 3, 4 (2 skipped, on
        // the same straight side) and 6, round a corner from 4.
        let pts = [
            (0.0, 0.0),
            (1.0, 0.0),
            (2.0, 0.0),
            (3.0, 0.0),
            (4.0, 0.0),
            (4.0, 2.0),
            (2.0, 2.0),
            (0.0, 2.0),
        ];
        let l: Vec<Key> = (0..pts.len() as u32)
            .map(|v| (v, [v as i64, 0, 0]))
            .collect();
        let places: HashMap<Key, DVec2> = l
            .iter()
            .zip(pts)
            .map(|(k, (x, y))| (*k, DVec2::new(x, y)))
            .collect();
        let seam_of: HashMap<u32, Vec<String>> = [0, 1, 3, 4, 6]
            .map(|v| (v, vec!["A".to_string()]))
            .into_iter()
            .collect();
        let s = seam_segments(&l, &places, &seam_of);
        let edges: Vec<(u32, u32)> = s.iter().map(|(_, a, b)| (a.0, b.0)).collect();
        // 1-2 and 2-3 filled; 4-5-6 turns a corner: not.
        assert_eq!(edges, vec![(0, 1), (1, 2), (2, 3), (3, 4)]);
        // The seam's last vertex follows a skipped one, and the outline turns at it (the
        // dress's back at the armhole corner, 29 mm of seam D lost before): 3-4 is the
        // seam's all the same.
        let seam_of: HashMap<u32, Vec<String>> = [0, 1, 2, 4]
            .map(|v| (v, vec!["A".to_string()]))
            .into_iter()
            .collect();
        let s = seam_segments(&l, &places, &seam_of);
        let edges: Vec<(u32, u32)> = s.iter().map(|(_, a, b)| (a.0, b.0)).collect();
        assert_eq!(edges, vec![(0, 1), (1, 2), (2, 3), (3, 4)]);
    }

    #[test]
    fn offset_mitres_right_angles_and_bevels_sharp_corners() {
        let sq = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(10.0, 10.0),
            DVec2::new(0.0, 10.0),
        ];
        let o = offset(&sq, 1.0);
        assert_eq!(o.len(), 4);
        assert!((o[0] - DVec2::new(-1.0, -1.0)).length() < 1e-9, "{o:?}");
        // A needle-sharp spike: its tip is bevelled (two points), not mitred far out.
        let spike = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(100.0, 0.5),
            DVec2::new(0.0, 1.0),
        ];
        let o = offset(&spike, 1.0);
        assert!(o.len() > 3);
        assert!(o.iter().all(|p| p.x < 106.0), "{o:?}");
    }

    /// The outline of `corners` as chained loops of places.
    fn outline(corners: &[[Key; 3]], places: &HashMap<Key, DVec2>) -> Vec<Vec<DVec2>> {
        chain(&boundary_of(corners))
            .iter()
            .map(|l| l.iter().map(|k| places[k]).collect())
            .collect()
    }

    #[test]
    fn triangles_a_weld_folded_away_go_back_into_the_outline() {
        let p = |x: f32, z: f32| Vec3::new(x, 0.0, z);
        let to2 = |q: Vec3| DVec2::new(q.x as f64, q.z as f64);
        let (c0, c1, c2, c3, m) = (
            p(0.0, 0.0),
            p(2.0, 0.0),
            p(2.0, 2.0),
            p(0.0, 2.0),
            p(1.0, 1.0),
        );
        // A notch: four triangles round a centre, the first folded away, its two corners
        // on the outline since merged into one vertex (7) as a seam's weld leaves them.
        let k = |v: u32, q: Vec3| key(v, q);
        let mut corners = vec![
            [k(7, c1), k(2, c2), k(4, m)],
            [k(2, c2), k(3, c3), k(4, m)],
            [k(3, c3), k(7, c0), k(4, m)],
        ];
        let mut places: HashMap<Key, DVec2> = corners
            .iter()
            .flatten()
            .map(|&q| {
                (
                    q,
                    to2([c0, c1, c2, c3, m]
                        .into_iter()
                        .find(|r| key(0, *r).1 == q.1)
                        .unwrap()),
                )
            })
            .collect();
        assert_eq!(outline(&corners, &places)[0].len(), 5, "the notch");
        add_eased(&mut corners, &mut places, &[[c0, c1, m]], to2);
        let l = &outline(&corners, &places)[0];
        assert_eq!(l.len(), 4, "{l:?}");
        assert!((perimeter(l) - 8.0).abs() < 1e-9);
        // A corner cut off: the square in two triangles, the one with corner c1 folded
        // away and c1 merged into another vertex (no key left at its place).
        let mut corners = vec![[k(0, c0), k(2, c2), k(3, c3)]];
        let mut places: HashMap<Key, DVec2> = [(k(0, c0), c0), (k(2, c2), c2), (k(3, c3), c3)]
            .into_iter()
            .map(|(q, r)| (q, to2(r)))
            .collect();
        add_eased(&mut corners, &mut places, &[[c0, c1, c2]], to2);
        let l = &outline(&corners, &places)[0];
        assert_eq!(l.len(), 4, "{l:?}");
        assert!((perimeter(l) - 8.0).abs() < 1e-9);
        // A triangle of another part (no outline edge of this one) stays out.
        let mut corners = vec![[k(0, c0), k(2, c2), k(3, c3)]];
        add_eased(
            &mut corners,
            &mut places,
            &[[p(5.0, 0.0), p(6.0, 0.0), p(6.0, 1.0)]],
            to2,
        );
        assert_eq!(corners.len(), 1);
    }
}
