//! Nearest-point queries that skip the tree when a nearby triangle is known (last frame's
//! answer): walk across edges from it to the triangle under the point, then prove the
//! answer from data computed once per triangle.
//!
//! The proof. Let `q` be the nearest point of triangle `t` to `p`, inside `t`'s face,
//! with `p` at height `h = |p - q| > 0` on the outer side of `t`'s plane. Split the
//! other triangles `s` in three:
//! - those below `t`'s plane (no corner higher than `RISE_TOLERANCE`): every point of
//!   `s` is at least `h - RISE_TOLERANCE` from `p`, no nearer than `t` itself;
//! - the few that rise above it nearest its centroid `c` (its near list, up to
//!   `MAX_NEAR`: a reflex edge next to `t`, a fold of the body): they are tested with
//!   `t`; let `d` be the least distance among them;
//! - the rest rise above it but none is nearer `p` than the bound below: no nearer than
//!   `d` when `d` is within that bound.
//!
//! The bound on the unlisted rising triangles is the lesser of two:
//! - those within `GATHER_RADIUS` of `c`: each lies no higher than its rise `r` above
//!   `t`'s plane, and its shadow on that plane is at least its gap `g` from `t`'s, so it
//!   is at least `hypot(g - l, h - r)` from a point at height `h` whose shadow is `l`
//!   from `t` (each part clamped at 0; a few such (gap, rise) pairs bound them all);
//!   each is also at least `clear[t] - |p - c|` from `p`, `clear` being the least
//!   distance from `c` to one (the triangle inequality), so the larger bound holds;
//! - those farther: at least `far[t] - |p - c|`.
//!
//! So when `d` is within that bound, the nearest of the tested triangles is the nearest
//! of all, to within a few `RISE_TOLERANCE` (1 µm; where two triangles tie that
//! closely, either may be returned). When `q` is on the edge `t` shares with `u` instead
//! (the walk crossed it from both sides), the same holds with "below both planes" for
//! the first group, provided `p - q` lies between the two face normals (then `q` is the
//! nearest point of the wedge below both), and both triangles' near lists and bounds for
//! the others. Corners are left to the tree.
//!
//! The listed triangles carry the same (gap, rise) pair and their plane, so most are
//! skipped without computing their nearest point. On a convex body nothing rises above
//! any face and every face or edge answer is proved; near a concave fold (an armpit, a
//! neck) the bound shrinks and the query falls back to the tree. The walk needs no proof:
//! it only picks where to start one.

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

/// At most this many rising triangles are listed (tested) with a triangle: the nearest
/// to its centroid.
const MAX_NEAR: usize = 12;

/// The unlisted rising triangles this near the centroid are bounded by (gap, rise)
/// pairs, m; those farther by their distance from it.
const GATHER_RADIUS: f32 = 0.06;

/// At most this many (gap, rise) pairs per triangle (merged pairs bound both).
const MAX_BOUNDS: usize = 4;

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
    face: Vec<Face>,
    /// The near lists, each face's at its `near` span.
    near: Vec<Listed>,
    /// The (gap, rise) pairs, each face's at its `bounds` span.
    bounds: Vec<[f32; 2]>,
}

/// What the proof needs of one triangle, together in memory.
#[derive(Clone, Copy, Debug, Default)]
struct Face {
    /// Unit normal from the winding, `(b - a) x (c - a)`.
    normal: Vec3,
    centroid: Vec3,
    /// Least distance from the centroid to a rising triangle not in the near list
    /// (`MAX_CLEARANCE` when none is nearer).
    clear: f32,
    /// The same for those beyond `GATHER_RADIUS`.
    far: f32,
    /// Its near list: the rising triangles tested with it.
    near: Span,
    /// Its (gap, rise) pairs, bounding its other rising triangles within
    /// `GATHER_RADIUS`.
    bounds: Span,
}

/// A face's part of one of the walk's shared lists.
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    start: u32,
    len: u32,
}

impl Span {
    /// The span of the items pushed to `items` since it held `start`.
    fn since(start: usize, items: usize) -> Self {
        Self {
            start: start as u32,
            len: (items - start) as u32,
        }
    }

