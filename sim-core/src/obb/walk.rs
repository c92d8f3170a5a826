//! Nearest-point queries that skip the tree when a nearby triangle is known (last frame's
//! answer): walk across edges from it to the triangle under the point, then prove the
//! answer from data computed once per triangle.
//!
//! The proof. Let `q` be the nearest point of triangle `t` to `p`, inside `t`'s face,
//! with `p` at height `h = |p - q| > 0` on the outer side of `t`'s plane. Split the
//! other triangles `s` in three:
//! - those below `t`'s plane (no corner higher than `RISE_TOLERANCE`): every point of
//!   `s` is at least `h - RISE_TOLERANCE` from `p`, no nearer than `t` itself;
//! - the few that rise above it near its centroid `c` (its near list, up to `MAX_NEAR`
//!   within `NEAR_RADIUS`: a reflex edge next to `t`, a fold of the body): they are
//!   tested, with `t`; let `d` be the least distance among them;
//! - the rest rise above it but are at least `clearance[t]` from `c`, so at least
//!   `clearance[t] - |p - c|` from `p` (the triangle inequality): no nearer than `d`
//!   when `d + |p - c| <= clearance[t]`.
//!
//! So when that inequality holds, the nearest of the tested triangles is the nearest of
//! all, to within a few `RISE_TOLERANCE` (1 µm; where two triangles tie that closely,
//! either may be returned). When `q` is on the edge `t` shares with `u` instead (the
//! walk crossed it from both sides), the same holds with "below both planes" for the
//! first group, provided `p - q` lies between the two face normals (then `q` is the
//! nearest point of the wedge below both), and both triangles' near lists and
//! clearances for the others. Corners are left to the tree.
//!
//! On a convex body nothing rises above any face and every face or edge answer is
//! proved; near a concave fold (an armpit, a neck) the clearance shrinks and the query
//! falls back to the tree. The walk needs no proof: it only picks where to start one.

use std::collections::HashMap;

use glam::Vec3;

use super::geometry::{Feature, Obb, closest_point_on_triangle};
use super::queries::NearestHit;
use super::tree::ObbTree;

/// Corners at most this far above a triangle's plane count as below it, m (absorbs the
/// rounding of coplanar neighbours).
const RISE_TOLERANCE: f32 = 1e-6;

/// Edge steps a walk may take before giving up (the tree answers instead).
const MAX_STEPS: usize = 8;

/// At most this many rising triangles are tested with a triangle ...
const MAX_NEAR: usize = 8;

/// ... and only those nearer its centroid than this, m: the rest only bound the clearance.
const NEAR_RADIUS: f32 = 0.03;

/// Clearances are searched no farther than this, m: enough to prove points up to about
/// 12 cm from the body, farther than a contact search reaches.
const MAX_CLEARANCE: f32 = 0.25;

/// A walk that could not prove its answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Miss {
    /// A triangle near the point, the tree's best hint (`u32::MAX` if none).
    pub near: u32,
    /// No surface point is nearer than this, m (0 when the walk learnt nothing).
    pub clear: f32,
}

impl Miss {
    fn at(near: u32) -> Self {
        Self { near, clear: 0.0 }
    }
}

/// Per-triangle data for the walk, indexed by the mesh's original triangle index.
#[derive(Clone, Debug, Default)]
pub struct SurfaceWalk {
    /// The triangle across local edge k (corner k to k + 1); `u32::MAX` on a boundary or
    /// non-manifold edge.
    across: Vec<[u32; 3]>,
    /// Unit normal from the winding, `(b - a) x (c - a)`.
    normal: Vec<Vec3>,
    /// Least distance from the centroid to a triangle that rises above this one's plane
    /// and is not in its near list (`MAX_CLEARANCE` when none is nearer).
    clearance: Vec<f32>,
    centroid: Vec<Vec3>,
    /// Triangle `t`'s near list, the rising triangles tested with it, is
    /// `near[near_start[t]..near_start[t + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
}

impl SurfaceWalk {
    /// Precomputes adjacency, near lists and clearances for the tree's mesh: a range
    /// search and a filtered nearest-point search per triangle, split over two threads
    /// (6-8 µs of CPU per triangle here: 40-70 ms for the mannequin).
    pub fn new(tree: &ObbTree) -> Self {
        let n = tree.indices.len();
        let mid = n / 2;
        let (first, second) = std::thread::scope(|s| {
            let second = s.spawn(|| Certificates::of(tree, mid as u32..n as u32));
            let first = Certificates::of(tree, 0..mid as u32);
            // A panic in the worker is a bug: re-raise it here.
            (
                first,
                second
                    .join()
                    .unwrap_or_else(|e| std::panic::resume_unwind(e)),
            )
        });
        let mut c = first;
        let offset = c.near.len() as u32;
        c.near_start
            .extend(second.near_start[1..].iter().map(|&i| i + offset));
        c.near.extend(second.near);
        c.normal.extend(second.normal);
        c.centroid.extend(second.centroid);
        c.clearance.extend(second.clearance);
        Self {
            across: adjacency(&tree.indices),
            normal: c.normal,
            clearance: c.clearance,
            centroid: c.centroid,
            near_start: c.near_start,
            near: c.near,
        }
    }

