//! Rigid bodies the cloth collides with: the paper's cube, a sphere, a procedural
//! mannequin, or any closed OBJ surface.

mod clearance;
mod shapes;
mod surface;

#[cfg(test)]
pub(crate) use shapes::icosphere;
pub use shapes::{
    Analytic, BodyKind, MANNEQUIN_CELL, Primitive, cube, mannequin, mannequin_parts, sphere,
};
pub use surface::{Body, BodyContact};
