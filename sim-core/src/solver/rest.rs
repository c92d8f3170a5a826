//! Sleep: a cloth that has come to rest stops being simulated until something touches it.
//!
//! A settled 128 x 128 drape still costs 24-32 ms a frame on two cores (the search, the
//! guard and the solver's passes over everything: docs/collision.md), so a design left
//! lying on the mannequin kept both cores busy and ran slower than real time, beside the
//! haptic loop. With a [`SleepRule`], [`Simulation`](super::Simulation) watches how far
//! the free vertices stray from where they were when the watch began; once they have
//! stayed within the rule's bounds for its `frames` frames, the cloth falls asleep: its
//! velocities are set to zero and later frames do nothing but check that nothing changed.
//!
//! What wakes it: the pen's pinch, an edit, a pin, a new material, zones or guard
//! setting (each wakes it explicitly), and, as a check against a caller that changes the
//! scene by its public fields, anything in its [`Stillness`] print: every position and
//! velocity (to the bit), the inverse masses, the live triangle count, the environment,
//! the substeps, the material, the stitches the design handed in, the stretch floor and
//! the body. A sleeping cloth is exactly where it was when it fell asleep: sleep never
//! moves a vertex, so it cannot cross anything.

use glam::Vec3;

use super::material::Material;
use super::model::{Environment, StretchFloor};
use super::stitch::Stitch;
use crate::collision::Body;

/// When a cloth falls asleep: for `frames` consecutive frames its free vertices strayed
/// from where they were at the start by no more than `rms_m` taken together (the root
/// mean square), and no more than a `restless` share of them by over `far_m`; and no seam
/// stitch was open, and the pen did not hold it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SleepRule {
    pub rms_m: f32,
    pub far_m: f32,
    pub restless: f32,
    pub frames: u32,
}

impl Default for SleepRule {
    /// A quarter of a millimetre together, and 2 mm for all but one vertex in a hundred,
    /// in one second at 60 frames a second. A drape that still slides moves centimetres a
    /// second. A settled one still trembles: the 64 x 64 scenes' cloths, at rest, moved
    /// 0.13-0.18 mm (root mean square) in a second, and a few vertices at their contacts
    /// slipped 2-3 mm and back (docs/models.md, "A cloth at rest sleeps"). A flap still
    /// swinging fails the mean: 1% of the vertices 2.5 mm out is already a quarter of a
    /// millimetre.
    fn default() -> Self {
        Self {
            rms_m: 2.5e-4,
            far_m: 2e-3,
            restless: 1e-2,
            frames: 60,
        }
    }
}

/// What a sleeping cloth must find unchanged to go on sleeping.
#[derive(Clone, Debug, PartialEq)]
pub struct Stillness {
    x: Vec<Vec3>,
    inv_mass: Vec<f32>,
    triangles: usize,
    env: Environment,
    substeps: usize,
    material: Material,
    stitches: Vec<Stitch>,
    stretch_floor: [u32; 5],
    /// The body's name, vertex count and the address of its vertices (a body replaced
    /// or reloaded has another).
    body: Option<(String, usize, usize)>,
}

/// The scene as sleep sees it.
pub struct Scene<'a> {
    pub x: &'a [Vec3],
    pub v: &'a [Vec3],
    pub inv_mass: &'a [f32],
    pub triangles: usize,
    pub env: &'a Environment,
    pub substeps: usize,
    pub material: &'a Material,
    pub stitches: &'a [Stitch],
    pub stretch_floor: StretchFloor,
    pub body: Option<&'a Body>,
    /// The pen holds the cloth.
    pub pinched: bool,
}

fn body_print(body: Option<&Body>) -> Option<(String, usize, usize)> {
    body.map(|b| {
        (
            b.name.clone(),
            b.vertices.len(),
            b.vertices.as_ptr() as usize,
        )
    })
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(p, q)| p.to_bits() == q.to_bits())
}

