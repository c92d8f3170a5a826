//! Rigid bodies the cloth collides with: the paper's cube, a sphere, a procedural
//! mannequin, or any closed OBJ surface.
//!
//! Inside: `analytic` (exact solids) and `clearance` (the distance grid) <- `surface`
//! (`Body`) <- `shapes` and `mannequin` (the builders); `check` reads a body OBJ and
//! checks it is a solid, below `shapes`.

mod analytic;
mod check;
mod clearance;
mod mannequin;
mod shapes;
mod surface;

pub use analytic::{Analytic, Primitive};
pub use check::{CheckedBody, check_body_text};
pub use mannequin::{
    A_POSE_DEG, ARM, ARM_RADIUS, MANNEQUIN_CELL, Pose, mannequin, mannequin_parts, posed_mannequin,
    posed_parts,
};
#[cfg(test)]
pub(crate) use shapes::icosphere;
pub use shapes::{BodyKind, HUMAN, body_from_obj_text, cube, sphere};
pub use surface::{Body, BodyContact};
