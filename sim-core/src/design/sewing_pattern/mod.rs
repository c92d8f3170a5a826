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

pub(crate) mod dart;
mod dxf;
mod labels;
mod meet;
mod notches;
mod offset;
mod shut;
mod svg;
mod untangle;

use rustc_hash::{FxHashMap as HashMap, FxHashSet};
use std::path::{Path, PathBuf};

use glam::{DVec2, DVec3, Vec3};

use super::document::Design;
use super::export::ExportError;
use super::garment::{Landmarks, PieceStart};
use crate::mesh::sets::Sets;

pub(crate) use dart::line_hit;
pub use dxf::dxf_string;
pub(crate) use labels::label;
pub use labels::seam_label;
use labels::seam_labels;
pub use notches::QUARTER_NOTCHES_MM;
pub(crate) use notches::in_material;
use notches::notches;
pub use offset::offset;
use offset::offset_tagged;
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
    /// at its quarters when the seam's longer side is longer than
    /// [`QUARTER_NOTCHES_MM`]. Sewn notch to notch, the two sides meet as the simulation
    /// paired them (by arc length).
    pub notches: Vec<(DVec2, DVec2)>,
    /// Drill holes: a sewn dart's point, marked on the fabric a little inside it (the
    /// dart's cap keeps its intake, so its legs are no longer cut edges).
    pub drills: Vec<DVec2>,
    /// The labels of this piece's seam stretches whose seam presses a dart toward its
    /// second leg ([`Seam::press_second`](crate::design::Seam)): a dart found on one is
    /// capped so.
    pub press_second: Vec<String>,
    /// Each dart's press mark (`finish`, `view_of`), with its seam's label: from the
    /// middle of the dart's mouth toward the leg its intake is pressed to. The studio
    /// draws it; the SVG and DXF do not (the cap says it).
    pub presses: Vec<(String, DVec2, DVec2)>,
    /// Where the piece started on the body (its record's placement), and where its
    /// own pattern coordinates' origin lies among its points: the SVG carries both, so
    /// that the pattern draped again starts the piece there.
    pub start: Option<(PieceStart, DVec2)>,
    /// For a seam's side whose ends the design's pairs tell apart: its label and the end
    /// that meets the start of the seam's other side (`meet`).
    pub seam_starts: Vec<(String, DVec2)>,
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
    /// Every place of the piece multiplied by `k` (millimetres to metres: 1e-3).
    fn scale(&mut self, k: f64) {
        for q in self.loops.iter_mut().chain(&mut self.cut).flatten() {
            *q *= k;
        }
        for (_, a, b) in &mut self.seams {
            *a *= k;
            *b *= k;
        }
        for (a, b) in self.notches.iter_mut().chain([&mut self.grain]) {
            *a *= k;
            *b *= k;
        }
        for q in &mut self.drills {
            *q *= k;
        }
        for (_, a, b) in &mut self.presses {
            *a *= k;
            *b *= k;
        }
        if let Some((_, o)) = &mut self.start {
            *o *= k;
        }
        for (_, q) in &mut self.seam_starts {
            *q *= k;
        }
    }

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
    // Each distinct corner key as a number, so the edges hash as one u64 each (hashing
    // the keys themselves made this the cost of the 128 x 128 cloth's piece list).
    let mut id: HashMap<Key, u32> = HashMap::default();
    id.reserve(slots.len() * 2);
    let tris: Vec<[u32; 3]> = live
        .iter()
        .map(|(_, t)| {
            [0, 1, 2].map(|k| {
                let n = id.len() as u32;
                *id.entry(key(t.v[k], t.rest[k])).or_insert(n)
            })
        })
        .collect();
    let edge = |a: u32, b: u32| (a as u64) << 32 | b as u64;
    let mut edge_tri: HashMap<u64, u32> = HashMap::default();
    edge_tri.reserve(tris.len() * 3);
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            edge_tri.insert(edge(t[k], t[(k + 1) % 3]), i as u32);
        }
    }
    // Triangles joined across shared pattern edges (union-find).
    let mut sets = Sets::new(tris.len());
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            if let Some(&j) = edge_tri.get(&edge(t[(k + 1) % 3], t[k])) {
                sets.join(i, j as usize);
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
    pieces_in(design, &pattern_parts(design), true, |p: Vec3| {
        let d = p.as_dvec3() - origin;
        DVec2::new(d.dot(u), d.dot(v)) * 1000.0
    })
}

/// The pattern as the studio's pattern view draws it: every piece where the view has it,
/// in the design's pattern plane (rest x and -z), in metres, with its seams (labelled as
/// in the pattern out) and its balance notches as cut without an allowance (5 mm into the
/// piece from its sewing line). The same outlines the pattern out writes, so the view
/// shows the cloth a weld eased into a seam, not the gap its mesh has there.
pub fn view_pieces(design: &Design) -> Vec<Piece> {
    view_of(design, &pattern_parts(design))
}

