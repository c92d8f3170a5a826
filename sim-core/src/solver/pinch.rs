//! The pen's hold on the cloth: the pinch, zero-length XPBD springs from the held vertices
//! to the pointer, pulling no harder than a force limit (the force the haptic loop
//! rendered, so the cloth is pulled no harder than the user's hand is pulled back).
//!
//! Which vertices to hold is the design's choice (`design::pinch`); this is the spring.

use glam::Vec3;

use super::state::Cloth;
use crate::collision::Body;

/// The pinch: the pointer holds the vertex nearest to it (the paper's pinch) and, with a
/// grip radius, the vertices around it too, each by a spring to the pointer plus its
/// offset at the moment of grabbing. The springs share the stiffness.
#[derive(Clone, Debug, PartialEq)]
pub struct Pinch {
    /// The vertex nearest to the pointer when grabbed.
    pub vertex: u32,
    /// Held vertices and their offsets from the pointer.
    pub held: Vec<(u32, Vec3)>,
    pub target: Vec3,
    /// Total stiffness of the springs, N/m.
    pub stiffness: f32,
    /// Most force the springs together may put on the cloth in a substep, N (None: no
    /// limit). cloth-sim sets it from the force the haptic loop rendered, so the cloth
    /// is pulled no harder than the user's hand is pulled back.
    pub force_limit: Option<f32>,
}

/// The pen during one substep: where the pinch's pointer end is, and the most force the
/// pinch may exert (see [`Pinch::force_limit`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenInput {
    pub target: Vec3,
    pub force_limit: Option<f32>,
}

/// The pinched vertex before a substep: where it is and how fast it moves, as the
/// substeps before it left it. A caller can report the pinch from it at substep rate:
/// cloth-sim sends the haptic loop its local model from it, so a frame slower than the
/// loop's 20 ms staleness limit (a 16k-vertex cloth under the guard) still feeds the pen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Held {
    pub position: Vec3,
    pub velocity: Vec3,
}

/// The frame before one of its substeps, as a [`PenPath`] is told it.
#[derive(Clone, Copy, Debug)]
pub struct Between<'a> {
    /// This substep (from 0) and the frame's count.
    pub substep: usize,
    pub substeps: usize,
    /// The pinched vertex now; `None` while the pen pinches nothing.
    pub held: Option<Held>,
    /// The cloth as the substeps before this one left it (positions, velocities, mesh).
    pub cloth: &'a Cloth,
    /// The body.
    pub body: Option<&'a Body>,
    /// Told while the frame is busy before this substep (a long contact search, on
    /// another thread): nothing has moved since the last telling, and the answer is not
    /// taken. A caller may report from it (the pen's model) all the same.
    pub heartbeat: bool,
}

/// Asked before every substep of a frame where the pen is: `None` for unchanged, and
/// taken only while pinching. A caller may also report from it at substep rate:
/// cloth-sim keeps the haptic loop's model fresh through a frame slower than the loop's
/// 20 ms staleness limit (the pinched vertex, or the cloth the pen may touch).
pub type PenPath<'a> = dyn FnMut(&Between<'_>) -> Option<PenInput> + 'a;

/// The pinch while it lasts, and what it pulled with in the last frame.
#[derive(Clone, Debug, Default)]
pub struct Grip {
    pub pinch: Option<Pinch>,
    /// The pinch force on the cloth in each substep of the last frame, N.
    pub forces: Vec<Vec3>,
    /// Substeps of the last frame whose pinch was scaled down to its force limit.
    pub limited: usize,
}

impl Grip {
    /// Forgets the last frame's forces.
    pub fn begin_frame(&mut self) {
        self.forces.clear();
        self.limited = 0;
    }

    /// The pinched vertex in `cloth` now (`None` while nothing is pinched).
    fn held(&self, cloth: &Cloth) -> Option<Held> {
        let i = self.pinch.as_ref()?.vertex as usize;
        let (&position, &velocity) = cloth.x.get(i).zip(cloth.v.get(i))?;
        Some(Held { position, velocity })
    }

    /// Before substep `k` of `n`: tells `pen` where the frame is, and while pinching
    /// moves the pointer end to where the pen is.
    pub fn follow(
        &mut self,
        k: usize,
        n: usize,
        pen: &mut PenPath<'_>,
        cloth: &Cloth,
        body: Option<&Body>,
    ) {
        let held = self.held(cloth);
        let between = Between {
            substep: k,
            substeps: n,
            held,
            cloth,
            body,
            heartbeat: false,
        };
        let input = pen(&between);
        let Some(p) = &mut self.pinch else { return };
        if let Some(input) = input
            && input.target.is_finite()
        {
            p.target = input.target;
            p.force_limit = input
                .force_limit
                .filter(|f| f.is_finite())
                .map(|f| f.max(0.0));
        }
    }

    /// While substep `k` of `n` waits for a long contact search: tells `pen` so
    /// ([`Between::heartbeat`]), the pinched vertex where it is.
    pub fn heartbeat(
        &self,
        (k, n): (usize, usize),
        pen: &mut PenPath<'_>,
        cloth: &Cloth,
        body: Option<&Body>,
    ) {
        let held = self.held(cloth);
        let _ = pen(&Between {
            substep: k,
            substeps: n,
            held,
            cloth,
            body,
            heartbeat: true,
        });
    }

    /// The springs' pass of one substep (`inv_h2` = 1 / h^2), recording their force.
    pub fn pull(&mut self, x: &mut [Vec3], inv_mass: &[f32], inv_h2: f32) {
        let Some(p) = &self.pinch else { return };
        // Zero-length XPBD springs to the pointer: compliance 1 / stiffness each.
        // Their corrections are found first, then applied scaled down together if
        // their force would exceed the limit.
        let k = p.stiffness / p.held.len().max(1) as f32;
        let alpha = inv_h2 / k;
        let correction = |i: usize, offset: Vec3, x: &[Vec3]| {
            let w = *inv_mass.get(i)?;
            let x = *x.get(i)?;
            (w > 0.0).then(|| ((p.target + offset - x) * (w / (w + alpha)), w))
        };
        let mut force = Vec3::ZERO;
        for &(v, offset) in &p.held {
            if let Some((dx, w)) = correction(v as usize, offset, x) {
                force += dx * (inv_h2 / w);
            }
        }
        let scale = match p.force_limit {
            Some(limit) if force.length() > limit => {
                self.limited += 1;
                limit / force.length()
            }
            _ => 1.0,
        };
        // Held vertices are distinct, so each correction is the one summed above.
        for &(v, offset) in &p.held {
            if let Some((dx, _)) = correction(v as usize, offset, x) {
                x[v as usize] += dx * scale;
            }
        }
        self.forces.push(force * scale);
    }
}

/// Runs `work` on a thread of its own while this one calls `beat` every `every`, until
/// the work is done (a panic in it is this thread's): a contact search of hundreds of
/// milliseconds on a 16k-vertex cloth then still lets the pen hear from the frame.
pub fn beating<R: Send>(
    work: impl FnOnce() -> R + Send,
    mut beat: impl FnMut(),
    every: std::time::Duration,
) -> R {
    use std::sync::mpsc::{RecvTimeoutError, channel};
    std::thread::scope(|s| {
        let (done, finished) = channel();
        let worker = s.spawn(move || {
            let r = work();
            // The receiver outlives the scope's threads: the send cannot fail.
            let _ = done.send(());
            r
        });
        while let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(every) {
            beat();
        }
        worker
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e))
    })
}
