//! The cloth against itself: every cloth vertex against the cloth's triangles, every cloth
//! edge against its edges, through the trees of `bvh.rs`. The work is split over threads
//! by vertex and by candidate edge pair; each thread lists its own pairs and the lists are
//! joined in order, so the result is the same whatever the thread count. An update looks
//! from the moved vertices and edges only, and finds the unmoved vertices near a moved
//! triangle through a tree over the vertices.

use std::ops::Range;

use glam::Vec3;

use super::bvh::Bvh;
use super::distance::{point_triangle, segment_segment};
use super::grid::Aabb;
use super::pair::{
    ClothView, NONE, Pair, PairKind, ProximityParams, boxes_apart, feature_key, keep, max_along,
    min_along, separating, triple_sign,
};

/// Below this many items a search runs on one thread (starting one costs more).
const PER_THREAD_MIN: usize = 2048;

/// Pairs of edges (or of tree nodes), by index.
type EdgePairs = Vec<(u32, u32)>;

/// One thread's share of a search, and its scratch.
#[derive(Clone, Debug, Default)]
pub(super) struct Part {
    pub(super) pairs: Vec<Pair>,
    pub(super) seen: Vec<u64>,
    pub(super) found: Vec<u32>,
    pub(super) near: Vec<(f32, u32, Vec3, [f32; 3])>,
    stack: Vec<u32>,
}

/// The primitives (vertices, edges or triangles) a search looks from: all `0..n`, or
/// those listed.
#[derive(Clone, Copy, Debug)]
pub(super) enum Items<'a> {
    All(usize),
    Only(&'a [u32]),
}

impl Items<'_> {
    pub(super) fn len(&self) -> usize {
        match self {
            Items::All(n) => *n,
            Items::Only(list) => list.len(),
        }
    }

    /// Calls `f` on the items `range` of the list.
    pub(super) fn each(&self, range: Range<usize>, f: impl FnMut(usize)) {
        match self {
            Items::All(_) => range.for_each(f),
            Items::Only(list) => list[range].iter().map(|&i| i as usize).for_each(f),
        }
    }
}

/// Runs `work` over `0..len` in up to `threads` parts (in order) and gives each part's
/// range to it.
pub(super) fn run_parts(
    parts: &mut Vec<Part>,
    threads: usize,
    len: usize,
    work: impl Fn(&mut Part, Range<usize>) + Sync,
) {
    let t = threads.clamp(1, 16).min(len / PER_THREAD_MIN).max(1);
    if parts.len() < t {
        parts.resize_with(t, Part::default);
    }
    for part in parts.iter_mut() {
        part.pairs.clear();
    }
    let range = |k: usize| k * len / t..(k + 1) * len / t;
    if t == 1 {
        work(&mut parts[0], 0..len);
        return;
    }
    std::thread::scope(|s| {
        let work = &work;
        for (k, part) in parts.iter_mut().take(t).enumerate() {
            s.spawn(move || work(part, range(k)));
        }
    });
}

/// The cloth-cloth search: the trees over the cloth's triangles and edges, and scratch.
#[derive(Clone, Debug, Default)]
pub struct ClothSearch {
    tri_tree: Bvh,
    edge_tree: Bvh,
    /// Over the vertices, for updates only (built at the first).
    vertex_tree: Bvh,
    candidates: Vec<(u32, u32)>,
    /// Scratch for finding the candidates: the tree's node pairs shared between the
    /// threads, each thread's stack and the candidates it found, and each edge's first
    /// candidate for putting them in order.
    tasks: Vec<(u32, u32)>,
    found: Vec<(EdgePairs, EdgePairs)>,
    bucket: Vec<u32>,
    stack: Vec<u32>,
    parts: Vec<Part>,
}

impl ClothSearch {
    /// Forgets the trees (the mesh changed); the next search builds them again.
    pub fn forget_mesh(&mut self) {
        self.tri_tree = Bvh::default();
        self.edge_tree = Bvh::default();
        self.vertex_tree = Bvh::default();
    }

