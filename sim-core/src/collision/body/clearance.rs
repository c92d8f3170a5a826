//! How far outside a body a point is at least, without a search: signed distances to the
//! surface sampled once on a grid around it. The signed distance is 1-Lipschitz, so at
//! any point `p` it is at least the nearest sample's value minus the distance to that
//! sample. The contact broad phase skips a particle this proves farther than it can
//! travel in a frame (most of a falling cloth near the body), leaving the searches to
//! the particles that may touch.

use glam::Vec3;

/// Grid spacing, m: a point is at most `CELL * sqrt(3) / 2` (1.7 cm) from its sample.
/// Coarser for bodies so large that it would take more than `MAX_SAMPLES`.
const CELL: f32 = 0.02;

/// The grid reaches this far past the surface's bounding box, m (at least five cells),
/// and samples are searched this far; farther ones take their sign from their
/// neighbours.
const MARGIN: f32 = 0.1;

/// At most this many samples (16 MB).
const MAX_SAMPLES: f32 = 2.0e6;

/// Sampled signed distances around a closed surface.
#[derive(Clone, Debug, Default)]
pub struct ClearanceGrid {
    /// The surface's bounding box: every point outside it is outside the body, at least
    /// as far as the box.
    lo: Vec3,
    hi: Vec3,
    /// Position of sample (0, 0, 0).
    origin: Vec3,
    /// Sample spacing, m.
    cell: f32,
    dims: [usize; 3],
    /// The samples, x fastest.
    samples: Vec<Sample>,
}

/// One sample of the grid: what a lookup reads, together in memory.
#[derive(Clone, Copy, Debug)]
struct Sample {
    /// Signed distance, at most the margin (samples farther outside hold the margin, a
    /// lower bound); `NEG_INFINITY` for samples deep inside.
    signed: f32,
    /// The triangle nearest the sample, `u32::MAX` when none is within the margin.
    nearest: u32,
}

impl ClearanceGrid {
    /// Samples the signed distance of a closed, outward-wound surface with these
    /// vertices (`signed_at(p, max_dist)`: the signed distance at `p` and the nearest
    /// triangle, when the surface is within `max_dist`), on two threads.
    pub fn new(
        vertices: &[Vec3],
        signed_at: impl Fn(Vec3, f32) -> Option<(f32, u32)> + Sync,
    ) -> Self {
        let lo = vertices.iter().copied().fold(Vec3::INFINITY, Vec3::min);
        let hi = vertices.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
        if !(lo.is_finite() && hi.is_finite()) {
            return Self::default();
        }
        // The finest spacing that keeps the grid within MAX_SAMPLES.
        let volume = |cell: f32| {
            let m = MARGIN.max(5.0 * cell);
            ((hi - lo + Vec3::splat(2.0 * m)) / cell + Vec3::ONE).element_product()
        };
        let mut cell = CELL;
        while volume(cell) > MAX_SAMPLES {
            cell *= 1.25;
        }
        let margin = MARGIN.max(5.0 * cell);
        let origin = lo - Vec3::splat(margin);
        let span = (hi - lo + Vec3::splat(2.0 * margin)) / cell;
        let dims = [0, 1, 2].map(|a| span[a].ceil() as usize + 1);
        let n = dims[0] * dims[1] * dims[2];
        let at = |i: usize| {
            let [x, y, z] = Self::coords(dims, i);
            origin + Vec3::new(x as f32, y as f32, z as f32) * cell
        };
        // `None`: no surface within the margin; its sign comes from its neighbours below.
        let sample = |range: std::ops::Range<usize>| -> Vec<Option<(f32, u32)>> {
            range.map(|i| signed_at(at(i), margin)).collect()
        };
        let mid = n / 2;
        let found = std::thread::scope(|s| {
            let second = s.spawn(|| sample(mid..n));
            let mut first = sample(0..mid);
            // A panic in the worker is a bug: re-raise it here.
            first.extend(
                second
                    .join()
                    .unwrap_or_else(|e| std::panic::resume_unwind(e)),
            );
            first
        });
        // A sample with no surface within the margin is farther than that on the same side
        // as any grid neighbour also without one, or with a positive distance: the
        // surface cannot pass between samples a cell apart without coming within a cell
        // (less than the margin) of one of them. The grid's edge is outside the
        // surface's box, so outside.
        let mut outside = vec![false; n];
        let mut stack: Vec<usize> = (0..n)
            .filter(|&i| found[i].is_some_and(|(d, _)| d > 0.0) || Self::on_edge(dims, i))
            .collect();
        while let Some(i) = stack.pop() {
            if outside[i] {
                continue;
            }
            outside[i] = true;
            for j in Self::neighbours(dims, i) {
                if !outside[j] && found[j].is_none() {
                    stack.push(j);
                }
            }
        }
        let samples = (0..n)
            .map(|i| match found[i] {
                Some((d, t)) => Sample {
                    signed: d.min(margin),
                    nearest: t,
                },
                None => Sample {
                    signed: if outside[i] {
                        margin
                    } else {
                        f32::NEG_INFINITY
                    },
                    nearest: u32::MAX,
                },
            })
            .collect();
        Self {
            lo,
            hi,
            origin,
            cell,
            dims,
            samples,
        }
    }

