//! Queries: nearest surface point within a distance (single and batched), ray cast, and
//! overlap with a box. Traversal uses a fixed-size stack on the call stack: no allocation.

use glam::Vec3;

use super::geometry::{Feature, Obb, closest_point_on_triangle, ray_triangle};
use super::tree::ObbTree;

/// Enough for any tree `build` makes: splits keep at least 1/8 of a node on each side, so
/// depth stays below 100 even for 10^6 triangles, and nearest-first DFS holds one pending
/// sibling per level.
const STACK: usize = 128;

/// The nearest surface point found by [`ObbTree::nearest`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NearestHit {
    /// Original index of the triangle.
    pub tri: u32,
    pub point: Vec3,
    pub distance: f32,
    pub feature: Feature,
}

/// The first hit of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub tri: u32,
    pub t: f32,
    pub point: Vec3,
}

impl ObbTree {
    /// Nearest point of the surface to `p` no farther than `max_dist`.
    pub fn nearest(&self, p: Vec3, max_dist: f32) -> Option<NearestHit> {
        self.nearest_with_hint(p, max_dist, None)
    }

    /// As [`nearest`](Self::nearest), seeding the search bound with a triangle that is
    /// probably close (e.g. last frame's answer). The answer is the same with or without
    /// the hint; the hint only prunes more of the tree.
    pub fn nearest_with_hint(
        &self,
        p: Vec3,
        max_dist: f32,
        hint: Option<u32>,
    ) -> Option<NearestHit> {
        self.nearest_counted(p, max_dist, hint, &mut 0)
    }

    /// As [`nearest_with_hint`](Self::nearest_with_hint), adding to `visits` the number
    /// of tree nodes the search opened: the operation count, free of cache effects.
    pub fn nearest_counted(
        &self,
        p: Vec3,
        max_dist: f32,
        hint: Option<u32>,
        visits: &mut usize,
    ) -> Option<NearestHit> {
        self.nearest_where(p, max_dist, hint, visits, |_| true, |_, _| true)
    }

    /// The nearest-point search over the triangles `tri_ok` keeps (given their tree slot
    /// and corners), skipping the subtrees whose box `node_ok` rejects (it must reject
    /// only boxes holding no kept triangle). With both always true this is
    /// [`nearest_counted`](Self::nearest_counted).
    pub(super) fn nearest_where(
        &self,
        p: Vec3,
        max_dist: f32,
        hint: Option<u32>,
        visits: &mut usize,
        node_ok: impl Fn(&Obb) -> bool,
        tri_ok: impl Fn(usize, &[Vec3; 3]) -> bool,
    ) -> Option<NearestHit> {
        if max_dist.is_nan() || max_dist < 0.0 || !p.is_finite() {
            return None;
        }
        let mut best_d2 = max_dist * max_dist;
        let mut best: Option<(u32, Vec3, Feature)> = None;
        if let Some(slot) = hint.and_then(|t| self.slot_of.get(t as usize))
            && tri_ok(*slot as usize, &self.tri_verts[*slot as usize])
        {
            let [a, b, c] = self.tri_verts[*slot as usize];
            let (q, f) = closest_point_on_triangle(p, a, b, c);
            let d2 = (q - p).length_squared();
            if d2 <= best_d2 {
                best_d2 = d2;
                best = Some((*slot, q, f));
            }
        }
        let mut stack = [(0u32, 0.0f32); STACK];
        let mut top = 0usize;
        let root_d2 = self.nodes[0].obb.distance_squared(p);
        if root_d2 > best_d2 || !node_ok(&self.nodes[0].obb) {
            return finish(self, best, best_d2);
        }
        stack[0] = (0, root_d2);
        top += 1;
        while top > 0 {
            top -= 1;
            let (ni, lb) = stack[top];
            if lb > best_d2 {
                continue;
            }
            *visits += 1;
            let node = &self.nodes[ni as usize];
            if node.is_leaf() {
                let s = node.tri_start as usize;
                for slot in s..s + node.tri_count as usize {
                    let tri = &self.tri_verts[slot];
                    if !tri_ok(slot, tri) {
                        continue;
                    }
                    let [a, b, c] = *tri;
                    let (q, f) = closest_point_on_triangle(p, a, b, c);
                    let d2 = (q - p).length_squared();
                    if d2 < best_d2 || (d2 == best_d2 && best.is_none()) {
                        best_d2 = d2;
                        best = Some((slot as u32, q, f));
                    }
                }
                continue;
            }
            let l = node.child;
            let r = l + 1;
            // A rejected child's bound is NaN: it compares false, so it is never pushed.
            let bound = |b: &Obb| {
                if node_ok(b) {
                    b.distance_squared(p)
                } else {
                    f32::NAN
                }
            };
            let dl = bound(&self.nodes[l as usize].obb);
            let dr = bound(&self.nodes[r as usize].obb);
            // Push the farther child first so the nearer one is explored first.
            let (near, dn, far, df) = if dl <= dr {
                (l, dl, r, dr)
            } else {
                (r, dr, l, dl)
            };
            if df <= best_d2 && top < STACK {
                stack[top] = (far, df);
                top += 1;
            }
            if dn <= best_d2 && top < STACK {
                stack[top] = (near, dn);
                top += 1;
            }
        }
        finish(self, best, best_d2)
    }

