//! What the operation scenarios do to the cloth, frame by frame: the paper's fit-cube
//! (drape, cut the corners away, sew the flaps along the cube's vertical edges), a pull
//! until the cloth tears, and painting a pattern. Each goes through the same public
//! operations a user drives.

use glam::Vec3;

use crate::collision::Body;
use crate::design::{Design, EditError, STITCH_PULL, TearMode};

/// Frames of plain draping before the operations start.
pub const DRAPE_FRAMES: u64 = 240;

/// What the fit-cube operations did.
#[derive(Clone, Copy, Debug, Default)]
pub struct FitOps {
    /// Corner pieces cut away.
    pub cuts: usize,
    /// Seams added (one per vertical edge of the cube).
    pub seams: usize,
    /// Stitched pairs, over all seams.
    pub pairs: usize,
}

/// The pattern position of vertex `v` relative to the pattern's centre (X, Z).
fn pattern(design: &Design, v: usize, centre: Vec3) -> (f32, f32) {
    let p = design.sim.cloth.rest.positions[v] - centre;
    (p.x, p.z)
}

/// The paper's fit: cut away the four corner squares of the draped cloth (the part beyond
/// both side faces at each vertical edge of the cube), then sew the two flaps that meet at
/// each vertical edge with a seam. The cut lines are the grid lines just outside the cube's
/// side faces.
pub fn fit_cube(design: &mut Design, body: &Body, grid: usize) -> Result<FitOps, EditError> {
    let (mn, mx) = body.bounds();
    let (pmin, pmax) = crate::mesh::bounds(&design.sim.cloth.rest.positions);
    let centre = (pmin + pmax) * 0.5;
    let size = pmax.x - pmin.x;
    let cell = size / grid.max(1) as f32;
    let half = 0.5 * (mx.x - mn.x).max(mx.z - mn.z);
    // First grid line at or outside the face.
    let k = ((0.5 * size + half) / cell - 1e-3).ceil();
    let e = k * cell - 0.5 * size;
    let tol = 0.25 * cell;
    let mut ops = FitOps::default();
    for (sx, sz) in [(1.0f32, 1.0f32), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)] {
        let corner: Vec<u32> = design
            .sim
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                let c = (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0 - centre;
                sx * c.x > e && sz * c.z > e
            })
            .map(|(s, _)| s)
            .collect();
        design.remove_triangles(&corner)?;
        ops.cuts += 1;
        let line = |on_x: bool| -> Vec<u32> {
            let mut v: Vec<(f32, u32)> = (0..design.sim.cloth.rest.positions.len())
                .filter_map(|i| {
                    let (px, pz) = pattern(design, i, centre);
                    let (across, along) = if on_x {
                        (sx * px, sz * pz)
                    } else {
                        (sz * pz, sx * px)
                    };
                    ((across - e).abs() < tol && along > e + tol).then_some((along, i as u32))
                })
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.into_iter().map(|(_, i)| i).collect()
        };
        let (a, b) = (line(true), line(false));
        let pull = design.pair_pull(&a, &b, STITCH_PULL);
        ops.pairs += design.add_seam(&a, &b, pull)?;
        ops.seams += 1;
    }
    Ok(ops)
}

