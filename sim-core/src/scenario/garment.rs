//! The dress-mannequin scenario's garment: a front and a back panel, meshed from their
//! outlines, placed in front of and behind the mannequin bent around an elliptic
//! cylinder round its torso (so they start close without touching), and sewn at both
//! shoulders and both sides. The rest shape stays the flat pattern; only the start
//! positions are bent (along the cylinder by arc length, so no side starts stretched).

use glam::{Vec2, Vec3};

use crate::design::{Design, EditError};
use crate::mesh::ClothMesh;
use crate::mesh::mesher::{MeshError, Outline, mesh_pieces};

/// A panel's width and height, m: the half of the torso's girth it covers less the side
/// gaps the seams close, and shoulder to hip.
pub const PANEL: Vec2 = Vec2::new(0.46, 0.75);
/// The elliptic cylinder the panels start on: semi-axes across (x) and front to back
/// (z), m, round the mannequin's torso (chest 0.18 x 0.11) with room for its shoulders.
const CYLINDER: Vec2 = Vec2::new(0.215, 0.175);
/// Height of the panels' top edge, m: above the shoulders (1.50 m).
const TOP: f32 = 1.53;
/// Where the pattern puts the two panels, their centres' x, m.
const PATTERN_X: [f32; 2] = [-0.3, 0.3];
/// The shoulder seams run from this far out from the panel's middle to its edge, m (the
/// neckline between stays open).
const NECK_HALF: f32 = 0.09;
/// How hard each stitch pulls, N: enough to close the 0.35 m over the shoulders before
/// the panels slide down the torso (a tailor pins the shoulders first), ten times the
/// interactive default.
const SEAM_PULL: f32 = 0.5;
/// The side seams start this far below the top, m (the armholes above stay open).
const ARMHOLE: f32 = 0.22;

/// The two panels as one cloth, flat in the pattern plane (front left, back right), with
/// triangles of about `edge` m.
pub fn panels(edge: f32) -> Result<ClothMesh, MeshError> {
    let (w, h) = (0.5 * PANEL.x, PANEL.y);
    // Each a rectangle with corners where the seams end, so a vertex lies at each end and
    // both sides of a seam have its length exactly.
    let corners = [
        (-w, -h),
        (w, -h),
        (w, -ARMHOLE),
        (w, 0.0),
        (NECK_HALF, 0.0),
        (-NECK_HALF, 0.0),
        (-w, 0.0),
        (-w, -ARMHOLE),
    ];
    let outlines = PATTERN_X.map(|cx| Outline {
        loops: vec![corners.map(|(x, y)| Vec2::new(cx + x, y)).to_vec()],
    });
    mesh_pieces(&outlines, edge)
}

/// Which panel a pattern point belongs to (0 front, 1 back) and its place on it: across
/// from the panel's middle, and down from its top (negative).
fn on_panel(rest: Vec3) -> (usize, Vec2) {
    let k = usize::from(rest.x > 0.0);
    // The pattern's y is -Z (see `mesher`); the top edge is at y = 0.
    (k, Vec2::new(rest.x - PATTERN_X[k], -rest.z))
}

/// The point of the cylinder's front half at arc length `s` from its middle.
fn along_ellipse(s: f32) -> (f32, f32) {
    // Arc length by steps of the angle, then the angle at `s` by interpolation.
    const STEPS: usize = 2000;
    let (a, b) = (CYLINDER.x, CYLINDER.y);
    let half = std::f32::consts::FRAC_PI_2;
    let mut acc = 0.0f32;
    let mut prev = Vec2::new(0.0, b);
    let target = s.abs();
    for k in 1..=STEPS {
        let phi = half * k as f32 / STEPS as f32;
        let p = Vec2::new(a * phi.sin(), b * phi.cos());
        let d = (p - prev).length();
        if acc + d >= target {
            let t = (target - acc) / d.max(1e-12);
            let q = prev.lerp(p, t);
            return (q.x * s.signum(), q.y);
        }
        acc += d;
        prev = p;
    }
    (a * s.signum(), 0.0)
}

/// Where each vertex starts: the front panel in front of the body (+Z), the back behind
/// it, both bent round the cylinder, centred on the body's axis `axis` (x, z).
pub fn place(rest: &[Vec3], axis: Vec2) -> Vec<Vec3> {
    rest.iter()
        .map(|&r| {
            let (k, p) = on_panel(r);
            let (x, z) = along_ellipse(p.x);
            let y = TOP + p.y;
            // The back is the front turned half round: its pattern's right lies on the
            // body's right too, seen from behind.
            let (x, z) = if k == 0 { (x, z) } else { (-x, -z) };
            Vec3::new(axis.x + x, y, axis.y + z)
        })
        .collect()
}