    /// The nearest surface point to `p`, when a walk from triangle `start` finds it and
    /// proves it (see the module doc): at any distance, with no bound to pass. Otherwise
    /// the [`Miss`] says which triangle near `p` the walk tested (the tree's best hint)
    /// and how near the surface can be: when the proof fails only on the clearance, the
    /// lesser of the tested distance and the clearance's bound.
    pub fn nearest(&self, tree: &ObbTree, p: Vec3, start: u32) -> Result<NearestHit, Miss> {
        let (mut t, mut prev) = (start, u32::MAX);
        if !p.is_finite() {
            return Err(Miss::at(t));
        }
        for _ in 0..MAX_STEPS {
            let [a, b, c] = tree.triangle(t).ok_or(Miss::at(prev))?;
            let (q, feature) = closest_point_on_triangle(p, a, b, c);
            let next = match feature {
                Feature::Face => return self.prove(tree, p, (q, feature), t, None),
                // Beyond the edge shared with the triangle the walk came from, seen from
                // both sides: the nearest point is on that edge.
                Feature::Edge(k)
                    if prev != u32::MAX && self.across[t as usize][k as usize] == prev =>
                {
                    return self.prove(tree, p, (q, feature), t, Some(prev));
                }
                Feature::Edge(k) => self.across[t as usize][k as usize],
                // Past a corner: leave by whichever of its two edges `p` is farther
                // beyond. Back where the walk came from means the corner itself is the
                // nearest point, which this does not prove.
                Feature::Vertex(k) => {
                    let corners = [a, b, c];
                    let beyond = |e: usize| {
                        let (u, v, w) = (corners[e], corners[(e + 1) % 3], corners[(e + 2) % 3]);
                        let inward = (v - u).cross(self.normal[t as usize]);
                        let inward = inward * (w - u).dot(inward).signum();
                        -(p - u).dot(inward)
                    };
                    let (k, before) = (k as usize, (k as usize + 2) % 3);
                    let e = if beyond(k) >= beyond(before) {
                        k
                    } else {
                        before
                    };
                    let next = self.across[t as usize][e];
                    if next == prev {
                        return Err(Miss::at(t));
                    }
                    next
                }
            };
            (prev, t) = (t, next);
        }
        Err(Miss::at(prev))
    }

    /// `q` is the nearest point of triangle `t` to `p`: inside its face, or (with `other`)
    /// on the edge it shares with `other`. The answer is the nearest of the triangles and
    /// their near lists, if the clearances prove it; otherwise the nearest of them.
    fn prove(
        &self,
        tree: &ObbTree,
        p: Vec3,
        (q, feature): (Vec3, Feature),
        t: u32,
        other: Option<u32>,
    ) -> Result<NearestHit, Miss> {
        let i = t as usize;
        let up = p - q;
        let a = up.dot(self.normal[i]);
        if a <= 0.0 {
            return Err(Miss::at(t));
        }
        // On an edge, `p - q` must lie between the two face normals: then no point below
        // both planes is nearer than `q` (it is the nearest point of that wedge). Both
        // triangles' edge features imply it when the walk crossed from `other`'s edge;
        // it is checked because it may have crossed from `other`'s corner.
        if let Some(s) = other {
            let ns = self.normal[s as usize];
            let (b, g) = (up.dot(ns), self.normal[i].dot(ns));
            if !(b > 0.0 && a - g * b >= 0.0 && b - g * a >= 0.0) {
                return Err(Miss::at(t));
            }
        }
        let mut best = (t, q, feature, up.length_squared());
        let mut test = |s: u32| {
            if let Some([a, b, c]) = tree.triangle(s) {
                let (q, f) = closest_point_on_triangle(p, a, b, c);
                let d2 = (q - p).length_squared();
                if d2 < best.3 {
                    best = (s, q, f, d2);
                }
            }
        };
        self.near_list(t).iter().for_each(|&s| test(s));
        if let Some(s) = other {
            test(s);
            self.near_list(s).iter().for_each(|&s| test(s));
        }
        let distance = best.3.sqrt();
        // How near an untested triangle rising above the face may be.
        let unlisted = |t: u32| {
            let t = t as usize;
            self.clearance[t] - (p - self.centroid[t]).length()
        };
        let unlisted = other.map_or(unlisted(t), |s| unlisted(t).min(unlisted(s)));
        if distance > unlisted {
            // Not proved, but nothing is nearer than either bound.
            return Err(Miss {
                near: best.0,
                clear: distance.min(unlisted).max(0.0),
            });
        }
        Ok(NearestHit {
            tri: best.0,
            point: best.1,
            distance,
            feature: best.2,
        })
    }

