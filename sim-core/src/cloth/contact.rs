//! Cloth-body contact. Once per frame, each particle's nearest body point within the
//! distance it can travel this frame is found (by a walk over the body's surface from
//! last frame's triangle when it can prove the answer, [`crate::obb::SurfaceWalk`],
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

use crate::body::Body;

/// How far a particle may move from where its nearest triangle was last searched before
/// it is searched again, m. The cached triangle's distance is then within twice this of
/// the true nearest distance, well under any sensible thickness.
pub const REUSE_DISTANCE: f32 = 0.001;

/// A particle without a triangle of its own starts its search from the previous
/// particle's, except the first of each block of this many (the thread split falls on a
/// block boundary, so neither thread reads the other's hints).
const NEIGHBOUR_BLOCK: usize = 64;

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
    hint: Vec<u32>,
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
                friction(&mut x[i], prev[i], n, -s, p.friction);
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
                    friction(&mut x[i], prev[i], Vec3::Y, depth, p.friction);
                }
            }
        }
    }
}

/// Position-level Coulomb friction: cancel the tangential displacement when it is within
/// the static cone (`mu * depth`), otherwise shorten it by that much.
#[inline]
fn friction(x: &mut Vec3, prev: Vec3, n: Vec3, depth: f32, mu: f32) {
    let dx = *x - prev;
    let tangential = dx - n * dx.dot(n);
    let len = tangential.length();
    let limit = mu * depth;
    if len <= limit {
        *x -= tangential;
    } else if len > 0.0 {
        *x -= tangential * (limit / len);
    }
}

/// How far particles can get this frame.
struct Reach {
    thickness: f32,
    reach_time: f32,
    max_accel: f32,
}

/// One contiguous range of the cache's per-particle arrays.
struct Slots<'a> {
    normal: &'a mut [Vec3],
    offset: &'a mut [f32],
    hint: &'a mut [u32],
    query_pos: &'a mut [Vec3],
    clear: &'a mut [f32],
    on_face: &'a mut [bool],
}

impl Reach {
    /// How far the particle may get from the body's side this frame, from its speed.
    fn of(&self, v: Vec3) -> f32 {
        self.thickness
            + v.length() * self.reach_time * 1.5
            + 0.5 * self.max_accel * self.reach_time * self.reach_time
            + 1e-3
    }
}

/// Searched a little farther than a particle can reach, so quiet particles can be skipped
/// next frame, m.
const SLACK: f32 = 0.02;

/// The same when the walk can answer: its fallback only needs to see a little past the
/// reach, m.
const WALK_SLACK: f32 = 0.005;

