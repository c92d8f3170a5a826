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
//! they can neither touch nor push. So are pairs of neighbours in the pattern (which carry
//! no energy, below) whose boxes lie more than `delta` apart across an axis, before their
//! distances are worked out: most candidates in a smooth stretch of a fine cloth.
//!
//! An update ([`Proximity::update`], after some vertices' boxes changed and the others'
//! stayed) keeps the pairs whose vertices all kept their boxes: what those boxes let the
//! primitives reach is as it was, and the guard has kept each such pair's bound since it
//! was found. It searches again every pair of a primitive with a moved corner (cloth
//! vertices, edges and triangles against the cloth and the body), and the vertex-face
//! pairs of unmoved vertices against moved triangles; so it lists what a full search of
//! the same boxes would.
//!
//! The contact energy (a penalty on `r - gap`) is carried by a subset that counts each
//! contact once, as in Offset Geometric Contact (Chen et al. 2025): a vertex against the
//! nearest feature of the other surface it is over (face, edge or corner, once per
//! feature), edge interiors against edge interiors, and a body corner against a cloth
//! face or edge. Cloth pairs that are neighbours in the pattern (closer than
//! `rest_exclusion` there) carry no energy: the membrane holds them, and a fresh cut's
//! two sides would push each other apart; they keep only the no-crossing bound.

use std::sync::Arc;

use glam::Vec3;

use super::body_pairs;
use super::body_side::BodyGrids;
use super::cloth_side::{ClothSearch, Items, Part, join_parts, run_parts};
use super::grid::Aabb;
use super::incremental::{self, Changed, RoleIndex};
use super::pair::{ClothView, NONE, Pair, PairCounts, PairKind, ProximityParams, keep};
use crate::collision::body::Body;

/// The pairs of one frame, and each vertex's place in them.
#[derive(Clone, Debug, Default)]
pub struct Proximity {
    pub pairs: Vec<Pair>,
    /// Each vertex's pairs, `pair * 4 + slot`.
    roles: RoleIndex,
    pub counts: PairCounts,
    /// What the last update changed (an update keeps every other pair in its place).
    changed: Changed,
    /// Scratch for updates: the new pairs, and the energies given again.
    fresh: Vec<Pair>,
    flips: Vec<(u32, bool)>,
    /// The cloth against itself: its trees (built for the mesh when it is first searched
    /// and after [`Proximity::clear`]) and scratch.
    cloth: ClothSearch,
    /// The body side's threads' shares and scratch.
    body_parts: Vec<Part>,
    /// Scratch for updates: vertices against moved triangles, and
    /// [`incremental::nearest_feature_energy`]'s.
    near: Vec<(u32, u32)>,
    nearest: Vec<(u32, f32, [u32; 3], u32)>,
    /// Scratch for [`body_pairs::one_energy_per_corner`].
    corner_keys: Vec<(u32, u64, [u32; 3], u32)>,
    /// What the last search was of (`None`: nothing yet, or forgotten).
    searched: Option<Searched>,
}

/// What a search was of: the mesh's size, which vertices were free, the settings and the
/// body (its hashes, held so that no other body's can take their place). An update needs
/// the same.
#[derive(Clone, Debug)]
struct Searched {
    sizes: [usize; 3],
    free: Vec<bool>,
    settings: (f32, f32, f32, Option<f32>),
    body: Option<Arc<BodyGrids>>,
}

impl Searched {
    fn of(c: &ClothView<'_>, p: &ProximityParams, body: Option<&Body>) -> Self {
        Self {
            sizes: [c.x.len(), c.tris.len(), c.edges.len()],
            free: c.free.to_vec(),
            settings: (p.radius, p.delta, p.rest_exclusion, p.floor),
            body: body.map(|b| b.grids.clone()),
        }
    }

    fn matches(&self, c: &ClothView<'_>, p: &ProximityParams, body: Option<&Body>) -> bool {
        self.sizes == [c.x.len(), c.tris.len(), c.edges.len()]
            && self.free == c.free
            && self.settings == (p.radius, p.delta, p.rest_exclusion, p.floor)
            && match (&self.body, body) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, &b.grids),
                _ => false,
            }
    }
}

impl Proximity {
    /// The pairs vertex `i` is in, each as `pair * 4 + slot`.
    #[inline]
    pub fn roles(&self, i: usize) -> &[u32] {
        self.roles.of(i)
    }

    /// Forgets every pair and the mesh (the cloth was edited, or there is nothing to
    /// search).
    pub fn clear(&mut self) {
        self.clear_pairs();
        self.cloth.forget_mesh();
    }

