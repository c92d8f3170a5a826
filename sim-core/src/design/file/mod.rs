//! The design file (`.saiho`): everything needed to resume a design — the live pieces
//! with their rest shapes and UVs, positions and velocities, pins, seams, the painted
//! texture, material, model, environment and the body.
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `SAIHODSN` |
//! | 4 | format version (`FORMAT`, currently 2; 1 still loads) |
//! | 4 | header length `H` |
//! | H | header, UTF-8 JSON ([`Header`]): settings, counts, and the byte range of each section |
//! | ... | sections, in any order, at the offsets the header gives (relative to the end of the header) |
//! | 8 | FNV-1a 64 checksum of every byte before it |
//!
//! Sections: `x` and `v` (f32 x 3 per vertex), `tris` (per triangle: 3 u32 indices, 3 x 3
//! f32 rest corners, 3 x 2 f32 UVs), `body_vertices` (f32 x 3), `body_triangles` (u32 x 3),
//! `texture` (PNG, RGBA8). The header's `pieces` (format 2) name the pieces (see
//! `PieceRecord`); a format 1 file has none and loads with its parts unnamed. Its `source`
//! names the pattern file the design was made from (absent in older files: none). A reader refuses a newer format, a bad checksum, or any count,
//! index or value out of range, and builds nothing in that case.
//!
//! Inside: `format` (container, header, readers) <- `write` and `read`.

mod format;
mod read;
mod store;
mod write;

pub use format::{DesignError, FORMAT, Header, MAGIC, SeamRecord, Section};
pub use store::{set_aside, temporary_of, unreadable_reason, write_atomically};