impl Slots<'_> {
    /// Caches particle `k`'s contact plane when `c` is within `reach`; says whether it is.
    fn set(&mut self, k: usize, c: Option<&crate::body::BodyContact>, reach: f32) -> bool {
        match c {
            Some(c) if c.signed_distance < reach => {
                self.normal[k] = c.normal;
                self.offset[k] = c.normal.dot(c.point);
                self.on_face[k] = c.on_face;
                true
            }
            _ => {
                self.normal[k] = Vec3::ZERO;
                self.on_face[k] = false;
                false
            }
        }
    }

    /// A full search for particle `k` at `x`, remembered as its query. Returns what it
    /// found, and whether that gave the particle a plane. `grid_near` is the body's
    /// clearance grid's triangle near `x` when the caller has looked it up already.
    fn query(
        &mut self,
        body: &Body,
        k: usize,
        x: Vec3,
        reach: f32,
        grid_near: Option<u32>,
    ) -> (Option<crate::body::BodyContact>, bool) {
        // A particle never found near the body starts from its neighbour's triangle, or
        // the one the body's clearance grid knows near it.
        let start = match self.hint[k] {
            u32::MAX if !k.is_multiple_of(NEIGHBOUR_BLOCK) && self.hint[k - 1] != u32::MAX => {
                self.hint[k - 1]
            }
            u32::MAX => grid_near.unwrap_or_else(|| body.outside_by(x).1),
            h => h,
        };
        // The walk from a known triangle is exact at any distance, so its fallback, the
        // tree, searches just past the reach; without one the tree searches farther, so
        // a far particle can be skipped for a while.
        let radius = reach + if start == u32::MAX { SLACK } else { WALK_SLACK };
        let (was_at, was_clear) = (self.query_pos[k], self.clear[k]);
        self.query_pos[k] = x;
        let (mut found, near) = body.contact_near(x, radius, start);
        // Nothing within the radius: outside and far, or deep inside (dragged in by the
        // cloth faster than its own velocity says). It was outside by `was_clear` at its
        // last query, so to be inside deeper than the radius now it must have moved more
        // than both: only then, and inside the body's root box, search without a bound.
        if found.is_none()
            && !(was_clear > 0.0 && (x - was_at).length() <= was_clear + radius)
            && body.tree().nodes()[0].obb.distance_squared(x) == 0.0
        {
            found = body.contact(x, f32::INFINITY, near);
        }
        self.hint[k] = found.map_or(near, |c| c.tri);
        self.clear[k] = found.map_or(radius, |c| c.signed_distance.max(0.0));
        let has = self.set(k, found.as_ref(), reach);
        (found, has)
    }
}

/// The broad phase for particles `base .. base + x.len()`; returns how many tree queries
/// it ran. Appends active particles (global indices) in order.
fn update_range(
    body: &Body,
    x: &[Vec3],
    v: &[Vec3],
    s: &mut Slots,
    base: usize,
    active: &mut Vec<u32>,
    r: &Reach,
) -> usize {
    let mut queries = 0;
    for k in 0..x.len() {
        let reach = r.of(v[k]);
        let moved = (x[k] - s.query_pos[k]).length();
        if s.clear[k] - moved > reach {
            s.normal[k] = Vec3::ZERO;
            continue;
        }
        // Barely moved since its last full query: its nearest triangle is (to within
        // 2 * REUSE_DISTANCE) still the one found then. A face contact keeps its plane
        // (the triangle's own); edge and corner contacts re-project onto the triangle.
        let has = if moved < REUSE_DISTANCE && s.on_face[k] && s.normal[k] != Vec3::ZERO {
            let near = x[k].dot(s.normal[k]) - s.offset[k] < reach;
            if !near {
                s.normal[k] = Vec3::ZERO;
                s.on_face[k] = false;
            }
            near
        } else if moved < REUSE_DISTANCE
            && s.hint[k] != u32::MAX
            && s.clear[k] < reach
            && let Some(c) = body.contact_on(x[k], s.hint[k])
        {
            s.set(k, Some(&c), reach)
        } else {
            let (outside, near) = body.outside_by(x[k]);
            if outside > reach {
                // Proved farther than it can travel without a search: remembered as a
                // query, with a triangle near it to start from when it comes nearer.
                s.query_pos[k] = x[k];
                s.clear[k] = outside;
                if near != u32::MAX {
                    s.hint[k] = near;
                }
                s.set(k, None, reach)
            } else {
                queries += 1;
                s.query(body, k, x[k], reach, Some(near)).1
            }
        };
        if has {
            active.push((base + k) as u32);
        }
    }
    queries
}

