//! OBB tree (Gottschalk, Lin & Manocha 1996, "OBBTree"), the paper's collision structure.
//!
//! Split by phase: [`tree`] (data), [`build`], [`queries`], [`refit`], [`validation`];
//! [`walk`] answers nearest-point queries near a known triangle without the tree.

mod build;
pub mod geometry;
mod queries;
mod refit;
mod tree;
mod validation;
mod walk;

#[cfg(test)]
mod tests;

pub use geometry::{Feature, Obb};
pub use queries::{NearestHit, RayHit};
pub use tree::{BuildOptions, ObbNode, ObbTree};
pub use validation::ValidationError;
pub use walk::{Miss, SurfaceWalk};