    fn of<'a, T>(&self, items: &'a [T]) -> &'a [T] {
        &items[self.start as usize..(self.start + self.len) as usize]
    }
}

/// A rising triangle listed with a face, with what bounds its distance without computing
/// it: its (gap, rise) pair as in the module doc, and its plane.
#[derive(Clone, Copy, Debug)]
struct Listed {
    tri: u32,
    gap: f32,
    rise: f32,
    normal: Vec3,
    offset: f32,
}

impl SurfaceWalk {
    /// Precomputes adjacency, near lists and bounds for the tree's mesh: a range search
    /// and a filtered nearest-point search per triangle, split over two threads
    /// (about 10 µs of CPU per triangle here: 55-65 ms for the mannequin).
    pub fn new(tree: &ObbTree) -> Self {
        Self::with_near_lists(tree, MAX_NEAR)
    }

    /// As [`new`](Self::new), listing at most `max_near` rising triangles per triangle
    /// (tests use short lists to put the bounds on the rest to work).
    pub(crate) fn with_near_lists(tree: &ObbTree, max_near: usize) -> Self {
        let n = tree.indices.len();
        let mid = n / 2;
        let (mut c, second) = std::thread::scope(|s| {
            let second = s.spawn(|| Certificates::of(tree, mid as u32..n as u32, max_near));
            let first = Certificates::of(tree, 0..mid as u32, max_near);
            // A panic in the worker is a bug: re-raise it here.
            (
                first,
                second
                    .join()
                    .unwrap_or_else(|e| std::panic::resume_unwind(e)),
            )
        });
        let (near, bounds) = (c.near.len() as u32, c.bounds.len() as u32);
        c.face.extend(second.face.into_iter().map(|mut f| {
            f.near.start += near;
            f.bounds.start += bounds;
            f
        }));
        c.near.extend(second.near);
        c.bounds.extend(second.bounds);
        Self {
            across: adjacency(&tree.indices),
            face: c.face,
            near: c.near,
            bounds: c.bounds,
        }
    }

    /// The nearest surface point to `p`, when a walk from triangle `start` finds it and
    /// proves it (see the module doc): at any distance, with no bound to pass. Otherwise
    /// the [`Miss`] says which triangle near `p` the walk tested (the tree's best hint)
    /// and how near the surface can be: when the proof fails only on the bounds, the
    /// lesser of the tested distance and the bound on the untested triangles.
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
                        let inward = (v - u).cross(self.face[t as usize].normal);
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
    /// their near lists, if the bounds on the others prove it; otherwise the nearest of
    /// them.
    fn prove(
        &self,
        tree: &ObbTree,
        p: Vec3,
        (q, feature): (Vec3, Feature),
        t: u32,
        other: Option<u32>,
    ) -> Result<NearestHit, Miss> {
        let nt = self.face[t as usize].normal;
        let up = p - q;
        let a = up.dot(nt);
        if a <= 0.0 {
            return Err(Miss::at(t));
        }
        // On an edge, `p - q` must lie between the two face normals: then no point below
        // both planes is nearer than `q` (it is the nearest point of that wedge). Both
        // triangles' edge features imply it when the walk crossed from `other`'s edge;
        // it is checked because it may have crossed from `other`'s corner.
        if let Some(s) = other {
            let ns = self.face[s as usize].normal;
            let (b, g) = (up.dot(ns), nt.dot(ns));
            if !(b > 0.0 && a - g * b >= 0.0 && b - g * a >= 0.0) {
                return Err(Miss::at(t));
            }
        }
        let mut best = Best {
            tri: t,
            point: q,
            feature,
            d2: up.length_squared(),
        };
        let at_t = self.height(t, up);
        self.test_listed(tree, p, t, at_t, &mut best);
        let at_other = other.map(|o| {
            let at_o = self.height(o, up);
            best.test(tree, p, o);
            self.test_listed(tree, p, o, at_o, &mut best);
            (o, at_o)
        });
        let distance = best.d2.sqrt();
        let unlisted = self.unlisted(t, p, at_t);
        let unlisted = at_other.map_or(unlisted, |(o, at_o)| {
            unlisted.min(self.unlisted(o, p, at_o))
        });
        if distance > unlisted {
            // Not proved, but nothing is nearer than either bound.
            return Err(Miss {
                near: best.tri,
                clear: distance.min(unlisted).max(0.0),
            });
        }
        Ok(NearestHit {
            tri: best.tri,
            point: best.point,
            distance,
            feature: best.feature,
        })
    }

