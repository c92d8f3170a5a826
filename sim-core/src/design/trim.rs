//! Exact cuts in the pattern plane (rest x and -z, metres): where a path crosses an edge
//! of the cloth, the edge is split there, so the cut runs along the path and not along
//! the mesh's edges. Removing whole triangles instead left a staircase a triangle deep in
//! the pattern out (the dress's neckline had spikes 1 cm high in its sewing line, and its
//! cut line crossed itself).
//!
//! A crossing that would leave a thin triangle (an angle under 20 degrees) moves the
//! nearer vertex onto the path instead, or passes through it where it lies within 1 mm
//! of the path (see `crossing_prims`).

use std::collections::HashSet;

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::prim::{Between, Prim};
use super::transaction::Batch;
use crate::mesh::{NONE, Tri};

/// Most crossings one segment of a path may have (a guard against a path that finds no
/// end).
const MAX_CROSSINGS: usize = 100_000;

/// A rest position's place in the pattern plane.
pub(super) fn plane(p: Vec3) -> Vec2 {
    Vec2::new(p.x, -p.z)
}

/// Where segment `p`-`q` crosses segment `a`-`b`: (share along `p`-`q`, share along
/// `a`-`b`), both in [0, 1]; none when they are parallel or miss.
fn crossing(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> Option<(f32, f32)> {
    let (r, s) = (q - p, b - a);
    let den = r.perp_dot(s);
    if den.abs() <= 1e-12 * r.length() * s.length() {
        return None;
    }
    let u = (a - p).perp_dot(s) / den;
    let t = (a - p).perp_dot(r) / den;
    ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&t)).then_some((u, t))
}

/// Whether `q` lies inside closed polygon `poly` (even-odd).
pub(crate) fn inside(poly: &[Vec2], q: Vec2) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

impl Design {
    /// Cuts the cloth away inside the closed polygon `outline` of the pattern plane
    /// (rest x and -z, m): each edge the outline crosses is split where it crosses it
    /// (or its crossing moved onto a vertex close by), then the triangles inside go, as
    /// one undoable edit ("trim"). The new border follows the outline. Returns how many
    /// triangles went; nothing changes when none lies inside or all would.
    pub fn trim(&mut self, outline: &[Vec2]) -> Result<usize, EditError> {
        self.check_editable()?;
        if outline.len() < 3 || outline.iter().any(|p| !p.is_finite()) {
            return Err(EditError::BadValue {
                name: "trim outline",
                rule: "at least three finite points",
                value: format!("{} points", outline.len()),
            });
        }
        let mut closed = outline.to_vec();
        closed.push(outline[0]);
        let mut applied = Vec::new();
        let mut batch = Batch::default();
        if let Err(e) = self.split_along(&closed, &mut applied, &mut batch) {
            self.abandon_batch(&applied, batch);
            return Err(e);
        }
        let cut: Vec<Prim> = (self.sim.cloth.live.iter())
            .filter(|(_, t)| inside(outline, plane((t.rest[0] + t.rest[1] + t.rest[2]) / 3.0)))
            .map(|(slot, t)| Prim::Tri {
                slot,
                old: Some(*t),
                new: None,
            })
            .collect();
        let n = cut.len();
        let result = if n == 0 {
            Err(EditError::NothingOnPattern {
                what: "cloth inside the outline",
            })
        } else if n == self.sim.cloth.live.tri_count() {
            Err(EditError::LastCloth)
        } else {
            self.apply_unsynced(&cut, &mut batch)
        };
        if let Err(e) = result {
            self.abandon_batch(&applied, batch);
            return Err(e);
        }
        applied.extend(cut);
        self.record_batch("trim", applied, batch);
        Ok(n)
    }

