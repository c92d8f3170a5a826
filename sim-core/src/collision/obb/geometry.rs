//! Exact geometric primitives used by the OBB tree: closest point on a triangle (with the
//! feature it lies on), ray/triangle intersection, and separating-axis overlap tests.

use glam::{Mat3, Vec3};

/// The part of a triangle a closest point lies on. Used to pick the right pseudo-normal
/// when deciding on which side of a closed surface a point is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    Face,
    /// Edge `k` runs from vertex `k` to vertex `(k + 1) % 3`.
    Edge(u8),
    Vertex(u8),
}

/// Closest point on triangle `(a, b, c)` to `p` (Ericson, Real-Time Collision Detection 5.1.5).
///
/// A degenerate triangle (corners that coincide or lie on one line, as cloth collapsed
/// onto itself can have) gives the nearest point of its sides: the regions' divisions are
/// 0 / 0 there. Found by fuzzing the design file (2026-11-29): a loaded cloth with such a
/// triangle made the guard's search clamp a NaN weight and panic.
#[inline]
pub fn closest_point_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, Feature) {
    let (q, f) = closest_point_by_region(p, a, b, c);
    if q.is_finite() {
        return (q, f);
    }
    nearest_on_sides(p, [a, b, c])
}

/// The nearest point to `p` on the three sides of a triangle, and the side (or corner).
#[cold]
fn nearest_on_sides(p: Vec3, v: [Vec3; 3]) -> (Vec3, Feature) {
    let mut best = (v[0], Feature::Vertex(0), f32::INFINITY);
    for k in 0..3 {
        let (s, e) = (v[k], v[(k + 1) % 3]);
        let d = e - s;
        let len2 = d.length_squared();
        let t = if len2 > 0.0 {
            ((p - s).dot(d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = s + d * t;
        let dist = (p - q).length_squared();
        if dist < best.2 {
            let f = if t <= 0.0 {
                Feature::Vertex(k as u8)
            } else if t >= 1.0 {
                Feature::Vertex(((k + 1) % 3) as u8)
            } else {
                Feature::Edge(k as u8)
            };
            best = (q, f, dist);
        }
    }
    (best.0, best.1)
}

#[inline]
fn closest_point_by_region(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> (Vec3, Feature) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, Feature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, Feature::Face)
}

/// Möller–Trumbore ray/triangle intersection, two-sided. Returns the ray parameter `t >= 0`.
#[inline]
pub fn ray_triangle(origin: Vec3, dir: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
    let e1 = b - a;
    let e2 = c - a;
    let pvec = dir.cross(e2);
    let det = e1.dot(pvec);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let tvec = origin - a;
    let u = tvec.dot(pvec) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let qvec = tvec.cross(e1);
    let v = dir.dot(qvec) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(qvec) * inv;
    (t >= 0.0).then_some(t)
}

/// An oriented box: centre, orthonormal axes (the columns of `axes`) and half extents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obb {
    pub center: Vec3,
    pub axes: Mat3,
    pub half: Vec3,
}

impl Obb {
    /// An axis-aligned box as an OBB.
    pub fn aabb(min: Vec3, max: Vec3) -> Self {
        Self {
            center: (min + max) * 0.5,
            axes: Mat3::IDENTITY,
            half: (max - min) * 0.5,
        }
    }

    /// `p` in the box's frame (relative to its centre).
    #[inline]
    pub fn to_local(&self, p: Vec3) -> Vec3 {
        self.axes.transpose() * (p - self.center)
    }

    /// Squared distance from `p` to the solid box (0 inside).
    #[inline]
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        let d = p - self.center;
        let l = Vec3::new(
            self.axes.x_axis.dot(d),
            self.axes.y_axis.dot(d),
            self.axes.z_axis.dot(d),
        );
        let excess = (l.abs() - self.half).max(Vec3::ZERO);
        excess.length_squared()
    }

    /// Slab test. Returns the entry parameter (clamped at 0) when the ray meets the box
    /// before `max_t`.
    #[inline]
    pub fn ray_entry(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<f32> {
        let o = self.to_local(origin);
        let d = self.axes.transpose() * dir;
        let mut t0 = 0.0f32;
        let mut t1 = max_t;
        for k in 0..3 {
            let (ok, dk, hk) = (o[k], d[k], self.half[k]);
            if dk.abs() < 1e-20 {
                if ok.abs() > hk {
                    return None;
                }
            } else {
                let inv = 1.0 / dk;
                let mut ta = (-hk - ok) * inv;
                let mut tb = (hk - ok) * inv;
                if ta > tb {
                    std::mem::swap(&mut ta, &mut tb);
                }
                t0 = t0.max(ta);
                t1 = t1.min(tb);
                if t0 > t1 {
                    return None;
                }
            }
        }
        Some(t0)
    }

    /// Separating-axis test between two OBBs (Gottschalk 1996, 15 axes).
    pub fn overlaps(&self, other: &Obb) -> bool {
        let a = [self.axes.x_axis, self.axes.y_axis, self.axes.z_axis];
        let b = [other.axes.x_axis, other.axes.y_axis, other.axes.z_axis];
        let mut r = [[0.0f32; 3]; 3];
        let mut abs_r = [[0.0f32; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = a[i].dot(b[j]);
                abs_r[i][j] = r[i][j].abs() + 1e-6;
            }
        }
        let tw = other.center - self.center;
        let t = [tw.dot(a[0]), tw.dot(a[1]), tw.dot(a[2])];
        let ea = self.half;
        let eb = other.half;
        for i in 0..3 {
            let ra = ea[i];
            let rb = eb[0] * abs_r[i][0] + eb[1] * abs_r[i][1] + eb[2] * abs_r[i][2];
            if t[i].abs() > ra + rb {
                return false;
            }
        }
        for j in 0..3 {
            let ra = ea[0] * abs_r[0][j] + ea[1] * abs_r[1][j] + ea[2] * abs_r[2][j];
            let rb = eb[j];
            let tj = t[0] * r[0][j] + t[1] * r[1][j] + t[2] * r[2][j];
            if tj.abs() > ra + rb {
                return false;
            }
        }
        for i in 0..3 {
            let i1 = (i + 1) % 3;
            let i2 = (i + 2) % 3;
            for j in 0..3 {
                let j1 = (j + 1) % 3;
                let j2 = (j + 2) % 3;
                let ra = ea[i1] * abs_r[i2][j] + ea[i2] * abs_r[i1][j];
                let rb = eb[j1] * abs_r[i][j2] + eb[j2] * abs_r[i][j1];
                let tl = t[i2] * r[i1][j] - t[i1] * r[i2][j];
                if tl.abs() > ra + rb {
                    return false;
                }
            }
        }
        true
    }

    /// Separating-axis test between this box and a triangle (Akenine-Möller's 13 axes, in
    /// the box frame).
    pub fn overlaps_triangle(&self, a: Vec3, b: Vec3, c: Vec3) -> bool {
        let v = [self.to_local(a), self.to_local(b), self.to_local(c)];
        let h = self.half;
        // Box face normals.
        for k in 0..3 {
            let mn = v[0][k].min(v[1][k]).min(v[2][k]);
            let mx = v[0][k].max(v[1][k]).max(v[2][k]);
            if mn > h[k] || mx < -h[k] {
                return false;
            }
        }
        let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
        // Triangle normal.
        let n = e[0].cross(e[1]);
        let d = n.dot(v[0]);
        let rn = h.x * n.x.abs() + h.y * n.y.abs() + h.z * n.z.abs();
        if d.abs() > rn * (1.0 + 1e-6) + 1e-9 {
            return false;
        }
        // Edge cross products.
        let units = [Vec3::X, Vec3::Y, Vec3::Z];
        for ek in e {
            for u in units {
                let axis = u.cross(ek);
                if axis.length_squared() < 1e-20 {
                    continue;
                }
                let p0 = axis.dot(v[0]);
                let p1 = axis.dot(v[1]);
                let p2 = axis.dot(v[2]);
                let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
                let mn = p0.min(p1).min(p2);
                let mx = p0.max(p1).max(p2);
                let eps = 1e-6 * (r + mx.abs().max(mn.abs()));
                if mn > r + eps || mx < -r - eps {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let (q, f) = closest_point_on_triangle(Vec3::new(0.2, 0.2, 1.0), a, b, c);
        assert!((q - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-6 && f == Feature::Face);
        assert_eq!(
            closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.0), a, b, c).1,
            Feature::Vertex(0)
        );
        assert_eq!(
            closest_point_on_triangle(Vec3::new(0.5, -1.0, 0.0), a, b, c).1,
            Feature::Edge(0)
        );
        assert_eq!(
            closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, c).1,
            Feature::Edge(1)
        );
        assert_eq!(
            closest_point_on_triangle(Vec3::new(-1.0, 0.5, 0.0), a, b, c).1,
            Feature::Edge(2)
        );
    }

    #[test]
    fn ray_hits_and_misses() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let t = ray_triangle(Vec3::new(0.2, 0.2, 2.0), -Vec3::Z, a, b, c);
        assert!((t.unwrap_or(f32::NAN) - 2.0).abs() < 1e-6);
        assert_eq!(
            ray_triangle(Vec3::new(0.8, 0.8, 2.0), -Vec3::Z, a, b, c),
            None
        );
        assert_eq!(
            ray_triangle(Vec3::new(0.2, 0.2, 2.0), Vec3::Z, a, b, c),
            None
        );
    }

    #[test]
    fn box_triangle_overlap() {
        let bx = Obb::aabb(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert!(bx.overlaps_triangle(
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(5.0, 0.0, 0.5),
            Vec3::new(0.0, 5.0, 0.5)
        ));
        assert!(!bx.overlaps_triangle(
            Vec3::new(0.0, 0.0, 1.5),
            Vec3::new(5.0, 0.0, 1.5),
            Vec3::new(0.0, 5.0, 1.5)
        ));
        // On the plane x + y = 2.5, past the box's edge at x + y = 2: only the triangle's
        // own normal separates them.
        assert!(!bx.overlaps_triangle(
            Vec3::new(2.5, 0.0, 0.0),
            Vec3::new(0.0, 2.5, 0.0),
            Vec3::new(2.5, 0.0, 5.0)
        ));
        assert!(bx.overlaps_triangle(
            Vec3::new(1.9, 0.0, 0.0),
            Vec3::new(0.0, 1.9, 0.0),
            Vec3::new(1.9, 0.0, 5.0)
        ));
    }

    #[test]
    fn a_degenerate_triangle_gives_the_nearest_point_of_its_sides() {
        // Found by fuzzing a design file: collapsed cloth triangles gave NaN (0 / 0 in the
        // regions' divisions), and the guard's search panicked clamping it.
        let o = Vec3::ZERO;
        let x = Vec3::new(1.0, 0.0, 0.0);
        let cases = [
            [o, o, o],                        // a point
            [o, o, x],                        // two corners at one place
            [o, x, Vec3::new(2.0, 0.0, 0.0)], // on one line
            [x, o, Vec3::new(0.5, 0.0, 0.0)], // on one line, another order
        ];
        let points = [
            Vec3::new(0.3, 0.7, -0.2),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(3.0, -2.0, 1.0),
            Vec3::new(0.5, 0.0, 0.0),
        ];
        for tri in cases {
            for p in points {
                let (q, _) = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
                assert!(q.is_finite(), "{tri:?} {p}: {q}");
                // Brute force: the nearest of many points along the sides.
                let best = (0..3)
                    .flat_map(|k| {
                        let (s, e) = (tri[k], tri[(k + 1) % 3]);
                        (0..=1000).map(move |i| s + (e - s) * (i as f32 / 1000.0))
                    })
                    .map(|r| r.distance(p))
                    .fold(f32::INFINITY, f32::min);
                assert!((q.distance(p) - best).abs() < 1e-3, "{tri:?} {p}: {q}");
            }
        }
    }
}
