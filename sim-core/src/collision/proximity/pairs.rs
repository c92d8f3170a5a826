//! The proximity search: every pair of primitives that could come near each other over
//! the coming frame, each with the direction that separates them now.
//!
//! Each cloth vertex is given a *motion box* before the search: the box of its
//! predicted path over the frame, grown by how far it may stray from it. The solver keeps
//! every vertex inside its box ([`super::guard`]), so a primitive never leaves the box of
//! its corners' boxes. Two primitives whose boxes, each grown by half the contact
//! distance `r`, do not overlap therefore stay at least `r` apart all frame. The pairs
//! whose grown boxes overlap are listed, as
//!
//! - a cloth vertex against a cloth triangle (self, vertex-face) or a body triangle,
//! - a cloth edge against a cloth edge (self, edge-edge) or a body edge,
//! - a cloth triangle against a body vertex,
//! - a cloth vertex against the floor,
//!
//! each with the unit direction `n` from the closest point of the second primitive to the
//! closest point of the first (the plane through either closest point, square to `n`,
//! separates the two convex primitives: Ericson 2005, 5.1). A pair stays apart while every
//! corner of the first keeps `n . x` above every corner of the second by `delta`
//! ([`Pair::bound_for`]): both are convex hulls of their corners, and the straight path
//! between two such states keeps it too (the difference of the projections is linear
//! along it). Listed pairs whose boxes cannot bring them within `r` along `n` are dropped:
//! they can neither touch nor push.
//!
//! The contact energy (a penalty on `r - gap`) is carried by a subset that counts each
//! contact once, as in Offset Geometric Contact (Chen et al. 2025): a vertex against the
//! nearest feature of the other surface it is over (face, edge or corner, once per
//! feature), edge interiors against edge interiors, and a body corner against a cloth
//! face or edge. Cloth pairs that are neighbours in the pattern (closer than
//! `rest_exclusion` there) carry no energy: the membrane holds them, and a fresh cut's
//! two sides would push each other apart; they keep only the no-crossing bound.

use glam::Vec3;

use super::body_side::BodyGrids;
use super::cloth_side::ClothSearch;
use super::distance::{point_triangle, segment_segment};
use super::grid::Aabb;
use super::pair::{
    ClothView, NONE, Pair, PairCounts, ProximityParams, feature_key, keep, min_along, separating,
};
use crate::collision::body::Body;

/// The pairs of one frame, and each vertex's place in them.
#[derive(Clone, Debug, Default)]
pub struct Proximity {
    pub pairs: Vec<Pair>,
    /// Vertex `i` is in pairs `roles[start[i]..start[i + 1]]`, each `pair * 4 + slot`.
    start: Vec<u32>,
    roles: Vec<u32>,
    pub counts: PairCounts,
    /// The cloth against itself: its trees (built for the mesh when it is first searched
    /// and after [`Proximity::clear`]) and scratch.
    cloth: ClothSearch,
    /// Scratch: features already given energy for the vertex being searched.
    seen: Vec<u64>,
    /// Scratch: (body vertex, cloth feature, pair) of the corner-face pairs.
    corner_keys: Vec<(u32, u64, u32)>,
}