impl Scene<'_> {
    /// What must stay as it is for the cloth to go on sleeping.
    pub fn print(&self) -> Stillness {
        Stillness {
            x: self.x.to_vec(),
            inv_mass: self.inv_mass.to_vec(),
            triangles: self.triangles,
            env: *self.env,
            substeps: self.substeps,
            material: *self.material,
            stitches: self.stitches.to_vec(),
            stretch_floor: self.stretch_floor.bits(),
            body: body_print(self.body),
        }
    }

    /// Whether the scene is what `s` recorded, with every velocity zero and no pinch.
    fn is(&self, s: &Stillness) -> bool {
        let bits = |p: &Vec3| p.to_array().map(f32::to_bits);
        !self.pinched
            && self.v.iter().all(|v| *v == Vec3::ZERO)
            && self.x.len() == s.x.len()
            && self.x.iter().zip(&s.x).all(|(p, q)| bits(p) == bits(q))
            && same_bits(self.inv_mass, &s.inv_mass)
            && self.triangles == s.triangles
            && *self.env == s.env
            && self.substeps == s.substeps
            && *self.material == s.material
            && self.stitches == s.stitches.as_slice()
            && self.stretch_floor.bits() == s.stretch_floor
            && body_print(self.body) == s.body
    }
}

/// The watch over a cloth's motion, and its sleep.
#[derive(Clone, Debug, Default)]
pub struct Rest {
    /// Where the vertices were when the watch began.
    anchor: Vec<Vec3>,
    /// Frames since then in which the vertices stayed within the rule's bounds.
    still: u32,
    asleep: Option<Stillness>,
    /// Frames slept since the simulation began.
    pub frames_asleep: u64,
    /// What a frame slept through reports: the contacts and queries of the frame it fell
    /// asleep in.
    pub last: (usize, usize),
}

impl Rest {
    pub fn asleep(&self) -> bool {
        self.asleep.is_some()
    }

    /// Wakes the cloth (if it slept) and starts the watch again.
    pub fn wake(&mut self) {
        self.asleep = None;
        self.anchor.clear();
        self.still = 0;
    }

    /// Before a frame: whether the cloth sleeps and its scene is as it fell asleep.
    /// [`Rest::slept`] or [`Rest::wake`] follows.
    pub fn still_asleep(&self, scene: &Scene<'_>) -> bool {
        self.asleep.as_ref().is_some_and(|s| scene.is(s))
    }

    /// Counts a frame slept through.
    pub fn slept(&mut self) {
        self.frames_asleep += 1;
    }

    /// After a simulated frame: watches the free vertices (those with `inv_mass` > 0);
    /// whether they have now been still long enough to sleep (then the caller zeroes the
    /// velocities and hands the scene to [`Rest::fall_asleep`]). Never while `held` (the
    /// pen pinches, or a seam stitch is open).
    pub fn watch(&mut self, rule: &SleepRule, x: &[Vec3], inv_mass: &[f32], held: bool) -> bool {
        if held || self.anchor.len() != x.len() {
            self.anchor.clear();
            self.anchor.extend_from_slice(x);
            self.still = 0;
            return false;
        }
        let far = rule.far_m * rule.far_m;
        let (mut free, mut sum, mut restless) = (0usize, 0.0f64, 0usize);
        for ((p, a), &w) in x.iter().zip(&self.anchor).zip(inv_mass) {
            if w > 0.0 {
                let d = p.distance_squared(*a);
                free += 1;
                sum += d as f64;
                // A NaN (a position gone bad) counts as moved.
                restless += usize::from(d > far || d.is_nan());
            }
        }
        let rms = (sum / free.max(1) as f64).sqrt();
        let allowed = (free as f64 * rule.restless as f64).floor() as usize;
        if rms > rule.rms_m as f64 || rms.is_nan() || restless > allowed {
            self.anchor.copy_from_slice(x);
            self.still = 0;
            return false;
        }
        self.still += 1;
        self.still >= rule.frames.max(1)
    }

    /// Puts the cloth to sleep as [`Scene::print`] recorded it (its velocities zero).
    pub fn fall_asleep(&mut self, print: Stillness) {
        self.asleep = Some(print);
    }
}

#[cfg(test)]
mod tests {
    // Test helpers: a failed unwrap is a failed test, with its location.
    #![allow(clippy::unwrap_used)]

    use glam::Vec3;

    use super::SleepRule;
    use crate::mesh::ClothMesh;
    use crate::solver::{Cloth, Environment, Material, ModelKind, Pinch, Simulation, Stitch};

