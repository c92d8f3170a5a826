//! One simulated scene: a cloth, an optional body, a model, and the frame loop (contact
//! broad phase, the model's substeps, the frame-end penetration check). It knows nothing
//! of designs: the design layer above hands it stitches and edits its cloth.

use std::time::Instant;

use glam::Vec3;

use super::implicit::Implicit;
use super::material::{Material, ModelKind};
use super::model::{Drive, Environment, FrameInput, Solver, StepError, StretchFloor};
use super::pinch::{Grip, PenPath, Pinch};
use super::rest::{Rest, Scene, SleepRule};
use super::seed::{Seed, seed_safe_step, seed_stable_step};
use super::state::Cloth;
use super::stitch::{Hold, Stitch};
use super::vbd::Vbd;
use super::xpbd::Xpbd;
use super::zones::MaterialZones;
use crate::collision::{Body, ContactCache};
use crate::error::{ConfigError, GeometryError, check_range};

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
    /// The cloth slept through the frame (see [`Simulation::sleep`]): nothing moved.
    pub asleep: bool,
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
    /// The pen's pinch, and what it pulled with in the last frame.
    pub(crate) grip: Grip,
    /// Open seam stitches, handed in by the design before each frame.
    pub stitches: Vec<Stitch>,
    /// The open stitches have stopped closing (the design's watch, `design::stalls`):
    /// they no longer keep the cloth from sleeping once it has come to rest.
    pub stitches_stalled: bool,
    /// Vertices kept on one side of planes, handed in by the design before each frame.
    pub holds: Vec<Hold>,
    /// The least stretch the xpbd model's strain limit holds a triangle to, and where
    /// (none: each its own limit): while tearing is on the design sets it a quarter past
    /// the tear threshold, so that a side can stretch far enough to tear (around the
    /// pen's grip alone when the pen tears).
    pub stretch_floor: StretchFloor,
    /// When the cloth falls asleep once it has come to rest (`solver::rest`); `None`, the
    /// default here, simulates every frame. cloth-sim's service turns it on.
    pub sleep: Option<SleepRule>,
    /// How often a long contact search tells the pen path that the frame is busy
    /// ([`Drive::heartbeat`]); `None`, the default here, never. cloth-sim's service sets
    /// it, and sends the pen's model from it.
    pub heartbeat: Option<std::time::Duration>,
    pub(crate) rest: Rest,
    pub(crate) contacts: ContactCache,
    pub(crate) solver: Box<dyn Solver>,
}

/// Default substeps per 1/60 s frame for XPBD (3.3 ms steps): stable and tethered for a
/// stiff cotton, within the 128 x 128 budget on one core.
pub const XPBD_DEFAULT_SUBSTEPS: usize = 5;

/// Default steps per 1/60 s frame for VBD.
pub const VBD_DEFAULT_SUBSTEPS: usize = 2;

/// Most substeps per frame [`Simulation::set_material`] accepts (the XPBD model's
/// interactive range).
pub const MAX_SUBSTEPS: usize = 100;