    /// Builds the trees for this mesh, unless they are built for it already.
    fn trees_for(&mut self, c: &ClothView<'_>) {
        let center = |vs: &[u32]| {
            vs.iter()
                .map(|&v| c.x.get(v as usize).copied().unwrap_or(Vec3::ZERO))
                .sum::<Vec3>()
                / vs.len() as f32
        };
        if self.tri_tree.len() != c.tris.len() || self.tri_tree.is_empty() {
            let centers: Vec<Vec3> = c.tris.iter().map(|t| center(t)).collect();
            self.tri_tree = Bvh::build(&centers);
        }
        if self.edge_tree.len() != c.edges.len() || self.edge_tree.is_empty() {
            let centers: Vec<Vec3> = c.edges.iter().map(|e| center(e)).collect();
            self.edge_tree = Bvh::build(&centers);
        }
    }

    /// Refits the trees to the boxes of `c` (grown by `reach`); with `vertices`, the
    /// vertex tree too (built if need be).
    fn refit(&mut self, c: &ClothView<'_>, reach: f32, vertices: bool) {
        self.trees_for(c);
        self.tri_tree
            .refit(c.tris.iter().map(|t| tri_box(c, t, reach)));
        self.edge_tree
            .refit(c.edges.iter().map(|e| edge_box(c, e, reach)));
        if vertices {
            if self.vertex_tree.len() != c.x.len() || self.vertex_tree.is_empty() {
                self.vertex_tree = Bvh::build(c.x);
            }
            self.vertex_tree
                .refit(c.boxes.iter().map(|b| b.grown(reach)));
        }
    }

    /// The cloth-cloth pairs, vertex-face then edge-edge, appended to `out`.
    pub fn search(
        &mut self,
        c: &ClothView<'_>,
        p: &ProximityParams,
        reach: f32,
        out: &mut Vec<Pair>,
    ) {
        self.refit(c, reach, false);
        self.vertex_face(c, p, reach, Items::All(c.x.len()), out);
        let threads = p
            .threads
            .clamp(1, 16)
            .min(c.edges.len() / PER_THREAD_MIN)
            .max(1);
        self.overlapping_edges(c, threads);
        // In edge order, whatever the tree's shape and the threads.
        let mut candidates = std::mem::take(&mut self.candidates);
        let lists = self.found[..threads]
            .iter()
            .map(|(list, _)| list.as_slice());
        in_order(lists, c.edges.len(), &mut self.bucket, &mut candidates);
        self.edge_edge(c, p, &candidates, out);
        self.candidates = candidates;
    }

    /// Before an update ([`ClothSearch::update`]): refits the trees to the boxes of `c`,
    /// and lists in `near` each vertex that did not move against each triangle of `dirty`
    /// (those with a moved corner) whose boxes meet, in order.
    pub fn prepare_update(
        &mut self,
        c: &ClothView<'_>,
        reach: f32,
        dirty: &[u32],
        moved: &[bool],
        near: &mut Vec<(u32, u32)>,
    ) {
        self.refit(c, reach, true);
        near.clear();
        let stack = &mut self.stack;
        for &t in dirty {
            let tri = c.tris[t as usize];
            let b = tri_box(c, &tri, reach);
            self.vertex_tree.query(&b, stack, |i| {
                if !moved[i as usize] && !tri.contains(&i) {
                    near.push((i, t));
                }
            });
        }
        near.sort_unstable();
    }