    /// After an edit of the mesh (vertices `n..` gone, triangles and edges another
    /// list), before an update: forgets the pairs of the gone vertices, and takes the
    /// last search as of this mesh. The trees are built again for a list of another
    /// length, and refitted (exact, whatever the items now are) for one of the same.
    /// The caller updates every vertex whose primitives changed as moved
    /// ([`Proximity::update`]); the pairs of the others stay as the last search found
    /// them, as in any update (their primitives, boxes and freedom are as they were).
    pub fn follow_mesh(&mut self, c: &ClothView<'_>) {
        let Some(s) = &mut self.searched else {
            return;
        };
        let n = c.x.len();
        let shrank = n < s.sizes[0];
        s.sizes = [n, c.tris.len(), c.edges.len()];
        s.free = c.free.to_vec();
        if shrank {
            // The update that follows indexes what is left, and reads each vertex's pairs
            // in it.
            let gone = |q: &Pair| (0..4).any(|k| q.side[k] != 0 && q.v[k] as usize >= n);
            self.pairs.retain(|q| !gone(q));
            self.roles.build(&self.pairs, n);
        }
    }

    /// Whether `other` has the same pairs with a vertex `moved` (in any order, each's
    /// geometry to 1e-6): an update searches those again as a full search does, and
    /// keeps the others as the last search found them (a check of the incremental
    /// searches).
    #[cfg(debug_assertions)]
    pub fn same_pairs_of(&self, other: &Proximity, moved: &[bool]) -> bool {
        type Key = (u8, [u32; 4], [i64; 4]);
        let r = |f: f32| (f as f64 * 1e6).round() as i64;
        let of_moved =
            |q: &&Pair| (0..4).any(|k| q.side[k] != 0 && moved.get(q.v[k] as usize) == Some(&true));
        let sorted = |p: &Proximity| {
            let mut k: Vec<Key> = (p.pairs.iter().filter(of_moved))
                .map(|q| {
                    let g = [r(q.n.x), r(q.n.y), r(q.n.z), r(q.delta + q.offset + q.w[1])];
                    (q.kind as u8, q.v, g)
                })
                .collect();
            k.sort_unstable();
            k
        };
        let (a, b) = (sorted(self), sorted(other));
        if a != b {
            let only = |x: &[Key], y: &[Key]| {
                x.iter()
                    .filter(|k| !y.contains(k))
                    .take(6)
                    .cloned()
                    .collect::<Vec<_>>()
            };
            eprintln!("pairs of the moved: {} against {}", a.len(), b.len());
            eprintln!("only in this: {:?}", only(&a, &b));
            eprintln!("only in the other: {:?}", only(&b, &a));
        }
        a == b
    }

    fn clear_pairs(&mut self) {
        self.searched = None;
        self.pairs.clear();
        self.roles.clear();
        self.counts = PairCounts::default();
    }

    /// Finds the frame's pairs (see the module's doc).
    pub fn detect(&mut self, cloth: &ClothView<'_>, body: Option<&Body>, p: &ProximityParams) {
        self.detect_with(cloth, body, p, |_| {});
    }

    /// [`Proximity::detect`], and `also` given the pairs found as soon as they are final,
    /// on another thread while they are indexed when the search has more than one.
    pub fn detect_with(
        &mut self,
        cloth: &ClothView<'_>,
        body: Option<&Body>,
        p: &ProximityParams,
        also: impl FnOnce(&[Pair]) + Send,
    ) {
        self.clear_pairs();
        let reach = 0.5 * p.radius;
        self.cloth.search(cloth, p, reach, &mut self.pairs);
        let n = cloth.x.len();
        if let Some(body) = body {
            let (es, ts) = (Items::All(cloth.edges.len()), Items::All(cloth.tris.len()));
            let parts = &mut self.body_parts;
            Self::body(
                parts,
                cloth,
                body,
                p,
                Items::All(n),
                es,
                ts,
                &mut self.pairs,
            );
        }
        if let Some(floor) = p.floor {
            Self::floor(cloth, floor, p, Items::All(n), &mut self.pairs);
        }
        self.finish(n, p.threads, also);
        self.searched = Some(Searched::of(cloth, p, body));
    }

