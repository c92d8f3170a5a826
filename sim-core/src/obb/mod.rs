//! OBB tree (Gottschalk, Lin & Manocha 1996, "OBBTree"), the paper's collision structure.
//!
//! Split by phase: [`tree`] (data), [`build`], [`queries`], [`refit`], [`validation`].

mod build;
pub mod geometry;
mod queries;
mod refit;
mod tree;
mod validation;

#[cfg(test)]
mod tests;

pub use geometry::{Feature, Obb};
pub use queries::{NearestHit, RayHit};
pub use tree::{BuildOptions, ObbNode, ObbTree};
pub use validation::ValidationError;