    /// Splits every edge the polyline `path` (pattern plane) crosses where it crosses it,
    /// segment by segment, applying each split at once into `batch` (the caller syncs);
    /// the primitives applied are added to `applied` (for the caller's undo record, or
    /// its rollback on an error). Returns the vertices the cut now runs through, in the
    /// path's order.
    pub(super) fn split_along(
        &mut self,
        path: &[Vec2],
        applied: &mut Vec<Prim>,
        batch: &mut Batch,
    ) -> Result<Vec<u32>, EditError> {
        let mut chain: Vec<u32> = Vec::new();
        let mut on_path: HashSet<u32> = HashSet::new();
        // The triangles near the path, then near each segment (with those each split
        // or move changes): one pass over the cloth, not one a crossing.
        let near = |t: &Tri, lo: Vec2, hi: Vec2| {
            let c = t.rest.map(plane);
            !(c.iter().all(|v| v.x < lo.x)
                || c.iter().all(|v| v.x > hi.x)
                || c.iter().all(|v| v.y < lo.y)
                || c.iter().all(|v| v.y > hi.y))
        };
        let (lo, hi) = path.iter().fold(
            (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let mut around: Vec<u32> = (self.sim.cloth.live.iter())
            .filter(|(_, t)| near(t, lo, hi))
            .map(|(s, _)| s)
            .collect();
        for w in path.windows(2) {
            let (p, q) = (w[0], w[1]);
            let (lo, hi) = (p.min(q), p.max(q));
            let live = &self.sim.cloth.live;
            let mut cands: Vec<u32> = (around.iter().copied())
                .filter(|&s| live.tri(s).is_some_and(|t| near(t, lo, hi)))
                .collect();
            // The segment's next crossing past the last one, found again after each
            // split: a split or a move changes the edges round it. A crossing at the
            // last one's place (an edge of the vertex just made or moved) is that one.
            let mut at = -1.0f32;
            for _ in 0..MAX_CROSSINGS {
                let Some((u, a, b, s)) = self.next_crossing(p, q, at + 1e-4, &cands, &on_path)
                else {
                    break;
                };
                at = u;
                let (vertex, prims) = self.crossing_prims(a, b, s, (p, q));
                if chain.last() != Some(&vertex) {
                    chain.push(vertex);
                    on_path.insert(vertex);
                }
                if prims.is_empty() {
                    continue;
                }
                self.apply_unsynced(&prims, batch)?;
                for prim in &prims {
                    if let Prim::Tri { slot, .. } = prim {
                        cands.push(*slot);
                        around.push(*slot);
                    }
                }
                applied.extend(prims);
            }
        }
        Ok(chain)
    }

    /// A vertex exactly at pattern place `e` on the live triangle whose pattern holds it,
    /// made and applied at once into `batch` (its primitives added to `applied`), so
    /// that a slit drawn to `e` ends there (ended at the vertex past it, a slit veered up
    /// to an edge's length off the line drawn). The corner within [`THROUGH_M`] of it;
    /// else, of the three corners, the one whose line through `e` splits the triangle
    /// best: the side across from it split where the line meets it, then the line at `e`
    /// (both edge splits, so that an undo and a redo place them between their ends as
    /// the cloth then stands). Where that would leave an angle under [`FAIR_DEG`] (`e`
    /// near a side), the nearest side crossed at `e`'s foot as a cut crosses an edge
    /// (`crossing_prims`). `None` when no triangle holds `e`.
    pub(super) fn vertex_at(
        &mut self,
        e: Vec2,
        applied: &mut Vec<Prim>,
        batch: &mut Batch,
    ) -> Result<Option<u32>, EditError> {
        let live = &self.sim.cloth.live;
        let Some(t) = live.iter().map(|(_, t)| *t).find(|t| holds(t, e)) else {
            return Ok(None);
        };
        let c = t.rest.map(plane);
        let nearest_corner = (0..3)
            .min_by(|&i, &j| c[i].distance(e).total_cmp(&c[j].distance(e)))
            .unwrap_or(0);
        if c[nearest_corner].distance(e) <= THROUGH_M {
            return Ok(Some(t.v[nearest_corner]));
        }
        // Through corner k: the far side split at share s from its first end, then the
        // line from corner k at share u; the worst angle of what both leave.
        let through = |k: usize| -> Option<(f32, f32, f32)> {
            let (a, b, cc) = (c[k], c[(k + 1) % 3], c[(k + 2) % 3]);
            let (r, w) = (e - a, cc - b);
            let den = r.perp_dot(w);
            if den.abs() < 1e-20 {
                return None;
            }
            let s = (b - a).perp_dot(r) / den;
            let f = b + w * s;
            let u = r.length() / (f - a).length().max(1e-20);
            if !(s > 0.0 && s < 1.0 && u > 0.0 && u < 1.0) {
                return None;
            }
            let inner = [[a, b, e], [e, b, f], [a, e, cc], [e, f, cc]];
            let across = worst_angle(&self.split_edge_prims(t.v[(k + 1) % 3], t.v[(k + 2) % 3], s));
            let worst = (inner.iter().map(min_angle)).fold(across, f32::min);
            Some((worst, s, u))
        };
        let best = (0..3)
            .filter_map(|k| through(k).map(|q| (k, q)))
            .max_by(|x, y| x.1.0.total_cmp(&y.1.0));
        let mut apply = |d: &mut Self, (made, prims): (u32, Vec<Prim>)| -> Result<u32, EditError> {
            d.apply_unsynced(&prims, batch)?;
            applied.extend(prims);
            Ok(made)
        };
        if let Some((k, (worst, s, u))) = best
            && worst >= FAIR_DEG
        {
            let (corner, b, cc) = (t.v[k], t.v[(k + 1) % 3], t.v[(k + 2) % 3]);
            let made = self.sim.cloth.len() as u32;
            let f = apply(self, (made, self.split_edge_prims(b, cc, s)))?;
            let made = self.sim.cloth.len() as u32;
            return apply(self, (made, self.split_edge_prims(corner, f, u))).map(Some);
        }
        // Else a crossing of the nearest side at `e`'s foot, as a cut makes one.
        let side = |k: usize| (c[k], c[(k + 1) % 3]);
        let k = (0..3)
            .min_by(|&i, &j| {
                distance_to_segment(e, side(i)).total_cmp(&distance_to_segment(e, side(j)))
            })
            .unwrap_or(0);
        let (a, b) = side(k);
        let foot = ((e - a).dot(b - a) / (b - a).length_squared().max(1e-20)).clamp(0.0, 1.0);
        let crossing = self.crossing_prims(t.v[k], t.v[(k + 1) % 3], foot, (e, e));
        apply(self, crossing).map(Some)
    }

    /// The first crossing of segment `p`-`q` (pattern plane) with an edge of the
    /// triangles in `slots` at share `from` along it or later: (share, a, b, share along
    /// `a`-`b` from `a`). An edge between two vertices `on_path` (the cut's, made on it)
    /// lies along the path: where it is all but parallel to it, its crossing is noise
    /// (one such put a vertex the cut had passed back into it, ahead of the one just
    /// made, and the cut detoured 14 mm through the mesh to join them).
    fn next_crossing(
        &self,
        p: Vec2,
        q: Vec2,
        from: f32,
        slots: &[u32],
        on_path: &HashSet<u32>,
    ) -> Option<(f32, u32, u32, f32)> {
        let mut best: Option<(f32, u32, u32, f32)> = None;
        for &slot in slots {
            let Some(t) = self.sim.cloth.live.tri(slot) else {
                continue;
            };
            let c = t.rest.map(plane);
            for k in 0..3 {
                let (i, j) = (k, (k + 1) % 3);
                if on_path.contains(&t.v[i]) && on_path.contains(&t.v[j]) {
                    continue;
                }
                let Some((u, s)) = crossing(p, q, c[i], c[j]) else {
                    continue;
                };
                if u >= from && best.is_none_or(|b| u < b.0) {
                    best = Some((u, t.v[i], t.v[j], s));
                }
            }
        }
        best
    }

    /// The primitives that split edge `a`-`b` at share `s` from `a`: a new vertex there
    /// (position and velocity between theirs), each triangle on the edge cut in two
    /// through it (its rest place and texture coordinate between the ends' in each).
    fn split_edge_prims(&self, a: u32, b: u32, s: f32) -> Vec<Prim> {
        let cloth = &self.sim.cloth;
        let m = cloth.len() as u32;
        let (ia, ib) = (a as usize, b as usize);
        let mut prims = vec![Prim::AddVertex {
            index: m,
            x: cloth.x[ia].lerp(cloth.x[ib], s),
            v: cloth.v[ia].lerp(cloth.v[ib], s),
            from: Some(Between { a, b, s }),
        }];
        let mut next = cloth.live.slots() as u32;
        for slot in cloth.live.edge(a, b) {
            if slot == NONE {
                continue;
            }
            let Some(&tri) = cloth.live.tri(slot) else {
                continue;
            };
            let (Some(ca), Some(cb)) = (tri.corner(a), tri.corner(b)) else {
                continue;
            };
            let rest = tri.rest[ca].lerp(tri.rest[cb], s);
            let uv = tri.uv[ca].lerp(tri.uv[cb], s);
            let with_m = |corner: usize| tri.with_corner(corner, m, rest, uv);
            prims.push(Prim::Tri {
                slot,
                old: Some(tri),
                new: Some(with_m(cb)),
            });
            prims.push(Prim::Tri {
                slot: next,
                old: None,
                new: Some(with_m(ca)),
            });
            next += 1;
        }
        prims
    }

    /// What a crossing of edge `a`-`b` at share `s` from `a` by segment `seg` becomes,
    /// the first that leaves no triangle with an angle under [`GOOD_DEG`]: the edge split
    /// there; the nearer end moved onto the crossing (an inner vertex with one pattern
    /// place); the cut through the nearer end as it is, when that is within
    /// [`THROUGH_M`] of the segment. Failing all three, the move if it keeps every angle
    /// over [`FAIR_DEG`] and better than the split, else the split if it keeps them over
    /// that, or over [`SLIVER_DEG`] where the nearer end lies more than [`SNAP_M`] off the
    /// segment, else through the nearer end. Applied in
    /// order, each crossing's vertex joins the one before by an edge.
    fn crossing_prims(&self, a: u32, b: u32, s: f32, seg: (Vec2, Vec2)) -> (u32, Vec<Prim>) {
        let made = self.sim.cloth.len() as u32;
        let split = self.split_edge_prims(a, b, s);
        let q_split = worst_angle(&split);
        if q_split >= GOOD_DEG {
            return (made, split);
        }
        let (near, far, t) = if s < 0.5 { (a, b, s) } else { (b, a, 1.0 - s) };
        let moved = self.move_prims(near, far, t);
        let q_move = if moved.is_empty() {
            0.0
        } else {
            worst_angle(&moved)
        };
        if q_move >= GOOD_DEG {
            return (near, moved);
        }
        // How far off the segment the cut would pass through the nearer end.
        let off = self
            .sim
            .cloth
            .live
            .tris_of(near)
            .first()
            .and_then(|&slot| self.sim.cloth.live.tri(slot))
            .and_then(|t| Some(plane(t.rest[t.corner(near)?])))
            .map_or(f32::MAX, |at| distance_to_segment(at, seg));
        if off <= THROUGH_M {
            return (near, Vec::new());
        }
        if q_move > q_split && q_move >= FAIR_DEG {
            (near, moved)
        } else if q_split >= FAIR_DEG || (q_split >= SLIVER_DEG && off > SNAP_M) {
            (made, split)
        } else {
            (near, Vec::new())
        }
    }

    /// The primitives that move inner vertex `v`, in the pattern, to share `t` of the way
    /// along its edge to `w` (its rest place and texture coordinate in every triangle);
    /// none when it is on the cloth's border, has more than one place in the pattern (a
    /// seam), or the move would turn a triangle over.
    fn move_prims(&self, v: u32, w: u32, t: f32) -> Vec<Prim> {
        let live = &self.sim.cloth.live;
        if live.is_boundary(v) {
            return Vec::new();
        }
        let fan: Vec<(u32, Tri)> = (live.tris_of(v).iter())
            .filter_map(|&slot| live.tri(slot).map(|t| (slot, *t)))
            .collect();
        let Some((_, on_edge)) = fan.iter().find(|(_, t)| t.corner(w).is_some()) else {
            return Vec::new();
        };
        let (Some(cv), Some(cw)) = (on_edge.corner(v), on_edge.corner(w)) else {
            return Vec::new();
        };
        let place = on_edge.rest[cv];
        let rest = place.lerp(on_edge.rest[cw], t);
        let uv = on_edge.uv[cv].lerp(on_edge.uv[cw], t);
        let mut prims = Vec::new();
        for (slot, tri) in &fan {
            let Some(c) = tri.corner(v) else {
                return Vec::new();
            };
            if tri.rest[c] != place {
                return Vec::new();
            }
            let mut n = *tri;
            n.rest[c] = rest;
            n.uv[c] = uv;
            if signed_area(tri) * signed_area(&n) <= 0.0 {
                return Vec::new();
            }
            prims.push(Prim::Tri {
                slot: *slot,
                old: Some(*tri),
                new: Some(n),
            });
        }
        prims
    }
}

/// A crossing's new triangles must keep every angle over this to be taken at once.
const GOOD_DEG: f32 = 20.0;
/// Or over this when the cut cannot pass through a vertex close by.
const FAIR_DEG: f32 = 8.0;
/// Or, where the nearer vertex lies more than [`SNAP_M`] off the path, a split's
/// triangles over this: a thin triangle is better than a cut off its line by up to half
/// an edge (7 mm at the grid's 31 mm edges, where a split at 7.4 degrees was turned down
/// for the nearer vertex).
const SLIVER_DEG: f32 = 4.0;
/// How far off the path a cut may pass through a vertex rather than leave a triangle
/// thinner than [`FAIR_DEG`], m.
const SNAP_M: f32 = 0.003;
/// How far from the path the cut may pass through a vertex as it is, m.
const THROUGH_M: f32 = 0.001;

/// Whether triangle `t`'s pattern holds place `e` (on its sides too).
fn holds(t: &Tri, e: Vec2) -> bool {
    let [a, b, c] = t.rest.map(plane);
    let (d1, d2, d3) = (
        (b - a).perp_dot(e - a),
        (c - b).perp_dot(e - b),
        (a - c).perp_dot(e - c),
    );
    let tol = -1e-12;
    (d1 >= tol && d2 >= tol && d3 >= tol) || (d1 <= -tol && d2 <= -tol && d3 <= -tol)
}

/// The smallest angle of a triangle's corners, degrees.
fn min_angle(t: &[Vec2; 3]) -> f32 {
    (0..3)
        .map(|k| {
            let (u, v) = (t[(k + 1) % 3] - t[k], t[(k + 2) % 3] - t[k]);
            u.angle_to(v).abs().to_degrees()
        })
        .fold(180.0, f32::min)
}

/// Twice the signed area of a triangle in the pattern plane.
fn signed_area(t: &Tri) -> f32 {
    let [p, q, r] = t.rest.map(plane);
    (q - p).perp_dot(r - p)
}

/// The smallest angle (degrees) of the triangles the primitives put in place.
fn worst_angle(prims: &[Prim]) -> f32 {
    let mut worst = 180.0f32;
    for p in prims {
        if let Prim::Tri { new: Some(t), .. } = p {
            worst = worst.min(min_angle(&t.rest.map(plane)));
        }
    }
    worst
}

/// The distance from `q` to segment `seg`.
pub(super) fn distance_to_segment(q: Vec2, (a, b): (Vec2, Vec2)) -> f32 {
    let d = b - a;
    let t = ((q - a).dot(d) / d.length_squared().max(1e-20)).clamp(0.0, 1.0);
    q.distance(a + d * t)
}
