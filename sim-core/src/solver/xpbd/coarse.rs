//! The stretch limits solved as a coarse level (hierarchical position based dynamics,
//! Mueller 2008): each lattice node stands for the patch of cloth around it, with the
//! patch's mass, and a link's correction moves the whole patch, blended smoothly between
//! nodes, instead of the node's one vertex.
//!
//! Moving only the node vertex, a link could carry no more than that vertex's mass over
//! the substep squared before the membranes around it pulled it back: where the cloth
//! hangs from a body (the top of the head) the links held nothing and the edges there
//! ended a third longer than at rest (docs/models.md). A patch of a 3-spacing lattice
//! weighs about nine vertices, of a 6-spacing one about thirty-six.
//!
//! Each vertex takes a node's correction with weight `1 - d / spacing` (`d` its shortest
//! rest path to the node), normalised over the nodes within the spacing: a node takes
//! its own correction whole (other nodes are at least a spacing away), and the blend
//! never reaches across a cut (the paths run through the live mesh).

use glam::Vec3;

use super::graph::{Bounded, Graph};

/// One link: two vertices (or node slots) and the length of the shortest rest path
/// between them.
pub(super) type Limit = (u32, u32, f32);

/// One level's blend: node slot `s` stands for vertex `nodes[s]` and blends its
/// correction into `patches[s]`, (vertex, tent weight) pairs; a vertex takes a weight
/// times its `inv_sum` (one over `sum`, the weights that reach it).
#[derive(Clone, Debug, Default)]
pub(super) struct Blend {
    spacing: f32,
    /// Slot to vertex (`u32::MAX`: the node's vertex is gone) and vertex to slot.
    nodes: Vec<u32>,
    slot: Vec<u32>,
    patches: Vec<Vec<(u32, f32)>>,
    sum: Vec<f32>,
    inv_sum: Vec<f32>,
    /// The links in node slots.
    links: Vec<Limit>,
    /// Each link's rest path through the edges: its length while a seam is sewn.
    loose: Vec<f32>,
}

impl Blend {
    /// The blend of the lattice with nodes `node` (by vertex) and `links`, through `g`.
    pub(super) fn of(
        g: &impl Graph,
        node: &[bool],
        links: &[Limit],
        loose: &[f32],
        spacing: f32,
        search: &mut Bounded,
    ) -> Self {
        let n = node.len();
        let nodes: Vec<u32> = (0..n as u32).filter(|&v| node[v as usize]).collect();
        let mut slot = vec![u32::MAX; n];
        for (s, &v) in nodes.iter().enumerate() {
            slot[v as usize] = s as u32;
        }
        let patches = nodes
            .iter()
            .map(|&v| patch(g, v, spacing, n, search))
            .collect();
        let mut b = Self {
            spacing,
            nodes,
            slot,
            patches,
            ..Self::default()
        };
        b.sum = vec![0.0; n];
        for &(u, w) in b.patches.iter().flatten() {
            b.sum[u as usize] += w;
        }
        b.inv_sum = b.sum.iter().map(|&t| inverse(t)).collect();
        b.relink(links, loose);
        b
    }

    /// Brings the blend in line with an edited mesh `g` of `n` vertices, whose lattice now
    /// has `links`. `near` holds every vertex within reach of what the edit touched (with
    /// its distance): a node within the spacing of a touched vertex has its patch found
    /// again (the argument of `StretchLimits::update`, with the spacing for the reach).
    pub(super) fn update(
        &mut self,
        g: &impl Graph,
        n: usize,
        links: &[Limit],
        loose: &[f32],
        near: &[(u32, f32)],
        search: &mut Bounded,
    ) {
        if n < self.slot.len() {
            // An undo took vertices away: so go their nodes and their places in patches.
            for (s, v) in self.nodes.iter_mut().enumerate() {
                if *v != u32::MAX && *v as usize >= n {
                    *v = u32::MAX;
                    for &(u, w) in &self.patches[s] {
                        if let Some(t) = self.sum.get_mut(u as usize) {
                            *t -= w;
                        }
                    }
                    self.patches[s].clear();
                }
                self.patches[s].retain(|&(u, _)| (u as usize) < n);
            }
            self.sum.truncate(n);
            self.inv_sum = self.sum.iter().map(|&t| inverse(t)).collect();
        }
        self.slot.resize(n, u32::MAX);
        self.sum.resize(n, 0.0);
        self.inv_sum.resize(n, 0.0);
        let mut redo = vec![false; self.nodes.len()];
        for &(u, d) in near {
            if d <= self.spacing
                && let Some(&s) = self.slot.get(u as usize)
                && s != u32::MAX
            {
                redo[s as usize] = true;
            }
        }
        // Only the sums of the vertices in a patch found again change: a patch's weights
        // come off them and the new ones go on.
        let mut changed = Vec::new();
        for (s, r) in redo.into_iter().enumerate() {
            if r && self.nodes[s] != u32::MAX {
                let new = patch(g, self.nodes[s], self.spacing, n, search);
                for &(u, w) in &self.patches[s] {
                    self.sum[u as usize] -= w;
                    changed.push(u);
                }
                for &(u, w) in &new {
                    self.sum[u as usize] += w;
                    changed.push(u);
                }
                self.patches[s] = new;
            }
        }
        for u in changed {
            self.inv_sum[u as usize] = inverse(self.sum[u as usize]);
        }
        self.relink(links, loose);
    }

