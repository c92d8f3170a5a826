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
//! as the rest distance between them through the cloth, times `1 + strain` (the most the
//! material itself stretches under the cloth's own weight, as for the pin tethers): the
//! straight rest distance where the straight line between them lies on the cloth
//! (`straight`), else the shortest path through the live mesh's rest edges. Neither is
//! shorter than the geodesic rest distance, so a link never holds the cloth tighter than
//! its material would: folding, draping and compression leave it slack. Only the
//! solver's lag is removed. (The edge path alone zigzags on a mesh whose triangles point
//! every way, several percent longer than the line: a garment's pieces hung that much
//! longer than cut before the links held.) While a seam is being sewn the links take the
//! edge path: its stitches pull the cloth across, and with every link straight the
//! shipped dress's last pair at a shoulder's neck end stayed open in most runs
//! (docs/models.md).
//! XPBD solves the links before and after the membranes in every substep, each level as a
//! coarse level of its own: a node stands for the patch of cloth around it, with the
//! patch's mass, and its correction moves the whole patch (`coarse`). An edit updates the
//! links and patches around what it touched (`StretchLimits::update`), so a cut or a tear
//! frees what it separates and a seam or an undo joins it again.
//!
//! Measured (docs/models.md): on the mannequin drape the mean strain falls from 41% to 5%
//! with links that move only their node vertices, and the drape comes to rest; with
//! patches, to under 1%.
//!
//! Where the cloth hangs from a body (a cube's rim, the top of the head) every link
//! through the support is loaded by everything below it. The links weight a vertex lying
//! on the body as half its inverse mass (`link_weights`): the body carries part of it.

use glam::Vec3;

use super::coarse::{Blend, Limit};
use super::graph::{Bounded, LiveGraph, RestGraph};
use super::straight::straight_rest;
use crate::collision::ContactCache;
use crate::solver::state::Cloth;

/// Lattice spacings in mean edge lengths, coarse first (the order they are solved in).
/// Each level costs about 3 links per node. On the 128 x 128 mannequin drape, before
/// the support weighting below: mean strain 6.3% with these, 10.2% with 3 alone, 5.9%
/// with 24, 6 and 3 (whose coarsest level makes an edit's update several times dearer).
/// Solved on patches (64 x 64 mannequin, mean / largest strain): 0.73% / 0.42 with these,
/// 0.56% / 0.39 with 12, 6 and 3, 0.30% / 0.40 with 6, 3 and 1.5, the last two at 1.25x
/// and 1.4x this pair's frame without the guard.
const LEVELS: [f32; 2] = [6.0, 3.0];

/// A link allows at least this strain over its rest path, even where the material's own
/// under the cloth's weight is less (0.1% for the default cotton): seams and the pen may
/// stretch a fabric that far freely (a cotton's 2000 N/m takes 10 N/m for it, about what
/// a seam's stitches pull with). With links that move whole patches (`coarse`) and only
/// the 0.1%, fit-cube's sewn flaps could not stretch round the cube's corners and 4 to 15
/// of its 48 pairs stayed open at grid 40 (the 1 mm contact makes the way round 0.4%
/// longer than the cube); with 0.5%, 46-48 welded and the mannequin drape's mean strain is
/// 0.9% (0.75%: 48 welded, 1.0%).
const MIN_SLACK: f32 = 0.005;

/// A link reaches the lattice nodes within this many spacings (through the mesh): the
/// four axis neighbours of a grid lattice and the diagonal its triangles run along.
const REACH: f32 = 1.5;

/// How much farther than a link's reach, along the edges, an edit looks for the ends of
/// links to find again: a straight link's line can cross what an edit touched at a
/// straight distance that the edge paths zigzag past (on the shipped dress they run 5.5%
/// longer than the line at the median, 8% at p90; a cut's other side is not on the way).
/// Only the link's nearer end need be found, and that end lies within about half the
/// link's length (plus the crossed triangle's size) of a touched vertex, so 1.15 leaves
/// room for paths up to nearly twice the line. Checked against a relink of every node
/// after every update in fit-cube, tear and both dresses at 1.5, 1.15 and 1.0: no update
/// differed (docs/performance.md, "the update is a relink after all"); 1.15 against 1.5
/// takes about a sixth off a cut, a sew and a tear.
const STRAIGHT_REACH: f32 = 1.15;

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