    /// The cloth pairs of the primitives that moved, appended to `out`: every
    /// vertex-face pair of vertices `moved`, those of the vertices and triangles `near`
    /// (their energy: whether they may carry it; [`super::incremental::nearest_feature_energy`] chooses), and
    /// every edge-edge pair of edges `dirty` (`is_dirty` of an edge says whether it is
    /// listed; a pair of two listed edges comes once).
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        c: &ClothView<'_>,
        p: &ProximityParams,
        reach: f32,
        moved: &[u32],
        near: &[(u32, u32)],
        dirty: &[u32],
        is_dirty: impl Fn(u32) -> bool,
        out: &mut Vec<Pair>,
    ) {
        self.vertex_face(c, p, reach, Items::Only(moved), out);
        for &(i, t) in near {
            let [a, b, cc] = c.tris[t as usize].map(|v| c.x[v as usize]);
            let found = point_triangle(c.x[i as usize], a, b, cc);
            out.extend(vertex_tri(c, p, i, t, found));
        }
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        let stack = &mut self.stack;
        for &a in dirty {
            let b = edge_box(c, &c.edges[a as usize], reach);
            self.edge_tree.query(&b, stack, |f| {
                if f != a && !(f < a && is_dirty(f)) && may_pair(c, a, f) {
                    candidates.push((a.min(f), a.max(f)));
                }
            });
        }
        candidates.sort_unstable();
        self.edge_edge(c, p, &candidates, out);
        self.candidates = candidates;
    }

    /// Vertices `items` against the cloth's triangles (the tree refitted).
    fn vertex_face(
        &mut self,
        c: &ClothView<'_>,
        p: &ProximityParams,
        reach: f32,
        items: Items<'_>,
        out: &mut Vec<Pair>,
    ) {
        let tree = &self.tri_tree;
        run_parts(&mut self.parts, p.threads, items.len(), |part, range| {
            items.each(range, |i| vertex_face(c, tree, p, reach, part, i))
        });
        join_parts(&self.parts, out);
    }

    /// Edge pairs `found` (their boxes overlap) tested.
    fn edge_edge(
        &mut self,
        c: &ClothView<'_>,
        p: &ProximityParams,
        found: &[(u32, u32)],
        out: &mut Vec<Pair>,
    ) {
        run_parts(&mut self.parts, p.threads, found.len(), |part, range| {
            edge_edge(c, p, &found[range], part)
        });
        join_parts(&self.parts, out);
    }
}

/// A cloth triangle's box for the trees: its corners' boxes, grown by `reach`.
fn tri_box(c: &ClothView<'_>, t: &[u32; 3], reach: f32) -> Aabb {
    t.iter()
        .fold(Aabb::EMPTY, |b, &v| b.union(c.boxes[v as usize]))
        .grown(reach)
}

/// A cloth edge's box for the trees.
fn edge_box(c: &ClothView<'_>, e: &[u32; 2], reach: f32) -> Aabb {
    c.boxes[e[0] as usize]
        .union(c.boxes[e[1] as usize])
        .grown(reach)
}

/// The pairs of `lists` (each `(a, b)` with `a < b < n`) sorted into `out`: counted into
/// buckets by `a`, then each bucket (a few pairs) sorted by `b`. A comparison sort of the
/// 100,000-180,000 candidates of a 64 x 64 cloth on the mannequin took 2-4 ms, as long
/// as finding them.
fn in_order<'a>(
    lists: impl Iterator<Item = &'a [(u32, u32)]> + Clone,
    n: usize,
    bucket: &mut Vec<u32>,
    out: &mut Vec<(u32, u32)>,
) {
    bucket.clear();
    bucket.resize(n + 1, 0);
    for &(a, _) in lists.clone().flatten() {
        bucket[a as usize + 1] += 1;
    }
    for k in 0..n {
        bucket[k + 1] += bucket[k];
    }
    out.clear();
    out.resize(bucket[n] as usize, (0, 0));
    for &(a, b) in lists.flatten() {
        let slot = &mut bucket[a as usize];
        out[*slot as usize] = (a, b);
        *slot += 1;
    }
    // `bucket[a]` is now where `a`'s pairs end, and so where `a + 1`'s begin.
    let mut begin = 0;
    for &end in &bucket[..n] {
        out[begin..end as usize].sort_unstable();
        begin = end as usize;
    }
}

impl ClothSearch {
    /// The edge pairs whose (refitted) boxes overlap and that may be a pair, into
    /// `found[..threads]`'s lists: the tree's node pairs dealt out to the threads in turn.
    fn overlapping_edges(&mut self, c: &ClothView<'_>, threads: usize) {
        if self.found.len() < threads {
            self.found.resize_with(threads, Default::default);
        }
        let tree = &self.edge_tree;
        let may = |a: u32, b: u32| may_pair(c, a, b);
        if threads == 1 {
            let (list, stack) = &mut self.found[0];
            list.clear();
            tree.self_pairs(stack, |a, b| list.extend(may(a, b).then_some((a, b))));
            return;
        }
        tree.self_pair_tasks(16 * threads, &mut self.tasks);
        let tasks = &self.tasks;
        std::thread::scope(|s| {
            for (k, (list, stack)) in self.found.iter_mut().take(threads).enumerate() {
                s.spawn(move || {
                    let mine: Vec<(u32, u32)> =
                        tasks.iter().skip(k).step_by(threads).copied().collect();
                    list.clear();
                    let keep = |a, b| list.extend(may(a, b).then_some((a, b)));
                    tree.self_pairs_from(&mine, stack, keep);
                });
            }
        });
    }
}

