//! Small-steps XPBD (Macklin, Storey, Lu et al. 2019): many substeps, one Gauss-Seidel
//! pass each. Compliance is the inverse of a physical stiffness (membrane moduli times
//! area, bending rigidity times the hinge weight), and the time-scaled compliance
//! `alpha / h^2` is recomputed for the substep, so material stiffness does not depend on
//! the substep count. With one iteration per substep the Lagrange multipliers start at
//! zero every substep and need not be stored.
//!
//! Gauss-Seidel moves a correction about one vertex per pass, so with few passes a long
//! hanging span stretches more than its material would (the sag then depends on the
//! substep count). Long-range attachments (Kim, Chentanez & Mueller 2012) fix that for
//! pinned cloth: every free vertex gets a unilateral tether to its nearest pins, as long
//! as the geodesic rest distance times `1 + strain`, where `strain` is what the material
//! itself would stretch under its full weight (`density * g * extent / stretch`). Tethers
//! never make the cloth stiffer than its material; they only stop the solver's lag.
//! Cloth held up by a body instead of pins gets the same remedy from the stretch limits
//! (`limits`): a coarse lattice of unilateral links solved before and after the
//! membranes.
//!
//! Inside: `coloring` and `simd` <- `groups` (the packed constraint groups) and `limits`
//! (stretch limits) <- `tethers`, `sewing` (whether a seam still closes), `strain_limit`
//! (the optional hard limit per triangle) and `settle` (an edit's stretch taken up
//! without becoming speed) <- `step` (the solver's state and its frame) <- `edit`
//! (keeping it in step with an edited cloth, and `rebuild` after a material change) <-
//! `solver` (the `Solver` trait's methods).

mod coarse;
mod coloring;
mod edit;
mod flutter;
mod graph;
mod groups;
mod guard;
mod guard_pass;
mod limits;
mod settle;
mod sewing;
mod simd;
mod solver;
mod step;
mod straight;
mod strain_limit;
mod tethers;

pub use step::Xpbd;
