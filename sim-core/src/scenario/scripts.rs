//! What the operation scenarios do to the cloth, frame by frame: the paper's fit-cube
//! (drape, cut the corners away, sew the flaps along the cube's vertical edges), a pull
//! until the cloth tears, and painting a pattern. Each goes through the same public
//! operations a user drives.

use glam::Vec3;

use crate::collision::Body;
use crate::design::{Design, EditError, STITCH_FORCE, TearMode};

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
        ops.pairs += design.add_seam(&a, &b, STITCH_FORCE)?;
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
