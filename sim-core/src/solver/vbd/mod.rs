//! Vertex Block Descent with a global step and penetration-free contact (`--model vbd`).
//! `elastic.rs` (the energy at one vertex) and `contact.rs` (penalty and friction at one
//! vertex) ← `global.rs` (the global step's factored matrix and filtered PCG) ←
//! `step.rs` (`Vbd`: a frame of steps, every move through the proximity guard) ←
//! `solver.rs` (`impl Solver`); `tests.rs`.

mod contact;
mod elastic;
mod global;
mod solver;
mod step;

pub use contact::CONTACT_STIFFNESS;
pub use step::{DEFAULT_ITERATIONS, Vbd};

#[cfg(test)]
mod tests;
