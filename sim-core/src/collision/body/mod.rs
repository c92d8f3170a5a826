//! Rigid bodies the cloth collides with: the paper's cube, a sphere, a procedural
//! mannequin, or any closed OBJ surface.
//!
//! Inside: `analytic` (exact solids) and `clearance` (the distance grid) <- `surface`
//! (`Body`) <- `shapes` and `mannequin` (the builders).

mod analytic;
mod clearance;
mod mannequin;
mod shapes;
mod surface;

pub use analytic::{Analytic, Primitive};
pub use mannequin::{MANNEQUIN_CELL, mannequin, mannequin_parts};
#[cfg(test)]
pub(crate) use shapes::icosphere;
pub use shapes::{BodyKind, cube, sphere};
pub use surface::{Body, BodyContact};
