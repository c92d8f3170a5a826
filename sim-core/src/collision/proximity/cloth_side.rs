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

/// One thread's share of a search, and its scratch.
#[derive(Clone, Debug, Default)]
pub struct Part {
    pairs: Vec<Pair>,
    vertex_face: usize,
    edge_edge: usize,
    seen: Vec<u64>,
    found: Vec<u32>,
    near: Vec<(f32, u32, Vec3, [f32; 3])>,
    stack: Vec<u32>,
}

/// Runs `work` over `0..len` in up to `threads` parts (in order) and gives each part's
/// range to it.
fn run_parts(
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
    pair_stack: Vec<(u32, u32)>,
    candidates: Vec<(u32, u32)>,
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
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        self.edge_tree
            .self_pairs(&mut self.pair_stack, |a, b| candidates.push((a, b)));
        // In edge order, whatever the tree's shape.
        candidates.sort_unstable();
        let found = &candidates;
        run_parts(&mut self.parts, p.threads, found.len(), |part, range| {
            edge_edge(c, p, &found[range], part)
        });
        join_parts(&self.parts, out, counts);
        self.candidates = candidates;
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
