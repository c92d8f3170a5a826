//! The cloth against itself: every cloth vertex against the cloth's triangles, every cloth
//! edge against its edges, through the trees of `bvh.rs`. The work is split over threads
//! by vertex and by candidate edge pair; each thread lists its own pairs and the lists are
//! joined in order, so the result is the same whatever the thread count.

use std::ops::Range;

use glam::Vec3;

use super::bvh::Bvh;
use super::distance::{point_triangle, segment_segment};
use super::grid::Aabb;
use super::pair::{
    ClothView, Pair, PairCounts, ProximityParams, feature_key, keep, max_along, min_along,
    separating,
};

/// Below this many items a search runs on one thread (starting one costs more).
const PER_THREAD_MIN: usize = 2048;

/// Pairs of edges (or of tree nodes), by index.
type EdgePairs = Vec<(u32, u32)>;

/// One thread's share of a search, and its scratch.
#[derive(Clone, Debug, Default)]
pub(super) struct Part {
    pub(super) pairs: Vec<Pair>,
    vertex_face: usize,
    edge_edge: usize,
    /// Pairs with the body listed.
    pub(super) body: usize,
    /// (body vertex, cloth feature, pair in `pairs`) of the body's corner-face pairs.
    pub(super) corner_keys: Vec<(u32, u64, u32)>,
    pub(super) seen: Vec<u64>,
    pub(super) found: Vec<u32>,
    pub(super) near: Vec<(f32, u32, Vec3, [f32; 3])>,
    stack: Vec<u32>,
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
        part.vertex_face = 0;
        part.edge_edge = 0;
        part.body = 0;
        part.corner_keys.clear();
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
    candidates: Vec<(u32, u32)>,
    /// Scratch for finding the candidates: the tree's node pairs shared between the
    /// threads, each thread's stack and the candidates it found, and each edge's first
    /// candidate for putting them in order.
    tasks: Vec<(u32, u32)>,
    found: Vec<(EdgePairs, EdgePairs)>,
    bucket: Vec<u32>,
    parts: Vec<Part>,
}

impl ClothSearch {
    /// Forgets the trees (the mesh changed); the next search builds them again.
    pub fn forget_mesh(&mut self) {
        self.tri_tree = Bvh::default();
        self.edge_tree = Bvh::default();
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

    /// The cloth-cloth pairs, vertex-face then edge-edge, appended to `out` and counted.
    pub fn search(
        &mut self,
        c: &ClothView<'_>,
        p: &ProximityParams,
        reach: f32,
        out: &mut Vec<Pair>,
        counts: &mut PairCounts,
    ) {
        self.trees_for(c);
        let tri_box = |t: &[u32; 3]| {
            t.iter()
                .fold(Aabb::EMPTY, |b, &v| b.union(c.boxes[v as usize]))
                .grown(reach)
        };
        self.tri_tree.refit(c.tris.iter().map(tri_box));
        let tree = &self.tri_tree;
        run_parts(&mut self.parts, p.threads, c.x.len(), |part, range| {
            vertex_face(c, tree, p, reach, part, range)
        });
        join_parts(&self.parts, out, counts);

        let edge_box = |e: &[u32; 2]| {
            c.boxes[e[0] as usize]
                .union(c.boxes[e[1] as usize])
                .grown(reach)
        };
        self.edge_tree.refit(c.edges.iter().map(edge_box));
        let threads = p
            .threads
            .clamp(1, 16)
            .min(c.edges.len() / PER_THREAD_MIN)
            .max(1);
        self.overlapping_edges(threads);
        // In edge order, whatever the tree's shape and the threads.
        let mut candidates = std::mem::take(&mut self.candidates);
        let lists = self.found[..threads]
            .iter()
            .map(|(list, _)| list.as_slice());
        in_order(lists, c.edges.len(), &mut self.bucket, &mut candidates);
        let found = &candidates;
        run_parts(&mut self.parts, p.threads, found.len(), |part, range| {
            edge_edge(c, p, &found[range], part)
        });
        join_parts(&self.parts, out, counts);
        self.candidates = candidates;
    }
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
    /// The edge pairs whose (refitted) boxes overlap, into `found[..threads]`'s lists:
    /// the tree's node pairs dealt out to the threads in turn.
    fn overlapping_edges(&mut self, threads: usize) {
        if self.found.len() < threads {
            self.found.resize_with(threads, Default::default);
        }
        let tree = &self.edge_tree;
        if threads == 1 {
            let (list, stack) = &mut self.found[0];
            list.clear();
            tree.self_pairs(stack, |a, b| list.push((a, b)));
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
                    tree.self_pairs_from(&mine, stack, |a, b| list.push((a, b)));
                });
            }
        });
    }
}