    /// A 0.3 m, 12 x 12 cloth dropped from 1 cm onto the floor (xpbd with its guard), set
    /// to sleep by `rule`.
    fn on_the_floor(rule: Option<SleepRule>) -> Simulation {
        let material = Material::default();
        let mesh = ClothMesh::grid(0.3, 0.3, 12, 12, 0.01).unwrap();
        let cloth = Cloth::new(mesh, &material).unwrap();
        let env = Environment::default();
        let mut sim = Simulation::new(cloth, None, ModelKind::Xpbd, material, env, None).unwrap();
        sim.sleep = rule;
        sim
    }

    /// Steps until the cloth sleeps; the frame it fell asleep in.
    fn until_asleep(sim: &mut Simulation, most: usize) -> usize {
        for f in 0..most {
            sim.step().unwrap();
            if sim.asleep() {
                return f;
            }
        }
        panic!("not asleep after {most} frames");
    }

    fn bits(x: &[Vec3]) -> Vec<[u32; 3]> {
        x.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
    }

    #[test]
    fn a_cloth_at_rest_sleeps_exactly_where_it_lay_and_costs_nothing_to_step() {
        let mut sim = on_the_floor(Some(SleepRule::default()));
        // The fall takes frames, and the rule a second of stillness after it.
        let fell = until_asleep(&mut sim, 600);
        assert!(
            fell >= 60,
            "asleep at frame {fell}, before any second of rest"
        );
        assert!(sim.cloth.v.iter().all(|v| *v == Vec3::ZERO));
        let x = bits(&sim.cloth.x);
        for _ in 0..30 {
            let stats = sim.step().unwrap();
            assert!(stats.asleep);
        }
        assert_eq!(bits(&sim.cloth.x), x, "a sleeping cloth moved");
        assert_eq!(sim.frames_asleep(), 30);
        // It lies on the floor: what fell asleep had landed.
        assert!(sim.cloth.x.iter().all(|p| p.y < 2e-3), "asleep in the air");
    }

    #[test]
    fn without_a_rule_a_cloth_at_rest_is_stepped_every_frame() {
        let mut sim = on_the_floor(None);
        for _ in 0..400 {
            assert!(!sim.step().unwrap().asleep);
        }
        assert_eq!(sim.frames_asleep(), 0);
    }

    #[test]
    fn a_falling_cloth_never_sleeps() {
        let mut sim = on_the_floor(Some(SleepRule::default()));
        sim.env.floor = None;
        for _ in 0..150 {
            sim.step().unwrap();
            assert!(!sim.asleep());
        }
    }

    #[test]
    fn the_pen_a_changed_scene_or_a_moved_vertex_wakes_it() {
        let mut sim = on_the_floor(Some(SleepRule::default()));
        until_asleep(&mut sim, 600);
        // The pinch lifts the vertex it holds.
        let v = 6 * 13 + 6;
        let target = sim.cloth.x[v] + Vec3::new(0.0, 0.05, 0.0);
        sim.set_pinch(Some(Pinch {
            vertex: v as u32,
            held: vec![(v as u32, Vec3::ZERO)],
            target,
            stiffness: 100.0,
            force_limit: None,
        }));
        assert!(!sim.asleep());
        for _ in 0..5 {
            assert!(!sim.step().unwrap().asleep);
        }
        assert!(sim.cloth.x[v].y > 5e-3, "the pinch did not lift the cloth");
        // Held, it never sleeps; let go, it falls back and sleeps again.
        for _ in 0..200 {
            sim.step().unwrap();
            assert!(!sim.asleep(), "asleep in the pen's hold");
        }
        sim.set_pinch(None);
        until_asleep(&mut sim, 600);
        // Gravity changed through the public field.
        sim.env.gravity = Vec3::new(2.0, -9.81, 0.0);
        assert!(!sim.step().unwrap().asleep);
        until_asleep(&mut sim, 900);
        // A vertex moved by hand.
        sim.cloth.x[v].y += 0.02;
        assert!(!sim.step().unwrap().asleep);
        assert!(
            sim.cloth.x[v].y < 0.02,
            "the moved vertex was not simulated"
        );
    }

    #[test]
    fn an_open_seam_stitch_keeps_the_cloth_awake() {
        let mut sim = on_the_floor(Some(SleepRule::default()));
        // Too weak to pull its two corners together against the floor's friction.
        sim.stitches = vec![Stitch {
            a: 0,
            b: 12,
            max_force: 1e-6,
        }];
        for _ in 0..400 {
            sim.step().unwrap();
            assert!(!sim.asleep());
        }
        sim.stitches.clear();
        until_asleep(&mut sim, 600);
    }
}