    /// Updates the pairs after the boxes of the vertices `moved` changed, the others'
    /// boxes being those of the last search, which was of this mesh with these settings
    /// (else this is [`Proximity::detect_with`]). The pairs of every primitive with a
    /// moved corner are searched again, and so are the cloth vertex-face pairs of the
    /// vertices near a moved triangle (each vertex's nearest feature gets the energy);
    /// the others are kept, their primitives' boxes and so what they can reach being as
    /// they were. The pairs are a full search's, in another order.
    ///
    /// When few vertices moved, the others' pairs keep their places in the list (but for
    /// a few moved down from its end), `also` is not called, the answer is true and
    /// [`Proximity::changed`] says where the update put things. Otherwise the list is
    /// made again, `also` is given it as [`Proximity::detect_with`] gives it, and the
    /// answer is false.
    pub fn update(
        &mut self,
        cloth: &ClothView<'_>,
        body: Option<&Body>,
        p: &ProximityParams,
        moved: &[bool],
        also: impl FnOnce(&[Pair]) + Send,
    ) -> bool {
        let n = cloth.x.len();
        let same = self
            .searched
            .as_ref()
            .is_some_and(|s| s.matches(cloth, p, body));
        if !same || moved.len() != n {
            self.detect_with(cloth, body, p, also);
            return false;
        }
        let reach = 0.5 * p.radius;
        let is_moved = |v: u32| moved.get(v as usize) == Some(&true);
        let moved_list: Vec<u32> = (0..n as u32).filter(|&v| is_moved(v)).collect();
        let dirty_tris: Vec<u32> = (0..cloth.tris.len() as u32)
            .filter(|&t| cloth.tris[t as usize].iter().any(|&v| is_moved(v)))
            .collect();
        let dirty_edges: Vec<u32> = (0..cloth.edges.len() as u32)
            .filter(|&e| cloth.edges[e as usize].iter().any(|&v| is_moved(v)))
            .collect();
        // The vertices that did not move whose vertex-face pairs change: over a moved
        // triangle before (found through the moved corners' pairs), or near one now.
        // Their nearest features are chosen again.
        let mut affected = vec![false; n];
        for &v in &moved_list {
            for &r in self.roles(v as usize) {
                let q = &self.pairs[(r / 4) as usize];
                if r % 4 != 0 && q.kind == PairKind::VertexFace {
                    affected[q.v[0] as usize] = true;
                }
            }
        }
        let mut near = std::mem::take(&mut self.near);
        self.cloth
            .prepare_update(cloth, reach, &dirty_tris, moved, &mut near);
        for &(i, _) in &near {
            affected[i as usize] = true;
        }
        let mut fresh = std::mem::take(&mut self.fresh);
        fresh.clear();
        let is_dirty = |e: u32| cloth.edges[e as usize].iter().any(|&v| is_moved(v));
        let (vs, es) = (&moved_list, &dirty_edges);
        self.cloth
            .update(cloth, p, reach, vs, &near, es, is_dirty, &mut fresh);
        self.near = near;
        if let Some(body) = body {
            let (vs, es, ts) = (Items::Only(vs), Items::Only(es), Items::Only(&dirty_tris));
            Self::body(&mut self.body_parts, cloth, body, p, vs, es, ts, &mut fresh);
        }
        if let Some(floor) = p.floor {
            Self::floor(cloth, floor, p, Items::Only(&moved_list), &mut fresh);
        }
        if moved_list.len() * IN_PLACE_UP_TO > n || !self.roles.covers(n) {
            // Many renewed (a cloth still falling): the list is made again in the
            // search's order, which keeps the guard's passes over it near in memory.
            // So it is after an edit that added vertices.
            let is_gone = |q: &Pair| (0..4).any(|k| q.side[k] != 0 && is_moved(q.v[k]));
            self.pairs.retain(|q| !is_gone(q));
            self.pairs.append(&mut fresh);
            self.fresh = fresh;
            let each = self.pairs.iter().enumerate();
            let face = |q: &Pair| q.kind == PairKind::VertexFace && affected[q.v[0] as usize];
            let ks: Vec<u32> = each
                .filter_map(|(k, q)| face(q).then_some(k as u32))
                .collect();
            let (scratch, flips) = (&mut self.nearest, &mut self.flips);
            incremental::nearest_feature_energy(cloth, p, &mut self.pairs, &ks, scratch, flips);
            self.finish(n, p.threads, also);
            return false;
        }
        let (pairs, counts, ch) = (&mut self.pairs, &mut self.counts, &mut self.changed);
        incremental::splice(
            pairs,
            &mut self.roles,
            n,
            vs,
            is_moved,
            &mut fresh,
            counts,
            ch,
        );
        self.fresh = fresh;
        // The energies: each affected vertex's vertex-face pairs (its own, slot 0), then
        // one per body corner and cloth edge.
        let mut ks = Vec::new();
        for i in (0..n).filter(|&i| affected[i]) {
            let own = self.roles.of(i).iter().filter(|&&r| r % 4 == 0);
            let face = |&&r: &&u32| self.pairs[(r / 4) as usize].kind == PairKind::VertexFace;
            ks.extend(own.filter(face).map(|&r| r / 4));
        }
        let flips = &mut self.flips;
        flips.clear();
        let scratch = &mut self.nearest;
        incremental::nearest_feature_energy(cloth, p, &mut self.pairs, &ks, scratch, flips);
        body_pairs::one_energy_per_corner(&mut self.pairs, &mut self.corner_keys, flips);
        incremental::settle_energy(&self.pairs, flips, &mut self.counts, &mut self.changed);
        #[cfg(debug_assertions)]
        {
            debug_assert_eq!(self.counts, PairCounts::of(&self.pairs));
            debug_assert!(self.roles.same_as_built(&self.pairs, n));
        }
        true
    }

