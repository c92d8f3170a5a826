//! Closest points between the primitives of two meshes, as weights of their vertices: a
//! point against a triangle, and a segment against a segment.

use glam::Vec3;

use crate::collision::obb::geometry::closest_point_on_triangle;

/// The point of triangle `(a, b, c)` nearest `p`, as barycentric weights of its corners.
pub fn point_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, [f32; 3]) {
    let (q, _) = closest_point_on_triangle(p, a, b, c);
    (q, barycentric(q, a, b, c))
}

/// The barycentric weights of `q` (in the plane of `a b c`, inside it) against its corners,
/// clamped to the triangle. A degenerate triangle gives the weights of its nearest corner.
pub fn barycentric(q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> [f32; 3] {
    // In f64: for a thin triangle the f32 normal equations lose the weights' last
    // digits, and the weights must rebuild the point.
    let (a64, q64) = (a.as_dvec3(), q.as_dvec3());
    let (v0, v1, v2) = (b.as_dvec3() - a64, c.as_dvec3() - a64, q64 - a64);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if den <= 1e-12 * (d00 * d11).max(1e-30) {
        let d = [(q - a).length(), (q - b).length(), (q - c).length()];
        let k = (0..3).min_by(|&i, &j| d[i].total_cmp(&d[j])).unwrap_or(0);
        let mut w = [0.0; 3];
        w[k] = 1.0;
        return w;
    }
    let v = ((d11 * d20 - d01 * d21) / den).clamp(0.0, 1.0);
    let w = ((d00 * d21 - d01 * d20) / den).clamp(0.0, 1.0 - v);
    [(1.0 - v - w) as f32, v as f32, w as f32]
}

/// The closest points of segments `p0 p1` and `q0 q1` (Ericson, Real-Time Collision
/// Detection 5.1.9): their parameters `s`, `t` in [0, 1].
pub fn segment_segment(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (f32, f32) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    const EPS: f32 = 1e-20;
    if a <= EPS && e <= EPS {
        return (0.0, 0.0);
    }
    if a <= EPS {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(r);
    if e <= EPS {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(d2);
    let den = a * e - b * b;
    let mut s = if den > 1e-12 * a * e {
        ((b * f - c * e) / den).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn v3() -> impl Strategy<Value = Vec3> {
        (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
    }

    proptest! {
        /// No sampled pair of points is closer than the pair found.
        #[test]
        fn segment_segment_is_closest(p0 in v3(), p1 in v3(), q0 in v3(), q1 in v3()) {
            let (s, t) = segment_segment(p0, p1, q0, q1);
            let best = (p0.lerp(p1, s) - q0.lerp(q1, t)).length();
            for i in 0..=20 {
                for j in 0..=20 {
                    let d = (p0.lerp(p1, i as f32 / 20.0) - q0.lerp(q1, j as f32 / 20.0)).length();
                    prop_assert!(best <= d + 1e-4, "{best} > {d}");
                }
            }
        }

        /// The weights rebuild the closest point.
        #[test]
        fn point_triangle_weights_rebuild_the_point(p in v3(), a in v3(), b in v3(), c in v3()) {
            prop_assume!((b - a).cross(c - a).length() > 1e-2);
            let (q, w) = point_triangle(p, a, b, c);
            let r = a * w[0] + b * w[1] + c * w[2];
            prop_assert!((q - r).length() < 1e-4, "{q} {r}");
            prop_assert!(w.iter().all(|&x| (0.0..=1.0).contains(&x)));
        }
    }
}
