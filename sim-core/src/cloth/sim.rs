//! One simulated scene: a cloth, an optional body, a model, and the frame loop.

use std::time::Instant;

use glam::Vec3;

use super::contact::{ContactCache, ContactParams};
use super::implicit::{Implicit, ImplicitError};
use super::material::{Material, ModelKind};
use super::seed::{Seed, seed_safe_step, seed_stable_step};
use super::state::Cloth;
use super::xpbd::Xpbd;
use crate::body::Body;
use crate::error::ConfigError;

/// The world around the cloth.
#[derive(Clone, Copy, Debug)]
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

/// What one frame cost.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameStats {
    /// Wall time of the whole frame (collision broad phase + all substeps), ms.
    pub wall_ms: f64,
    pub collision_ms: f64,
    pub contacts: usize,
    pub queries: usize,
    /// Particles the end-of-frame check found inside the body and pushed out.
    pub rescued: usize,
    /// Edges torn this frame.
    pub torn: usize,
    /// Seam stitches welded this frame.
    pub welded: usize,
}

#[derive(Debug, thiserror::Error)]
pub enum StepError {
    #[error(
        "the simulation diverged (NaN or infinite positions) at frame {frame}; the step is too large for this model and stiffness"
    )]
    Diverged { frame: u64 },
    #[error(transparent)]
    Implicit(#[from] ImplicitError),
}

#[derive(Debug)]
pub(crate) enum Solver {
    Xpbd(Box<Xpbd>),
    Seed(Seed),
    Implicit(Box<Implicit>),
}

#[derive(Debug)]
pub struct Simulation {
    pub cloth: Cloth,
    pub body: Option<Body>,
    pub env: Environment,
    pub material: Material,
    pub model: ModelKind,
    pub substeps: usize,
    /// For the seed model, its stable step bound, s.
    pub stable_step: Option<f64>,
    /// Things the user should be told (e.g. substeps raised to stay stable).
    pub notices: Vec<String>,
    pub frame: u64,
    /// The cloth's painted texture.
    pub texture: crate::edit::Texture,
    /// Undo and redo of operations.
    pub history: crate::edit::History,
    /// Tearing of overstretched edges.
    pub tear: crate::edit::TearSettings,
    /// Seams being stitched (welded pairs stay, as `a == b`).
    pub seams: Vec<crate::edit::Seam>,
    /// The texture as PNG for design files, with the texture version it encodes.
    pub(crate) png_cache: Option<(u64, Vec<u8>)>,
    pub(crate) contacts: ContactCache,
    pub(crate) solver: Solver,
}

/// Default substeps per 1/60 s frame for XPBD (3.3 ms steps): stable and tethered for a
/// stiff cotton, within the 128 x 128 budget on one core.
pub const XPBD_DEFAULT_SUBSTEPS: usize = 5;

/// Most substeps per frame [`Simulation::set_material`] accepts.
pub const MAX_SUBSTEPS: usize = 100;

/// Side of the cloth's texture, texels.
pub const TEXTURE_SIZE: usize = 1024;

impl Simulation {
    pub fn new(
        cloth: Cloth,
        body: Option<Body>,
        model: ModelKind,
        material: Material,
        env: Environment,
        substeps: Option<usize>,
    ) -> Result<Self, ConfigError> {
        material.validate()?;
        if !(env.frame_dt.is_finite() && env.frame_dt > 0.0) {
            return Err(ConfigError::OutOfRange {
                name: "frame dt",
                rule: "a positive number of seconds",
                value: env.frame_dt.to_string(),
            });
        }
        if substeps == Some(0) {
            return Err(ConfigError::OutOfRange {
                name: "substeps",
                rule: ">= 1",
                value: "0".into(),
            });
        }
        let mut notices = Vec::new();
        let mut stable_step = None;
        let contact = ContactParams {
            thickness: material.thickness,
            friction: material.friction,
            floor: env.floor,
        };
        let (solver, substeps) = match model {
            ModelKind::Xpbd => (
                Solver::Xpbd(Box::new(Xpbd::new(&cloth, &material))),
                substeps.unwrap_or(XPBD_DEFAULT_SUBSTEPS),
            ),
            ModelKind::Implicit => (
                Solver::Implicit(Box::new(Implicit::new(&cloth, &material))),
                substeps.unwrap_or(1),
            ),
            ModelKind::Seed => {
                // The bound for any shape the draping cloth takes, not just flat at rest.
                let bound = seed_safe_step(&cloth, material.seed_stiffness);
                stable_step = Some(bound);
                // Keep a 10% margin under the bound.
                let needed = ((env.frame_dt as f64) / (0.9 * bound)).ceil().max(1.0) as usize;
                let n = match substeps {
                    Some(n) if (env.frame_dt as f64 / n as f64) > bound => {
                        return Err(ConfigError::UnstableStep {
                            step_s: env.frame_dt as f64 / n as f64,
                            bound_s: bound,
                            stiffness: material.seed_stiffness,
                            needed,
                        });
                    }
                    Some(n) => n,
                    None => {
                        notices.push(format!(
                            "seed model: stable step bound {:.3e} s for any shape of the cloth ({:.3e} s flat at rest; k = {} N/m, unit masses); using {needed} substeps per {:.4} s frame",
                            bound,
                            seed_stable_step(&cloth, material.seed_stiffness),
                            material.seed_stiffness,
                            env.frame_dt
                        ));
                        needed
                    }
                };
                (
                    Solver::Seed(Seed::new(&cloth, material.seed_stiffness, contact)),
                    n,
                )
            }
        };
        let contacts = ContactCache::new(cloth.len());
        Ok(Self {
            cloth,
            body,
            env,
            material,
            model,
            substeps,
            stable_step,
            notices,
            frame: 0,
            texture: crate::edit::Texture::new(TEXTURE_SIZE, TEXTURE_SIZE, [235, 235, 230, 255]),
            history: crate::edit::History::default(),
            tear: crate::edit::TearSettings::default(),
            seams: Vec::new(),
            png_cache: None,
            contacts,
            solver,
        })
    }

