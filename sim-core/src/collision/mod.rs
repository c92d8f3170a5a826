//! Collision, below the solvers: the paper's OBB tree (`obb`, split by phase), the bodies
//! the cloth lies on (`body`: surfaces, the clearance grid, the shapes) and the cloth's
//! contact with them (`contact`: the per-frame broad phase and per-substep projection),
//! and the exact crossing counts that judge it all (`crossings`).
//!
//! Imports only `mesh` and `error`; the solvers read its `ContactCache`.

pub mod body;
pub mod contact;
pub mod crossings;
pub mod obb;
pub mod proximity;

pub use body::{Body, BodyContact, BodyKind};
pub use contact::{ContactCache, ContactParams};