    /// A lower bound on how far outside the body `p` is (0 or less: it may be inside or
    /// on it), and the triangle nearest `p`'s sample (`u32::MAX` if none is known).
    pub fn outside_by(&self, p: Vec3) -> (f32, u32) {
        if self.samples.is_empty() {
            return (0.0, u32::MAX);
        }
        let to_box = (self.lo - p).max(p - self.hi).max(Vec3::ZERO).length();
        let g = ((p - self.origin) / self.cell).round();
        let inside_grid = g.cmpge(Vec3::ZERO).all()
            && (g.x as usize) < self.dims[0]
            && (g.y as usize) < self.dims[1]
            && (g.z as usize) < self.dims[2];
        if !inside_grid || !p.is_finite() {
            return (if p.is_finite() { to_box } else { 0.0 }, u32::MAX);
        }
        let (x, y, z) = (g.x as usize, g.y as usize, g.z as usize);
        let i = x + self.dims[0] * (y + self.dims[1] * z);
        let s = self.samples[i];
        let bound = s.signed - (p - (self.origin + g * self.cell)).length();
        (bound.max(to_box), s.nearest)
    }

    /// Sample `i`'s grid coordinates (x fastest).
    fn coords(dims: [usize; 3], i: usize) -> [usize; 3] {
        [i % dims[0], i / dims[0] % dims[1], i / dims[0] / dims[1]]
    }

    fn on_edge(dims: [usize; 3], i: usize) -> bool {
        let [x, y, z] = Self::coords(dims, i);
        x == 0 || y == 0 || z == 0 || x + 1 == dims[0] || y + 1 == dims[1] || z + 1 == dims[2]
    }

    fn neighbours(dims: [usize; 3], i: usize) -> impl Iterator<Item = usize> {
        let [x, y, z] = Self::coords(dims, i);
        let (sx, sy) = (1, dims[0]);
        let sz = dims[0] * dims[1];
        [
            (x > 0).then(|| i - sx),
            (x + 1 < dims[0]).then(|| i + sx),
            (y > 0).then(|| i - sy),
            (y + 1 < dims[1]).then(|| i + sy),
            (z > 0).then(|| i - sz),
            (z + 1 < dims[2]).then(|| i + sz),
        ]
        .into_iter()
        .flatten()
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use proptest::prelude::*;

    use crate::collision::body::{Body, icosphere};
    use crate::collision::obb::geometry::closest_point_on_triangle;

    /// A 15 cm icosphere with bumps of up to 15%, closed and outward wound. Its centre
    /// is more than the grid's margin inside, so the sign there comes from propagation.
    fn bumpy_body(bumps: &[f32]) -> Body {
        let (v, t) = icosphere(3);
        let v = v
            .iter()
            .zip(bumps)
            .map(|(p, b)| *p * 0.15 * (1.0 + b))
            .collect();
        Body::new("bumpy", v, t, None).unwrap()
    }

    /// The exact signed distance: the nearest of all triangles, signed by the body.
    fn signed(body: &Body, p: Vec3) -> f32 {
        let d = body
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| body.vertices[i as usize]);
                (closest_point_on_triangle(p, a, b, c).0 - p).length()
            })
            .fold(f32::INFINITY, f32::min);
        let sign = body
            .contact(p, f32::INFINITY, u32::MAX)
            .map_or(1.0, |c| c.signed_distance.signum());
        sign * d
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]

        #[test]
        fn the_bound_never_exceeds_the_distance_outside(
            bumps in prop::collection::vec(-0.15f32..0.15, 642),
            points in prop::collection::vec((-0.4f32..0.4, -0.4f32..0.4, -0.4f32..0.4), 1..80),
        ) {
            let body = bumpy_body(&bumps);
            // A sample is at most this far from any point of the grid.
            let r = super::CELL * 3f32.sqrt() / 2.0;
            for (x, y, z) in points {
                let p = Vec3::new(x, y, z);
                let (bound, near) = body.outside_by(p);
                let d = signed(&body, p);
                // A positive bound says the point is outside by at least that much.
                prop_assert!(bound <= 0.0 || bound <= d + 1e-5, "bound {bound} at {p} where the distance is {d}");
                prop_assert!(near == u32::MAX || (near as usize) < body.triangles.len());
                // And it is tight to within two sample radii where it was sampled.
                if d > 0.0 && d < super::MARGIN - r {
                    prop_assert!(bound >= d - 2.0 * r - 1e-5, "bound {bound} at {p}, distance {d}");
                }
            }
        }
    }
}
