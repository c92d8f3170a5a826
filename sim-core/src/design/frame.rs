//! A design's frame: its seams' stitches handed to the solver, one simulation frame, then
//! what the frame did to the design as edits (tears of overstretched edges, welds of
//! stitches that closed).

use std::time::Instant;

use glam::Vec3;

use super::document::Design;
use super::parts::open_stitches;
use crate::solver::{FrameStats, Hold, PenPath, StepError};

/// How long a garment's pieces float while their seams pull, frames (1 s): long enough
/// for GarmentCode's shirt to close all 346 of its stitched pairs before it falls onto the
/// shoulders (docs/garments.md, "Sewn in the air"). GarmentCode's own simulator starts
/// its drapes the same way, with gravity off for its first steps.
pub const AFLOAT_FRAMES: u32 = 60;

/// How long a garment's holds last, frames (6.7 s): GarmentCode's simulator attaches its
/// garments' labelled edges for its first 400 frames of 1/60 s.
pub const HOLD_FRAMES: u32 = 400;

impl Design {
    /// Lets the cloth float, without gravity, for the next [`AFLOAT_FRAMES`] frames or
    /// until every seam has closed, whichever comes first: a garment's pieces, placed
    /// round the body, are sewn together before they fall onto it, so that a seam is not
    /// left to close over a shoulder that friction holds it on. Meanwhile a seam's end
    /// pairs wait for the pair beside them ([`ENDS_WAIT_FROM`](super::ENDS_WAIT_FROM)).
    pub fn float_while_sewing(&mut self) {
        self.afloat = AFLOAT_FRAMES;
        self.afloat_damping = 0.0;
    }

    /// [`Design::float_while_sewing`], the cloth's motion dying away at `rate` per second
    /// while it floats (its velocities scaled by `exp(-rate dt)` each frame; a rate that
    /// is not a positive number is none). The stitches then draw the pieces together
    /// without the whiplash that, on fine meshes, folds a seam's end under the other
    /// piece: at 30 1/s the 5k and the 2 x 8k dress weld every pair and come to rest,
    /// where sewn as it falls the 2 x 8k dress leaves three open (docs/garments.md,
    /// "Every pair of both dresses welded, at rest").
    pub fn float_while_sewing_damped(&mut self, rate: f32) {
        self.float_while_sewing();
        self.afloat_damping = if rate.is_finite() { rate.max(0.0) } else { 0.0 };
    }

    /// Holds `holds` for the next [`HOLD_FRAMES`] frames (replacing any held before):
    /// a garment's waistband kept from falling below the body's waist while the garment
    /// settles, so that it does not slide down the body before friction takes it. A
    /// vertex a weld merges away hands its hold to the vertex it merged into.
    pub fn hold_while_draping(&mut self, holds: Vec<Hold>) {
        self.hold_frames = if holds.is_empty() { 0 } else { HOLD_FRAMES };
        self.holds = holds;
    }

    /// After a weld merged `from` into `to`: `from`'s hold becomes `to`'s (unless `to`
    /// is held already).
    pub(super) fn hand_hold(&mut self, from: u32, to: u32) {
        if self.holds.iter().any(|h| h.vertex == to) {
            self.holds.retain(|h| h.vertex != from);
        } else if let Some(h) = self.holds.iter_mut().find(|h| h.vertex == from) {
            h.vertex = to;
        }
    }

    /// The vertices held now, and for how many more frames.
    pub fn held(&self) -> (&[Hold], u32) {
        if self.hold_frames == 0 {
            (&[], 0)
        } else {
            (&self.holds, self.hold_frames)
        }
    }

    /// Whether the cloth floats this frame (see [`Design::float_while_sewing`]).
    pub fn afloat(&self) -> bool {
        self.afloat > 0 && self.seams.iter().any(|s| s.open_pairs().next().is_some())
    }

    /// Steps one frame. On divergence the error says so; the state is then not usable.
    pub fn step(&mut self) -> Result<FrameStats, StepError> {
        self.step_with(&mut |_| None)
    }