/// [`view_pieces`] of the parts `parts` (as [`pattern_parts`] finds them).
pub(crate) fn view_of(design: &Design, parts: &[Vec<u32>]) -> Vec<Piece> {
    let mut pieces = pieces_in(design, parts, false, |p: Vec3| {
        DVec2::new(p.x as f64, -p.z as f64) * 1000.0
    });
    let longest = notches::longest_sides(&pieces);
    for p in &mut pieces {
        let darts = dart::darts(p);
        p.notches = notches(p, 0.0, &longest, &darts);
        p.drills = darts.iter().map(|d| d.drill(&p.loops)).collect();
        p.presses = darts.iter().map(|d| d.press_mark(&p.loops)).collect();
        p.scale(1e-3);
    }
    pieces
}

/// [`pieces`] of the parts `parts`, with each rest position mapped into the plane by
/// `to2`; with their starts on the body (`Piece::start`) and their seams' meeting ends
/// (`Piece::seam_starts`) when `starts` (the pattern out: finding the body's landmarks
/// takes a pass over its mesh, which the pattern view, sent after edits, does without).
fn pieces_in(
    design: &Design,
    parts: &[Vec<u32>],
    starts: bool,
    to2: impl Fn(Vec3) -> DVec2 + Copy,
) -> Vec<Piece> {
    // The designer's names of the seams that have one, by label.
    let seam_names_of: HashMap<String, String> = design
        .seams
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.name.is_empty())
        .map(|(i, s)| (seam_label(i), s.name.clone()))
        .collect();
    // The seams that press a dart toward its second leg, by label.
    let pressed_second: FxHashSet<String> = (design.seams.iter().enumerate())
        .filter(|(_, s)| s.press_second)
        .map(|(i, _)| seam_label(i))
        .collect();
    let live = &design.sim.cloth.live;
    let names = design.describe(parts);
    let seam_of = seam_labels(design, parts);
    let eased: Vec<[Vec3; 3]> = design
        .seams
        .iter()
        .flat_map(|s| &s.eased)
        .copied()
        .collect();
    let marks = starts.then(|| Landmarks::of(design.sim.body.as_ref()));
    let mut sides = Vec::new();
    let mut out = Vec::new();
    for (part, info) in parts.iter().zip(names) {
        let mut c = Corners::default();
        for t in part.iter().filter_map(|&s| live.tri(s)) {
            let tri = [0, 1, 2].map(|k| c.id(key(t.v[k], t.rest[k]), || to2(t.rest[k])));
            c.tris.push(tri);
        }
        add_eased(&mut c, &eased, to2);
        let boundary: Vec<(Key, Key)> = boundary_of(&c.tris)
            .into_iter()
            .map(|(a, b)| (c.keys[a as usize], c.keys[b as usize]))
            .collect();
        // The places of the outline's corners, all that is drawn from here on.
        let places: HashMap<Key, DVec2> = boundary
            .iter()
            .map(|&(a, _)| (a, c.places[c.ids[&a] as usize]))
            .collect();
        let key_loops = shut::sewn_shut_dropped(chain(&boundary), &c, &places);
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
        let keyed: Vec<(String, Key, Key)> = (key_loops.iter())
            .flat_map(|l| seam_segments(l, &places, &seam_of))
            .collect();
        if starts {
            sides.extend(meet::sides(out.len(), &keyed, &places));
        }
        let seams: Vec<(String, DVec2, DVec2)> = (keyed.into_iter())
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
        let mut press_second: Vec<String> = Vec::new();
        for (label, _, _) in &seams {
            // A seam's stretch ("B2") carries the seam's name ("B") and its press.
            let base = label.trim_end_matches(|c: char| c.is_ascii_digit());
            if let Some(name) = seam_names_of.get(base)
                && !seam_names.iter().any(|(l, _)| l == label)
            {
                seam_names.push((label.clone(), name.clone()));
            }
            if pressed_second.contains(base) && !press_second.contains(label) {
                press_second.push(label.clone());
            }
        }
        let start = start_of(design, part, info.record, marks.as_ref(), to2);
        out.push(Piece {
            name: info.name,
            cut: loops.clone(),
            loops,
            seams,
            seam_names,
            grain,
            fabric: info.fabric,
            notches: Vec::new(),
            drills: Vec::new(),
            press_second,
            presses: Vec::new(),
            start,
            seam_starts: Vec::new(),
        });
    }
    if starts {
        meet::seam_starts(design, sides, &mut out);
    }
    out
}

/// Part `part`'s start on the body (its record `record`'s, for the body with `marks`), and
/// where its own coordinates' origin lies, mapped by `to2`.
fn start_of(
    design: &Design,
    part: &[u32],
    record: Option<usize>,
    marks: Option<&Landmarks>,
    to2: impl Fn(Vec3) -> DVec2,
) -> Option<(PieceStart, DVec2)> {
    let live = &design.sim.cloth.live;
    let rest_y = part
        .first()
        .and_then(|&s| live.tri(s))
        .map_or(0.0, |t| t.rest[0].y);
    let (start, origin) = super::garment::record_start(design, record?, marks?, rest_y)?;
    Some((start, to2(origin)))
}