/// The parts' pairs appended to `out` in order.
pub(super) fn join_parts(parts: &[Part], out: &mut Vec<Pair>) {
    for part in parts {
        out.extend_from_slice(&part.pairs);
    }
}

/// Vertex `i` against the cloth's triangles (`tree`, refitted), nearest first, so the
/// feature of the cloth it is over gets the energy (once per feature).
fn vertex_face(
    c: &ClothView<'_>,
    tree: &Bvh,
    p: &ProximityParams,
    reach: f32,
    part: &mut Part,
    i: usize,
) {
    let b = c.boxes[i];
    if !b.is_finite() {
        return;
    }
    let Part {
        found, near, stack, ..
    } = part;
    found.clear();
    tree.query(&b.grown(reach), stack, |t| found.push(t));
    let xi = c.x[i];
    near.clear();
    // Neighbours in the pattern carry no energy, so they are pairs only where their boxes
    // meet: most of the candidates in a smooth stretch of cloth, dropped before the
    // distances are worked out.
    // So are those `vertex_tri` refuses (its own, all held with it).
    let held = !c.free[i];
    found.retain(|&t| {
        let tri = &c.tris[t as usize];
        !(tri.contains(&(i as u32))
            || (held && tri.iter().all(|&v| !c.free[v as usize]))
            || (boxes_apart(c.boxes, &[i as u32], tri, p.delta)
                && c.rest_near(&[i as u32], tri, p.rest_exclusion)))
    });
    near.extend(found.iter().map(|&t| {
        let [a, bb, cc] = c.tris[t as usize].map(|v| c.x[v as usize]);
        let (q, w) = point_triangle(xi, a, bb, cc);
        ((xi - q).length(), t, q, w)
    }));
    near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    part.seen.clear();
    for k in 0..part.near.len() {
        let (_, t, q, w) = part.near[k];
        let Some(mut pair) = vertex_tri(c, p, i as u32, t, (q, w)) else {
            continue;
        };
        if pair.energy {
            let key = feature_key(c.tris[t as usize], t, w);
            if part.seen.contains(&key) {
                pair.energy = false;
            } else {
                part.seen.push(key);
            }
        }
        part.pairs.push(pair);
    }
}

/// Vertex `i` against triangle `t`, `(q, w)` the triangle's point nearest the vertex and
/// its weights: the pair (its energy: whether it may carry energy), unless their boxes can
/// neither bring them within the contact distance nor make them cross.
fn vertex_tri(
    c: &ClothView<'_>,
    p: &ProximityParams,
    i: u32,
    t: u32,
    (q, w): (Vec3, [f32; 3]),
) -> Option<Pair> {
    let tri = c.tris[t as usize];
    let free = |v: u32| c.free[v as usize];
    if tri.contains(&i) || (!free(i) && tri.iter().all(|&v| !free(v))) {
        return None;
    }
    // Neighbours in the pattern carry no energy: a pair only where their boxes meet.
    let near = c.rest_near(&[i], &tri, p.rest_exclusion);
    if near && boxes_apart(c.boxes, &[i], &tri, p.delta) {
        return None;
    }
    let xi = c.x[i as usize];
    let [a, bb, cc] = tri.map(|v| c.x[v as usize]);
    let alt = (bb - a).cross(cc - a);
    let side = || triple_sign(a, bb, cc, xi);
    let (n, sep0) = separating(&[xi], &[a, bb, cc], (xi, q), alt, side);
    let gap_max = c.boxes[i as usize].min_along(n) - max_along(c.boxes, &tri, n);
    let energy = gap_max < p.radius && !near;
    if !energy && gap_max >= p.delta {
        return None;
    }
    Some(Pair {
        v: [i, tri[0], tri[1], tri[2]],
        w: [1.0, -w[0], -w[1], -w[2]],
        side: [1, -1, -1, -1],
        n,
        offset: 0.0,
        body_bound: f32::NEG_INFINITY,
        delta: keep(p.delta, sep0),
        energy,
        kind: PairKind::VertexFace,
        body_vertex: NONE,
    })
}