    /// Where the last [`Proximity::update`] that kept pairs put them.
    pub fn changed(&self) -> &Changed {
        &self.changed
    }

    /// After a search: one energy per body corner and cloth edge, then the counts and
    /// each vertex's pairs, with `also` given the final pairs meanwhile (on a second
    /// thread when there are enough pairs to be worth the handoff: the caller's pass over
    /// them, the guard's reach, costs about what the indexing does).
    fn finish(&mut self, n: usize, threads: usize, also: impl FnOnce(&[Pair]) + Send) {
        self.flips.clear();
        body_pairs::one_energy_per_corner(&mut self.pairs, &mut self.corner_keys, &mut self.flips);
        let (pairs, roles) = (&self.pairs, &mut self.roles);
        let mut index = || {
            roles.build(pairs, n);
            PairCounts::of(pairs)
        };
        self.counts = if threads > 1 && pairs.len() >= FINISH_PARALLEL_FROM {
            std::thread::scope(|s| {
                s.spawn(|| also(pairs));
                index()
            })
        } else {
            also(pairs);
            index()
        };
    }

    /// Cloth vertices `vs`, edges `es` and triangles `ts` against the body's triangles,
    /// creases and corners, each kind split over the threads and joined in order to
    /// `out`.
    #[allow(clippy::too_many_arguments)]
    fn body(
        parts: &mut Vec<Part>,
        c: &ClothView<'_>,
        body: &Body,
        p: &ProximityParams,
        vs: Items<'_>,
        es: Items<'_>,
        ts: Items<'_>,
        out: &mut Vec<Pair>,
    ) {
        let reach = 0.5 * p.radius;
        run_parts(parts, p.threads, vs.len(), |part, range| {
            vs.each(range, |i| {
                body_pairs::vertex_face(c, body, p, reach, part, i)
            })
        });
        join_parts(parts, out);
        run_parts(parts, p.threads, es.len(), |part, range| {
            es.each(range, |e| body_pairs::edge_edge(c, body, p, reach, part, e))
        });
        join_parts(parts, out);
        run_parts(parts, p.threads, ts.len(), |part, range| {
            ts.each(range, |t| {
                body_pairs::corner_face(c, body, p, reach, part, t)
            })
        });
        join_parts(parts, out);
    }

    fn floor(
        c: &ClothView<'_>,
        floor: f32,
        p: &ProximityParams,
        vs: Items<'_>,
        out: &mut Vec<Pair>,
    ) {
        vs.each(0..vs.len(), |i| {
            let b = c.boxes[i];
            if !c.free[i] || !b.is_finite() || b.lo.y - floor >= p.radius {
                return;
            }
            let sep0 = c.x[i].y - floor;
            out.push(Pair {
                v: [i as u32, NONE, NONE, NONE],
                w: [1.0, 0.0, 0.0, 0.0],
                side: [1, 0, 0, 0],
                n: Vec3::Y,
                offset: -floor,
                body_bound: floor,
                delta: keep(p.delta, sep0),
                energy: true,
                kind: PairKind::Floor,
                body_vertex: NONE,
            });
        });
    }

    /// Whether every pair keeps its bound at `x` (for tests and debug checks).
    pub fn all_hold(&self, x: &[Vec3], slack: f32) -> bool {
        self.pairs.iter().all(|q| q.holds(x, slack))
    }
}

/// An update that renews at most one vertex in this many changes the pair list in place
/// ([`incremental::splice`]); one renewing more lists the pairs again in the search's
/// order. (In place throughout, the 128 x 128 drape's 200 landing frames took 20-35%
/// longer: docs/collision.md.)
const IN_PLACE_UP_TO: usize = 32;

/// Pairs from which [`Proximity::finish`] hands its caller's pass to a second thread
/// (a handoff costs 36-126 µs on the development VM; the guard's reach, about 12 ns a
/// pair).
const FINISH_PARALLEL_FROM: usize = 20_000;

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

/// A `side` x `side` sheet of 1 cm cells lying 1-3 mm over the top of a 30 cm sphere at
/// the origin: positions, triangles and places in the pattern (for tests).
#[cfg(test)]
pub(super) fn sheet_over_a_sphere(side: usize) -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec3>) {
    let (h, r, half) = (0.01f32, 0.3f32, (side / 2) as f32);
    let (mut x, mut pattern, mut tris) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..side {
        for i in 0..side {
            let (px, pz) = ((i as f32 - half) * h, (j as f32 - half) * h);
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
    (x, tris, pattern)
}

#[cfg(test)]
mod tests;