fn join_parts(parts: &[Part], out: &mut Vec<Pair>, counts: &mut PairCounts) {
    for part in parts {
        out.extend_from_slice(&part.pairs);
        counts.vertex_face += part.vertex_face;
        counts.edge_edge += part.edge_edge;
    }
}

/// Vertices `range` against the cloth's triangles (`tree`, refitted).
fn vertex_face(
    c: &ClothView<'_>,
    tree: &Bvh,
    p: &ProximityParams,
    reach: f32,
    part: &mut Part,
    range: Range<usize>,
) {
    for i in range {
        let b = c.boxes[i];
        if !b.is_finite() {
            continue;
        }
        let Part {
            found, near, stack, ..
        } = part;
        found.clear();
        tree.query(&b.grown(reach), stack, |t| found.push(t));
        // Nearest first, so the feature a vertex is over gets the energy.
        let xi = c.x[i];
        near.clear();
        near.extend(found.iter().filter_map(|&t| {
            let tri = c.tris[t as usize];
            if tri.contains(&(i as u32)) || (!c.free[i] && tri.iter().all(|&v| !c.free[v as usize]))
            {
                return None;
            }
            let [a, bb, cc] = tri.map(|v| c.x[v as usize]);
            let (q, w) = point_triangle(xi, a, bb, cc);
            Some(((xi - q).length(), t, q, w))
        }));
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        part.seen.clear();
        for k in 0..part.near.len() {
            let (_, t, q, w) = part.near[k];
            let tri = c.tris[t as usize];
            let [a, bb, cc] = tri.map(|v| c.x[v as usize]);
            let (n, sep0) = separating(&[xi], &[a, bb, cc], xi, q, (bb - a).cross(cc - a));
            let gap_max = b.min_along(n) - max_along(c.boxes, &tri, n);
            let rest_near = c.rest_near(&[i as u32], &tri, p.rest_exclusion);
            let mut energy = !rest_near && gap_max < p.radius;
            if !energy && gap_max >= p.delta {
                continue;
            }
            if energy {
                let key = feature_key(tri, t, w);
                if part.seen.contains(&key) {
                    energy = false;
                } else {
                    part.seen.push(key);
                }
            }
            part.pairs.push(Pair {
                v: [i as u32, tri[0], tri[1], tri[2]],
                w: [1.0, -w[0], -w[1], -w[2]],
                side: [1, -1, -1, -1],
                n,
                offset: 0.0,
                body_bound: f32::NEG_INFINITY,
                delta: keep(p.delta, sep0),
                energy,
            });
            part.vertex_face += 1;
        }
    }
}

/// Edge pairs `found` (their boxes overlap) tested and listed.
fn edge_edge(c: &ClothView<'_>, p: &ProximityParams, found: &[(u32, u32)], part: &mut Part) {
    for &(a, f) in found {
        let e = c.edges[a as usize];
        let g = c.edges[f as usize];
        if e.iter().any(|v| g.contains(v)) || e.iter().chain(&g).all(|&v| !c.free[v as usize]) {
            continue;
        }
        let [p0, p1] = e.map(|v| c.x[v as usize]);
        let [q0, q1] = g.map(|v| c.x[v as usize]);
        let (s, t) = segment_segment(p0, p1, q0, q1);
        let (n, sep0) = separating(
            &[p0, p1],
            &[q0, q1],
            p0.lerp(p1, s),
            q0.lerp(q1, t),
            (p1 - p0).cross(q1 - q0),
        );
        let gap_max = min_along(c.boxes, &e, n) - max_along(c.boxes, &g, n);
        let interior = s > 1e-4 && s < 1.0 - 1e-4 && t > 1e-4 && t < 1.0 - 1e-4;
        let energy = interior && gap_max < p.radius && !c.rest_near(&e, &g, p.rest_exclusion);
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
        });
        part.edge_edge += 1;
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
            let (mut pairs, mut counts) = (Vec::new(), PairCounts::default());
            ClothSearch::default().search(&cloth, &params, 0.002, &mut pairs, &mut counts);
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
}