    /// Tests `t`'s listed triangles that may be nearer `p` than `best`, given `p`'s
    /// (height, lateral distance) from `t`.
    fn test_listed(&self, tree: &ObbTree, p: Vec3, t: u32, (h, l): (f32, f32), best: &mut Best) {
        for s in self.face[t as usize].near.of(&self.near) {
            let off_plane = s.normal.dot(p) - s.offset;
            let (x, z) = ((s.gap - l).max(0.0), (h - s.rise).max(0.0));
            if off_plane * off_plane < best.d2 && x * x + z * z < best.d2 {
                best.test(tree, p, s.tri);
            }
        }
    }

    /// How near `p` a rising triangle not in `t`'s near list may be, given `p`'s (height,
    /// lateral distance) from `t`.
    fn unlisted(&self, t: u32, p: Vec3, (h, l): (f32, f32)) -> f32 {
        let f = &self.face[t as usize];
        let pairs = f.bounds.of(&self.bounds).iter().map(|&[gap, rise]| {
            let (x, z) = ((gap - l).max(0.0), (h - rise).max(0.0));
            x * x + z * z
        });
        let from_c = (p - f.centroid).length();
        let gathered = pairs.fold(f32::INFINITY, f32::min).sqrt();
        gathered.max(f.clear - from_c).min(f.far - from_c)
    }

    /// `p`'s height above `t`'s plane and the distance of its shadow on that plane from
    /// `t`, where `up` is `p` minus its nearest point of `t`.
    fn height(&self, t: u32, up: Vec3) -> (f32, f32) {
        let h = up.dot(self.face[t as usize].normal);
        (h, (up.length_squared() - h * h).max(0.0).sqrt())
    }

    /// How many triangles have some other part of the surface rising above their plane
    /// within `MAX_CLEARANCE` (none on a convex body).
    pub fn concave_count(&self) -> usize {
        (0..self.face.len())
            .filter(|&t| {
                let f = &self.face[t];
                f.clear < MAX_CLEARANCE || f.near.len > 0 || f.bounds.len > 0
            })
            .count()
    }
}

/// The nearest triangle tested so far.
struct Best {
    tri: u32,
    point: Vec3,
    feature: Feature,
    d2: f32,
}

impl Best {
    fn test(&mut self, tree: &ObbTree, p: Vec3, s: u32) {
        if let Some([a, b, c]) = tree.triangle(s) {
            let (q, f) = closest_point_on_triangle(p, a, b, c);
            let d2 = (q - p).length_squared();
            if d2 < self.d2 {
                *self = Self {
                    tri: s,
                    point: q,
                    feature: f,
                    d2,
                };
            }
        }
    }
}

/// The per-triangle part of a [`SurfaceWalk`] for a range of triangles.
#[derive(Default)]
struct Certificates {
    face: Vec<Face>,
    near: Vec<Listed>,
    bounds: Vec<[f32; 2]>,
}