/// A part's triangles by corner number, and each number's key and pattern place.
#[derive(Default)]
struct Corners {
    tris: Vec<[u32; 3]>,
    keys: Vec<Key>,
    places: Vec<DVec2>,
    ids: HashMap<Key, u32>,
}

impl Corners {
    /// The number of corner `k`, a new one placed at `place()` if it has none yet.
    fn id(&mut self, k: Key, place: impl FnOnce() -> DVec2) -> u32 {
        if let Some(&i) = self.ids.get(&k) {
            return i;
        }
        let i = self.keys.len() as u32;
        self.ids.insert(k, i);
        self.keys.push(k);
        self.places.push(place());
        i
    }
}

/// The directed pattern edges of `tris` (corner numbers) without their twin: the
/// part's outline.
fn boundary_of(tris: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let edge = |a: u32, b: u32| (a as u64) << 32 | b as u64;
    let edges = || {
        tris.iter()
            .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
    };
    let mut directed: FxHashSet<u64> = FxHashSet::default();
    directed.reserve(tris.len() * 3);
    directed.extend(edges().map(|(a, b)| edge(a, b)));
    edges()
        .filter(|&(a, b)| !directed.contains(&edge(b, a)))
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
fn add_eased(c: &mut Corners, eased: &[[Vec3; 3]], to2: impl Fn(Vec3) -> DVec2) {
    let mut left: Vec<usize> = (0..eased.len()).collect();
    while !left.is_empty() {
        let boundary = boundary_of(&c.tris);
        let next_of: HashMap<u32, u32> = boundary.iter().map(|&(a, b)| (a, b)).collect();
        let prev_of: HashMap<u32, u32> = boundary.iter().map(|&(a, b)| (b, a)).collect();
        let before = left.len();
        left.retain(|&n| {
            let t = eased[n];
            let q = t.map(|p| key(0, p).1);
            let at = |c: &Corners, w: u32| c.keys[w as usize].1;
            for i in 0..3 {
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                // The triangle's side i -> j is the twin of outline edge (u, v).
                let Some(&(u, v)) = boundary
                    .iter()
                    .find(|&&(u, v)| at(c, u) == q[j] && at(c, v) == q[i])
                else {
                    continue;
                };
                // Its third corner: next to the edge on the outline, or a place no live
                // triangle has, one corner for every eased triangle there (two eased
                // side by side share the corner the welds merged away; each with a
                // corner of its own, the outline ran out to their far corner and back).
                let third = [next_of.get(&v), prev_of.get(&u)]
                    .into_iter()
                    .flatten()
                    .copied()
                    .find(|&w| at(c, w) == q[k])
                    .unwrap_or_else(|| c.id((u32::MAX, q[k]), || to2(t[k])));
                let mut tri = [v, u, third];
                // In the triangle's own winding: i, j, k.
                tri.rotate_right(i);
                c.tris.push(tri);
                return false;
            }
            true
        });
        if left.len() == before {
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
        // (`out` before: a run can follow a run just filled, one vertex between them.)
        if own[i].is_some() || out[(i + n - 1) % n].is_none() {
            continue;
        }
        // A run of unlabelled edges starts at i: fill it if the same seam resumes soon.
        let before = out[(i + n - 1) % n];
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
    let longest = notches::longest_sides(&pieces);
    for p in &mut pieces {
        let darts = dart::darts(p);
        if allowance_mm > 0.0 {
            // A dart's mouth is bridged by its cap (`dart`). Elsewhere, where the line
            // folds back closer than twice the allowance (a narrow notch, a slit), the
            // offset crosses itself: the loops it closes off are not cut.
            p.cut = (p.loops.iter().enumerate())
                .map(|(i, l)| {
                    // A slit (a hole with no width: a cut that ends inside the piece)
                    // is cut as it is: offset, it became a hole twice the allowance wide.
                    let perimeter: f64 = (0..l.len())
                        .map(|k| l[k].distance(l[(k + 1) % l.len()]))
                        .sum();
                    if i > 0 && area2(l).abs() < SLIT_MM * perimeter {
                        return l.clone();
                    }
                    let here: Vec<&dart::Dart> =
                        darts.iter().filter(|d| d.loop_index == i).collect();
                    let cut = dart::cut_line(l, allowance_mm, &here);
                    untangle::untangle(cut, area2(l))
                })
                .collect();
        }
        p.notches = notches(p, allowance_mm, &longest, &darts);
        p.drills = darts.iter().map(|d| d.drill(&p.loops)).collect();
        p.presses = darts.iter().map(|d| d.press_mark(&p.loops)).collect();
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
        for q in &mut p.drills {
            *q += shift;
        }
        p.grain.0 += shift;
        p.grain.1 += shift;
        if let Some((_, o)) = &mut p.start {
            *o += shift;
        }
        for (_, q) in &mut p.seam_starts {
            *q += shift;
        }
        x += hi.x - lo.x + LAYOUT_GAP_MM;
    }
    pieces
}

/// A hole in a piece narrower than this on average (mm: twice its area over its
/// perimeter) is a slit: cut along, not round.
const SLIT_MM: f64 = 1.0;

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
pub(crate) mod tests;
