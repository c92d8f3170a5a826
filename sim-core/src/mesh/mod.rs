//! Triangle meshes: the cloth's pattern, its topology, and OBJ input/output.

mod cloth_mesh;
pub mod live;
pub mod obj;
mod topology;

pub use cloth_mesh::{ClothMesh, MAX_VERTICES};
pub use live::{LiveMesh, Tri, edge_key};
pub use topology::{Edge, Hinge, Topology};

use glam::Vec3;

/// Axis-aligned bounds `(min, max)` of a point set (infinite and inverted when empty).
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(a, b), &p| (a.min(p), b.max(p)),
    )
}
