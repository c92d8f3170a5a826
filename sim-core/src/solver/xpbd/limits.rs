//! Long-range stretch limits: a coarse lattice over the cloth whose links may not grow
//! longer than their rest distance through the mesh.
//!
//! Gauss–Seidel moves a correction about one vertex per pass, and with one pass per
//! substep a constraint can only carry a load of about `m / h^2` (vertex mass over the
//! substep squared) before it stretches: the material's modulus does not enter. A fine
//! cloth has light vertices, so at 5 substeps a 128 x 128 cloth dropped on the mannequin
//! stretched as it landed (its far parts decelerate only when the news reaches them) and
//! friction then held the stretch: edges ended 41% longer than at rest on average, and
//! the drape never came to rest.
//!
//! The links carry a correction 3 and 6 edges per pass. Every few vertices are lattice
//! nodes, each linked to the nodes around it by a unilateral distance constraint as long
//! as the shortest path between them through the live mesh's rest edges, times
//! `1 + strain` (the most the material itself stretches under the cloth's own weight, as
//! for the pin tethers). A path through rest edges is never shorter than the geodesic
//! rest distance, so a link never holds the cloth tighter than its material would:
//! folding, draping and compression leave it slack. Only the solver's lag is removed.
//! XPBD solves the links before and after the membranes in every substep, split into the
//! same two halves and straddling part as the membranes (`parts`). An edit updates
//! the links around what it touched (`StretchLimits::update`), so a cut or a tear frees
//! what it separates and a seam or an undo joins it again.
//!
//! Measured (docs/models.md): on the mannequin drape the mean strain falls from 41% to 5% and the
//! drape comes to rest; the frame costs about 0.6 ms more at 128 x 128.
//!
//! Where the cloth hangs from a body (a cube's rim, the top of the head) every link
//! through the support is loaded by everything below it, and the support's own vertices
//! carry it at `m / h^2` like any constraint. The links weight a vertex lying on the body
//! as half its inverse mass (`link_weights`), which roughly halves the worst stretch
//! there; it does not remove it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::Vec3;

use crate::collision::ContactCache;
use crate::solver::state::Cloth;

/// Lattice spacings in mean edge lengths, coarse first (the order they are solved in).
/// Each level costs about 3 links per node. On the 128 x 128 mannequin drape, before
/// the support weighting below: mean strain 6.3% with these, 10.2% with 3 alone, 5.9%
/// with 24, 6 and 3 (whose coarsest level makes an edit's update several times dearer).
const LEVELS: [f32; 2] = [6.0, 3.0];

/// A link reaches the lattice nodes within this many spacings (through the mesh): the
/// four axis neighbours of a grid lattice and the diagonal its triangles run along.
const REACH: f32 = 1.5;

/// A vertex lying on the body passes this share of its inverse mass to the links (the
/// rest of a correction goes to the other end: the body carries that part), rising
/// smoothly to all of it `SUPPORT_BAND` off the surface. Weights that switch with the
/// contacts feed motion (measured: 1e-6 J left on the mannequin drape at 0.5 as a step,
/// 1e-8 J with this ramp).
const SUPPORT_SHARE: f32 = 0.5;
const SUPPORT_BAND: f32 = 0.005;

/// The inverse masses the links use this frame: `inv_mass`, lowered for vertices on the
/// body at the frame's start (see `SUPPORT_SHARE`).
pub(super) fn link_weights(
    inv_mass: &[f32],
    x: &[Vec3],
    contacts: &ContactCache,
    thickness: f32,
    out: &mut Vec<f32>,
) {
    out.clear();
    out.extend(inv_mass.iter().zip(x).enumerate().map(|(i, (&w, &p))| {
        match contacts.gap(i, p, thickness) {
            Some(g) => {
                let t = (g / SUPPORT_BAND).clamp(0.0, 1.0);
                w * (SUPPORT_SHARE + (1.0 - SUPPORT_SHARE) * t)
            }
            None => w,
        }
    }));
}

/// One link: two vertices and the length of the shortest rest path between them.
pub(super) type Limit = (u32, u32, f32);

/// One lattice: its spacing (m), which vertices are its nodes, and its links.
#[derive(Clone, Debug, Default)]
struct Level {
    spacing: f32,
    node: Vec<bool>,
    links: Vec<Limit>,
}

/// The stretch limits of a cloth, kept in step with its edits.
#[derive(Clone, Debug, Default)]
pub(crate) struct StretchLimits {
    levels: Vec<Level>,
    /// A link may be `1 + strain` times its rest path: the material's own stretch under
    /// the cloth's weight.
    strain: f32,
    /// The links again, coarse level first, split like the solver's groups: both ends
    /// below `mid`, both at or above it (indices relative to `mid`), and the rest. The
    /// first two touch no common vertex, so they can run side by side.
    parts: [Vec<Limit>; 3],
    mid: u32,
}