    /// The links in node slots, with their `loose` lengths.
    fn relink(&mut self, links: &[Limit], loose: &[f32]) {
        let slot = &self.slot;
        let of = |v: u32| slot.get(v as usize).copied().filter(|&s| s != u32::MAX);
        (self.links, self.loose) = links
            .iter()
            .zip(loose)
            .filter_map(|(&(a, b, r), &l)| Some(((of(a)?, of(b)?, r), l)))
            .unzip();
    }

    /// The nodes' inverse masses from the vertices' (`w`): a patch's mass is the blended
    /// sum of its vertices' masses; a patch holding a vertex that does not move (pinned,
    /// held) does not move either.
    pub(super) fn node_weights(&self, w: &[f32], out: &mut Vec<f32>) {
        out.clear();
        out.extend(self.patches.iter().map(|p| {
            let mut m = 0.0f32;
            for &(v, phi) in p {
                match w.get(v as usize) {
                    Some(&wv) if wv > 0.0 => m += phi * self.inv_sum[v as usize] / wv,
                    _ => return 0.0,
                }
            }
            if m > 0.0 { 1.0 / m } else { 0.0 }
        }));
    }

    /// One pass over the level's links on its nodes, each as long as its rest, or `loose`
    /// (0 to 1) of the way from it to its rest path through the edges, times `scale`;
    /// then every vertex that moves (`w` > 0) takes the blend of the moved nodes'
    /// corrections. `node_w` from `node_weights`; `q` is scratch.
    pub(super) fn solve(
        &self,
        scale: f32,
        x: &mut [Vec3],
        w: &[f32],
        node_w: &[f32],
        loose: f32,
        q: &mut Vec<Vec3>,
    ) {
        let n = x.len().min(w.len()).min(self.inv_sum.len());
        if self.links.is_empty() || node_w.len() != self.nodes.len() {
            return;
        }
        q.clear();
        q.resize(self.nodes.len(), Vec3::ZERO);
        let mut moved = false;
        for (&(a, b, rest), &path) in self.links.iter().zip(&self.loose) {
            let (a, b) = (a as usize, b as usize);
            let max = (rest + (path - rest) * loose) * scale;
            let (pa, pb) = (self.nodes[a] as usize, self.nodes[b] as usize);
            if pa >= n || pb >= n {
                continue;
            }
            let d = (x[pa] + q[a]) - (x[pb] + q[b]);
            let l2 = d.length_squared();
            if l2 <= max * max {
                continue;
            }
            let ws = node_w[a] + node_w[b];
            if ws <= 0.0 {
                continue;
            }
            let l = l2.sqrt();
            let s = (l - max) / (l * ws);
            q[a] -= d * (s * node_w[a]);
            q[b] += d * (s * node_w[b]);
            moved = true;
        }
        if !moved {
            return;
        }
        for (p, &dq) in self.patches.iter().zip(q.iter()) {
            if dq == Vec3::ZERO {
                continue;
            }
            for &(v, phi) in p {
                let v = v as usize;
                if v < n && w[v] > 0.0 {
                    x[v] += dq * (phi * self.inv_sum[v]);
                }
            }
        }
    }
}

/// One over a vertex's sum of weights, 0 where none reaches it (a sum kept up to date by
/// subtraction can end a rounding error above 0 when its last patch goes).
fn inverse(sum: f32) -> f32 {
    if sum > 1e-6 { 1.0 / sum } else { 0.0 }
}

/// The tent weights `1 - d / spacing` of the vertices (below `n`) within `spacing` of `v`.
fn patch(g: &impl Graph, v: u32, spacing: f32, n: usize, search: &mut Bounded) -> Vec<(u32, f32)> {
    let mut p = Vec::new();
    search.run(g, v, spacing, |u, d| {
        let w = 1.0 - d / spacing;
        if w > 0.0 && (u as usize) < n {
            p.push((u, w));
        }
    });
    p
}

#[cfg(test)]
impl Blend {
    /// Each slot's node and (vertex, share) pairs, sorted by vertex.
    pub(super) fn shares(&self) -> Vec<(u32, Vec<(u32, f32)>)> {
        self.nodes
            .iter()
            .zip(&self.patches)
            .map(|(&v, p)| {
                let mut p: Vec<(u32, f32)> = p
                    .iter()
                    .map(|&(u, w)| (u, w * self.inv_sum[u as usize]))
                    .collect();
                p.sort_unstable_by_key(|e| e.0);
                (v, p)
            })
            .collect()
    }

    /// Vertices reached by no node.
    pub(super) fn uncovered(&self) -> usize {
        self.inv_sum.iter().filter(|&&s| s == 0.0).count()
    }
}
