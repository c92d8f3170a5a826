//! The design, above the solver: what a designer owns ([`Design`]: the simulated cloth
//! with its edits, seams, paint, tearing settings and history), the paper's operations as
//! one file each (cut, tear, sew, seam, paint, pin, pinch, and selections on the pattern),
//! undo and redo, the design file and the exports.
//!
//! Every change to the design is a list of primitive edits ([`Prim`], `prim`), each of
//! which knows its inverse; an operation applies its list as one transaction
//! (`transaction`) and pushes it on the history. Imports `solver`, `collision`, `mesh` and
//! `error`; nothing imports it but the scenarios and the processes.
//!
//! Inside, bottom up: `error`, `texture`, `parts` (seams, tearing settings) <- `prim`
//! <- `history` <- `document` (the `Design`) <- `transaction` <- the operations (`cut`,
//! `tear`, `sew`, `seam`, `paint`, `pin`, `pinch`, `pattern`) <- `stalls` (open pairs
//! that stopped closing, told) <- `frame`; `export`,
//! `sewing_pattern` (the pieces' outlines as SVG and AAMA DXF) and `file` read a design;
//! `pieces` (named pieces and the list of the cloth's parts), `fabrics` (each piece's
//! fabric handed to the solver as a material zone) and `garment` (a pattern's pieces
//! placed round the body, meshed, sewn; the pattern files read in) sit beside them.

mod atlas;
mod commute;
mod cut;
mod dart;
mod document;
mod error;
pub mod export;
mod fabrics;
pub mod file;
mod frame;
pub mod garment;
mod history;
mod no_cross;
mod paint;
mod part_names;
mod parts;
mod pattern;
mod piece_edit;
mod piece_list;
mod pieces;
mod pin;
mod pinch;
mod prim;
mod seam;
mod seam_lengths;
mod sew;
pub mod sewing_pattern;
mod slit;
mod stalls;
mod stroke;
mod tear;
#[cfg(test)]
mod tests;
mod texture;
mod transaction;
mod trim;
mod unpick;
mod zip;

pub use dart::{DART_WIDTH_M, TailorsPress};
pub use document::{CLOTH_COLOUR, Design, TEXTURE_SIZE};
pub use error::EditError;
pub use fabrics::{EDITED, fabric_zones};
pub use frame::{AFLOAT_FRAMES, HOLD_FRAMES};
pub use history::History;
pub use parts::{STITCH_PULL, Seam, TearMode, TearSettings, open_stitches};
pub use piece_edit::{ARM_STEP, MAX_PIECE_VERTICES};
pub use piece_list::PieceInfo;
pub use pieces::{MAX_NAME, PartName, PieceRecord};
pub use prim::{Between, Edit, MergeAt, Prim};
pub use seam::SEAM_MISMATCH;
pub use stalls::{Across, STALL_TOLD_AFTER};
pub use texture::{PaintPatch, TILE, Texture};
pub use unpick::Removed;

/// A design of `mesh` under `model` with no gravity and no floor: the cloth stays where
/// it is put, so a test sees only what an edit does.
#[cfg(test)]
pub(crate) fn floating(mesh: crate::mesh::ClothMesh, model: crate::solver::ModelKind) -> Design {
    use crate::solver::{Cloth, Environment, Material, Simulation};
    let m = Material::default();
    let cloth = Cloth::new(mesh, &m).unwrap();
    let env = Environment {
        floor: None,
        gravity: glam::Vec3::ZERO,
        ..Environment::default()
    };
    Design::new(Simulation::new(cloth, None, model, m, env, None).unwrap())
}
