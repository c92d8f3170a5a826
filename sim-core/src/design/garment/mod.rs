//! Garments: a pattern's pieces (read from SVG, DXF or GarmentCode JSON, or made by
//! hand) arranged round the body, meshed, and sewn.
//!
//! Inside, bottom up: `cone` (a fan rolled up on a cone round the body) <- `place`
//! (named places, placements, a body's landmarks) <- `fans` (a fan drawn in a pattern
//! file, found in its outline and started at the waist) <- `spec`
//! (the pattern before it is cloth; arrangement by name) <- `assemble` (layout in the
//! design's pattern plane, meshing, start positions; sewing) and `import` (pattern files
//! in: `garmentcode`, and the SVG and DXF readers of `mesh`); `waist` (whether a held
//! waist can stay up on the body once let go); `fit` (the garment's length round the
//! bust, waist and hips beside the body's, from level sections of both).

mod assemble;
mod cone;
mod conform;
mod fans;
pub mod fit;
mod garmentcode;
mod import;
mod place;
mod spec;
mod start;
mod waist;

pub use assemble::LAYER;
pub use assemble::{Assembled, GarmentError, HOLD_PULL, Sewn, assemble, holds, sew};
pub(crate) use assemble::{PATTERN_GAP, SIMPLIFY};
pub use garmentcode::read_garmentcode;
pub(crate) use garmentcode::{FLAT_OUT_TRIES, moved_out};
pub use import::{ImportError, load_pattern, own_body, pattern_from_outlines};
pub use place::{GC_RAISE, Landmarks, MAX_DROP, Place, PlaceError, Placement, Start, place};
pub use spec::{DEFAULT_FABRIC, EdgeRef, HoldSpec, PatternSpec, PieceSpec, SeamSpec, SpecError};
pub(crate) use start::record_start;
pub use start::{PieceStart, signature};
pub use waist::{HIPS_BELOW, Waist, cloth_top};
