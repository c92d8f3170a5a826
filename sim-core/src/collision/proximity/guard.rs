//! The guard: where a vertex may go. Every position the solver gives a vertex passes
//! through [`constrain`], which keeps it in its motion box and on its side of every pair
//! it is in ([`super::pairs`]), the other vertices staying where they are. The set it
//! keeps to is convex and holds the vertex's current position, so moving there never
//! breaks a pair another vertex already keeps: each move is feasible for all.

use glam::Vec3;

use super::grid::Aabb;
use super::pairs::Proximity;

/// What the guard did to one move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Guarded {
    /// The move was free.
    #[default]
    Free,
    /// It was projected onto the box or a pair's bound.
    Projected,
    /// Projection was not enough; the move was shortened.
    Shortened,
}

/// Rounds of projection before a move is shortened instead.
const PROJECTION_ROUNDS: usize = 10;

/// The position for vertex `i` nearest (or near) `target` that keeps its box and pairs;
/// `x[i]` is where it is now and must be feasible (it is, when every earlier move went
/// through here).
pub fn constrain(
    i: usize,
    target: Vec3,
    x: &[Vec3],
    bx: &Aabb,
    prox: &Proximity,
) -> (Vec3, Guarded) {
    let current = x[i];
    let roles = prox.roles(i);
    let mut t = target.clamp(bx.lo, bx.hi);
    let mut how = if t == target {
        Guarded::Free
    } else {
        Guarded::Projected
    };
    if roles.is_empty() {
        return (t, how);
    }
    // Rounds of projection onto the violated half-spaces (each then back into the box),
    // which settle a vertex pressed into a corner of several of them. A vertex that is
    // not settled after them is shortened, and often does not move at all: with 3 rounds,
    // 195 moves a frame of the 32 x 32 fold were shortened, with 10, 75 (30 rounds: 79).
    for _ in 0..PROJECTION_ROUNDS {
        let mut moved = false;
        for &r in roles {
            let pair = &prox.pairs[(r / 4) as usize];
            let (m, h) = pair.bound_for((r % 4) as usize, x);
            let d = m.dot(t) - h;
            if d < 0.0 {
                t -= m * d;
                moved = true;
            }
        }
        if !moved {
            return (t, how);
        }
        how = Guarded::Projected;
        t = t.clamp(bx.lo, bx.hi);
    }
    // Still outside: go from the current position toward it as far as every bound allows.
    let step = t - current;
    let mut tau = 1.0f32;
    for &r in roles {
        let pair = &prox.pairs[(r / 4) as usize];
        let (m, h) = pair.bound_for((r % 4) as usize, x);
        let (a, b) = (m.dot(current) - h, m.dot(step));
        if a + b * tau < 0.0 {
            tau = if a > 0.0 && b < 0.0 {
                tau.min(a / -b)
            } else {
                0.0
            };
        }
    }
    // A little short of the bound, so rounding cannot put it past.
    let tau = (tau * 0.999).max(0.0);
    (current + step * tau, Guarded::Shortened)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::proximity::pair::{ClothView, ProximityParams};

    #[test]
    fn a_vertex_over_a_triangle_stays_above_it() {
        // A triangle at y = 0 and a vertex 5 mm over it pushed 2 cm down.
        let x = vec![
            Vec3::new(-0.1, 0.0, -0.1),
            Vec3::new(0.1, 0.0, -0.1),
            Vec3::new(0.0, 0.0, 0.1),
            Vec3::new(0.0, 0.005, 0.0),
        ];
        let boxes: Vec<Aabb> = x.iter().map(|&p| Aabb::point(p).grown(0.03)).collect();
        let pattern = vec![Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::new(5.0, 0.0, 5.0)];
        let cloth = ClothView {
            x: &x,
            boxes: &boxes,
            tris: &[[0, 1, 2]],
            edges: &[[0, 1], [1, 2], [0, 2]],
            pattern: &pattern,
            bridged: &[],
            free: &[true; 4],
        };
        let mut prox = Proximity::default();
        let params = ProximityParams {
            radius: 0.004,
            delta: 1e-4,
            rest_exclusion: 0.01,
            floor: None,
            threads: 1,
        };
        prox.detect(&cloth, None, &params);
        assert!(!prox.pairs.is_empty());
        let (p, how) = constrain(3, Vec3::new(0.01, -0.02, 0.0), &x, &boxes[3], &prox);
        assert!(p.y >= 1e-4 - 1e-7, "{p}");
        assert_ne!(how, Guarded::Free);
        // Sideways it slides freely.
        assert!((p.x - 0.01).abs() < 1e-6, "{p}");
        // And a corner of the triangle pushed up cannot pass the vertex either.
        let (q, _) = constrain(0, Vec3::new(0.0, 0.05, 0.0), &x, &boxes[0], &prox);
        assert!(q.y <= 0.005 - 1e-4 + 1e-7, "{q}");
    }
}
