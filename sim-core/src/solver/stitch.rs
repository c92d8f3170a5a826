//! Seam stitches as the solver sees them: zero-length springs between two vertices whose
//! force is bounded, so sewing pulls flaps together without exploding (Blender warns that
//! unbounded sewing forces do). The design decides which pairs are stitched (its seams).

use glam::Vec3;

/// Stiffness of a seam stitch, N/m (its force is also capped per seam).
pub const STITCH_STIFFNESS: f32 = 100.0;

/// One open stitch: vertices `a` and `b` pulled together with at most `max_force` N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stitch {
    pub a: u32,
    pub b: u32,
    pub max_force: f32,
}

/// A stitch step for the solver: pulls `a` and `b` together as a zero-length XPBD spring
/// of stiffness [`STITCH_STIFFNESS`], the correction bounded so the force stays under
/// `max_force`.
pub fn stitch(x: &mut [Vec3], w: &[f32], s: &Stitch, inv_h2: f32) {
    let (a, b) = (s.a as usize, s.b as usize);
    let (Some(&wa), Some(&wb)) = (w.get(a), w.get(b)) else {
        return;
    };
    if wa + wb == 0.0 || b >= x.len() {
        return;
    }
    let d = x[b] - x[a];
    let len = d.length();
    if len < 1e-9 {
        return;
    }
    let alpha = inv_h2 / STITCH_STIFFNESS;
    // XPBD: delta lambda in position units; force = lambda / h^2.
    let dl = (len / (wa + wb + alpha)).min(s.max_force / inv_h2);
    let n = d / len;
    x[a] += n * (wa * dl);
    x[b] -= n * (wb * dl);
}
