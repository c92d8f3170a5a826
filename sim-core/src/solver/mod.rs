//! The cloth models, above collision and below the design: the cloth's state and material,
//! the [`Solver`] trait with its three models (`xpbd`, the default; `seed`, the 2005
//! paper's mass-spring; `implicit`, backward Euler as the reference), the pen's pinch
//! spring and the seams' stitches as the solvers see them, and [`Simulation`]: one scene
//! and its frame loop.
//!
//! Imports `collision`, `mesh` and `error`; never the design or the scenarios.

mod constraints;
mod implicit;
mod material;
mod model;
mod motion;
mod pinch;
mod rest;
mod seed;
mod sim;
mod state;
mod stitch;
mod stretch;
mod vbd;
mod xpbd;
mod zones;

pub use constraints::{BendConstraint, Membrane, bending_energy, build_bending, build_membranes};
pub use implicit::{EarlyStop, Implicit, ImplicitError};
pub use material::{
    DEFAULT_BEND_DAMPING, DEFAULT_SHEAR_DAMPING, DEFAULT_THICKNESS, Material, ModelKind,
};
pub use model::{ContactStats, Drive, Environment, FrameInput, Solver, StepError, StretchFloor};
pub use pinch::{Between, Grip, Held, PenInput, PenPath, Pinch, beating};
pub(crate) use rest::Rest;
pub use rest::SleepRule;
pub use seed::{Seed, seed_safe_step, seed_stable_step};
pub use sim::{
    FrameStats, MAX_FRAME_SUBSTEPS, MAX_SUBSTEPS, Simulation, VBD_DEFAULT_SUBSTEPS,
    XPBD_DEFAULT_SUBSTEPS,
};
pub use state::Cloth;
pub use stitch::{ClosingWatch, HOLD_STIFFNESS, Hold, STITCH_STIFFNESS, Stitch};
pub use stretch::{ThreadStretch, thread_stretch};
pub use vbd::{CONTACT_STIFFNESS, DEFAULT_ITERATIONS, Vbd};
pub use xpbd::Xpbd;
pub use zones::{MaterialZones, Scales, Zone};
