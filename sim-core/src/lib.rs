//! Saiho's cloth simulation core, a library in layers, each importing only those below:
//!
//! - [`scenario`]: headless scenarios (scripted designs, reports, exports);
//! - [`design`]: what a designer owns and the operations on it (cut, tear, sew, seam,
//!   paint, pin, pinch), undo, the design file, exports;
//! - [`solver`]: the cloth's state and material, the three models behind the `Solver`
//!   trait, and [`solver::Simulation`], one scene's frame loop;
//! - [`collision`]: the OBB tree, bodies, cloth-body contact;
//! - [`mesh`]: triangle meshes, topology, the live mesh, OBJ;
//! - [`error`]: the error types the layers share.
//!
//! The processes (`cloth-sim run` and the rest) live in their own crates; this library
//! knows nothing of iceoryx2 or command lines. Units are SI (m, kg, s, N) and Y is up, as
//! in OBJ.

pub mod collision;
pub mod design;
pub mod error;
pub mod fabric;
pub mod mesh;
pub mod scenario;
pub mod solver;
