//! Cloth-body contact: the per-frame broad phase, the per-substep projection with
//! friction (`cache`), and the per-particle searches it runs over ranges (`broad`).

mod broad;
mod cache;
#[cfg(test)]
mod tests;

pub use broad::REUSE_DISTANCE;
pub use cache::{ContactCache, ContactParams, StaticFriction};
