//! Seam stitches as the solver sees them: zero-length springs between two vertices whose
//! force is bounded, so sewing pulls flaps together without exploding (Blender warns that
//! unbounded sewing forces do). The design decides which pairs are stitched (its seams).

use glam::Vec3;
use rustc_hash::FxHashMap as HashMap;

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

/// How much nearer than its least distance so far a stitched pair must come to count as
/// closing (m).
pub const CLOSING_STEP: f32 = 1e-3;

/// Whether stitched pairs are still closing: each open pair's least distance so far, and
/// the frames since some pair last came [`CLOSING_STEP`] nearer than that or the set of
/// open pairs changed (a weld, a new seam, an edit). Least distances only fall, by at
/// least a step each time, so a pair can count as closing only finitely often: whatever
/// a watcher does once the pairs stall cannot set it swinging. The xpbd model's links
/// (`xpbd::sewing`) and the design (`design::stalls`, to tell the designer) each keep one.
#[derive(Clone, Debug, Default)]
pub struct ClosingWatch {
    least: HashMap<(u32, u32), f32>,
    /// Scratch for the next frame's `least` (kept, so a frame allocates nothing).
    next: HashMap<(u32, u32), f32>,
    quiet: u32,
}

impl ClosingWatch {
    /// Looks at this frame's open `pairs` at `x` and returns the frames since one last
    /// closed: 0 when one came nearer (or a pair was new, or one went). With no pairs,
    /// forgets them all (0).
    pub fn observe(&mut self, pairs: impl Iterator<Item = (u32, u32)>, x: &[Vec3]) -> u32 {
        let mut progress = false;
        let next = &mut self.next;
        next.clear();
        for (a, b) in pairs {
            let (Some(pa), Some(pb)) = (x.get(a as usize), x.get(b as usize)) else {
                continue;
            };
            let d = pa.distance(*pb);
            let least = match self.least.get(&(a, b)) {
                Some(&l) if d > l - CLOSING_STEP => l,
                // Nearer, or a pair not seen before.
                _ => {
                    progress = true;
                    d
                }
            };
            next.insert((a, b), least);
        }
        // Every pair was known: the same set unless a known one went (welded).
        progress |= next.len() != self.least.len();
        std::mem::swap(&mut self.least, &mut self.next);
        self.quiet = if progress || self.least.is_empty() {
            0
        } else {
            self.quiet.saturating_add(1)
        };
        self.quiet
    }

    /// Forgets every pair: the next frame starts the count afresh.
    pub fn reset(&mut self) {
        self.least.clear();
        self.quiet = 0;
    }
}

/// Stiffness of a hold, N/m per held vertex (its force is also capped).
pub const HOLD_STIFFNESS: f32 = 100.0;

/// One held vertex: kept on the normal's side of the plane `normal . x = level`, pulled
/// back along the normal only when it is past it (it moves freely on its side and within
/// the plane), with at most `max_force` N. A garment's waistband is kept from falling
/// below the body's waist so while the garment settles (GarmentCode's simulator does the
/// same with its one-sided "attachment" constraints).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hold {
    pub vertex: u32,
    /// Unit length.
    pub normal: Vec3,
    pub level: f32,
    pub max_force: f32,
}

impl Hold {
    /// How far the vertex at `x` is along the normal from its plane, m (negative: past
    /// it, on the side it is kept from).
    pub fn off(&self, x: Vec3) -> f32 {
        self.normal.dot(x) - self.level
    }

    /// How far the vertex at `x` is past its plane, m (0 on its own side).
    pub fn past(&self, x: Vec3) -> f32 {
        (-self.off(x)).max(0.0)
    }
}

/// A hold step for the solver: moves a vertex past its plane back toward it as an XPBD
/// spring of stiffness [`HOLD_STIFFNESS`], the correction bounded so the force stays
/// under `max_force`.
pub fn hold(x: &mut [Vec3], w: &[f32], h: &Hold, inv_h2: f32) {
    let i = h.vertex as usize;
    let (Some(&wi), Some(xi)) = (w.get(i), x.get_mut(i)) else {
        return;
    };
    let c = h.past(*xi);
    if wi == 0.0 || !(c > 0.0 && c.is_finite()) {
        return;
    }
    let alpha = inv_h2 / HOLD_STIFFNESS;
    let dl = (c / (wi + alpha)).min(h.max_force / inv_h2);
    *xi += h.normal * (wi * dl);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn waist() -> Hold {
        Hold {
            vertex: 1,
            normal: Vec3::Y,
            level: 1.0,
            max_force: 0.05,
        }
    }

    #[test]
    fn a_hold_pulls_a_vertex_past_its_plane_back_and_only_across_it() {
        let inv_h2 = 3600.0 * 25.0;
        let w = [1e4, 1e4];
        let mut x = [Vec3::ZERO, Vec3::new(0.3, 0.999, -0.2)];
        hold(&mut x, &w, &waist(), inv_h2);
        // 1 mm off: well under the force limit, so most of the way in one step.
        assert!((x[1].y - 1.0).abs() < 2e-4, "{}", x[1].y);
        assert_eq!(
            (x[1].x, x[1].z),
            (0.3, -0.2),
            "it slides freely in the plane"
        );
        assert_eq!(x[0], Vec3::ZERO, "the others are not held");
        // Above the plane it is free.
        x[1].y = 1.001;
        hold(&mut x, &w, &waist(), inv_h2);
        assert_eq!(x[1].y, 1.001);
    }

    #[test]
    fn a_hold_pulls_no_harder_than_its_limit_and_leaves_a_pinned_vertex() {
        let inv_h2 = 3600.0 * 25.0;
        let mut x = [Vec3::ZERO, Vec3::new(0.0, 0.5, 0.0)];
        hold(&mut x, &[1e4, 1e4], &waist(), inv_h2);
        // 0.05 N over a step of 1/300 s moves a vertex of w = 1e4 at most w F h^2.
        let most = 1e4 * 0.05 / inv_h2;
        assert!((x[1].y - 0.5 - most).abs() < 1e-6, "{}", x[1].y - 0.5);
        let mut pinned = [Vec3::ZERO, Vec3::new(0.0, 0.5, 0.0)];
        hold(&mut pinned, &[1e4, 0.0], &waist(), inv_h2);
        assert_eq!(pinned[1].y, 0.5);
        // A vertex not in the cloth is no matter.
        let far = Hold {
            vertex: 9,
            ..waist()
        };
        hold(&mut pinned, &[1e4, 0.0], &far, inv_h2);
    }
}
