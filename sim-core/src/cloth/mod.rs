//! Cloth state and the three models: `xpbd` (default), `seed` (the paper's mass-spring)
//! and `implicit` (backward Euler, the reference).

mod coloring;
mod constraints;
mod contact;
mod implicit;
mod limits;
mod material;
mod seed;
pub(crate) mod sim;
mod state;
mod xpbd;
mod xpbd_edit;
mod xpbd_simd;

pub use constraints::{BendConstraint, Membrane, bending_energy, build_bending, build_membranes};
pub use contact::{ContactCache, ContactParams};
pub use implicit::Implicit;
pub use material::{Material, ModelKind};
pub use seed::{Seed, seed_safe_step, seed_stable_step};
pub use sim::{Environment, FrameStats, Simulation, StepError, XPBD_DEFAULT_SUBSTEPS};
pub use state::Cloth;
pub use xpbd::Xpbd;