    /// Steps one frame. On divergence the error says so; the state is then not usable.
    pub fn step(&mut self) -> Result<FrameStats, StepError> {
        self.step_with(&mut |_, _| None)
    }

    /// Steps one frame, asking `pen(substep, substeps)` before each substep where the
    /// pinch's pointer is and how hard it may pull (`None`: unchanged). This is how
    /// cloth-sim follows the pen at substep rate.
    pub fn step_with(
        &mut self,
        pen: &mut dyn FnMut(usize, usize) -> Option<crate::edit::PenInput>,
    ) -> Result<FrameStats, StepError> {
        let t0 = Instant::now();
        let mut stats = FrameStats::default();
        let cp = ContactParams {
            thickness: self.material.thickness,
            friction: self.material.friction,
            floor: self.env.floor,
        };
        if let Some(body) = &self.body {
            self.contacts.update(
                body,
                &self.cloth.x,
                &self.cloth.v,
                self.env.frame_dt,
                self.env.gravity.length(),
                &cp,
            );
            stats.contacts = self.contacts.active_count();
            stats.queries = self.contacts.last_queries;
        }
        stats.collision_ms = t0.elapsed().as_secs_f64() * 1e3;
        self.load_stitches();
        match &mut self.solver {
            Solver::Xpbd(s) => s.step(
                &mut self.cloth,
                &self.contacts,
                &self.env,
                self.substeps,
                pen,
            ),
            Solver::Seed(s) => s.step(&mut self.cloth, &self.contacts, &self.env, self.substeps),
            Solver::Implicit(s) => {
                s.step(&mut self.cloth, &self.contacts, &self.env, self.substeps)?
            }
        }
        if let Some(body) = &self.body {
            let t1 = Instant::now();
            stats.rescued = self.contacts.resolve_penetrations(
                body,
                &mut self.cloth.x,
                &mut self.cloth.v,
                &self.cloth.inv_mass,
                self.env.frame_dt,
                self.env.gravity.length(),
                &cp,
            );
            stats.collision_ms += t1.elapsed().as_secs_f64() * 1e3;
        }
        stats.torn = self.tear_overstretched();
        stats.welded = self.weld_close_stitches();
        self.frame += 1;
        stats.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        if !self.cloth.is_finite() {
            return Err(StepError::Diverged { frame: self.frame });
        }
        Ok(stats)
    }

    /// Pins vertex `i` where it is (rebuilds what depends on the free set).
    pub fn pin(&mut self, i: usize) {
        self.cloth.pin(i);
        match &mut self.solver {
            Solver::Implicit(s) => s.repin(&self.cloth),
            Solver::Xpbd(s) => s.sync(&self.cloth, &[], &[], &[i as u32]),
            Solver::Seed(_) => {}
        }
    }

    /// Changes the running design's material, and its substeps per frame when given, in
    /// place: positions, velocities, pins, seams, the pinch and the history stay; masses
    /// follow the new density and the XPBD constraints are rebuilt from the live mesh with
    /// the new stiffness. An invalid material, a substep count outside 1..=MAX_SUBSTEPS or
    /// a model other than XPBD is refused and nothing changes.
    pub fn set_material(
        &mut self,
        material: Material,
        substeps: Option<usize>,
    ) -> Result<(), ConfigError> {
        material.validate()?;
        if let Some(n) = substeps
            && !(1..=MAX_SUBSTEPS).contains(&n)
        {
            return Err(ConfigError::OutOfRange {
                name: "substeps",
                rule: "between 1 and 100",
                value: n.to_string(),
            });
        }
        let Solver::Xpbd(old) = &mut self.solver else {
            return Err(ConfigError::OutOfRange {
                name: "model",
                rule: "xpbd to change the material in place",
                value: self.model.name().into(),
            });
        };
        if material.density != self.material.density {
            for i in 0..self.cloth.len() {
                self.cloth.update_mass(i, material.density);
            }
        }
        let limits = std::mem::take(&mut old.limits);
        let mut fresh = Xpbd::with_limits(&self.cloth, &material, Some(limits));
        fresh.prev.clone_from(&old.prev);
        fresh.threads = old.threads;
        fresh.pinch = old.pinch.take();
        fresh.stitches = std::mem::take(&mut old.stitches);
        **old = fresh;
        self.material = material;
        if let Some(n) = substeps {
            self.substeps = n;
        }
        Ok(())
    }

    /// Threads for the XPBD constraint passes and the collision broad phase (1 or 2). The
    /// result does not depend on it. Returns the count in use.
    pub fn set_threads(&mut self, threads: usize) -> usize {
        let threads = threads.clamp(1, 2);
        self.contacts.threads = threads;
        if let Solver::Xpbd(s) = &mut self.solver {
            s.threads = threads;
        }
        threads
    }

    /// Threads in use (see [`set_threads`](Self::set_threads)).
    pub fn threads(&self) -> usize {
        self.contacts.threads
    }

    /// Total energy for the seed model (kinetic + spring + gravity with unit masses).
    pub fn seed_energy(&self) -> Option<f64> {
        match &self.solver {
            Solver::Seed(s) => Some(s.energy(&self.cloth, self.env.gravity)),
            _ => None,
        }
    }

    pub fn constraint_count(&self) -> usize {
        match &self.solver {
            Solver::Xpbd(s) => s.constraint_count(),
            _ => self.cloth.topology.edges.len(),
        }
    }
}