/// The frame-end check for one range of particles; returns how many it moved out.
fn resolve_range(
    body: &Body,
    x: &mut [Vec3],
    v: &mut [Vec3],
    inv_mass: &[f32],
    s: &mut Slots,
    r: &Reach,
) -> usize {
    let mut fixed = 0;
    for k in 0..x.len() {
        if inv_mass[k] == 0.0 {
            continue;
        }
        let moved = (x[k] - s.query_pos[k]).length();
        if moved < s.clear[k] {
            continue;
        }
        let reach = r.of(v[k]);
        // Deep enough for the next frame's update, and at least to `moved + thickness`
        // (what can have gone in since the last query).
        let reach = reach.max(moved + r.thickness - SLACK);
        let (Some(c), _) = s.query(body, k, x[k], reach, None) else {
            continue;
        };
        if c.signed_distance < 0.0 {
            x[k] = c.point + c.normal * r.thickness;
            let vn = v[k].dot(c.normal);
            if vn < 0.0 {
                v[k] -= c.normal * vn;
            }
            fixed += 1;
        }
    }
    fixed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::sphere;

    const DT: f32 = 1.0 / 60.0;

    fn params() -> ContactParams {
        ContactParams {
            thickness: 0.004,
            friction: 0.0,
            floor: None,
        }
    }

    /// Particles on a ring around a 0.2 m sphere, `height` from its surface, moving
    /// tangentially at `speed`.
    fn ring(n: usize, height: f32, speed: f32) -> (Vec<Vec3>, Vec<Vec3>) {
        (0..n)
            .map(|i| {
                let a = i as f32 / n as f32 * std::f32::consts::TAU;
                let dir = Vec3::new(a.cos(), 0.3, a.sin()).normalize();
                let tangent = Vec3::Y.cross(dir).normalize();
                (dir * (0.2 + height), tangent * speed)
            })
            .unzip()
    }

    /// A 0.2 m sphere, a ring of particles around it (see [`ring`]) and their cache after
    /// one broad phase.
    struct Ring {
        body: Body,
        p: ContactParams,
        x: Vec<Vec3>,
        v: Vec<Vec3>,
        inv_mass: Vec<f32>,
        cache: ContactCache,
    }

    fn ring_on_sphere(n: usize, height: f32, speed: f32) -> Ring {
        let body = sphere(Vec3::ZERO, 0.2, 3).unwrap();
        let p = params();
        let (x, v) = ring(n, height, speed);
        let mut cache = ContactCache::new(x.len());
        cache.update(&body, &x, &v, DT, 9.81, &p);
        Ring {
            inv_mass: vec![1.0; x.len()],
            body,
            p,
            x,
            v,
            cache,
        }
    }

    /// Every particle has a plane, at the gap a cache searching from scratch finds.
    fn assert_planes_of_a_fresh_cache(
        cache: &ContactCache,
        body: &Body,
        x: &[Vec3],
        v: &[Vec3],
        p: &ContactParams,
    ) {
        let mut fresh = ContactCache::new(x.len());
        fresh.update(body, x, v, DT, 9.81, p);
        for (i, &xi) in x.iter().enumerate() {
            let (a, b) = (cache.gap(i, xi, 0.0), fresh.gap(i, xi, 0.0));
            let (a, b) = (a.unwrap(), b.unwrap());
            assert!((a - b).abs() < 1e-6, "{a} {b}");
        }
    }

    #[test]
    fn the_frame_end_search_is_kept_for_the_next_update() {
        let Ring {
            body,
            p,
            mut x,
            mut v,
            inv_mass,
            mut cache,
        } = ring_on_sphere(64, 0.005, 0.5);
        assert_eq!(cache.last_queries, x.len());
        assert_eq!(cache.active_count(), x.len());
        // The frame moves every particle 8 mm along the surface: more than its clearance.
        for (x, v) in x.iter_mut().zip(&v) {
            *x = (*x + *v * DT).normalize() * 0.205;
        }
        let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
        assert_eq!(moved, 0);
        // The next frame's update finds them where the check searched: no new search, and
        // the same planes it would have found.
        cache.update(&body, &x, &v, DT, 9.81, &p);
        assert_eq!(cache.last_queries, 0);
        assert_eq!(cache.active_count(), x.len());
        assert_planes_of_a_fresh_cache(&cache, &body, &x, &v, &p);
    }

    #[test]
    fn a_particle_found_inside_at_frame_end_is_moved_out_and_searched_again_next_frame() {
        let Ring {
            body,
            p,
            mut x,
            mut v,
            inv_mass,
            mut cache,
        } = ring_on_sphere(8, 0.005, 0.0);
        // Dragged 3 cm into the sphere and moving inward.
        x[0] *= 0.835;
        v[0] = -x[0];
        let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
        assert_eq!(moved, 1);
        let r = x[0].length();
        assert!((r - 0.204).abs() < 2e-3, "moved out to {r}");
        // The inward 0.17 m/s is gone (up to the facet's tilt from the radius).
        let inward = -v[0].dot(x[0].normalize());
        assert!(inward < 0.02, "inward velocity left: {inward}");
        cache.update(&body, &x, &v, DT, 9.81, &p);
        assert_eq!(cache.last_queries, 1);
    }

    #[test]
    fn a_particle_teleported_deep_inside_is_still_found_inside() {
        // Searched 5 mm outside, then (an edit, a grab) 12 cm inside a 0.2 m sphere at
        // rest: deeper than the search radius, so the bounded search finds nothing. It
        // moved farther than its clearance plus the radius, so the unbounded search runs
        // and the frame-end check moves it out.
        let Ring {
            body,
            p,
            mut x,
            mut v,
            inv_mass,
            mut cache,
        } = ring_on_sphere(4, 0.005, 0.0);
        x[0] = x[0].normalize() * 0.08;
        let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
        assert_eq!(moved, 1);
        assert!(
            (x[0].length() - 0.204).abs() < 2e-3,
            "moved out to {}",
            x[0].length()
        );
    }

    #[test]
    fn sliding_particles_get_the_planes_a_fresh_tree_search_gives() {
        // Particles sliding 8 mm a frame along a sphere, 5 mm above it: after the first
        // frame every search starts from last frame's triangle (the walk answers them),
        // and the planes are the ones an unhinted tree search gives.
        let Ring {
            body,
            p,
            mut x,
            v,
            mut cache,
            ..
        } = ring_on_sphere(64, 0.005, 0.5);
        for _ in 0..5 {
            cache.update(&body, &x, &v, DT, 9.81, &p);
            for (i, &xi) in x.iter().enumerate() {
                let tree = body.contact(xi, 1.0, u32::MAX).unwrap();
                let gap = cache.gap(i, xi, 0.0).unwrap();
                assert!((gap - tree.signed_distance).abs() < 1e-5, "{gap} {tree:?}");
            }
            for (x, v) in x.iter_mut().zip(&v) {
                *x = (*x + *v * DT).normalize() * 0.205;
            }
        }
        let (_, start) = body.contact_near(x[0], 0.1, cache.hint[0]);
        assert_ne!(start, u32::MAX);
    }

    #[test]
    fn particles_the_body_grid_proves_out_of_reach_are_not_searched_until_near() {
        // 8 cm off the sphere, falling toward it at 1 m/s: they could travel ~2.7 cm this
        // frame, and the body's clearance grid proves them farther than that.
        let Ring {
            body,
            p,
            mut x,
            mut v,
            cache: mut far,
            ..
        } = ring_on_sphere(64, 0.08, 0.0);
        for (x, v) in x.iter().zip(v.iter_mut()) {
            *v = -x.normalize();
        }
        far.update(&body, &x, &v, DT, 9.81, &p);
        assert_eq!(far.last_queries, 0);
        assert_eq!(far.active_count(), 0);
        // Within reach a frame later: searched, and given the planes a fresh cache gives.
        for x in x.iter_mut() {
            *x = x.normalize() * 0.21;
        }
        far.update(&body, &x, &v, DT, 9.81, &p);
        assert_eq!(far.last_queries, x.len());
        assert_eq!(far.active_count(), x.len());
        assert_planes_of_a_fresh_cache(&far, &body, &x, &v, &p);
    }
}
