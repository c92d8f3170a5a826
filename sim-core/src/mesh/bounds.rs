//! Axis-aligned bounds of point sets.

use glam::{Vec2, Vec3};

/// Axis-aligned bounds `(min, max)` of a point set (infinite and inverted when empty).
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), &p| (a.min(p), b.max(p)),
    )
}

/// Bounds `(min, max)` of a set of pattern points (infinite and inverted when empty).
pub fn bounds2(points: &[Vec2]) -> (Vec2, Vec2) {
    points.iter().fold(
        (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
        |(a, b), &p| (a.min(p), b.max(p)),
    )
}