impl StretchLimits {
    /// The lattices of `cloth`. `strain` is the slack allowed over the rest distance;
    /// `mid` is where the solver splits the vertex range in two.
    pub(super) fn build(cloth: &Cloth, strain: f32, mid: usize) -> Self {
        let g = RestGraph::of(cloth);
        let n = g.len();
        let h = g.mean_edge();
        let mut limits = Self {
            strain: strain.max(0.0),
            ..Self::default()
        };
        if n == 0 || h <= 0.0 || !h.is_finite() {
            return limits;
        }
        let mut search = Bounded::new(n);
        for level in LEVELS {
            let spacing = level * h;
            let mut lv = Level {
                spacing,
                node: vec![false; n],
                links: Vec::new(),
            };
            // Greedy in index order: a vertex becomes a node unless a node is nearer than
            // the spacing. On a grid this is the lattice of every `level`-th row and column.
            let mut blocked = vec![false; n];
            for v in 0..n as u32 {
                if blocked[v as usize] || g.neighbours(v).is_empty() {
                    continue;
                }
                lv.node[v as usize] = true;
                search.run(&g, v, REACH * spacing, |u, d| {
                    if d < spacing * 0.999 {
                        blocked[u as usize] = true;
                    }
                    if u != v && lv.node[u as usize] && !pinned_pair(cloth, u, v) {
                        lv.links.push((u, v, d));
                    }
                });
            }
            limits.levels.push(lv);
        }
        limits.split(mid);
        limits
    }

    /// Sorts the links into `parts` around `mid`.
    pub(super) fn split(&mut self, mid: usize) {
        let mid = mid as u32;
        self.mid = mid;
        self.parts = Default::default();
        for &(a, b, rest) in self.levels.iter().flat_map(|l| &l.links) {
            let part = if a < mid && b < mid {
                0
            } else if a >= mid && b >= mid {
                1
            } else {
                2
            };
            let off = if part == 1 { mid } else { 0 };
            self.parts[part].push((a - off, b - off, rest));
        }
    }

    /// No links at all (off, or a cloth without triangles).
    pub(super) fn is_empty(&self) -> bool {
        self.levels.iter().all(|l| l.links.is_empty())
    }

    /// A new material's slack (see `strain`).
    pub(super) fn set_strain(&mut self, strain: f32) {
        self.strain = strain.max(0.0);
    }

    /// Number of links.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.levels.iter().map(|l| l.links.len()).sum()
    }

    /// Brings the links in line with `cloth` after an edit. `touched` are the vertices of
    /// every triangle the edit removed or added, and those whose pin changed.
    ///
    /// A link whose shortest path changed had that path run through a touched vertex, so
    /// both its ends lie within its length of one. The stretch of path from an end to the
    /// first touched vertex on it survives the edit (an edge leaves or changes only with a
    /// triangle, and then both its ends are touched), so a search from the touched
    /// vertices through the edited mesh finds every such end. Their links are dropped and
    /// found again from the edited mesh; the nodes stay where they were.
    pub(super) fn update(&mut self, cloth: &Cloth, touched: &[u32]) {
        self.relink(cloth, touched);
        self.split(self.mid as usize);
    }

    fn relink(&mut self, cloth: &Cloth, touched: &[u32]) {
        if self.levels.is_empty() {
            return;
        }
        // The live mesh itself is the graph here: building the compressed rows would cost
        // more than the searches (an edit must stay well under 2 ms).
        let g = LiveGraph(cloth);
        let n = cloth.len();
        let reach = self
            .levels
            .iter()
            .map(|l| REACH * l.spacing)
            .fold(0.0f32, f32::max);
        let mut search = Bounded::new(n);
        let sources: Vec<u32> = touched
            .iter()
            .copied()
            .filter(|&v| (v as usize) < n)
            .collect();
        let mut near: Vec<(u32, f32)> = Vec::new();
        search.run_from(&g, &sources, reach, |u, d, _| near.push((u, d)));
        for lv in &mut self.levels {
            lv.node.resize(n, false);
            let r = REACH * lv.spacing;
            let mut affected = vec![false; n];
            let mut redo = Vec::new();
            for &(u, d) in &near {
                if d <= r && lv.node[u as usize] && !affected[u as usize] {
                    affected[u as usize] = true;
                    redo.push(u);
                }
            }
            // Ends past the cloth (vertices an undo removed) go with their links.
            lv.links.retain(|&(a, b, _)| {
                (a as usize) < n
                    && (b as usize) < n
                    && !affected[a as usize]
                    && !affected[b as usize]
            });
            for &a in &redo {
                search.run(&g, a, r, |b, d| {
                    let found_twice = affected[b as usize] && b < a;
                    if b != a && lv.node[b as usize] && !found_twice && !pinned_pair(cloth, a, b) {
                        lv.links.push((b, a, d));
                    }
                });
            }
        }
    }

    /// One pass over part `part` of the links (0: the lower half, with `x` and `w` that
    /// half; 1: the upper half, `x` and `w` from `mid` on; 2: the rest, all of `x`),
    /// coarse level first: pulls each overlong pair back to its limit, by inverse mass.
    pub(super) fn solve(&self, part: usize, x: &mut [Vec3], w: &[f32]) {
        if let Some(links) = self.parts.get(part) {
            solve(links, 1.0 + self.strain, x, w);
        }
    }

    #[cfg(test)]
    fn links(&self) -> impl Iterator<Item = Limit> + '_ {
        self.levels.iter().flat_map(|l| l.links.iter().copied())
    }
}