    fn near_list(&self, t: u32) -> &[u32] {
        let t = t as usize;
        &self.near[self.near_start[t] as usize..self.near_start[t + 1] as usize]
    }

    /// How many triangles have some other part of the surface rising above their plane
    /// within `MAX_CLEARANCE` (none on a convex body).
    pub fn concave_count(&self) -> usize {
        (0..self.clearance.len())
            .filter(|&t| {
                self.clearance[t] < MAX_CLEARANCE || self.near_start[t] != self.near_start[t + 1]
            })
            .count()
    }
}

/// The per-triangle part of a [`SurfaceWalk`] for a range of triangles.
struct Certificates {
    normal: Vec<Vec3>,
    centroid: Vec<Vec3>,
    clearance: Vec<f32>,
    /// Starts at 0; one more entry than triangles.
    near_start: Vec<u32>,
    near: Vec<u32>,
}

impl Certificates {
    fn of(tree: &ObbTree, range: std::ops::Range<u32>) -> Self {
        let n = range.len();
        let mut c = Self {
            normal: Vec::with_capacity(n),
            centroid: Vec::with_capacity(n),
            clearance: Vec::with_capacity(n),
            near_start: Vec::with_capacity(n + 1),
            near: Vec::new(),
        };
        c.near_start.push(0);
        let mut found: Vec<(f32, u32)> = Vec::new();
        for t in range {
            let [a, b, cc] = tree.triangle(t).unwrap_or([Vec3::ZERO; 3]);
            let nrm = (b - a).cross(cc - a).normalize_or_zero();
            let centre = (a + b + cc) / 3.0;
            let level = nrm.dot(a) + RISE_TOLERANCE;
            let rises = |tri: &[Vec3; 3]| tri.iter().any(|v| nrm.dot(*v) > level);
            let box_rises = |b: &Obb| {
                let reach = (b.axes.transpose() * nrm).abs().dot(b.half);
                nrm.dot(b.center) + reach > level
            };
            // The rising triangles within NEAR_RADIUS of the centroid, nearest first: up
            // to MAX_NEAR are listed; the next one, or the nearest beyond the radius,
            // gives the clearance.
            found.clear();
            tree.for_each_within(centre, NEAR_RADIUS, box_rises, rises, |s, d| {
                found.push((d, s))
            });
            found.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            let clearance = match found.get(MAX_NEAR) {
                Some(&(d, _)) => d,
                None => {
                    let listed = |slot: usize| found.iter().any(|&(_, s)| s == tree.tri_ids[slot]);
                    let rest = |slot: usize, tri: &[Vec3; 3]| rises(tri) && !listed(slot);
                    tree.nearest_where(centre, MAX_CLEARANCE, None, &mut 0, box_rises, rest)
                        .map_or(MAX_CLEARANCE, |hit| hit.distance)
                }
            };
            c.near.extend(found.iter().take(MAX_NEAR).map(|&(_, s)| s));
            c.normal.push(nrm);
            c.centroid.push(centre);
            // A degenerate triangle (zero normal) proves nothing.
            c.clearance
                .push(if nrm == Vec3::ZERO { 0.0 } else { clearance });
            c.near_start.push(c.near.len() as u32);
        }
        c
    }
}

/// For each triangle, the triangle across each local edge (corner k to k + 1), or
/// `u32::MAX` where the edge does not have exactly two triangles.
fn adjacency(indices: &[[u32; 3]]) -> Vec<[u32; 3]> {
    // Edge -> (first triangle, its local edge, triangles on the edge).
    let mut edges: HashMap<(u32, u32), (u32, u8, u32)> = HashMap::with_capacity(indices.len() * 2);
    for (t, tri) in indices.iter().enumerate() {
        for k in 0..3 {
            let (i, j) = (tri[k], tri[(k + 1) % 3]);
            edges
                .entry((i.min(j), i.max(j)))
                .and_modify(|e| e.2 += 1)
                .or_insert((t as u32, k as u8, 1));
        }
    }
    let mut across = vec![[u32::MAX; 3]; indices.len()];
    for (t, tri) in indices.iter().enumerate() {
        for k in 0..3 {
            let (i, j) = (tri[k], tri[(k + 1) % 3]);
            if let Some(&(first, fk, 2)) = edges.get(&(i.min(j), i.max(j)))
                && first != t as u32
            {
                across[t][k] = first;
                across[first as usize][fk as usize] = t as u32;
            }
        }
    }
    across
}