/// A lower bound on the distance between the shadows of triangles `t` and `s` on the
/// plane with unit normal `n`: the largest gap along the six edges' in-plane normals.
fn shadow_gap(n: Vec3, t: &[Vec3; 3], s: &[Vec3; 3]) -> f32 {
    let span = |u: Vec3, tri: &[Vec3; 3]| {
        let d = tri.map(|v| u.dot(v));
        (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
    };
    let mut gap = 0.0f32;
    for tri in [t, s] {
        for k in 0..3 {
            let e = tri[(k + 1) % 3] - tri[k];
            let u = n.cross(e).normalize_or_zero();
            let ((t0, t1), (s0, s1)) = (span(u, t), span(u, s));
            gap = gap.max(s0 - t1).max(t0 - s1);
        }
    }
    gap
}

/// Merges a set of (gap, rise) pairs into at most `MAX_BOUNDS` that bound each of them
/// from below: drops every pair another has no larger gap and no smaller rise than,
/// then replaces the two closest in gap by (the smaller gap, the larger rise).
fn merge_bounds(pairs: &mut Vec<[f32; 2]>) {
    pairs.sort_unstable_by(|x, y| x[0].total_cmp(&y[0]).then(y[1].total_cmp(&x[1])));
    let mut top = f32::NEG_INFINITY;
    pairs.retain(|&[_, rise]| {
        let keep = rise > top;
        top = top.max(rise);
        keep
    });
    // Gaps now increase and so do rises.
    while pairs.len() > MAX_BOUNDS {
        let i = (0..pairs.len() - 1)
            .min_by(|&i, &j| {
                (pairs[i + 1][0] - pairs[i][0]).total_cmp(&(pairs[j + 1][0] - pairs[j][0]))
            })
            .unwrap_or(0);
        pairs[i][1] = pairs[i + 1][1];
        pairs.remove(i + 1);
    }
}

impl Certificates {
    fn of(tree: &ObbTree, range: std::ops::Range<u32>, max_near: usize) -> Self {
        let mut c = Self {
            face: Vec::with_capacity(range.len()),
            ..Self::default()
        };
        // The rising triangles within GATHER_RADIUS: (distance from the centroid, gap,
        // rise, triangle), and their ids sorted.
        let mut rising: Vec<(f32, f32, f32, u32)> = Vec::new();
        let mut gathered: Vec<u32> = Vec::new();
        let mut pairs: Vec<[f32; 2]> = Vec::new();
        for t in range {
            let tri = tree.triangle(t).unwrap_or([Vec3::ZERO; 3]);
            let [a, b, cc] = tri;
            let normal = (b - a).cross(cc - a).normalize_or_zero();
            let centroid = (a + b + cc) / 3.0;
            let level = normal.dot(a) + RISE_TOLERANCE;
            let rises = |tri: &[Vec3; 3]| tri.iter().any(|v| normal.dot(*v) > level);
            let box_rises = |b: &Obb| {
                let reach = (b.axes.transpose() * normal).abs().dot(b.half);
                normal.dot(b.center) + reach > level
            };
            rising.clear();
            tree.for_each_within(centroid, GATHER_RADIUS, box_rises, rises, |s, d| {
                let st = tree.triangle(s).unwrap_or([Vec3::ZERO; 3]);
                let rise = st
                    .map(|v| normal.dot(v - a))
                    .into_iter()
                    .fold(0.0, f32::max);
                rising.push((d, shadow_gap(normal, &tri, &st), rise, s));
            });
            rising.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.3.cmp(&y.3)));
            let (listed, rest) = rising.split_at(rising.len().min(max_near));
            let near_start = c.near.len();
            c.near.extend(listed.iter().map(|&(_, gap, rise, s)| {
                let [a, b, cc] = tree.triangle(s).unwrap_or([Vec3::ZERO; 3]);
                let normal = (b - a).cross(cc - a).normalize_or_zero();
                Listed {
                    tri: s,
                    gap,
                    rise,
                    normal,
                    offset: normal.dot(a),
                }
            }));
            pairs.clear();
            pairs.extend(rest.iter().map(|&(_, gap, rise, _)| [gap, rise]));
            merge_bounds(&mut pairs);
            let bounds_start = c.bounds.len();
            c.bounds.extend_from_slice(&pairs);
            gathered.clear();
            gathered.extend(rising.iter().map(|r| r.3));
            gathered.sort_unstable();
            let beyond = |slot: usize, tri: &[Vec3; 3]| {
                rises(tri) && gathered.binary_search(&tree.tri_ids[slot]).is_err()
            };
            let far = tree
                .nearest_where(centroid, MAX_CLEARANCE, None, &mut 0, box_rises, beyond)
                .map_or(MAX_CLEARANCE, |hit| hit.distance);
            let clear = rest.first().map_or(far, |r| r.0.min(far));
            // A degenerate triangle (zero normal) proves nothing.
            let degenerate = normal == Vec3::ZERO;
            c.face.push(Face {
                normal,
                centroid,
                clear: if degenerate { 0.0 } else { clear },
                far: if degenerate { 0.0 } else { far },
                near: Span::since(near_start, c.near.len()),
                bounds: Span::since(bounds_start, c.bounds.len()),
            });
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