impl Proximity {
    /// The pairs vertex `i` is in, each as `pair * 4 + slot`.
    #[inline]
    pub fn roles(&self, i: usize) -> &[u32] {
        match (self.start.get(i), self.start.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.roles[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Forgets every pair and the mesh (the cloth was edited, or there is nothing to
    /// search).
    pub fn clear(&mut self) {
        self.clear_pairs();
        self.cloth.forget_mesh();
    }

    fn clear_pairs(&mut self) {
        self.pairs.clear();
        self.start.clear();
        self.roles.clear();
        self.counts = PairCounts::default();
    }

    /// Finds the frame's pairs (see the module's doc).
    pub fn detect(&mut self, cloth: &ClothView<'_>, body: Option<&Body>, p: &ProximityParams) {
        self.clear_pairs();
        let reach = 0.5 * p.radius;
        self.cloth
            .search(cloth, p, reach, &mut self.pairs, &mut self.counts);
        if let Some(body) = body {
            let grids = &*body.grids;
            self.body_vertex_face(cloth, body, grids, p, reach);
            self.body_edge_edge(cloth, body, grids, p, reach);
            self.body_corner_face(cloth, body, grids, p, reach);
        }
        if let Some(floor) = p.floor {
            self.floor(cloth, floor, p);
        }
        self.counts.with_energy = self.pairs.iter().filter(|q| q.energy).count();
        self.index_roles(cloth.x.len());
    }

    /// A pair of cloth vertices `vs` (weights `w`) with the body, closest points `on_cloth`
    /// and `on_body`; `corners` are the body primitive's corners.
    #[allow(clippy::too_many_arguments)]
    fn push_body(
        &mut self,
        c: &ClothView<'_>,
        vs: &[u32],
        w: &[f32],
        on_cloth: Vec3,
        on_body: Vec3,
        corners: &[Vec3],
        fallback: Vec3,
        energy: bool,
        p: &ProximityParams,
    ) -> bool {
        let cloth_pts: Vec<Vec3> = vs.iter().map(|&v| c.x[v as usize]).collect();
        let (n, sep0) = separating(&cloth_pts, corners, on_cloth, on_body, fallback);
        let body_bound = corners
            .iter()
            .map(|b| n.dot(*b))
            .fold(f32::NEG_INFINITY, f32::max);
        let gap_max = min_along(c.boxes, vs, n) - body_bound;
        if gap_max >= p.radius {
            return false;
        }
        let mut pair = Pair {
            v: [NONE; 4],
            w: [0.0; 4],
            side: [0; 4],
            n,
            offset: -n.dot(on_body),
            body_bound,
            delta: keep(p.delta, sep0),
            energy,
        };
        for (k, (&v, &wk)) in vs.iter().zip(w).enumerate() {
            pair.v[k] = v;
            pair.w[k] = wk;
            pair.side[k] = 1;
        }
        self.pairs.push(pair);
        true
    }

    fn body_vertex_face(
        &mut self,
        c: &ClothView<'_>,
        body: &Body,
        grids: &BodyGrids,
        p: &ProximityParams,
        reach: f32,
    ) {
        let at = |i: u32| body.vertices[i as usize];
        let mut found: Vec<u32> = Vec::new();
        for i in 0..c.x.len() {
            let b = c.boxes[i];
            if !c.free[i] || !b.is_finite() {
                continue;
            }
            found.clear();
            grids.triangles.query(&b.grown(reach), |t| found.push(t));
            let xi = c.x[i];
            let mut near: Vec<(f32, u32, Vec3, [f32; 3])> = found
                .iter()
                .map(|&t| {
                    let [a, bb, cc] = body.triangles[t as usize].map(at);
                    let (q, w) = point_triangle(xi, a, bb, cc);
                    ((xi - q).length(), t, q, w)
                })
                .collect();
            near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            self.seen.clear();
            for (_, t, q, w) in near {
                let tri = body.triangles[t as usize];
                let key = feature_key(tri, t, w);
                let energy = !self.seen.contains(&key);
                let corners = tri.map(at);
                let normal = body.face_normal(t);
                if self.push_body(c, &[i as u32], &[1.0], xi, q, &corners, normal, energy, p) {
                    self.counts.body_vertex_face += 1;
                    if energy {
                        self.seen.push(key);
                    }
                }
            }
        }
    }

    fn body_edge_edge(
        &mut self,
        c: &ClothView<'_>,
        body: &Body,
        grids: &BodyGrids,
        p: &ProximityParams,
        reach: f32,
    ) {
        let at = |i: u32| body.vertices[i as usize];
        let mut found: Vec<u32> = Vec::new();
        for e in c.edges {
            if !c.free[e[0] as usize] && !c.free[e[1] as usize] {
                continue;
            }
            let eb = c.boxes[e[0] as usize].union(c.boxes[e[1] as usize]);
            if !eb.is_finite() {
                continue;
            }
            found.clear();
            grids.edge_grid.query(&eb.grown(reach), |f| found.push(f));
            for &f in &found {
                let [q0, q1] = grids.edges[f as usize].map(at);
                let [p0, p1] = e.map(|v| c.x[v as usize]);
                let (s, t) = segment_segment(p0, p1, q0, q1);
                let interior = s > 1e-4 && s < 1.0 - 1e-4 && t > 1e-4 && t < 1.0 - 1e-4;
                let fallback = (p1 - p0).cross(q1 - q0);
                if self.push_body(
                    c,
                    e,
                    &[1.0 - s, s],
                    p0.lerp(p1, s),
                    q0.lerp(q1, t),
                    &[q0, q1],
                    fallback,
                    interior,
                    p,
                ) {
                    self.counts.body_edge_edge += 1;
                }
            }
        }
    }

    fn body_corner_face(
        &mut self,
        c: &ClothView<'_>,
        body: &Body,
        grids: &BodyGrids,
        p: &ProximityParams,
        reach: f32,
    ) {
        let mut found: Vec<u32> = Vec::new();
        self.corner_keys.clear();
        for (ti, t) in c.tris.iter().enumerate() {
            if t.iter().all(|&v| !c.free[v as usize]) {
                continue;
            }
            let tb = t
                .iter()
                .fold(Aabb::EMPTY, |b, &v| b.union(c.boxes[v as usize]));
            if !tb.is_finite() {
                continue;
            }
            found.clear();
            grids.vertices.query(&tb.grown(reach), |b| found.push(b));
            for &slot in &found {
                let bv = grids.corners[slot as usize];
                let b = body.vertices[bv as usize];
                let [x0, x1, x2] = t.map(|v| c.x[v as usize]);
                let (q, w) = point_triangle(b, x0, x1, x2);
                let key = feature_key(*t, ti as u32, w);
                // A body corner against a cloth corner is the cloth vertex's contact.
                let corner_of_cloth = key >> 62 == 3;
                let fallback = (x1 - x0).cross(x2 - x0);
                let before = self.pairs.len() as u32;
                if self.push_body(c, t, &w, q, b, &[b], fallback, !corner_of_cloth, p) {
                    self.counts.body_corner_face += 1;
                    if !corner_of_cloth {
                        self.corner_keys.push((bv, key, before));
                    }
                }
            }
        }
        // One energy per (body corner, cloth feature): an edge is found from both its
        // triangles.
        self.corner_keys.sort_unstable();
        for k in 1..self.corner_keys.len() {
            let (a, b) = (self.corner_keys[k - 1], self.corner_keys[k]);
            if (a.0, a.1) == (b.0, b.1) {
                self.pairs[b.2 as usize].energy = false;
            }
        }
    }

    fn floor(&mut self, c: &ClothView<'_>, floor: f32, p: &ProximityParams) {
        for i in 0..c.x.len() {
            let b = c.boxes[i];
            if !c.free[i] || !b.is_finite() || b.lo.y - floor >= p.radius {
                continue;
            }
            let sep0 = c.x[i].y - floor;
            self.pairs.push(Pair {
                v: [i as u32, NONE, NONE, NONE],
                w: [1.0, 0.0, 0.0, 0.0],
                side: [1, 0, 0, 0],
                n: Vec3::Y,
                offset: -floor,
                body_bound: floor,
                delta: keep(p.delta, sep0),
                energy: true,
            });
            self.counts.floor += 1;
        }
    }

    /// Each vertex's pairs, by counting sort.
    fn index_roles(&mut self, n: usize) {
        self.start.clear();
        self.start.resize(n + 1, 0);
        for q in &self.pairs {
            for k in 0..4 {
                if q.side[k] != 0 && (q.v[k] as usize) < n {
                    self.start[q.v[k] as usize + 1] += 1;
                }
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        self.roles.clear();
        self.roles.resize(self.start[n] as usize, 0);
        let mut fill = self.start.clone();
        for (pi, q) in self.pairs.iter().enumerate() {
            for k in 0..4 {
                if q.side[k] != 0 && (q.v[k] as usize) < n {
                    let v = q.v[k] as usize;
                    self.roles[fill[v] as usize] = (pi * 4 + k) as u32;
                    fill[v] += 1;
                }
            }
        }
    }

    /// Whether every pair keeps its bound at `x` (for tests and debug checks).
    pub fn all_hold(&self, x: &[Vec3], slack: f32) -> bool {
        self.pairs.iter().all(|q| q.holds(x, slack))
    }
}

/// A hash cell for a set of boxes: about their mean size, at least 2 mm.
pub(super) fn grid_cell(boxes: impl Iterator<Item = Aabb>) -> f32 {
    let (mut sum, mut n) = (0.0f32, 0usize);
    for b in boxes.step_by(7) {
        if b.is_finite() {
            sum += (b.hi - b.lo).max_element();
            n += 1;
        }
    }
    if n == 0 {
        0.01
    } else {
        (sum / n as f32).max(0.002)
    }
}
