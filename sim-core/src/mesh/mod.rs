//! Triangle meshes: the cloth's pattern, its topology, and OBJ input/output.

mod cloth_mesh;
pub mod obj;
mod topology;

pub use cloth_mesh::{ClothMesh, MAX_VERTICES};
pub use topology::{Edge, Hinge, Topology};