/// Distance from the cloth's side panels to the cube's side faces, beyond the contact
/// thickness: over the live vertices whose pattern position lies beyond exactly one side
/// face (the panels that should hang flat against that face), at least 2 cm below the top
/// edge, `(mean, max)` in metres.
pub fn fit_gap(design: &Design, body: &Body) -> (f64, f64) {
    let (mn, mx) = body.bounds();
    let (pmin, pmax) = crate::mesh::bounds(&design.sim.cloth.rest.positions);
    let centre = (pmin + pmax) * 0.5;
    let half = 0.5 * (mx.x - mn.x).max(mx.z - mn.z);
    let th = design.sim.material.thickness;
    let gaps: Vec<f64> = (0..design.sim.cloth.len())
        .filter(|&i| design.sim.cloth.live.vertex_alive(i as u32))
        .filter(|&i| {
            let q = if i < design.sim.cloth.rest.positions.len() {
                design.sim.cloth.rest.positions[i] - centre
            } else {
                // A vertex made by a split: its pattern place is its triangles' corner.
                design
                    .sim
                    .cloth
                    .live
                    .tris_of(i as u32)
                    .first()
                    .and_then(|&t| design.sim.cloth.live.tri(t))
                    .and_then(|t| t.corner(i as u32).map(|k| t.rest[k]))
                    .unwrap_or(centre)
                    - centre
            };
            (q.x.abs() > half) != (q.z.abs() > half) && design.sim.cloth.x[i].y < mx.y - 0.02
        })
        .map(|i| {
            let d = body
                .signed_distance(design.sim.cloth.x[i], 1.0)
                .unwrap_or(1.0);
            (d - th).max(0.0) as f64
        })
        .collect();
    if gaps.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
    (mean, gaps.iter().copied().fold(0.0, f64::max))
}

/// The tear scenario's setup after draping: hold the cloth on the cube's top face (pin
/// what lies on it), switch tearing on, and grip the cloth's first corner.
pub fn tear_setup(design: &mut Design, body: &Body) -> Result<u32, EditError> {
    let (mn, mx) = body.bounds();
    let on_top: Vec<u32> = (0..design.sim.cloth.len() as u32)
        .filter(|&i| {
            let p = design.sim.cloth.x[i as usize];
            p.y > mx.y - 0.005
                && p.x > mn.x + 0.05
                && p.x < mx.x - 0.05
                && p.z > mn.z + 0.05
                && p.z < mx.z - 0.05
        })
        .collect();
    for v in on_top {
        design.set_pin(v, true)?;
    }
    design.tear.enabled = true;
    design.tear.mode = TearMode::Delete;
    let corner = design.sim.cloth.x[0];
    // A hand's grip: the corner and the cloth within 4 cm of it.
    design.pinch_begin(corner, 0.02, 0.04, 200.0)
}

/// Where the tear scenario's pointer is `t` seconds into the pull: away from the cube,
/// horizontally and down, at 0.5 m/s.
pub fn tear_target(start: Vec3, centre: Vec3, t: f32) -> Vec3 {
    let out = Vec3::new(start.x - centre.x, 0.0, start.z - centre.z).normalize_or(Vec3::X);
    start + (out + Vec3::new(0.0, -0.3, 0.0)).normalize() * (0.5 * t)
}

/// Paints the paint scenario's pattern on the cube's top face: a ring of 24 dots and a
/// centre spot. Returns the strokes that landed.
pub fn paint_pattern(design: &mut Design, body: &Body) -> usize {
    let (mn, mx) = body.bounds();
    let c = Vec3::new(
        0.5 * (mn.x + mx.x),
        mx.y + design.sim.material.thickness,
        0.5 * (mn.z + mx.z),
    );
    let mut strokes = 0;
    let colors = [[200, 30, 40, 255], [30, 90, 200, 255], [240, 180, 20, 255]];
    for k in 0..24 {
        let a = k as f32 / 24.0 * std::f32::consts::TAU;
        let p = c + Vec3::new(0.12 * a.cos(), 0.0, 0.12 * a.sin());
        if design.paint(p, 0.015, colors[k % 3]).is_ok() {
            strokes += 1;
        }
    }
    if design.paint(c, 0.05, [20, 20, 20, 255]).is_ok() {
        strokes += 1;
    }
    strokes
}

/// The fold scenario's timeline, in frames: the cloth settles on the floor, its first
/// corner is carried over to the opposite one (a diagonal fold, two layers), released,
/// then a corner on the fold line is carried over to the other end of it (four layers),
/// released, and the layers settle.
pub const FOLD_SETTLE: u64 = 30;
pub const FOLD_CARRY: [u64; 2] = [180, 150];
pub const FOLD_START: [u64; 2] = [FOLD_SETTLE, 300];
/// Frames the pen holds still at the end of a carry before it lets go.
pub const FOLD_HOLD: u64 = 15;
/// Frames a whole fold run needs: both folds and a second's settling after the last.
pub const FOLD_FRAMES: u64 = 300 + 150 + FOLD_HOLD + 60;

