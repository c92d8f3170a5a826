//! The cloth's rest edges as a graph, and Dijkstra's search through it out to a radius:
//! the shortest rest paths that the stretch limits, their patches and the pin tethers
//! are measured by.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::solver::state::Cloth;

/// Rest edges to search along.
pub(super) trait Graph {
    /// Calls `f(neighbour, rest length)` for the edges of `v` (an edge may come twice).
    fn for_each_neighbour(&self, v: u32, f: impl FnMut(u32, f32));
}

impl Graph for RestGraph {
    fn for_each_neighbour(&self, v: u32, mut f: impl FnMut(u32, f32)) {
        for &(u, l) in self.neighbours(v) {
            f(u, l);
        }
    }
}

/// The live mesh read as a graph, triangle by triangle around each vertex.
pub(super) struct LiveGraph<'a>(pub &'a Cloth);

impl Graph for LiveGraph<'_> {
    fn for_each_neighbour(&self, v: u32, mut f: impl FnMut(u32, f32)) {
        let live = &self.0.live;
        for t in live.tris_of(v).iter().filter_map(|&s| live.tri(s)) {
            if let Some(k) = t.v.iter().position(|&u| u == v) {
                for j in [(k + 1) % 3, (k + 2) % 3] {
                    f(t.v[j], (t.rest[k] - t.rest[j]).length());
                }
            }
        }
    }
}

/// The mesh's rest edges as compressed rows: `adj[start[v]..start[v + 1]]` are the
/// (neighbour, rest length) pairs of `v`, from the live triangles only.
pub(super) struct RestGraph {
    start: Vec<u32>,
    adj: Vec<(u32, f32)>,
}

impl RestGraph {
    pub(super) fn of(cloth: &Cloth) -> Self {
        let n = cloth.len();
        let mut start = vec![0u32; n + 1];
        for (_, t) in cloth.live.iter() {
            for &v in &t.v {
                start[v as usize + 1] += 2;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut adj = vec![(0u32, 0.0f32); start[n] as usize];
        for (_, t) in cloth.live.iter() {
            for k in 0..3 {
                let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
                let l = (t.rest[k] - t.rest[(k + 1) % 3]).length();
                for (from, to) in [(a, b), (b, a)] {
                    adj[fill[from as usize] as usize] = (to, l);
                    fill[from as usize] += 1;
                }
            }
        }
        Self { start, adj }
    }

    pub(super) fn len(&self) -> usize {
        self.start.len() - 1
    }

    pub(super) fn neighbours(&self, v: u32) -> &[(u32, f32)] {
        &self.adj[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// Mean rest length of the edges (each counted once per triangle side).
    pub(super) fn mean_edge(&self) -> f32 {
        if self.adj.is_empty() {
            return 0.0;
        }
        self.adj.iter().map(|&(_, l)| l).sum::<f32>() / self.adj.len() as f32
    }
}

/// Dijkstra out to a radius, reusing its buffers between runs (only the entries a run
/// touched are reset). Also used for the pin tethers.
pub(super) struct Bounded {
    dist: Vec<f32>,
    /// The source each reached vertex is nearest to.
    from: Vec<u32>,
    touched: Vec<u32>,
    heap: BinaryHeap<Reverse<(u32, u32)>>,
}

impl Bounded {
    pub(super) fn new(n: usize) -> Self {
        Self {
            dist: vec![f32::INFINITY; n],
            from: vec![u32::MAX; n],
            touched: Vec::new(),
            heap: BinaryHeap::new(),
        }
    }

    /// Calls `visit(v, d)` for every vertex within `radius` of `source`, nearest first.
    pub(super) fn run(
        &mut self,
        g: &impl Graph,
        source: u32,
        radius: f32,
        mut visit: impl FnMut(u32, f32),
    ) {
        self.run_from(g, &[source], radius, |v, d, _| visit(v, d));
    }

    /// Calls `visit(v, d, s)` for every vertex within `radius` of `sources`, nearest
    /// first, with `s` the nearest source and `d` the distance to it.
    pub(super) fn run_from(
        &mut self,
        g: &impl Graph,
        sources: &[u32],
        radius: f32,
        mut visit: impl FnMut(u32, f32, u32),
    ) {
        for &v in &self.touched {
            self.dist[v as usize] = f32::INFINITY;
        }
        self.touched.clear();
        self.heap.clear();
        for &s in sources {
            if self.dist[s as usize] != 0.0 {
                self.dist[s as usize] = 0.0;
                self.from[s as usize] = s;
                self.touched.push(s);
                self.heap.push(Reverse((0, s)));
            }
        }
        while let Some(Reverse((bits, u))) = self.heap.pop() {
            let du = f32::from_bits(bits);
            if du > self.dist[u as usize] {
                continue;
            }
            let src = self.from[u as usize];
            visit(u, du, src);
            let (dist, from, touched, heap) = (
                &mut self.dist,
                &mut self.from,
                &mut self.touched,
                &mut self.heap,
            );
            g.for_each_neighbour(u, |v, l| {
                let d = du + l;
                if d <= radius && d < dist[v as usize] {
                    if dist[v as usize].is_infinite() {
                        touched.push(v);
                    }
                    dist[v as usize] = d;
                    from[v as usize] = src;
                    // Non-negative floats order like their bit patterns.
                    heap.push(Reverse((d.to_bits(), v)));
                }
            });
        }
    }
}