/// Whether edges `a` and `b` may be a pair (no shared vertex, one free), sifted as the
/// trees find them: edges sharing a vertex are half a smooth cloth's candidates.
fn may_pair(c: &ClothView<'_>, a: u32, b: u32) -> bool {
    let (e, g) = (c.edges[a as usize], c.edges[b as usize]);
    !(e.iter().any(|v| g.contains(v)) || e.iter().chain(&g).all(|&v| !c.free[v as usize]))
}

/// Edge pairs `found` (their boxes overlap, and [`may_pair`]) tested and listed.
fn edge_edge(c: &ClothView<'_>, p: &ProximityParams, found: &[(u32, u32)], part: &mut Part) {
    for &(a, f) in found {
        let e = c.edges[a as usize];
        let g = c.edges[f as usize];
        let near = c.rest_near(&e, &g, p.rest_exclusion);
        if near && boxes_apart(c.boxes, &e, &g, p.delta) {
            continue;
        }
        let [p0, p1] = e.map(|v| c.x[v as usize]);
        let [q0, q1] = g.map(|v| c.x[v as usize]);
        let (s, t) = segment_segment(p0, p1, q0, q1);
        // `((p1 - p0) x (q1 - q0)) . (p0 - q0)`, whose sign is that of
        // `((p1 - q0) x (q1 - q0)) . (p0 - q0)`.
        let side = || triple_sign(q0, p1, q1, p0);
        let (n, sep0) = separating(
            &[p0, p1],
            &[q0, q1],
            (p0.lerp(p1, s), q0.lerp(q1, t)),
            (p1 - p0).cross(q1 - q0),
            side,
        );
        let gap_max = min_along(c.boxes, &e, n) - max_along(c.boxes, &g, n);
        let interior = s > 1e-4 && s < 1.0 - 1e-4 && t > 1e-4 && t < 1.0 - 1e-4;
        let energy = interior && gap_max < p.radius && !near;
        if !energy && gap_max >= p.delta {
            continue;
        }
        part.pairs.push(Pair {
            v: [e[0], e[1], g[0], g[1]],
            w: [1.0 - s, s, -(1.0 - t), -t],
            side: [1, 1, -1, -1],
            n,
            offset: 0.0,
            body_bound: f32::NEG_INFINITY,
            delta: keep(p.delta, sep0),
            energy,
            kind: PairKind::EdgeEdge,
            body_vertex: NONE,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::proximity::unique_edges;

    /// Two sheets of `side x side` vertices, 3 mm apart, the upper one falling onto the
    /// lower and crumpled a little so that pairs point every way.
    fn two_sheets(side: usize) -> (Vec<Vec3>, Vec<Aabb>, Vec<[u32; 3]>, Vec<Vec3>) {
        let h = 0.01;
        let (mut x, mut tris, mut pattern) = (Vec::new(), Vec::new(), Vec::new());
        for sheet in 0..2 {
            let base = x.len() as u32;
            for j in 0..side {
                for i in 0..side {
                    let wobble = 0.001 * ((i * 7 + j * 3) % 5) as f32;
                    x.push(Vec3::new(
                        i as f32 * h,
                        0.003 * sheet as f32 + wobble,
                        j as f32 * h,
                    ));
                    // The sheets lie apart in the pattern.
                    pattern.push(Vec3::new(
                        i as f32 * h + 2.0 * sheet as f32,
                        0.0,
                        j as f32 * h,
                    ));
                }
            }
            let at = |i: usize, j: usize| base + (j * side + i) as u32;
            for j in 0..side - 1 {
                for i in 0..side - 1 {
                    tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                    tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
        let half = x.len() / 2;
        let boxes = x
            .iter()
            .enumerate()
            .map(|(k, &p)| {
                let fall = if k >= half {
                    Vec3::new(0.0, -0.004, 0.0)
                } else {
                    Vec3::ZERO
                };
                Aabb::point(p).with(p + fall).grown(0.0005)
            })
            .collect();
        (x, boxes, tris, pattern)
    }

    #[test]
    fn candidates_come_out_in_edge_order() {
        // A scrambled list, as a tree gives it: every (a, b), a < b < 40, that a hash keeps.
        let n = 40u32;
        let mut pairs: Vec<(u32, u32)> = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .filter(|&(a, b)| (a * 7919 + b * 104_729) % 5 < 3)
            .collect();
        pairs.sort_by_key(|&(a, b)| (a * 31 + b * 17) % 97);
        let (mut bucket, mut out) = (Vec::new(), vec![(9, 9)]);
        let (one, two) = pairs.split_at(pairs.len() / 3);
        in_order([one, two].into_iter(), n as usize, &mut bucket, &mut out);
        let mut expected = pairs.clone();
        expected.sort_unstable();
        assert!(expected.len() > 300);
        assert_eq!(out, expected);
        in_order(std::iter::empty(), n as usize, &mut bucket, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn the_search_is_the_same_on_any_number_of_threads() {
        let (x, boxes, tris, pattern) = two_sheets(46);
        let edges = unique_edges(&tris);
        let free = vec![true; x.len()];
        let cloth = ClothView::unwelded((&x, &boxes), (&tris, &edges), &pattern, &free);
        let search = |threads: usize| {
            let params = ProximityParams::for_tests(threads, None);
            let mut pairs = Vec::new();
            ClothSearch::default().search(&cloth, &params, 0.002, &mut pairs);
            let counts = crate::collision::proximity::PairCounts::of(&pairs);
            (pairs, counts)
        };
        let (pairs, counts) = search(1);
        assert!(
            x.len() >= 2 * PER_THREAD_MIN,
            "the test must split the work"
        );
        assert!(counts.vertex_face > 1000 && counts.edge_edge > 1000);
        assert!(pairs.iter().any(|q| q.energy));
        for threads in [2, 3] {
            let (many, many_counts) = search(threads);
            assert_eq!(counts, many_counts, "{threads} threads");
            assert_eq!(pairs, many, "{threads} threads");
        }
        // Every pair holds where the search found the cloth.
        assert!(pairs.iter().all(|q| q.holds(&x, 1e-6)));
    }

    #[test]
    fn neighbours_in_the_pattern_are_pairs_only_where_their_boxes_meet() {
        // A vertex falling 2 cm beside a triangle 4 mm to its side and 2 mm below, both
        // near each other in the pattern (no energy between them). Their boxes lie 3 mm
        // apart across x, so they cannot meet; but the direction between their closest
        // points leans down, and along it the vertex's tall box overlaps the triangle's:
        // that test alone listed the pair as a bound.
        let x = vec![
            Vec3::new(0.004, -0.002, -0.005),
            Vec3::new(0.004, -0.002, 0.005),
            Vec3::new(0.014, -0.002, 0.0),
            Vec3::ZERO,
        ];
        let tris = [[0, 1, 2]];
        let edges = unique_edges(&tris);
        let free = vec![true; 4];
        let params = ProximityParams::for_tests(1, None);
        let pattern: Vec<Vec3> = x.iter().map(|p| Vec3::new(p.x, 0.0, p.z)).collect();
        let search = |boxes: &[Aabb]| {
            let cloth = ClothView::unwelded((&x, boxes), (&tris, &edges), &pattern, &free);
            let mut pairs = Vec::new();
            ClothSearch::default().search(&cloth, &params, 0.5 * params.radius, &mut pairs);
            pairs
        };
        let mut boxes: Vec<Aabb> = x.iter().map(|&p| Aabb::point(p).grown(0.0005)).collect();
        boxes[3] = boxes[3].with(Vec3::new(0.0, -0.02, 0.0));
        assert!(boxes_apart(&boxes, &[3], &[0, 1, 2], 0.002));
        assert!(search(&boxes).is_empty());
        // Free to move 4 mm sideways too, it can reach the triangle: the pair is listed,
        // as a bound without energy.
        boxes[3] = boxes[3].with(Vec3::new(0.004, 0.0, 0.0));
        let pairs = search(&boxes);
        assert_eq!(pairs.len(), 1);
        assert_eq!(pairs[0].v, [3, 0, 1, 2]);
        assert!(!pairs[0].energy);
    }
}
