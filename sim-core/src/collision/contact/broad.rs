//! The broad phase's per-particle work: the search for a particle's nearest body point
//! (walk first, then the tree), cached as a plane, and the frame-end check, each over one
//! contiguous range of particles so the two halves can run on two threads.

use glam::Vec3;

use crate::collision::body::{Body, BodyContact};

/// How far a particle may move from where its nearest triangle was last searched before
/// it is searched again, m. The cached triangle's distance is then within twice this of
/// the true nearest distance, well under any sensible thickness.
pub const REUSE_DISTANCE: f32 = 0.001;

/// A particle without a triangle of its own starts its search from the previous
/// particle's, except the first of each block of this many (the thread split falls on a
/// block boundary, so neither thread reads the other's hints).
pub(super) const NEIGHBOUR_BLOCK: usize = 64;

/// How far particles can get this frame.
pub(super) struct Reach {
    pub(super) thickness: f32,
    pub(super) reach_time: f32,
    pub(super) max_accel: f32,
}

/// One contiguous range of the cache's per-particle arrays.
pub(super) struct Slots<'a> {
    pub(super) normal: &'a mut [Vec3],
    pub(super) offset: &'a mut [f32],
    pub(super) hint: &'a mut [u32],
    pub(super) query_pos: &'a mut [Vec3],
    pub(super) clear: &'a mut [f32],
    pub(super) on_face: &'a mut [bool],
}

impl Reach {
    /// How far the particle may get from the body's side this frame, from its speed.
    pub(super) fn of(&self, v: Vec3) -> f32 {
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
    pub(super) fn set(&mut self, k: usize, c: Option<&BodyContact>, reach: f32) -> bool {
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
    pub(super) fn query(
        &mut self,
        body: &Body,
        k: usize,
        x: Vec3,
        reach: f32,
        grid_near: Option<u32>,
    ) -> (Option<BodyContact>, bool) {
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
pub(super) fn update_range(
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
pub(super) fn resolve_range(
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