/// A link's rest length between `a` and `b`, whose shortest rest path through the edges
/// is `path`: their straight rest distance where the straight line between them lies on
/// the cloth (`straight`), else the path; neither is shorter than the geodesic.
fn rest_between(cloth: &Cloth, a: u32, b: u32, path: f32) -> f32 {
    straight_rest(&cloth.live, a, b).map_or(path, |s| s.min(path))
}

/// One lattice: its spacing (m), which vertices are its nodes, and its links.
#[derive(Clone, Debug, Default)]
struct Level {
    spacing: f32,
    node: Vec<bool>,
    links: Vec<Limit>,
    /// Each link's rest path through the edges (its length while a seam is sewn).
    loose: Vec<f32>,
    /// The level solved on patches (`coarse`).
    blend: Blend,
}

/// Scratch of the coarse solve: each level's node inverse masses this frame, and node
/// positions.
#[derive(Clone, Debug, Default)]
pub(super) struct CoarseScratch {
    node_w: Vec<Vec<f32>>,
    /// How loose the links are this frame, 0 to 1: from their straight rest distances
    /// to their rest paths (1 while a seam is being sewn, `sewing`).
    loose: f32,
    q: Vec<Vec3>,
}

/// The stretch limits of a cloth, kept in step with its edits.
#[derive(Clone, Debug, Default)]
pub(crate) struct StretchLimits {
    levels: Vec<Level>,
    /// A link may be `1 + strain` times its rest length: the material's own stretch under
    /// the cloth's weight, at least `MIN_SLACK`.
    strain: f32,
}

