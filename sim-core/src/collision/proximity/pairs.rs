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

use super::body_side;
use super::cloth_side::{ClothSearch, Part, run_parts};
use super::grid::Aabb;
use super::pair::{ClothView, NONE, Pair, PairCounts, ProximityParams, keep};
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
    /// The body side's threads' shares and scratch.
    body_parts: Vec<Part>,
    /// Scratch: (body vertex, cloth feature, pair among the corner-face pairs) of the
    /// corner-face pairs.
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
            self.body(cloth, body, p, reach);
        }
        if let Some(floor) = p.floor {
            self.floor(cloth, floor, p);
        }
        self.counts.with_energy = self.pairs.iter().filter(|q| q.energy).count();
        self.index_roles(cloth.x.len());
    }

    /// The cloth's vertices, edges and triangles against the body's triangles, creases
    /// and corners, each kind split over the threads and joined in order.
    fn body(&mut self, c: &ClothView<'_>, body: &Body, p: &ProximityParams, reach: f32) {
        let parts = &mut self.body_parts;
        run_parts(parts, p.threads, c.x.len(), |part, range| {
            body_side::vertex_face(c, body, p, reach, part, range)
        });
        self.counts.body_vertex_face += join_body(parts, &mut self.pairs, None);
        run_parts(parts, p.threads, c.edges.len(), |part, range| {
            body_side::edge_edge(c, body, p, reach, part, range)
        });
        self.counts.body_edge_edge += join_body(parts, &mut self.pairs, None);
        run_parts(parts, p.threads, c.tris.len(), |part, range| {
            body_side::corner_face(c, body, p, reach, part, range)
        });
        let first = self.pairs.len();
        self.corner_keys.clear();
        self.counts.body_corner_face +=
            join_body(parts, &mut self.pairs, Some(&mut self.corner_keys));
        body_side::one_energy_per_corner(&mut self.corner_keys, &mut self.pairs[first..]);
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

/// The parts' body pairs appended to `out` in order, and how many; with `keys`, their
/// corner keys too, renumbered to count from the first pair appended.
fn join_body(
    parts: &[Part],
    out: &mut Vec<Pair>,
    mut keys: Option<&mut Vec<(u32, u64, u32)>>,
) -> usize {
    let (first, mut n) = (out.len(), 0);
    for part in parts {
        let offset = (out.len() - first) as u32;
        if let Some(keys) = keys.as_deref_mut() {
            keys.extend(part.corner_keys.iter().map(|&(b, f, q)| (b, f, q + offset)));
        }
        out.extend_from_slice(&part.pairs);
        n += part.body;
    }
    n
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::body::sphere;
    use crate::collision::proximity::unique_edges;

    /// A 70 x 70 sheet (1 cm cells) lying 1-3 mm over the top of a 30 cm sphere, falling
    /// 2 mm onto it.
    fn sheet_on_a_sphere() -> (Vec<Vec3>, Vec<Aabb>, Vec<[u32; 3]>, Vec<Vec3>) {
        let (side, h, r) = (70usize, 0.01f32, 0.3f32);
        let (mut x, mut pattern, mut tris) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..side {
            for i in 0..side {
                let (px, pz) = ((i as f32 - 35.0) * h, (j as f32 - 35.0) * h);
                let top = (r * r - px * px - pz * pz).max(0.0).sqrt();
                let lift = 0.001 + 0.001 * ((i * 7 + j * 3) % 3) as f32;
                x.push(Vec3::new(px, top + lift, pz));
                pattern.push(Vec3::new(px, 0.0, pz));
            }
        }
        let at = |i: usize, j: usize| (j * side + i) as u32;
        for j in 0..side - 1 {
            for i in 0..side - 1 {
                tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let boxes = x
            .iter()
            .map(|&p| Aabb::point(p).with(p - Vec3::Y * 0.002).grown(0.0005))
            .collect();
        (x, boxes, tris, pattern)
    }

    #[test]
    fn the_body_search_is_the_same_on_any_number_of_threads() {
        let body = sphere(Vec3::ZERO, 0.3, 3).expect("a sphere");
        let (x, boxes, tris, pattern) = sheet_on_a_sphere();
        let edges = unique_edges(&tris);
        let free = vec![true; x.len()];
        let cloth = ClothView {
            x: &x,
            boxes: &boxes,
            tris: &tris,
            edges: &edges,
            pattern: &pattern,
            bridged: &[],
            free: &free,
        };
        let search = |threads: usize| {
            let params = ProximityParams {
                radius: 0.004,
                delta: 1e-4,
                rest_exclusion: 0.03,
                floor: None,
                threads,
            };
            let mut prox = Proximity::default();
            prox.detect(&cloth, Some(&body), &params);
            (prox.pairs, prox.counts)
        };
        let (pairs, counts) = search(1);
        assert!(
            counts.body_vertex_face > 100
                && counts.body_edge_edge > 100
                && counts.body_corner_face > 100,
            "{counts:?}"
        );
        // The same corner of the sphere against one cloth edge, found from both its
        // triangles, carries one energy.
        let corner_pairs = pairs.iter().filter(|q| q.side == [1, 1, 1, 0]);
        assert!(corner_pairs.clone().any(|q| q.energy));
        assert!(corner_pairs.clone().any(|q| !q.energy));
        for threads in [2, 3] {
            let (many, many_counts) = search(threads);
            assert_eq!(counts, many_counts, "{threads} threads");
            assert_eq!(pairs, many, "{threads} threads");
        }
        assert!(pairs.iter().all(|q| q.holds(&x, 1e-6)));
    }
}
