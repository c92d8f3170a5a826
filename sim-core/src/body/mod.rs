//! Rigid bodies the cloth collides with: the paper's cube, a sphere, a procedural
//! mannequin, or any closed OBJ surface.

mod body;
mod shapes;

pub use body::{Body, BodyContact};
pub use shapes::{Analytic, BodyKind, Primitive};
