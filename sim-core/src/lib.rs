//! Saiho's cloth simulation core: cloth meshes and models (XPBD, the paper's mass-spring,
//! implicit Euler), bodies with OBB-tree collision, and the headless scenarios.
//!
//! Units are SI (m, kg, s, N) and Y is up, as in OBJ.

pub mod body;
pub mod cloth;
pub mod edit;
pub mod error;
pub mod mesh;
pub mod obb;
pub mod scenario;
pub mod service;
