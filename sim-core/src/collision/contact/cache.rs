//! Cloth-body contact. Once per frame, each particle's nearest body point within the
//! distance it can travel this frame is found (by a walk over the body's surface from
//! last frame's triangle when it can prove the answer, [`crate::collision::obb::SurfaceWalk`],
//! otherwise by the OBB tree); that contact is cached as a plane
//! (point + outward normal). Every substep re-projects particles onto their cached planes
//! and applies Coulomb friction (Macklin et al. 2019 "Small Steps": broad phase once per
//! frame, narrow phase per substep).
//!
//! No tunnelling: a particle that could reach the body this frame has a plane, and the
//! plane is enforced every substep, so it cannot step through a surface thicker than one
//! substep's travel (at 2 m/s and 10 substeps of a 60 Hz frame: 3.3 mm).
//!
//! A particle whose last query found nothing within `R` is skipped while it stays farther
//! than its travel bound from the body: `R - |x - x_query| > reach` proves it (the distance
//! to a fixed surface is 1-Lipschitz). Before a search, the body's clearance grid may
//! prove the same ([`Body::outside_by`]); most of a falling cloth is skipped that way.
//!
//! At frame end, particles that moved past their known clearance are searched again (the
//! safety net for concave corners), and that search is kept as their next frame's, so no
//! particle is searched twice between two frames.

use glam::Vec3;

use super::broad::{NEIGHBOUR_BLOCK, Reach, Slots, resolve_range, update_range};
use crate::collision::body::Body;

/// Contact settings.
#[derive(Clone, Copy, Debug)]
pub struct ContactParams {
    pub thickness: f32,
    pub friction: f32,
    /// Height of the floor plane (`y = floor`), if any.
    pub floor: Option<f32>,
}

/// Per-particle contact planes for the current frame.
#[derive(Clone, Debug, Default)]
pub struct ContactCache {
    /// Outward normal of the contact plane, zero when the particle has no contact.
    normal: Vec<Vec3>,
    /// Plane offset: the constraint is `x . normal >= offset + thickness`.
    offset: Vec<f32>,
    /// Last frame's nearest triangle (search hint), `u32::MAX` for none.
    pub(super) hint: Vec<u32>,
    /// Where the particle was at its last query and how far the surface was known to be.
    query_pos: Vec<Vec3>,
    clear: Vec<f32>,
    /// The cached plane is the hint triangle's face plane (valid while within reuse range).
    on_face: Vec<bool>,
    /// Particles with an active plane this frame.
    active: Vec<u32>,
    /// Whether any particle can reach the floor this frame.
    floor_near: bool,
    /// Threads for the broad phase (1 or 2); the result does not depend on it.
    pub threads: usize,
    spare_active: Vec<u32>,
    /// Queries run in the last update (for reports).
    pub last_queries: usize,
}

impl ContactCache {
    pub fn new(n: usize) -> Self {
        Self {
            normal: vec![Vec3::ZERO; n],
            offset: vec![0.0; n],
            hint: vec![u32::MAX; n],
            query_pos: vec![Vec3::splat(f32::INFINITY); n],
            clear: vec![0.0; n],
            on_face: vec![false; n],
            active: Vec::with_capacity(n),
            floor_near: true,
            threads: 1,
            spare_active: Vec::new(),
            last_queries: 0,
        }
    }

    /// Follows the cloth's vertex count after an edit, keeping what is known about the
    /// vertices that stay; new ones are queried on the next update.
    pub fn resize(&mut self, n: usize) {
        if self.normal.len() == n {
            return;
        }
        self.normal.resize(n, Vec3::ZERO);
        self.offset.resize(n, 0.0);
        self.hint.resize(n, u32::MAX);
        self.query_pos.resize(n, Vec3::splat(f32::INFINITY));
        self.clear.resize(n, 0.0);
        self.on_face.resize(n, false);
        self.active.retain(|&i| (i as usize) < n);
    }

    pub fn active_count(&self) -> usize {
        self.active.len()
    }