/// The height of a carry's arc over half the distance it covers (1: the circle a stiff
/// flap's corner follows about the fold line).
const ARC: f32 = 0.8;
/// How far short of the opposite corner a carry ends, m.
const SHORT: f32 = 0.02;

/// The fold scenario's hand: which fold it is in and where its carry goes.
#[derive(Clone, Debug, Default)]
pub struct Fold {
    /// Folds finished (released).
    pub done: usize,
    /// The carry under way: where it started, where it ends, and its arc's height.
    carry: Option<(Vec3, Vec3, f32)>,
    /// The vertices the other hand holds down while this one folds.
    held_down: Vec<u32>,
}

/// The other hand: it holds the cloth down within this distance (seen from above) of the
/// middle of the part that stays, as a person folding does, m.
const HAND: f32 = 0.05;

/// The pattern corners of the cloth: (min x+z, max x+z, max x-z, min x-z), and its
/// centre, as vertices.
fn corners(design: &Design) -> [u32; 5] {
    let rest = &design.sim.cloth.rest.positions;
    let pick = |key: &dyn Fn(Vec3) -> f32| {
        (0..rest.len())
            .filter(|&i| design.sim.cloth.live.vertex_alive(i as u32))
            .max_by(|&a, &b| key(rest[a]).total_cmp(&key(rest[b])))
            .unwrap_or(0) as u32
    };
    let (lo, hi) = crate::mesh::bounds(rest);
    let mid = (lo + hi) * 0.5;
    [
        pick(&|p| -(p.x + p.z)),
        pick(&|p| p.x + p.z),
        pick(&|p| p.x - p.z),
        pick(&|p| p.z - p.x),
        pick(&|p| -(p - mid).length()),
    ]
}

impl Fold {
    /// What the hand does at frame `f`: grip and start a carry, move the pen along it,
    /// or let go.
    pub fn at_frame(&mut self, design: &mut Design, f: u64) -> Result<(), EditError> {
        let th = design.sim.material.thickness;
        let [a, c, b, d, o] = corners(design);
        let at = |d: &Design, v: u32| d.sim.cloth.x[v as usize];
        for k in 0..2 {
            let (start, carry) = (FOLD_START[k], FOLD_CARRY[k]);
            let (from, to, layers) = if k == 0 { (a, c, 1.0) } else { (b, d, 2.0) };
            if f == start {
                // The other hand holds down the middle of the part that stays.
                let stays = if k == 0 {
                    (at(design, b) + at(design, c) + at(design, d)) / 3.0
                } else {
                    (at(design, c) + at(design, d) + at(design, o)) / 3.0
                };
                self.held_down = (0..design.sim.cloth.len() as u32)
                    .filter(|&v| {
                        let p = design.sim.cloth.x[v as usize];
                        design.sim.cloth.live.vertex_alive(v)
                            && !design.sim.cloth.is_pinned(v as usize)
                            && (p.x - stays.x).hypot(p.z - stays.z) < HAND
                    })
                    .collect();
                for &v in &self.held_down {
                    design.set_pin(v, true)?;
                }
                let s = design.sim.cloth.x[from as usize];
                // The carry ends over the other corner, on the layers already there, short
                // of it by what the fold's crease takes up (a hand stops where the flap
                // lies flat rather than drag the cloth).
                let to = design.sim.cloth.x[to as usize];
                let e = to + (s - to).normalize_or_zero() * SHORT + Vec3::Y * (layers * 2.0 * th);
                // A hand's grip: the corner and the cloth within 5 cm of it.
                design.pinch_begin(s, 0.05, 0.05, 200.0)?;
                self.carry = Some((s, e, ARC * 0.5 * (e - s).length()));
            } else if f > start && f <= start + carry {
                if let Some((s, e, h)) = self.carry {
                    // Half an ellipse over the fold line, a little inside the circle
                    // a stiff flap's corner would follow, so the flap hangs slack.
                    let u = (f - start) as f32 / carry as f32;
                    let a = std::f32::consts::PI * u * u * (3.0 - 2.0 * u);
                    let mid = (s + e) * 0.5;
                    design.pinch_move(mid + (s - mid) * a.cos() + Vec3::Y * (h * a.sin()));
                }
            } else if f == start + carry + FOLD_HOLD && self.carry.take().is_some() {
                design.pinch_end();
                for v in std::mem::take(&mut self.held_down) {
                    design.set_pin(v, false)?;
                }
                self.done += 1;
            }
        }
        Ok(())
    }
}

