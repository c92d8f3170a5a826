//! Axis-aligned bounds of point sets.

use glam::Vec3;

/// Axis-aligned bounds `(min, max)` of a point set (infinite and inverted when empty).
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), &p| (a.min(p), b.max(p)),
    )
}