    /// The frame's broad phase. `reach_time` is the frame duration; `max_accel` bounds the
    /// acceleration (gravity) over it.
    pub fn update(
        &mut self,
        body: &Body,
        x: &[Vec3],
        v: &[Vec3],
        reach_time: f32,
        max_accel: f32,
        p: &ContactParams,
    ) {
        let n = x.len();
        self.resize(n);
        self.active.clear();
        self.last_queries = 0;
        self.floor_near = p.floor.is_none_or(|floor| {
            let level = floor + p.thickness;
            x.iter().zip(v).any(|(x, v)| {
                x.y - v.length() * reach_time * 1.5
                    - 0.5 * max_accel * reach_time * reach_time
                    - 1e-3
                    < level
            })
        });
        let env = Reach {
            thickness: p.thickness,
            reach_time,
            max_accel,
        };
        let mid = self.split_point(n);
        let mut active_a = std::mem::take(&mut self.active);
        let mut active_b = std::mem::take(&mut self.spare_active);
        active_b.clear();
        let (mut first, mut second) = self.slots(mid);
        let (qa, qb) = if mid < n {
            std::thread::scope(|s| {
                let hb = s.spawn(|| {
                    update_range(
                        body,
                        &x[mid..],
                        &v[mid..],
                        &mut second,
                        mid,
                        &mut active_b,
                        &env,
                    )
                });
                let qa = update_range(
                    body,
                    &x[..mid],
                    &v[..mid],
                    &mut first,
                    0,
                    &mut active_a,
                    &env,
                );
                // A panic in the worker is a bug: re-raise it here.
                (
                    qa,
                    hb.join().unwrap_or_else(|e| std::panic::resume_unwind(e)),
                )
            })
        } else {
            (
                update_range(body, x, v, &mut first, 0, &mut active_a, &env),
                0,
            )
        };
        // Same order as one thread: the first half's particles, then the second's.
        active_a.extend_from_slice(&active_b);
        self.active = active_a;
        self.spare_active = active_b;
        self.last_queries = qa + qb;
    }

    /// Where the particle range is split between the two threads (`n`: one thread).
    fn split_point(&self, n: usize) -> usize {
        if self.threads > 1 && n >= 4096 {
            n / 2 / NEIGHBOUR_BLOCK * NEIGHBOUR_BLOCK
        } else {
            n
        }
    }

    /// The per-particle arrays as two ranges, `..mid` and `mid..`.
    fn slots(&mut self, mid: usize) -> (Slots<'_>, Slots<'_>) {
        let (n0, n1) = self.normal.split_at_mut(mid);
        let (o0, o1) = self.offset.split_at_mut(mid);
        let (h0, h1) = self.hint.split_at_mut(mid);
        let (q0, q1) = self.query_pos.split_at_mut(mid);
        let (c0, c1) = self.clear.split_at_mut(mid);
        let (f0, f1) = self.on_face.split_at_mut(mid);
        (
            Slots {
                normal: n0,
                offset: o0,
                hint: h0,
                query_pos: q0,
                clear: c0,
                on_face: f0,
            },
            Slots {
                normal: n1,
                offset: o1,
                hint: h1,
                query_pos: q1,
                clear: c1,
                on_face: f1,
            },
        )
    }

    /// The frame's safety net. A single cached plane per particle cannot stop a particle
    /// sliding into a concave corner (a neck above a shoulder) at speed. A particle that
    /// moved less than its clearance since its query cannot be inside (distance to the
    /// surface is 1-Lipschitz); the others are searched again, and any found inside is
    /// projected out to `thickness` with its inward velocity removed. Returns how many
    /// were moved.
    ///
    /// The search is the one the next frame's [`update`](Self::update) would run (same
    /// radius, from the velocity the frame ends with), and its answer is kept: that
    /// update then finds these particles unmoved and reuses it instead of searching
    /// again. The arguments after `inv_mass` are `update`'s.
    pub fn resolve_penetrations(
        &mut self,
        body: &Body,
        x: &mut [Vec3],
        v: &mut [Vec3],
        inv_mass: &[f32],
        reach_time: f32,
        max_accel: f32,
        p: &ContactParams,
    ) -> usize {
        let n = x.len().min(v.len()).min(inv_mass.len());
        self.resize(x.len());
        let env = Reach {
            thickness: p.thickness,
            reach_time,
            max_accel,
        };
        // Most frames nothing moved past its clearance: count first, and share the
        // searches between the threads only when there are enough to pay for one.
        let due = (0..n)
            .filter(|&i| inv_mass[i] != 0.0 && (x[i] - self.query_pos[i]).length() >= self.clear[i])
            .count();
        if due == 0 {
            return 0;
        }
        let mid = if due >= 256 { self.split_point(n) } else { n };
        let (mut first, mut second) = self.slots(mid);
        let (xa, xb) = x[..n].split_at_mut(mid);
        let (va, vb) = v[..n].split_at_mut(mid);
        let (ma, mb) = inv_mass[..n].split_at(mid);
        if mid < n {
            std::thread::scope(|s| {
                let hb = s.spawn(|| resolve_range(body, xb, vb, mb, &mut second, &env));
                let fa = resolve_range(body, xa, va, ma, &mut first, &env);
                fa + hb.join().unwrap_or_else(|e| std::panic::resume_unwind(e))
            })
        } else {
            resolve_range(body, xa, va, ma, &mut first, &env)
        }
    }

    /// How far `x` is beyond particle `i`'s contact plane of this frame and the
    /// thickness (negative: pressed in), or `None` when it has no plane.
    pub fn gap(&self, i: usize, x: Vec3, thickness: f32) -> Option<f32> {
        let n = *self.normal.get(i)?;
        (n != Vec3::ZERO).then(|| x.dot(n) - self.offset[i] - thickness)
    }