    /// Steps one frame, telling `pen` before each substep where the frame is and asking
    /// it where the pinch's pointer is and how hard it may pull (`None`: unchanged; see
    /// [`Simulation::step_with`](crate::solver::Simulation::step_with)); then tears what
    /// is overstretched (when tearing is on) and welds stitches that closed, each as an
    /// undoable edit.
    pub fn step_with(&mut self, pen: &mut PenPath<'_>) -> Result<FrameStats, StepError> {
        let t0 = Instant::now();
        self.sim.stitches.clear();
        let afloat = self.afloat();
        // A garment sewn in the air sews its seams' ends last (`ENDS_WAIT_FROM`).
        let ends_wait = afloat;
        self.sim
            .stitches
            .extend(open_stitches(&self.seams, ends_wait));
        self.watch_stalls();
        self.sim.stitches_stalled = self.stitches_stalled();
        self.sim.stretch_floor = self.tear_floor();
        self.sim.holds.clear();
        if self.hold_frames > 0 {
            self.hold_frames -= 1;
            // A vertex no longer in the cloth (its piece deleted) is not held.
            let live = &self.sim.cloth.live;
            (self.sim.holds).extend(self.holds.iter().filter(|h| live.vertex_alive(h.vertex)));
        }
        self.afloat = if afloat { self.afloat - 1 } else { 0 };
        let gravity = self.sim.env.gravity;
        if afloat {
            self.sim.env.gravity = Vec3::ZERO;
        }
        let stepped = self.sim.step_with(pen);
        self.sim.env.gravity = gravity;
        if afloat && self.afloat_damping > 0.0 {
            // Velocities only: nothing moves, so nothing can cross.
            let keep = (-self.afloat_damping * self.sim.env.frame_dt).exp();
            self.sim.cloth.v.iter_mut().for_each(|v| *v *= keep);
        }
        let mut stats = stepped?;
        stats.torn = self.tear_overstretched();
        stats.welded = self.weld_close_stitches();
        stats.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        Ok(stats)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// A 0.5 m cloth of 8 x 8 cells at y = 1 under gravity, nothing under it, its first
    /// row sewn to its last (0.5 m apart: a tube to close).
    fn tube() -> Design {
        tube_of(ModelKind::Xpbd)
    }

    fn tube_of(model: ModelKind) -> Design {
        let n = 8u32;
        let mesh = ClothMesh::grid(0.5, 0.5, n as usize, n as usize, 1.0).unwrap();
        let mut d = crate::design::floating(mesh, model);
        d.sim.env.gravity = Vec3::new(0.0, -9.81, 0.0);
        let a: Vec<u32> = (0..=n).collect();
        let b: Vec<u32> = (0..=n).map(|i| n * (n + 1) + i).collect();
        d.add_seam(&a, &b, 0.05).unwrap();
        d
    }

    fn mean_y(d: &Design) -> f32 {
        d.sim.cloth.x.iter().map(|p| p.y).sum::<f32>() / d.sim.cloth.x.len() as f32
    }

    /// Damped while it floats, the tube's stitches draw it together more slowly (its
    /// fastest vertex slower at every frame), and once it falls the damping is gone: it
    /// falls as fast as an undamped cloth. A rate that is no positive number is none.
    #[test]
    fn a_garment_sewn_in_the_air_damped_moves_slower_only_while_it_floats() {
        let fastest = |d: &Design| d.sim.cloth.v.iter().map(|v| v.length()).fold(0.0, f32::max);
        let (mut free, mut damped) = (tube(), tube());
        free.float_while_sewing();
        damped.float_while_sewing_damped(30.0);
        for f in 0..8 {
            free.step().unwrap();
            damped.step().unwrap();
            let (a, b) = (fastest(&free), fastest(&damped));
            assert!(b < a, "frame {f}: damped {b} m/s, undamped {a}");
        }
        for _ in 8..AFLOAT_FRAMES {
            damped.step().unwrap();
        }
        assert!(!damped.afloat());
        let v0 = damped.sim.cloth.v.iter().map(|v| v.y).sum::<f32>();
        damped.step().unwrap();
        let v1 = damped.sim.cloth.v.iter().map(|v| v.y).sum::<f32>();
        let n = damped.sim.cloth.len() as f32;
        // Gravity's 9.81 / 60 m/s in the frame, undamped (the material's own 0.6 1/s aside).
        assert!((v0 - v1) / n > 0.15, "{} m/s gained", (v0 - v1) / n);
        for bad in [f32::NAN, -1.0, f32::INFINITY] {
            let mut d = tube();
            d.float_while_sewing_damped(bad);
            assert_eq!(d.afloat_damping, 0.0, "{bad}");
        }
    }

    /// Afloat, damped or not, the tube's seam (9 pairs) pulls all but its two end pairs
    /// until the pair beside an end welds; falling, every pair pulls; once the float is
    /// over, every open pair pulls.
    #[test]
    fn a_seams_ends_wait_while_the_garment_floats() {
        let pulled = |d: &mut Design| {
            d.step().unwrap();
            d.sim.stitches.len()
        };
        let mut d = tube();
        assert_eq!(pulled(&mut d), 9, "falling");
        for damped in [false, true] {
            let mut d = tube();
            if damped {
                d.float_while_sewing_damped(30.0);
            } else {
                d.float_while_sewing();
            }
            assert_eq!(pulled(&mut d), 7, "afloat, damped {damped}");
            let (a, b) = d.seams[0].pairs[0];
            assert!(!d.sim.stitches.iter().any(|s| (s.a, s.b) == (a, b)));
            while d.afloat() {
                d.step().unwrap();
            }
            let open = d.seams[0].open_pairs().count();
            assert_eq!(pulled(&mut d), open, "the float over, damped {damped}");
        }
    }

    #[test]
    fn a_garment_floats_while_its_seams_pull_then_falls() {
        let mut falling = tube();
        let y0 = mean_y(&falling);
        falling.step().unwrap();
        // Gravity: 0.5 g t^2 is 1.4 mm in a frame.
        assert!(mean_y(&falling) < y0 - 1e-3, "{}", y0 - mean_y(&falling));

        let mut d = tube();
        let g = d.sim.env.gravity;
        d.float_while_sewing();
        assert!(d.afloat());
        for _ in 0..10 {
            d.step().unwrap();
        }
        // The stitches pull across, nothing pulls down; gravity is back between frames.
        assert!((mean_y(&d) - y0).abs() < 1e-4, "{}", mean_y(&d) - y0);
        assert_eq!(d.sim.env.gravity, g);
        assert!(d.seams[0].open_pairs().next().is_some(), "closed already");
        for _ in 10..AFLOAT_FRAMES {
            d.step().unwrap();
        }
        // At most AFLOAT_FRAMES frames, then it falls.
        assert!(!d.afloat());
        let y1 = mean_y(&d);
        d.step().unwrap();
        assert!(mean_y(&d) < y1 - 5e-4, "{}", y1 - mean_y(&d));
    }

    /// The tube's cloth unsewn, under `model`, its first row held at or above its own
    /// level, 1 m, each vertex with up to 0.2 N: 9 x 0.05 N would carry the cloth's 0.37 N
    /// as forces, but under xpbd the cloth's constraints, solved after the holds, take
    /// part of each pull back (it sagged 4 cm in half a second).
    fn held_tube(model: ModelKind) -> Design {
        let mut d = tube_of(model);
        d.seams.clear();
        let holds = (0..=8)
            .map(|vertex| Hold {
                vertex,
                normal: Vec3::Y,
                level: 1.0,
                max_force: 0.2,
            })
            .collect();
        d.hold_while_draping(holds);
        d
    }

    #[test]
    fn a_held_waistband_stays_at_its_level_until_the_hold_ends() {
        // The held row's lowest and highest vertex.
        let low = |d: &Design| (0..=8).map(|i| d.sim.cloth.x[i].y).fold(f32::MAX, f32::min);
        let high = |d: &Design| (0..=8).map(|i| d.sim.cloth.x[i].y).fold(f32::MIN, f32::max);
        // The vbd model holds it too: the hanging cloth keeps it on the plane, not below.
        let mut d = held_tube(ModelKind::Vbd);
        for _ in 0..30 {
            d.step().unwrap();
        }
        assert!(
            low(&d) > 0.995 && high(&d) < 1.01,
            "vbd: {} {}",
            low(&d),
            high(&d)
        );
        let mut d = held_tube(ModelKind::Xpbd);
        let mut free = tube();
        free.seams.clear();
        for _ in 0..30 {
            d.step().unwrap();
            free.step().unwrap();
        }
        // Half a second: the free cloth fell 0.7 m, the held row stayed (within 5 mm:
        // the holds are springs).
        assert!(high(&free) < 0.5, "{}", high(&free));
        assert!(
            low(&d) > 0.995 && high(&d) < 1.01,
            "{} {}",
            low(&d),
            high(&d)
        );
        assert_eq!(d.held(), (&d.holds[..], HOLD_FRAMES - 30));
        assert_eq!(d.sim.holds.len(), 9);
        // The hold ends: it falls.
        d.hold_frames = 1;
        d.step().unwrap();
        assert_eq!(d.held().1, 0);
        assert!(d.held().0.is_empty());
        let y = high(&d);
        for _ in 0..10 {
            d.step().unwrap();
        }
        assert!(d.sim.holds.is_empty());
        assert!(high(&d) < y - 0.02, "{} {}", y, high(&d));
    }

    #[test]
    fn a_weld_hands_a_hold_to_the_vertex_it_keeps() {
        let mut d = held_tube(ModelKind::Xpbd);
        d.hand_hold(3, 40);
        assert!(d.holds.iter().any(|h| h.vertex == 40));
        assert!(!d.holds.iter().any(|h| h.vertex == 3));
        // Onto one held already: one hold, not two.
        d.hand_hold(4, 5);
        assert_eq!(d.holds.iter().filter(|h| h.vertex == 5).count(), 1);
        assert!(!d.holds.iter().any(|h| h.vertex == 4));
        assert_eq!(d.holds.len(), 8);
        // An empty list holds nothing, for no frames.
        d.hold_while_draping(Vec::new());
        assert_eq!(d.held().1, 0);
    }

    #[test]
    fn a_garment_whose_seams_have_all_closed_no_longer_floats() {
        let mut d = tube();
        d.float_while_sewing();
        for s in &mut d.seams {
            for p in &mut s.pairs {
                p.1 = p.0;
            }
        }
        assert!(!d.afloat());
        let y0 = mean_y(&d);
        d.step().unwrap();
        assert!(mean_y(&d) < y0 - 1e-3);
    }
}