impl StretchLimits {
    /// The lattices of `cloth`. `strain` is the slack allowed over the rest distance.
    pub(super) fn build(cloth: &Cloth, strain: f32) -> Self {
        let g = RestGraph::of(cloth);
        let n = g.len();
        let h = g.mean_edge();
        let mut limits = Self {
            strain: strain.max(MIN_SLACK),
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
                loose: Vec::new(),
                blend: Blend::default(),
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
                        lv.links.push((u, v, rest_between(cloth, u, v, d)));
                        lv.loose.push(d);
                    }
                });
            }
            lv.blend = Blend::of(&g, &lv.node, &lv.links, &lv.loose, spacing, &mut search);
            limits.levels.push(lv);
        }
        limits
    }

    /// The nodes' inverse masses for this frame from the vertices' `w`, and how `loose`
    /// the links are (`CoarseScratch::loose`).
    pub(super) fn node_weights(&self, w: &[f32], loose: f32, scratch: &mut CoarseScratch) {
        scratch.loose = loose;
        scratch.node_w.resize(self.levels.len(), Vec::new());
        for (lv, out) in self.levels.iter().zip(&mut scratch.node_w) {
            lv.blend.node_weights(w, out);
        }
    }

    /// One pass over every level's links on patches, coarse level first (`coarse`).
    pub(super) fn solve_coarse(&self, x: &mut [Vec3], w: &[f32], scratch: &mut CoarseScratch) {
        let scale = 1.0 + self.strain;
        for (lv, nw) in self.levels.iter().zip(&scratch.node_w) {
            lv.blend
                .solve(scale, x, w, nw, scratch.loose, &mut scratch.q);
        }
    }

    /// No links at all (off, or a cloth without triangles).
    pub(super) fn is_empty(&self) -> bool {
        self.levels.iter().all(|l| l.links.is_empty())
    }

    /// A new material's slack (see `strain`).
    pub(super) fn set_strain(&mut self, strain: f32) {
        self.strain = strain.max(MIN_SLACK);
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
    /// both its ends lie within its length of one. A link whose straight line crossed a
    /// touched triangle has its ends within its length of a touched vertex in a straight
    /// line, and so within [`STRAIGHT_REACH`] times that along the edges wherever the
    /// edge paths run no more than that much longer than the line (on the shipped dress,
    /// vertices 8-27 cm apart: 1.055 at the median, 1.08 at p90). The stretch of path
    /// from an end to the first touched vertex on it survives the edit (an edge leaves or
    /// changes only with a triangle, and then both its ends are touched), so a search
    /// from the touched vertices through the edited mesh finds every such end. Their links
    /// are dropped and found again from the edited mesh; the nodes stay where they were.
    pub(super) fn update(&mut self, cloth: &Cloth, touched: &[u32]) {
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
            .map(|l| REACH * l.spacing * STRAIGHT_REACH)
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
                if d <= r * STRAIGHT_REACH && lv.node[u as usize] && !affected[u as usize] {
                    affected[u as usize] = true;
                    redo.push(u);
                }
            }
            // Ends past the cloth (vertices an undo removed) go with their links.
            let keep = |&(a, b, _): &Limit| {
                (a as usize) < n
                    && (b as usize) < n
                    && !affected[a as usize]
                    && !affected[b as usize]
            };
            let mut i = 0;
            lv.loose.retain(|_| {
                i += 1;
                keep(&lv.links[i - 1])
            });
            lv.links.retain(keep);
            for &a in &redo {
                search.run(&g, a, r, |b, d| {
                    let found_twice = affected[b as usize] && b < a;
                    if b != a && lv.node[b as usize] && !found_twice && !pinned_pair(cloth, a, b) {
                        lv.links.push((b, a, rest_between(cloth, b, a, d)));
                        lv.loose.push(d);
                    }
                });
            }
            lv.blend
                .update(&g, n, &lv.links, &lv.loose, &near, &mut search);
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
        let links: Vec<Limit> = StretchLimits::build(&c, 0.0).links().collect();
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

    /// One coarse pass of `l` over `c`, weighted by the cloth's inverse masses.
    fn pass(l: &StretchLimits, c: &mut Cloth) {
        let mut scratch = CoarseScratch::default();
        l.node_weights(&c.inv_mass, 0.0, &mut scratch);
        l.solve_coarse(&mut c.x, &c.inv_mass, &mut scratch);
    }

    /// The longest edge of `c` over its rest length.
    fn worst_edge(c: &Cloth) -> f32 {
        c.live
            .iter()
            .flat_map(|(_, t)| {
                (0..3).map(move |k| {
                    let (a, b) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
                    (a, b, (t.rest[k] - t.rest[(k + 1) % 3]).length())
                })
            })
            .map(|(a, b, r)| (c.x[a] - c.x[b]).length() / r)
            .fold(0.0f32, f32::max)
    }

    #[test]
    fn bending_without_stretching_leaves_every_link_slack() {
        let mut c = cloth(36);
        let l = StretchLimits::build(&c, 0.0);
        let links: Vec<Limit> = l.links().collect();
        // Roll the cloth onto a cylinder of radius 0.2 m: an isometry, so no path through
        // the cloth gets longer and every straight distance gets shorter or stays.
        for p in &mut c.x {
            let a = p.x / 0.2;
            *p = Vec3::new(0.2 * a.sin(), 0.2 * (1.0 - a.cos()), p.z);
        }
        let before = c.x.clone();
        pass(&l, &mut c);
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
        let edge_before = worst_edge(&c);
        pass(&l, &mut c);
        let once = worst(&c.x);
        // The cloth between the nodes moves with them: no edge gets longer.
        let edge_once = worst_edge(&c);
        for _ in 0..30 {
            pass(&l, &mut c);
        }
        let converged = worst(&c.x);
        assert!(
            stretched > 1.15 && once < stretched - 0.05 && converged < 1.01,
            "{stretched} -> {once} -> {converged}"
        );
        assert!(
            edge_once <= edge_before + 1e-4 && worst_edge(&c) < edge_once - 0.02,
            "edges {edge_before} -> {edge_once} -> {}",
            worst_edge(&c)
        );
    }

    /// The links sorted by their ends.
    fn sorted(l: &StretchLimits) -> Vec<(u32, u32, f32)> {
        let mut v: Vec<_> = l.links().map(|(a, b, m)| (a.min(b), a.max(b), m)).collect();
        v.sort_unstable_by_key(|&(a, b, _)| (a, b));
        v
    }

    /// One level's (node, patch shares), see `Blend::shares`.
    type Shares = Vec<(u32, Vec<(u32, f32)>)>;

    /// Each level's blend.
    fn blends(l: &StretchLimits) -> Vec<Shares> {
        l.levels.iter().map(|lv| lv.blend.shares()).collect()
    }

    /// The same blends up to rounding.
    fn assert_same_blends(got: &StretchLimits, want: &[Shares]) {
        let got = blends(got);
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().flatten().zip(want.iter().flatten()) {
            assert_eq!(g.0, w.0, "node");
            let same = g.1.len() == w.1.len()
                && g.1
                    .iter()
                    .zip(&w.1)
                    .all(|(a, b)| a.0 == b.0 && (a.1 - b.1).abs() < 1e-5);
            assert!(same, "node {}: patch {:?} against {:?}", g.0, g.1, w.1);
        }
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

    /// Takes out of `c` every triangle with a corner for which `out` holds: the triangles
    /// taken (slot, triangle) and their corners, sorted, once each.
    fn cut_out(c: &mut Cloth, out: impl Fn(u32) -> bool) -> (Vec<(u32, Tri)>, Vec<u32>) {
        let cut: Vec<(u32, Tri)> = (c.live.iter())
            .filter(|(_, t)| t.v.iter().any(|&v| out(v)))
            .map(|(slot, t)| (slot, *t))
            .collect();
        let mut touched: Vec<u32> = cut.iter().flat_map(|(_, t)| t.v).collect();
        touched.sort_unstable();
        touched.dedup();
        for (slot, _) in &cut {
            c.live.set(*slot, None).unwrap();
        }
        (cut, touched)
    }

    #[test]
    fn a_cut_frees_what_it_separates_and_undo_brings_it_back() {
        let n = 24;
        let mut c = cloth(n);
        let mut limits = StretchLimits::build(&c, 0.0);
        let original = sorted(&limits);
        let original_blends = blends(&limits);
        assert!(limits.levels.iter().all(|lv| lv.blend.uncovered() == 0));
        // Cut the cloth in two along the middle column of vertices.
        let mid = (n / 2) as u32;
        let on_cut = |v: u32| v % (n as u32 + 1) == mid;
        let (cut, touched) = cut_out(&mut c, on_cut);
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
        // Likewise the patches: none reaches across the cut.
        assert_same_blends(&limits, &blends(&all));
        for (_, patch) in blends(&limits).iter().flatten() {
            assert!(patch.iter().all(|&(u, _)| side(u) == side(patch[0].0)));
        }
        // Undo: the triangles come back, and so do the links.
        for (slot, t) in &cut {
            c.live.set(*slot, Some(*t)).unwrap();
        }
        limits.update(&c, &touched);
        assert_same(&limits, &original);
        assert_same_blends(&limits, &original_blends);
    }

    #[test]
    fn pinned_pairs_and_pinned_ends() {
        let mut c = cloth(12);
        for v in 0..c.len() {
            c.pin(v);
        }
        assert_eq!(
            StretchLimits::build(&c, 0.0).len(),
            0,
            "links between pinned vertices"
        );
        // Pinned along its left edge and stretched across: what is pinned stays, and the
        // rest is pulled in.
        let mut c = cloth(24);
        let left = |v: usize| v.is_multiple_of(25);
        for v in (0..c.len()).filter(|&v| left(v)) {
            c.pin(v);
        }
        for p in &mut c.x {
            p.x *= 1.3;
        }
        let before = c.x.clone();
        pass(&StretchLimits::build(&c, 0.0), &mut c);
        for v in (0..c.len()).filter(|&v| left(v)) {
            assert_eq!(c.x[v], before[v], "pinned vertex {v} moved");
        }
        let right = 24;
        assert!(c.x[right].x < before[right].x - 0.01, "not pulled in");
    }

    /// A hole cut in a meshed piece (every triangle round the 30 vertices nearest its
    /// middle): the update gives the links a relink of every node gives, and undo gives
    /// the links back.
    #[test]
    fn a_hole_in_a_meshed_piece_relinks_as_a_relink_of_every_node() {
        let mut c = meshed();
        let mut limits = StretchLimits::build(&c, 0.0);
        let original = sorted(&limits);
        let centre = c.x.iter().copied().sum::<Vec3>() / c.len() as f32;
        let mut middle: Vec<u32> = (0..c.len() as u32).collect();
        let off = |v: u32| c.x[v as usize].distance(centre);
        middle.sort_by(|&a, &b| off(a).total_cmp(&off(b)));
        let (hole, touched) = cut_out(&mut c, |v| middle[..30].contains(&v));
        limits.update(&c, &touched);
        let mut all = limits.clone();
        let every: Vec<u32> = (0..c.len() as u32).collect();
        all.update(&c, &every);
        assert_same(&limits, &sorted(&all));
        assert_ne!(sorted(&limits), original, "the hole changed no link");
        for (slot, t) in &hole {
            c.live.set(*slot, Some(*t)).unwrap();
        }
        limits.update(&c, &touched);
        assert_same(&limits, &original);
    }

    /// A 0.6 m square meshed with triangles that point every way (the mesher's, 3 cm),
    /// flat at rest.
    fn meshed() -> Cloth {
        let outline = crate::mesh::mesher::Outline::rectangle(0.6, 0.6);
        let mesh = crate::mesh::mesher::mesh_outline(&outline, 0.03).unwrap();
        Cloth::new(mesh, &Material::default()).unwrap()
    }

    /// The warp and weft of a flat cloth at rest.
    fn threads(c: &Cloth) -> (Vec3, Vec3) {
        let t = c.live.iter().next().unwrap().1;
        let warp = crate::mesh::live::warp_of(t.rest, t.uv);
        let n = (t.rest[1] - t.rest[0]).cross(t.rest[2] - t.rest[0]);
        (warp, n.normalize().cross(warp))
    }

    /// Each vertex of `c` put where `f` takes its rest place's (warp, weft) coordinates.
    fn deform(c: &mut Cloth, f: impl Fn(f32, f32) -> Vec3) {
        let (warp, weft) = threads(c);
        let places = c.live.pattern_places(c.len());
        for (x, r) in c.x.iter_mut().zip(places) {
            *x = f(r.dot(warp), r.dot(weft));
        }
    }

    /// On a mesh whose triangles point every way, an edge path zigzags: links as long as
    /// it let the threads stretch several percent before they held (the shipped dress
    /// hung 6% longer than cut, median). The links take the straight rest distance, so a
    /// piece stretched 4% along its warp is pulled back to the links' slack; while a seam
    /// is sewn they take the path again.
    #[test]
    fn a_meshed_piece_is_held_at_its_straight_rest_distances() {
        const PASSES: usize = 4;
        let c = meshed();
        let l = StretchLimits::build(&c, 0.0);
        let places = c.live.pattern_places(c.len());
        let straight = |a: u32, b: u32| (places[a as usize] - places[b as usize]).length();
        let mut longer = 0;
        for (lv, (&(a, b, rest), &path)) in (l.levels.iter())
            .flat_map(|lv| std::iter::repeat(lv).zip(lv.links.iter().zip(&lv.loose)))
        {
            assert!(
                rest >= straight(a, b) * 0.9999,
                "link {a}-{b} under the straight distance"
            );
            assert!(rest <= path, "link {a}-{b} longer than its path");
            // A square is convex: every link's straight line lies on it.
            assert!(
                (rest - straight(a, b)).abs() < 1e-4 * lv.spacing,
                "{rest} {}",
                straight(a, b)
            );
            if path > rest * 1.01 {
                longer += 1;
            }
        }
        let n = l.len();
        assert!(
            longer * 5 > n,
            "only {longer} of {n} paths zigzag a percent over the line"
        );

        // Stretched 4% along the warp, then a few coarse passes: each link's ends as far
        // apart as they are, over their straight rest distance.
        let over = |loose: f32| {
            let mut c = meshed();
            let (warp, weft) = threads(&c);
            deform(&mut c, |u, v| warp * u * 1.04 + weft * v);
            for _ in 0..PASSES {
                let mut scratch = CoarseScratch::default();
                l.node_weights(&c.inv_mass, loose, &mut scratch);
                l.solve_coarse(&mut c.x, &c.inv_mass, &mut scratch);
            }
            let mut r: Vec<f32> = (l.links())
                .map(|(a, b, _)| (c.x[a as usize] - c.x[b as usize]).length() / straight(a, b))
                .collect();
            r.sort_unstable_by(f32::total_cmp);
            (r[r.len() / 2], r[r.len() * 9 / 10])
        };
        let (held, sewing) = (over(0.0), over(1.0));
        // Held: the median link within its 0.5% slack, nine in ten within 2% (measured
        // 1.0048 and 1.012: four passes do not finish it).
        assert!(held.0 < 1.006 && held.1 < 1.02, "links held at {held:?}");
        // Sewing: the paths, a few percent longer, leave most of the 4% (1.042).
        assert!(sewing.1 > 1.03, "links while sewing at {sewing:?}");
    }
}