    /// Drops all cached planes (e.g. after the cloth was moved by an edit).
    pub fn reset(&mut self) {
        let (n, threads) = (self.normal.len(), self.threads);
        *self = Self::new(n);
        self.threads = threads;
    }

    /// The narrow phase of one substep: pushes particles out along their planes (and above
    /// the floor) and applies friction to the displacement `x - prev` of this substep.
    ///
    /// Penetration that was already there at the substep's start (a contact plane that
    /// moved between frames, a corner) is undone without creating velocity: `prev` moves
    /// out with `x` by that much, so `(x - prev) / h` carries no kick.
    pub fn project(&self, x: &mut [Vec3], prev: &mut [Vec3], inv_mass: &[f32], p: &ContactParams) {
        self.project_keeping(x, prev, inv_mass, p, None);
    }

    /// [`ContactCache::project`], and with `spare` (as long as `x`), each pushed particle's
    /// static friction left unused: the tangential move it could still cancel this
    /// substep, with the plane's normal ([`StaticFriction`]). Particles not pushed get 0.
    pub fn project_keeping(
        &self,
        x: &mut [Vec3],
        prev: &mut [Vec3],
        inv_mass: &[f32],
        p: &ContactParams,
        mut spare: Option<&mut StaticFriction>,
    ) {
        if let Some(s) = spare.as_deref_mut() {
            s.clear(x.len());
        }
        for &i in &self.active {
            let i = i as usize;
            if inv_mass[i] == 0.0 {
                continue;
            }
            let n = self.normal[i];
            let s = x[i].dot(n) - self.offset[i] - p.thickness;
            if s < 0.0 {
                x[i] -= n * s;
                let s0 = prev[i].dot(n) - self.offset[i] - p.thickness;
                if s0 < 0.0 {
                    prev[i] -= n * s0.max(s);
                }
                let left = friction(&mut x[i], prev[i], n, -s, p.friction);
                if let Some(sp) = spare.as_deref_mut() {
                    sp.keep(i, n, left);
                }
            }
        }
        if let Some(floor) = p.floor.filter(|_| self.floor_near) {
            let level = floor + p.thickness;
            for i in 0..x.len() {
                if x[i].y < level && inv_mass[i] > 0.0 {
                    let depth = level - x[i].y;
                    x[i].y = level;
                    if prev[i].y < level {
                        prev[i].y += (level - prev[i].y).min(depth);
                    }
                    let left = friction(&mut x[i], prev[i], Vec3::Y, depth, p.friction);
                    if let Some(sp) = spare.as_deref_mut() {
                        sp.keep(i, Vec3::Y, left);
                    }
                }
            }
        }
    }
}

/// The static friction each particle's contact left unused in a substep: Coulomb's cone
/// holds a tangential move up to `mu` times the push along the normal, and what the
/// push's own substep did not use still holds the moves made after it (the strain
/// limit's: `Xpbd::limit_and_guard`). Without it, the limit dragged the cloth lying on the
/// mannequin along its surface as if it had no friction: the 128 x 128 drape crept at up
/// to 9 cm/s and never settled (docs/models.md).
#[derive(Clone, Debug, Default)]
pub struct StaticFriction {
    left: Vec<f32>,
    normal: Vec<Vec3>,
}

impl StaticFriction {
    fn clear(&mut self, n: usize) {
        self.left.clear();
        self.left.resize(n, 0.0);
        self.normal.resize(n, Vec3::ZERO);
    }

    fn keep(&mut self, i: usize, n: Vec3, left: f32) {
        // The floor after a plane: the larger budget, along its normal.
        if left > self.left[i] {
            self.left[i] = left;
            self.normal[i] = n;
        }
    }

    /// Holds back the tangential part of particle `i`'s move from `from` to `x` with the
    /// friction left (and uses it up): all of it inside the cone, else shortened by it.
    pub fn hold(&mut self, i: usize, from: Vec3, x: &mut Vec3) {
        let Some(&left) = self.left.get(i) else {
            return;
        };
        if left <= 0.0 {
            return;
        }
        let n = self.normal[i];
        let d = *x - from;
        let t = d - n * d.dot(n);
        let len = t.length();
        if len <= left {
            *x -= t;
            self.left[i] = left - len;
        } else {
            *x -= t * (left / len);
            self.left[i] = 0.0;
        }
    }
}

/// Position-level Coulomb friction: cancel the tangential displacement when it is within
/// the static cone (`mu * depth`), otherwise shorten it by that much. Returns the part of
/// the cone left unused (0 when sliding).
#[inline]
fn friction(x: &mut Vec3, prev: Vec3, n: Vec3, depth: f32, mu: f32) -> f32 {
    let dx = *x - prev;
    let tangential = dx - n * dx.dot(n);
    let len = tangential.length();
    let limit = mu * depth;
    if len <= limit {
        *x -= tangential;
        limit - len
    } else {
        if len > 0.0 {
            *x -= tangential * (limit / len);
        }
        0.0
    }
}