fn pinned_pair(cloth: &Cloth, a: u32, b: u32) -> bool {
    cloth.is_pinned(a as usize) && cloth.is_pinned(b as usize)
}

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
struct LiveGraph<'a>(&'a Cloth);

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
    fn mean_edge(&self) -> f32 {
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
    fn run(&mut self, g: &impl Graph, source: u32, radius: f32, mut visit: impl FnMut(u32, f32)) {
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

/// One pass over the links: pulls each pair longer than `scale` times its rest path back
/// to that, by inverse mass.
fn solve(limits: &[Limit], scale: f32, x: &mut [Vec3], w: &[f32]) {
    for &(a, b, rest) in limits {
        let max = rest * scale;
        let (a, b) = (a as usize, b as usize);
        let d = x[a] - x[b];
        let l2 = d.length_squared();
        if l2 <= max * max {
            continue;
        }
        let ws = w[a] + w[b];
        if ws <= 0.0 {
            continue;
        }
        let l = l2.sqrt();
        let s = (l - max) / (l * ws);
        x[a] -= d * (s * w[a]);
        x[b] += d * (s * w[b]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::mesh::Tri;
    use crate::solver::Material;

    fn cloth(n: usize) -> Cloth {
        Cloth::new(
            ClothMesh::grid(1.0, 1.0, n, n, 0.0).unwrap(),
            &Material::default(),
        )
        .unwrap()
    }

    #[test]
    fn a_grid_gets_a_lattice_at_each_level() {
        let c = cloth(48);
        let links: Vec<Limit> = StretchLimits::build(&c, 0.0, c.len() / 2).links().collect();
        // 6 and 3 edges: 9^2 and 17^2 nodes, about 3 links each (fewer on the border).
        let expect = 3 * (9 * 9 + 17 * 17);
        assert!(
            links.len() > expect * 3 / 4 && links.len() < expect * 5 / 4,
            "{} links",
            links.len()
        );
        // Along a grid line the shortest path is straight: the limit is the rest distance.
        let h = 1.0 / 48.0;
        let (a, b, max) = links
            .iter()
            .copied()
            .find(|&(a, b, _)| (c.x[a as usize] - c.x[b as usize]).length() > 5.0 * h)
            .unwrap();
        let d = (c.x[a as usize] - c.x[b as usize]).length();
        assert!(max >= d * 0.9999, "limit {max} under the rest distance {d}");
    }

    #[test]
    fn bending_without_stretching_leaves_every_link_slack() {
        let mut c = cloth(36);
        let links: Vec<Limit> = StretchLimits::build(&c, 0.0, c.len() / 2).links().collect();
        // Roll the cloth onto a cylinder of radius 0.2 m: an isometry, so no path through
        // the cloth gets longer and every straight distance gets shorter or stays.
        for p in &mut c.x {
            let a = p.x / 0.2;
            *p = Vec3::new(0.2 * a.sin(), 0.2 * (1.0 - a.cos()), p.z);
        }
        let before = c.x.clone();
        solve(&links, 1.0, &mut c.x, &c.inv_mass);
        assert_eq!(c.x, before);
        // Stretched by 20% across, the links pull it back.
        for p in &mut c.x {
            p.x *= 1.2;
        }
        let worst = |x: &[Vec3]| {
            links
                .iter()
                .map(|&(a, b, max)| (x[a as usize] - x[b as usize]).length() / max)
                .fold(0.0f32, f32::max)
        };
        let stretched = worst(&c.x);
        solve(&links, 1.0, &mut c.x, &c.inv_mass);
        let once = worst(&c.x);
        for _ in 0..30 {
            solve(&links, 1.0, &mut c.x, &c.inv_mass);
        }
        let converged = worst(&c.x);
        assert!(
            stretched > 1.15 && once < stretched - 0.05 && converged < 1.01,
            "{stretched} -> {once} -> {converged}"
        );
    }

    /// The links sorted by their ends.
    fn sorted(l: &StretchLimits) -> Vec<(u32, u32, f32)> {
        let mut v: Vec<_> = l.links().map(|(a, b, m)| (a.min(b), a.max(b), m)).collect();
        v.sort_unstable_by_key(|&(a, b, _)| (a, b));
        v
    }

    /// Same pairs, same limits up to rounding (a path summed from either end rounds
    /// differently).
    fn assert_same(got: &StretchLimits, want: &[(u32, u32, f32)]) {
        let got = sorted(got);
        let differ = got.len() != want.len()
            || got
                .iter()
                .zip(want)
                .any(|(g, w)| (g.0, g.1) != (w.0, w.1) || (g.2 - w.2).abs() > 1e-6);
        assert!(!differ, "{} links, {} expected", got.len(), want.len());
    }

    #[test]
    fn a_cut_frees_what_it_separates_and_undo_brings_it_back() {
        let n = 24;
        let mut c = cloth(n);
        let mut limits = StretchLimits::build(&c, 0.0, c.len() / 2);
        let original = sorted(&limits);
        // Cut the cloth in two along the middle column of vertices.
        let mid = (n / 2) as u32;
        let on_cut = |v: u32| v % (n as u32 + 1) == mid;
        let cut: Vec<(u32, Tri)> = c
            .live
            .iter()
            .filter(|(_, t)| t.v.iter().any(|&v| on_cut(v)))
            .map(|(slot, t)| (slot, *t))
            .collect();
        let mut touched: Vec<u32> = cut.iter().flat_map(|(_, t)| t.v).collect();
        touched.sort_unstable();
        touched.dedup();
        for (slot, _) in &cut {
            c.live.set(*slot, None).unwrap();
        }
        limits.update(&c, &touched);
        let side = |v: u32| v % (n as u32 + 1) < mid;
        assert!(!limits.is_empty());
        for (a, b, _) in limits.links() {
            assert_eq!(side(a), side(b), "link {a}-{b} across the cut");
        }
        // The same as relinking every node of the cut cloth.
        let mut all = limits.clone();
        let every: Vec<u32> = (0..c.len() as u32).collect();
        all.update(&c, &every);
        assert_same(&limits, &sorted(&all));
        // Undo: the triangles come back, and so do the links.
        for (slot, t) in &cut {
            c.live.set(*slot, Some(*t)).unwrap();
        }
        limits.update(&c, &touched);
        assert_same(&limits, &original);
    }

    #[test]
    fn the_halves_share_no_vertex_and_every_link_is_in_one_part() {
        let c = cloth(30);
        let mid = c.len() / 2;
        let l = StretchLimits::build(&c, 0.0, mid);
        let m = mid as u32;
        assert!(l.parts[0].iter().all(|&(a, b, _)| a < m && b < m));
        // The upper half's links are relative to `mid`.
        assert!(
            l.parts[1]
                .iter()
                .all(|&(a, b, _)| a + m < c.len() as u32 && b + m < c.len() as u32)
        );
        assert!(l.parts[2].iter().all(|&(a, b, _)| (a < m) != (b < m)));
        let mut parts: Vec<(u32, u32)> = l.parts[0]
            .iter()
            .chain(&l.parts[2])
            .map(|&(a, b, _)| (a.min(b), a.max(b)))
            .chain(
                l.parts[1]
                    .iter()
                    .map(|&(a, b, _)| (a.min(b) + m, a.max(b) + m)),
            )
            .collect();
        parts.sort_unstable();
        let mut all: Vec<(u32, u32)> = l.links().map(|(a, b, _)| (a.min(b), a.max(b))).collect();
        all.sort_unstable();
        assert!(!l.parts[1].is_empty() && !l.parts[2].is_empty());
        assert_eq!(parts, all);
    }

    #[test]
    fn pinned_pairs_and_pinned_ends() {
        let mut c = cloth(12);
        for v in 0..c.len() {
            c.pin(v);
        }
        assert_eq!(
            StretchLimits::build(&c, 0.0, c.len() / 2).len(),
            0,
            "links between pinned vertices"
        );
        let mut x = vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0)];
        // A pinned end stays; the free end takes the whole correction.
        solve(&[(0, 1, 1.0)], 1.0, &mut x, &[0.0, 1.0]);
        assert_eq!(x, vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)]);
        solve(&[(0, 1, 0.5)], 1.0, &mut x, &[0.0, 0.0]);
        assert_eq!(x[1], Vec3::new(1.0, 0.0, 0.0));
    }
}
