//! Fabrics: the measured library (`library`), and the textile industry's drape test
//! (`cusick`, measured by `shadow`) that checks the model against the published drapes.
//!
//! A layer between the solver (which takes a [`Material`](crate::solver::Material)) and
//! the design (whose pieces name their fabric).

pub mod cusick;
pub mod library;
pub mod shadow;

pub use cusick::{CusickConfig, CusickError, CusickResult, Standard};
pub use library::{Fabric, FabricError, FabricSi, Library, Units};
