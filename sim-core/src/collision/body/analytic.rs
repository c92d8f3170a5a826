//! Exact solids for bodies built from primitives: signed distances of boxes, spheres,
//! capsules and ellipsoids, and of their union.

use glam::Vec3;

/// A solid primitive with a signed distance (exact for boxes, spheres and capsules; a
/// first-order estimate for ellipsoids whose sign is exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    Box { center: Vec3, half: Vec3 },
    Ellipsoid { center: Vec3, radii: Vec3 },
    Capsule { a: Vec3, b: Vec3, radius: f32 },
}

impl Primitive {
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        match *self {
            Self::Box { center, half } => {
                let q = (p - center).abs() - half;
                q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
            }
            Self::Ellipsoid { center, radii } => {
                let k = ((p - center) / radii).length();
                (k - 1.0) * radii.min_element()
            }
            Self::Capsule { a, b, radius } => {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                (p - (a + ab * t)).length() - radius
            }
        }
    }
}

/// The exact solid of a primitive-built body (a union).
#[derive(Clone, Debug, PartialEq)]
pub struct Analytic {
    pub parts: Vec<Primitive>,
}

impl Analytic {
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        self.parts
            .iter()
            .map(|s| s.signed_distance(p))
            .fold(f32::INFINITY, f32::min)
    }
}