/// How the cloth lies on the floor, seen from above: the layers over each lying
/// triangle (the most common count and the largest), the least height between two
/// layers where they overlap (pairs that are neighbours in the pattern left out, as at a
/// fold's crease), and the cloth's highest point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Layers {
    pub mode: usize,
    pub max: usize,
    pub gap_min_m: f64,
    pub height_max_m: f64,
}

pub fn layers(design: &Design) -> Layers {
    use crate::collision::proximity::{Aabb, BoxGrid};
    let sim = &design.sim;
    let x = &sim.cloth.x;
    let th = sim.material.thickness;
    // Triangles lying within 60 degrees of flat: (corners, rest centroid).
    let lying: Vec<([Vec3; 3], Vec3)> = sim
        .cloth
        .live
        .iter()
        .filter_map(|(_, t)| {
            let p = t.v.map(|v| x[v as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            (n.y.abs() >= 0.5).then_some((p, (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0))
        })
        .collect();
    let mut side = 0.0f32;
    for (_, t) in sim.cloth.live.iter() {
        side = side.max((t.rest[1] - t.rest[0]).length());
    }
    let exclusion = 2.0 * side + 2.0 * th;
    let flat = |p: &[Vec3; 3]| {
        let mut b = Aabb::of(p);
        (b.lo.y, b.hi.y) = (0.0, 0.0);
        b
    };
    let mut grid = BoxGrid::default();
    grid.build(lying.iter().map(|(p, _)| flat(p)), 2.0 * side.max(1e-3));
    let mut counts = vec![0usize; 64];
    let mut out = Layers {
        gap_min_m: f64::INFINITY,
        ..Layers::default()
    };
    for (p, rest_c) in &lying {
        let c = (p[0] + p[1] + p[2]) / 3.0;
        let mut n = 0usize;
        grid.query(&Aabb::point(Vec3::new(c.x, 0.0, c.z)), |k| {
            let (q, rest_q) = &lying[k as usize];
            let Some(y) = height_over(q, c.x, c.z) else {
                return;
            };
            n += 1;
            if (*rest_c - *rest_q).length() >= exclusion {
                out.gap_min_m = out.gap_min_m.min((c.y - y).abs() as f64);
            }
        });
        counts[n.min(63)] += 1;
        out.max = out.max.max(n);
    }
    out.mode = (0..counts.len()).max_by_key(|&k| counts[k]).unwrap_or(0);
    out.height_max_m = x.iter().map(|p| p.y as f64).fold(0.0, f64::max);
    out
}

/// The height of triangle `p` over the floor point `(px, pz)`, if that point lies within
/// the triangle seen from above.
fn height_over(p: &[Vec3; 3], px: f32, pz: f32) -> Option<f32> {
    let (a, b, c) = (p[0], p[1], p[2]);
    let det = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
    if det.abs() < 1e-12 {
        return None;
    }
    let u = ((px - a.x) * (c.z - a.z) - (c.x - a.x) * (pz - a.z)) / det;
    let v = ((b.x - a.x) * (pz - a.z) - (px - a.x) * (b.z - a.z)) / det;
    let eps = -1e-6;
    (u >= eps && v >= eps && u + v <= 1.0 - eps).then_some(a.y + u * (b.y - a.y) + v * (c.y - a.y))
}