/// The border vertices of panel `k` on the segment from `a` to `b` (panel coordinates),
/// in order from `a`.
fn border(design: &Design, k: usize, a: Vec2, b: Vec2) -> Vec<u32> {
    let cloth = &design.sim.cloth;
    let dir = (b - a).normalize_or_zero();
    let len = (b - a).length();
    let mut on: Vec<(f32, u32)> = (0..cloth.rest.positions.len() as u32)
        .filter(|&v| cloth.live.vertex_alive(v) && cloth.live.is_boundary(v))
        .filter_map(|v| {
            let (kv, p) = on_panel(cloth.rest.positions[v as usize]);
            let t = (p - a).dot(dir);
            let off = (p - a - dir * t).length();
            (kv == k && off < 1e-4 && t > -1e-4 && t < len + 1e-4).then_some((t, v))
        })
        .collect();
    on.sort_by(|x, y| x.0.total_cmp(&y.0));
    on.into_iter().map(|(_, v)| v).collect()
}

/// What sewing the panels did.
#[derive(Clone, Copy, Debug, Default)]
pub struct Sewn {
    pub seams: usize,
    pub pairs: usize,
    /// The largest difference between a seam's two sides' pattern lengths, m.
    pub mismatch_m: f32,
}

/// Sews the shoulders (the top edges' outer parts) and the sides (the side edges below
/// the armholes), front to back on each side of the body.
pub fn sew_panels(design: &mut Design) -> Result<Sewn, EditError> {
    let (w, h) = (0.5 * PANEL.x, PANEL.y);
    let mut sewn = Sewn::default();
    for s in [1.0f32, -1.0] {
        // The body's side s: the front's +s edge meets the back's -s edge.
        let shoulder_front = border(
            design,
            0,
            Vec2::new(s * NECK_HALF, 0.0),
            Vec2::new(s * w, 0.0),
        );
        let shoulder_back = border(
            design,
            1,
            Vec2::new(-s * NECK_HALF, 0.0),
            Vec2::new(-s * w, 0.0),
        );
        let side_front = border(design, 0, Vec2::new(s * w, -ARMHOLE), Vec2::new(s * w, -h));
        let side_back = border(
            design,
            1,
            Vec2::new(-s * w, -ARMHOLE),
            Vec2::new(-s * w, -h),
        );
        for (a, b) in [(shoulder_front, shoulder_back), (side_front, side_back)] {
            let d = (design.pattern_length(&a) - design.pattern_length(&b)).abs();
            sewn.mismatch_m = sewn.mismatch_m.max(d);
            sewn.pairs += design.add_seam(&a, &b, SEAM_PULL)?;
            sewn.seams += 1;
        }
    }
    Ok(sewn)
}

/// The front neckline: half its width and its depth, m (a square neck between the
/// shoulder seams).
const NECKLINE: Vec2 = Vec2::new(0.07, 0.08);

/// Cuts the front's neckline away: the triangles of the front panel whose pattern
/// centre lies in the square below the middle of its top edge. Returns how many.
pub fn cut_neckline(design: &mut Design) -> Result<usize, EditError> {
    let slots: Vec<u32> = design
        .sim
        .cloth
        .live
        .iter()
        .filter(|(_, t)| {
            let (k, c) = on_panel((t.rest[0] + t.rest[1] + t.rest[2]) / 3.0);
            k == 0 && c.x.abs() < NECKLINE.x && c.y > -NECKLINE.y
        })
        .map(|(s, _)| s)
        .collect();
    design.remove_triangles(&slots)
}

/// Share of 36 directions round the torso at chest height (1.25-1.35 m) in which some
/// of the garment is found within 0.4 m of the body's axis (each triangle sampled at its
/// corners, edge middles and centre, so a coarse mesh is seen too).
pub fn torso_coverage(design: &Design, axis: Vec2) -> f64 {
    let mut seen = [false; 36];
    let x = &design.sim.cloth.x;
    for (_, t) in design.sim.cloth.live.iter() {
        let [a, b, c] = t.v.map(|v| x[v as usize]);
        for p in [
            a,
            b,
            c,
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c) / 3.0,
        ] {
            let d = Vec2::new(p.x - axis.x, p.z - axis.y);
            if (1.25..=1.35).contains(&p.y) && d.length() < 0.4 {
                let ang = d.y.atan2(d.x) + std::f32::consts::PI;
                let k = ((ang / std::f32::consts::TAU * 36.0) as usize).min(35);
                seen[k] = true;
            }
        }
    }
    seen.iter().filter(|&&s| s).count() as f64 / 36.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cylinder_is_followed_by_arc_length() {
        let (x, z) = along_ellipse(0.0);
        assert!(x.abs() < 1e-6 && (z - CYLINDER.y).abs() < 1e-6);
        // Short steps along it are as long as the arc they cover.
        for k in 0..20 {
            let s = k as f32 * 0.01;
            let (x0, z0) = along_ellipse(s);
            let (x1, z1) = along_ellipse(s + 0.01);
            let d = Vec2::new(x1 - x0, z1 - z0).length();
            assert!((d - 0.01).abs() < 2e-4, "{s}: {d}");
        }
        let (xm, _) = along_ellipse(-0.1);
        assert!(xm < 0.0);
    }
}