    /// Calls `found(triangle, distance)` for every triangle `tri_ok` keeps within
    /// `max_dist` of `p`, skipping the subtrees whose box `node_ok` rejects (as in
    /// [`nearest_where`](Self::nearest_where)).
    pub(super) fn for_each_within(
        &self,
        p: Vec3,
        max_dist: f32,
        node_ok: impl Fn(&Obb) -> bool,
        tri_ok: impl Fn(&[Vec3; 3]) -> bool,
        mut found: impl FnMut(u32, f32),
    ) {
        let r2 = max_dist * max_dist;
        let mut stack = [0u32; STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !(node.obb.distance_squared(p) <= r2 && node_ok(&node.obb)) {
                continue;
            }
            if node.is_leaf() {
                let s = node.tri_start as usize;
                for slot in s..s + node.tri_count as usize {
                    let tri = &self.tri_verts[slot];
                    if !tri_ok(tri) {
                        continue;
                    }
                    let (q, _) = closest_point_on_triangle(p, tri[0], tri[1], tri[2]);
                    let d2 = (q - p).length_squared();
                    if d2 <= r2 {
                        found(self.tri_ids[slot], d2.sqrt());
                    }
                }
            } else if top + 2 <= STACK {
                stack[top] = node.child;
                stack[top + 1] = node.child + 1;
                top += 2;
            }
        }
    }

    /// Nearest points for a batch of particles, each with its own maximum distance and an
    /// optional hint (pass `u32::MAX` for none). Uses up to `threads` threads.
    pub fn nearest_batch(
        &self,
        points: &[Vec3],
        max_dist: &[f32],
        hints: &[u32],
        out: &mut [Option<NearestHit>],
        threads: usize,
    ) {
        let n = points.len().min(max_dist.len()).min(out.len());
        let run = |range: std::ops::Range<usize>, out: &mut [Option<NearestHit>]| {
            for (k, i) in range.enumerate() {
                let hint = hints.get(i).copied().filter(|&h| h != u32::MAX);
                out[k] = self.nearest_with_hint(points[i], max_dist[i], hint);
            }
        };
        if threads <= 1 || n < 2048 {
            run(0..n, &mut out[..n]);
            return;
        }
        let chunk = n.div_ceil(threads);
        std::thread::scope(|s| {
            for (c, out_chunk) in out[..n].chunks_mut(chunk).enumerate() {
                let start = c * chunk;
                let end = (start + chunk).min(n);
                s.spawn(move || run(start..end, out_chunk));
            }
        });
    }

    /// First intersection of the ray `origin + t * dir`, `0 <= t <= max_t`.
    pub fn ray_cast(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<RayHit> {
        if !origin.is_finite() || !dir.is_finite() || dir.length_squared() == 0.0 {
            return None;
        }
        let mut best_t = max_t;
        let mut best: Option<u32> = None;
        let mut stack = [(0u32, 0.0f32); STACK];
        let mut top = 0usize;
        if let Some(t0) = self.nodes[0].obb.ray_entry(origin, dir, best_t) {
            stack[0] = (0, t0);
            top = 1;
        }
        while top > 0 {
            top -= 1;
            let (ni, entry) = stack[top];
            if entry > best_t {
                continue;
            }
            let node = &self.nodes[ni as usize];
            if node.is_leaf() {
                let s = node.tri_start as usize;
                for slot in s..s + node.tri_count as usize {
                    let [a, b, c] = self.tri_verts[slot];
                    if let Some(t) = ray_triangle(origin, dir, a, b, c)
                        && t <= best_t
                    {
                        best_t = t;
                        best = Some(slot as u32);
                    }
                }
                continue;
            }
            let l = node.child;
            let r = l + 1;
            let el = self.nodes[l as usize].obb.ray_entry(origin, dir, best_t);
            let er = self.nodes[r as usize].obb.ray_entry(origin, dir, best_t);
            let mut push = |n: u32, e: Option<f32>| {
                if let Some(e) = e
                    && top < STACK
                {
                    stack[top] = (n, e);
                    top += 1;
                }
            };
            match (el, er) {
                (Some(a), Some(b)) if a <= b => {
                    push(r, er);
                    push(l, el);
                }
                _ => {
                    push(l, el);
                    push(r, er);
                }
            }
        }
        best.map(|slot| RayHit {
            tri: self.tri_ids[slot as usize],
            t: best_t,
            point: origin + dir * best_t,
        })
    }

    /// Appends to `out` the original index of every triangle that overlaps the solid box.
    pub fn overlap_box(&self, query: &Obb, out: &mut Vec<u32>) {
        let mut stack = [0u32; STACK];
        let mut top = 1usize;
        while top > 0 {
            top -= 1;
            let node = &self.nodes[stack[top] as usize];
            if !node.obb.overlaps(query) {
                continue;
            }
            if node.is_leaf() {
                let s = node.tri_start as usize;
                for slot in s..s + node.tri_count as usize {
                    let [a, b, c] = self.tri_verts[slot];
                    if query.overlaps_triangle(a, b, c) {
                        out.push(self.tri_ids[slot]);
                    }
                }
            } else if top + 2 <= STACK {
                stack[top] = node.child;
                stack[top + 1] = node.child + 1;
                top += 2;
            }
        }
    }
}

fn finish(tree: &ObbTree, best: Option<(u32, Vec3, Feature)>, d2: f32) -> Option<NearestHit> {
    best.map(|(slot, point, feature)| NearestHit {
        tri: tree.tri_ids[slot as usize],
        point,
        distance: d2.sqrt(),
        feature,
    })
}
