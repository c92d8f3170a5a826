//! [`Design`]: what a designer owns — the simulated cloth with its edits, the seams, the
//! painted texture, tearing settings and the history.

use super::history::History;
use super::parts::{Seam, TearSettings};
use super::pieces::PieceRecord;
use super::prim::Prim;
use super::texture::Texture;
use crate::error::GeometryError;
use crate::solver::Simulation;

/// Side of the cloth's texture, texels.
pub const TEXTURE_SIZE: usize = 1024;

/// The colour of unpainted cloth.
pub const CLOTH_COLOUR: [u8; 4] = [235, 235, 230, 255];

#[derive(Debug)]
pub struct Design {
    /// The simulated scene: cloth, body, model. The design edits its cloth only through
    /// primitive edits (`Prim`).
    pub sim: Simulation,
    /// The cloth's painted texture.
    pub texture: Texture,
    /// Undo and redo of operations.
    pub history: History,
    /// Tearing of overstretched edges.
    pub tear: TearSettings,
    /// Seams being stitched (welded pairs stay, as `a == b`).
    pub seams: Vec<Seam>,
    /// The pieces as named when the design was made from a pattern (empty for a cloth
    /// made otherwise); see `pieces`.
    pub pieces: Vec<PieceRecord>,
    /// The pattern file the design was made from, as its maker named it (empty: none
    /// known): the design file keeps it, so that a resumed or loaded design can be
    /// draped again from it.
    pub source: String,
    /// The texture as PNG for design files, with the texture version it encodes.
    pub(super) png_cache: Option<(u64, Vec<u8>)>,
    /// Frames since each seam (by index) last welded a pair: a seam stalled that long
    /// may zip (`seam.rs`).
    pub(super) seam_idle: Vec<u32>,
    /// Stitched pairs whose weld the mesh refused (it would not stay manifold) since the
    /// cloth last changed: not tried again until it does. Each try applied the weld,
    /// rolled it back and brought the solver and its contact search up to date, every
    /// frame: the resting dress took 60-90 ms a frame instead of 15 (`seam.rs`).
    pub(super) weld_refused: Vec<(u32, u32)>,
    /// The moves that parted the last update's fresh cut ([`Design::part_copies`]),
    /// until the edit that made it takes them into its history.
    pub(super) parting: Vec<Prim>,
    /// Frames left in which the cloth floats (no gravity) while its seams pull
    /// ([`Design::float_while_sewing`]).
    pub(super) afloat: u32,
    /// How fast the floating cloth's motion dies away, 1/s (0: undamped;
    /// [`Design::float_while_sewing_damped`]).
    pub(super) afloat_damping: f32,
    /// Vertices kept on one side of planes while the garment settles, and for how many
    /// more frames
    /// ([`Design::hold_while_draping`]).
    pub(super) holds: Vec<crate::solver::Hold>,
    pub(super) hold_frames: u32,
    /// Whether the open stitched pairs still close (`stalls`).
    pub(super) stalls: super::parts::Stalls,
}

impl Design {
    /// A new design around `sim`: unpainted, no seams, nothing to undo, tearing off.
    pub fn new(sim: Simulation) -> Self {
        Self::with_texture(sim, Texture::new(TEXTURE_SIZE, TEXTURE_SIZE, CLOTH_COLOUR))
    }

    /// [`Design::new`] with the texture given (a loaded one: no blank texture made first).
    pub fn with_texture(sim: Simulation, texture: Texture) -> Self {
        Self {
            sim,
            texture,
            history: History::default(),
            tear: TearSettings::default(),
            seams: Vec::new(),
            pieces: Vec::new(),
            source: String::new(),
            png_cache: None,
            seam_idle: Vec::new(),
            weld_refused: Vec::new(),
            parting: Vec::new(),
            afloat: 0,
            afloat_damping: 0.0,
            holds: Vec::new(),
            hold_frames: 0,
            stalls: Default::default(),
        }
    }

    /// Checks the live mesh and state (see [`Simulation::validate`]).
    pub fn validate(&self) -> Result<(), GeometryError> {
        self.sim.validate()
    }
}