/// Most substeps per frame any model runs (the seed model's stable count for a fine cloth
/// can pass a thousand; beyond this a frame takes seconds).
pub const MAX_FRAME_SUBSTEPS: usize = 10_000;

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
        if let Some(n) = substeps {
            check_range("substeps", n, 1, MAX_FRAME_SUBSTEPS, " per frame")?;
        }
        let mut notices = Vec::new();
        let mut stable_step = None;
        let contact = material.contact_params(env.floor);
        // The models' elements scale from this (the cloth's zones: pieces of other fabrics).
        let reference = cloth.zones.reference(&material);
        let (solver, substeps): (Box<dyn Solver>, usize) = match model {
            ModelKind::Vbd => (
                Box::new(Vbd::new(&cloth, &reference)),
                substeps.unwrap_or(VBD_DEFAULT_SUBSTEPS),
            ),
            ModelKind::Xpbd => (
                Box::new(Xpbd::new(&cloth, &reference)),
                substeps.unwrap_or(XPBD_DEFAULT_SUBSTEPS),
            ),
            ModelKind::Implicit => (
                Box::new(Implicit::new(&cloth, &reference)),
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
                    None if needed > MAX_FRAME_SUBSTEPS => {
                        return Err(ConfigError::Range {
                            name: "the seed model's stable substep count",
                            min: "1".into(),
                            max: MAX_FRAME_SUBSTEPS.to_string(),
                            unit: " per frame (lower --seed-stiffness or the grid)",
                            value: needed.to_string(),
                        });
                    }
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
                    Box::new(Seed::new(&cloth, material.seed_stiffness, contact)),
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
            grip: Grip::default(),
            stitches: Vec::new(),
            stitches_stalled: false,
            holds: Vec::new(),
            stretch_floor: StretchFloor::NONE,
            sleep: None,
            heartbeat: None,
            rest: Rest::default(),
            contacts,
            solver,
        })
    }

    /// Steps one frame. On divergence the error says so; the state is then not usable.
    pub fn step(&mut self) -> Result<FrameStats, StepError> {
        self.step_with(&mut |_| None)
    }

    /// Whether the model's contact is never crossed (vbd, and xpbd with its guard).
    pub fn never_crosses(&self) -> bool {
        self.solver.never_crosses()
    }

    /// Turns the model's no-crossing guard on or off (xpbd); whether it has one.
    pub fn set_guard(&mut self, on: bool) -> bool {
        self.rest.wake();
        self.solver.set_guard(&self.cloth, on)
    }

    /// Whether the model follows edits and the pen (see [`Solver::editable`]).
    pub fn editable(&self) -> bool {
        self.solver.editable()
    }

    /// Steps one frame, telling `pen` before each substep where the frame is
    /// ([`Between`](super::Between)) and asking it where the pinch's pointer is and how
    /// hard it may pull (`None`: unchanged). This is how cloth-sim follows the pen at
    /// substep rate (xpbd and vbd; the other models do not ask).
    pub fn step_with(&mut self, pen: &mut PenPath<'_>) -> Result<FrameStats, StepError> {
        let t0 = Instant::now();
        let mut stats = FrameStats::default();
        if self.rest.asleep() {
            if self.sleep.is_some() && self.rest.still_asleep(&self.scene()) {
                self.rest.slept();
                self.grip.begin_frame();
                self.frame += 1;
                // The contacts are those of the frame it fell asleep in.
                (stats.contacts, stats.queries) = self.rest.last;
                stats.asleep = true;
                stats.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
                return Ok(stats);
            }
            self.rest.wake();
        }
        let cp = self.material.contact_params(self.env.floor);
        let own_contact = self.solver.own_contact();
        if let Some(body) = self.body.as_ref().filter(|_| !own_contact) {
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
        let mut drive = Drive {
            grip: &mut self.grip,
            stitches: &self.stitches,
            holds: &self.holds,
            pen,
            stretch_floor: self.stretch_floor,
            heartbeat: self.heartbeat,
        };
        let frame = FrameInput {
            cloth: &mut self.cloth,
            body: self.body.as_ref(),
            contacts: &self.contacts,
            env: &self.env,
            substeps: self.substeps,
        };
        self.solver.step(frame, &mut drive)?;
        if let Some(c) = self.solver.contact_stats() {
            stats.contacts = c.pairs.with_energy;
            stats.queries = c.pairs.vertex_face
                + c.pairs.edge_edge
                + c.pairs.body_vertex_face
                + c.pairs.body_edge_edge
                + c.pairs.body_corner_face;
            stats.collision_ms += c.detect_us as f64 * 1e-3;
        }
        if let Some(body) = self
            .body
            .as_ref()
            .filter(|_| !own_contact && !self.solver.never_crosses())
        {
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
        self.frame += 1;
        if !self.cloth.in_scene() {
            return Err(StepError::Diverged { frame: self.frame });
        }
        self.watch_rest(&stats);
        stats.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        Ok(stats)
    }

    /// After a frame: puts the cloth to sleep once it has been still for the rule's
    /// frames (its velocities zeroed; see `solver::rest`), unless the pen holds it, a
    /// vertex is held, or a seam stitch is open and still closing (a seam is never left
    /// half sewn while it closes; one whose pairs stopped closing, which the designer has
    /// been told of, lets a cloth at rest sleep: it cost a core for nothing before).
    fn watch_rest(&mut self, stats: &FrameStats) {
        let Some(rule) = self.sleep else { return };
        let sewing = !self.stitches.is_empty() && !self.stitches_stalled;
        let held = self.grip.pinch.is_some() || sewing || !self.holds.is_empty();
        if self
            .rest
            .watch(&rule, &self.cloth.x, &self.cloth.inv_mass, held)
        {
            self.cloth.v.iter_mut().for_each(|v| *v = Vec3::ZERO);
            let print = self.scene().print();
            self.rest.fall_asleep(print);
            self.rest.last = (stats.contacts, stats.queries);
        }
    }

    /// The scene as sleep compares it.
    fn scene(&self) -> Scene<'_> {
        Scene {
            x: &self.cloth.x,
            v: &self.cloth.v,
            inv_mass: &self.cloth.inv_mass,
            triangles: self.cloth.live.iter().count(),
            env: &self.env,
            substeps: self.substeps,
            material: &self.material,
            stitches: &self.stitches,
            stretch_floor: self.stretch_floor,
            body: self.body.as_ref(),
            pinched: self.grip.pinch.is_some(),
        }
    }

    /// Whether the cloth sleeps (it came to rest, and nothing has touched it since).
    pub fn asleep(&self) -> bool {
        self.rest.asleep()
    }

    /// Frames the cloth slept through since the simulation began.
    pub fn frames_asleep(&self) -> u64 {
        self.rest.frames_asleep
    }

    /// Wakes a sleeping cloth: the next frame is simulated, and the watch starts again.
    pub fn wake(&mut self) {
        self.rest.wake();
    }

    /// After the design edited the cloth (triangle slots, edge keys, and vertices whose
    /// mass or pin changed, each sorted and without repeats): brings masses, the contact
    /// cache and the model up to date with the live mesh.
    pub fn cloth_edited(&mut self, tris: &[u32], edges: &[u64], verts: &[u32]) {
        self.rest.wake();
        for &v in verts {
            self.cloth.update_mass(v as usize, self.material.density);
        }
        self.contacts.resize(self.cloth.len());
        if self.solver.editable() {
            self.solver.sync(&self.cloth, tris, edges, verts);
        }
    }

    /// Pins vertex `i` where it is (rebuilds what depends on the free set).
    pub fn pin(&mut self, i: usize) {
        self.rest.wake();
        self.cloth.pin(i);
        self.solver.pinned(&self.cloth, i as u32);
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
        self.rest.wake();
        if let Some(n) = substeps
            && !(1..=MAX_SUBSTEPS).contains(&n)
        {
            return Err(ConfigError::OutOfRange {
                name: "substeps",
                rule: "between 1 and 100",
                value: n.to_string(),
            });
        }
        let zones = self.cloth.zones.clone();
        self.cloth.zones.rebase(&material);
        let reference = self.cloth.zones.reference(&material);
        if let Err(e) = self.solver.set_material(&mut self.cloth, &reference) {
            self.cloth.zones = zones;
            return Err(e);
        }
        self.material = material;
        if let Some(n) = substeps {
            self.substeps = n;
        }
        Ok(())
    }

    /// Gives the pieces of the cloth their own materials (`zones`, over this
    /// simulation's material), in place like [`set_material`](Self::set_material):
    /// masses follow each triangle's density and the model's elements are rebuilt. A
    /// model that cannot change its material in place refuses, and nothing changes.
    pub fn set_zones(&mut self, zones: MaterialZones) -> Result<(), ConfigError> {
        if zones == self.cloth.zones {
            return Ok(());
        }
        self.rest.wake();
        let old = self.cloth.zones.clone();
        // Masses first: the models pack inverse masses with their elements.
        self.cloth.set_zones(zones, self.material.density);
        let reference = self.cloth.zones.reference(&self.material);
        if let Err(e) = self.solver.set_material(&mut self.cloth, &reference) {
            self.cloth.set_zones(old, self.material.density);
            return Err(e);
        }
        Ok(())
    }

    /// Threads for the XPBD constraint passes and the collision broad phase (1 or 2). The
    /// result does not depend on it. Returns the count in use.
    pub fn set_threads(&mut self, threads: usize) -> usize {
        let threads = threads.clamp(1, 2);
        self.contacts.threads = threads;
        self.solver.set_threads(threads);
        threads
    }

    /// Threads in use (see [`set_threads`](Self::set_threads)).
    pub fn threads(&self) -> usize {
        self.contacts.threads
    }

    /// Total energy for the seed model (kinetic + spring + gravity with unit masses).
    pub fn seed_energy(&self) -> Option<f64> {
        self.solver.energy(&self.cloth, self.env.gravity)
    }

    /// The cloth's exact crossings as it is now, with itself and the body
    /// (`collision::crossings`).
    pub fn crossings(&self) -> crate::collision::crossings::Crossings {
        crate::collision::crossings::count(
            &self.cloth.x,
            &self.cloth.live.triangles(),
            self.body.as_ref(),
        )
    }

    /// Pairs of the cloth's primitives in contact now, whatever the model: a vertex and a
    /// triangle, or two edges, closer than the contact thickness and more than two
    /// triangle sides plus twice the thickness apart in the pattern (so a flat cloth has
    /// none: folds, layers and pieces lying on each other are what it counts).
    pub fn self_contacts(&self) -> usize {
        let live = &self.cloth.live;
        let th = self.material.thickness;
        crate::collision::proximity::count_self_contacts(
            &self.cloth.x,
            &live.triangles(),
            &live.pattern_places(self.cloth.len()),
            th,
            2.0 * live.mean_rest_side() + 2.0 * th,
        )
    }

    pub fn constraint_count(&self) -> usize {
        self.solver.constraint_count(&self.cloth)
    }

    /// Checks the live mesh and state: indices, manifold edges, no degenerate triangle,
    /// UVs in range, nothing NaN.
    pub fn validate(&self) -> Result<(), GeometryError> {
        self.cloth.live.validate(&self.cloth.x)?;
        if let Some(i) = self.cloth.v.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite { vertex: i });
        }
        Ok(())
    }

    /// The pen's pinch, while it lasts.
    pub fn pinch(&self) -> Option<&Pinch> {
        self.grip.pinch.as_ref()
    }

    /// Holds the cloth with `pinch` (the design chose the vertices), replacing any pinch.
    pub fn set_pinch(&mut self, pinch: Option<Pinch>) {
        self.rest.wake();
        self.grip.pinch = pinch;
    }

    /// Moves the pinch's pointer end.
    pub fn pinch_move(&mut self, target: Vec3) {
        if let Some(p) = &mut self.grip.pinch
            && target.is_finite()
        {
            p.target = target;
        }
    }

    /// Substeps of the last frame in which the pinch pulled at its force limit.
    pub fn pinch_limited_substeps(&self) -> usize {
        self.grip.limited
    }

    /// The force the pinch springs put on the cloth (their sum) in each substep of the
    /// last frame, N (the pen feels the opposite).
    pub fn pinch_forces(&self) -> &[Vec3] {
        &self.grip.forces
    }
}
