//! Contact as energy, seen from one vertex: each pair that carries energy
//! ([`crate::collision::proximity`]) pushes with a penalty `k (r - gap)` along its
//! direction while the gap is under the contact distance `r`, with Coulomb friction on
//! the pair's sliding over the step (IPC's smoothed static-to-kinetic friction, Li et
//! al. 2020, with the normal force of the current iterate).

use glam::{Mat3, Vec3};

use crate::collision::proximity::{NONE, Proximity};

/// Penalty stiffness of a contact, N/m: a cloth's whole weight resting on a few dozen
/// vertices presses each well under a tenth of a millimetre in.
pub const CONTACT_STIFFNESS: f32 = 1000.0;

/// Sliding below this over a step is static friction (the smoothing of IPC's `f1`), m.
const STICK: f32 = 1e-5;

/// The contact's settings for a step.
#[derive(Clone, Copy, Debug)]
pub struct ContactTerms {
    pub radius: f32,
    pub stiffness: f32,
    pub friction: f32,
}

impl ContactTerms {
    /// Adds vertex `i`'s contact force and Hessian block from its pairs, at `x`, with
    /// `xt` the step's start (friction opposes the sliding since then).
    #[inline]
    pub fn add_vertex(
        &self,
        i: usize,
        prox: &Proximity,
        x: &[Vec3],
        xt: &[Vec3],
        f: &mut Vec3,
        hess: &mut Mat3,
    ) {
        for &r in prox.roles(i) {
            let pair = &prox.pairs[(r / 4) as usize];
            if !pair.energy {
                continue;
            }
            let k = (r % 4) as usize;
            let gap = pair.gap(x);
            if gap >= self.radius {
                continue;
            }
            let n = pair.n;
            let wk = pair.w[k];
            let lambda = self.stiffness * (self.radius - gap);
            *f += n * (lambda * wk);
            let nn = Mat3::from_cols(n * n.x, n * n.y, n * n.z);
            *hess += nn * (self.stiffness * wk * wk);
            if self.friction > 0.0 {
                let mut u = Vec3::ZERO;
                for j in 0..4 {
                    if pair.v[j] != NONE {
                        let v = pair.v[j] as usize;
                        u += (x[v] - xt[v]) * pair.w[j];
                    }
                }
                let ut = u - n * n.dot(u);
                let len = ut.length();
                // f1(y) / y of IPC: 2/e - y/e^2 below e, 1/y above.
                let phi = if len < STICK {
                    2.0 / STICK - len / (STICK * STICK)
                } else {
                    1.0 / len
                };
                let mu = self.friction * lambda * phi;
                *f -= ut * (mu * wk);
                *hess += (Mat3::IDENTITY - nn) * (mu * wk * wk);
            }
        }
    }
}
