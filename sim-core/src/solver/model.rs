//! What every cloth model offers the simulation: the [`Solver`] trait, the world around
//! the cloth ([`Environment`]) and what drives it besides gravity and contact ([`Drive`]).

use glam::Vec3;

use super::material::{Material, ModelKind};
use super::pinch::{Grip, PenPath};
use super::state::Cloth;
use super::stitch::{Hold, Stitch};
use crate::collision::proximity::PairCounts;
use crate::collision::{Body, ContactCache};
use crate::error::ConfigError;

/// The world around the cloth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    pub gravity: Vec3,
    /// Duration of one frame, s (substeps are inside it).
    pub frame_dt: f32,
    /// Floor height, if there is a floor.
    pub floor: Option<f32>,
}

impl Default for Environment {
    fn default() -> Self {
        Self {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            frame_dt: 1.0 / 60.0,
            floor: Some(0.0),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum StepError {
    #[error(
        "the simulation diverged (positions not finite, or beyond 10 km) at frame {frame}; the step is too large for this model and stiffness"
    )]
    Diverged { frame: u64 },
    /// The implicit model's sparse Cholesky factorisation failed.
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}

/// What pulls on the cloth during a frame besides gravity and contact: the pen's pinch,
/// where the pen is before each substep, and the seams' stitches. Models that do not
/// follow edits ([`Solver::editable`] false) ignore it.
pub struct Drive<'a, 'p> {
    pub grip: &'a mut Grip,
    pub stitches: &'a [Stitch],
    /// Vertices kept on one side of planes (a waistband above the waist while a garment
    /// settles).
    pub holds: &'a [Hold],
    pub pen: &'a mut PenPath<'p>,
    /// While a long contact search runs, tell `pen` this often that the frame is busy
    /// ([`Between::heartbeat`](super::Between)); `None`: never (scenarios, tests).
    pub heartbeat: Option<std::time::Duration>,
    /// The least largest stretch the strain limit holds a triangle to
    /// ([`Simulation::stretch_floor`](super::Simulation::stretch_floor)).
    pub stretch_floor: StretchFloor,
}

/// The least largest stretch the strain limit holds a triangle to, and where: a tear by
/// the pen loosens the limit around the grip alone, so that the cloth it pulls can
/// stretch far enough to tear there while the rest keeps its limit (loosened everywhere,
/// a sewn dress sagged at its seams and tore there, far from the pen).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StretchFloor {
    /// The least limit (0: each triangle its own).
    pub ratio: f32,
    /// Only triangles with a corner within this distance of this point (`None`: every
    /// triangle).
    pub within: Option<(Vec3, f32)>,
}

impl StretchFloor {
    /// None at all: each triangle keeps its own limit.
    pub const NONE: Self = Self {
        ratio: 0.0,
        within: None,
    };

    /// The least limit of a triangle with corners `p`.
    #[inline]
    pub fn at(&self, p: &[Vec3; 3]) -> f32 {
        match self.within {
            _ if self.ratio <= 0.0 => 0.0,
            None => self.ratio,
            Some((c, r)) if p.iter().any(|q| q.distance_squared(c) <= r * r) => self.ratio,
            Some(_) => 0.0,
        }
    }

    /// The same bits (the sleep watch compares the scene by its bits).
    pub fn bits(&self) -> [u32; 5] {
        let (c, r) = self.within.unwrap_or((Vec3::NAN, f32::NAN));
        [self.ratio, c.x, c.y, c.z, r].map(f32::to_bits)
    }
}

/// One frame's work for a model: the cloth, this frame's contact planes, the world, and
/// the substeps to advance `env.frame_dt` in.
pub struct FrameInput<'a> {
    pub cloth: &'a mut Cloth,
    /// The body, for models that search their own contacts (VBD).
    pub body: Option<&'a Body>,
    pub contacts: &'a ContactCache,
    pub env: &'a Environment,
    pub substeps: usize,
}

/// What the last frame's contact did, for models with penetration-free contact.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct ContactStats {
    pub pairs: PairCounts,
    /// Moves the guard projected onto a bound, and moves it had to shorten.
    pub projected: usize,
    pub shortened: usize,
    /// Moves inside their vertex's reach, whose pairs the guard did not need to check.
    pub skipped: usize,
    /// Time the proximity search took, µs.
    pub detect_us: u64,
    /// Searches run, searches that looked again only where vertices left their boxes,
    /// and frames (or substeps) that kept the last search's pairs.
    pub searches: usize,
    pub updates: usize,
    pub reused: usize,
}

/// A cloth model. [`Simulation`](super::Simulation) holds one and calls it once a frame,
/// after the contact broad phase and before the frame-end penetration check.
pub trait Solver: std::fmt::Debug + Send {
    fn kind(&self) -> ModelKind;

    /// Advances one frame, pulled by `drive`.
    fn step(&mut self, frame: FrameInput<'_>, drive: &mut Drive<'_, '_>) -> Result<(), StepError>;

    /// Constraints (or springs) the model solves.
    fn constraint_count(&self, cloth: &Cloth) -> usize;

    /// Whether the model follows edits of the live mesh (cut, sew, tear, pins as edits)
    /// and the pen's pinch and stitches. Only then may the design edit the cloth.
    fn editable(&self) -> bool {
        false
    }

    /// Brings the model in line with `cloth` after an edit touched these triangle slots,
    /// edge keys and vertices (masses or pins). Only called when [`editable`](Self::editable).
    fn sync(&mut self, _cloth: &Cloth, _tris: &[u32], _edges: &[u64], _verts: &[u32]) {}

    /// Vertex `vertex` was pinned outside an edit (a scene's setup).
    fn pinned(&mut self, _cloth: &Cloth, _vertex: u32) {}

    /// Changes the material in place: masses follow its density, positions and
    /// everything else stay. Models that cannot refuse, and nothing changes.
    fn set_material(
        &mut self,
        _cloth: &mut Cloth,
        _material: &Material,
    ) -> Result<(), ConfigError> {
        Err(ConfigError::OutOfRange {
            name: "model",
            rule: "xpbd to change the material in place",
            value: self.kind().name().into(),
        })
    }

    /// Threads for the model's passes (1 or 2); results do not depend on it.
    fn set_threads(&mut self, _threads: usize) {}

    /// What the last frame's contact did (models with their own contact search).
    fn contact_stats(&self) -> Option<ContactStats> {
        None
    }

    /// Whether the model searches its own contacts with the body (then the simulation's
    /// per-particle planes are not needed).
    fn own_contact(&self) -> bool {
        false
    }

    /// Whether the model's contact is never crossed (the proximity guard): then an edit
    /// that would make a crossing (a sew, an undo or redo) is refused, and the frame-end
    /// rescue of vertices inside the body, which moves them outside the guard, is off.
    fn never_crosses(&self) -> bool {
        false
    }

    /// Turns the model's no-crossing guard on or off (models that have one: xpbd);
    /// returns whether the model has it. Off, the cloth is as fast as its solver alone
    /// and can cross itself and the body.
    fn set_guard(&mut self, _cloth: &Cloth, _on: bool) -> bool {
        false
    }

    /// Total energy, for models that define one for tests (the seed model).
    fn energy(&self, _cloth: &Cloth, _gravity: Vec3) -> Option<f64> {
        None
    }
}
