//! Triangle meshes, the bottom layer: edge keys, topology (edges and hinges), the cloth's
//! pattern mesh, the live (edited) mesh and OBJ input/output. Imports nothing above it.
//!
//! Inside: `edge` <- `topology` <- `cloth_mesh` <- `live`; `obj` reads into a `ClothMesh`;
//! `mesher` meshes a pattern outline into one; `svg` and `dxf` read pattern files into
//! outlines (`dxf` uses `svg`'s `NamedOutline`); `section` cuts a mesh at a level (a tape
//! measure's loops); `bounds` and `sets` (union-find) serve
//! them all.

mod bounds;
mod bridges;
mod cloth_mesh;
pub mod dxf;
mod edge;
pub mod live;
pub mod mesher;
pub mod obj;
pub mod png;
pub mod section;
pub mod sets;
pub mod svg;
mod topology;

/// The farthest a vertex may lie from the origin along any axis, m: a scene is a room,
/// and a coordinate past this is another unit or a damaged file (and would overflow the
/// areas and lengths computed from it).
pub const MAX_COORD: f32 = 1.0e4;

pub use bounds::{bounds, bounds2};
pub use cloth_mesh::{ClothMesh, MAX_VERTICES};
pub use edge::{edge_ends, edge_key};
pub use live::{LiveMesh, NONE, Tri, warp_of};
pub use topology::{Edge, Hinge, Topology};
