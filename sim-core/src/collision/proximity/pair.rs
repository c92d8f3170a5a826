//! One pair of primitives near each other ([`Pair`]), the search's settings and view of
//! the cloth, and the geometry both sides of the search share: the direction that
//! separates two primitives, how far their boxes can bring them along it, which feature
//! of a triangle is nearest.

use glam::Vec3;

use super::grid::Aabb;
use crate::mesh::edge_key;

/// No vertex in this slot of a [`Pair`].
pub const NONE: u32 = u32::MAX;

/// One pair of primitives near each other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    /// Cloth vertices (`NONE` for an unused slot).
    pub v: [u32; 4],
    /// Signed weights: the gap is `n . sum(w x) + offset`.
    pub w: [f32; 4],
    /// Which side each vertex is on: +1 the first primitive, -1 the second, 0 unused.
    pub side: [i8; 4],
    /// Unit direction from the second primitive to the first.
    pub n: Vec3,
    /// The body's (or floor's) part of the gap.
    pub offset: f32,
    /// With the body or floor: the most `n . b` over its primitive's corners (cloth
    /// vertices keep `n . x >= body_bound + delta`); `-inf` for a cloth pair.
    pub body_bound: f32,
    /// The least separation along `n` this pair keeps.
    pub delta: f32,
    /// Whether the pair carries contact energy.
    pub energy: bool,
    pub kind: PairKind,
    /// A body corner-face pair's body vertex (`NONE` for the other kinds).
    pub body_vertex: u32,
}

/// What a [`Pair`] pairs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairKind {
    /// A cloth vertex (slot 0) against a cloth triangle.
    VertexFace,
    /// A cloth edge (slots 0, 1) against a cloth edge.
    EdgeEdge,
    /// A cloth vertex against a body triangle.
    BodyVertexFace,
    /// A cloth edge against a body crease.
    BodyEdgeEdge,
    /// A cloth triangle against a body corner.
    BodyCornerFace,
    /// A cloth vertex against the floor.
    Floor,
}

impl Pair {
    /// The gap along `n` between the two closest points found, as they are now.
    #[inline]
    pub fn gap(&self, x: &[Vec3]) -> f32 {
        let mut p = Vec3::ZERO;
        for k in 0..4 {
            if self.v[k] != NONE {
                p += x[self.v[k] as usize] * self.w[k];
            }
        }
        self.n.dot(p) + self.offset
    }

    /// The half-space vertex `k` of the pair must stay in while the others stay where they
    /// are now: `(m, h)` with `m . x >= h`.
    #[inline]
    pub fn bound_for(&self, k: usize, x: &[Vec3]) -> (Vec3, f32) {
        let s = self.side[k] as f32;
        let m = self.n * s;
        if self.body_bound > f32::NEG_INFINITY {
            return (m, self.body_bound + self.delta);
        }
        let mut h = f32::NEG_INFINITY;
        for j in 0..4 {
            if self.side[j] as f32 == -s && self.v[j] != NONE {
                h = h.max(m.dot(x[self.v[j] as usize]));
            }
        }
        (m, h + self.delta)
    }

    /// Whether every vertex keeps its bound (with `slack` to spare for rounding).
    pub fn holds(&self, x: &[Vec3], slack: f32) -> bool {
        (0..4).all(|k| {
            self.side[k] == 0 || {
                let (m, h) = self.bound_for(k, x);
                m.dot(x[self.v[k] as usize]) >= h - slack
            }
        })
    }
}

/// The search's settings.
#[derive(Clone, Copy, Debug)]
pub struct ProximityParams {
    /// Contact distance `r`: the energy pushes primitives apart to this gap, m.
    pub radius: f32,
    /// The least separation every pair keeps, m.
    pub delta: f32,
    /// Cloth primitives closer than this in the pattern carry no contact energy, m.
    pub rest_exclusion: f32,
    pub floor: Option<f32>,
    /// Threads the cloth-cloth search may use (1 or more).
    pub threads: usize,
}

/// The cloth as the search sees it.
#[derive(Clone, Copy, Debug)]
pub struct ClothView<'a> {
    pub x: &'a [Vec3],
    /// Each vertex's motion box for the frame.
    pub boxes: &'a [Aabb],
    pub tris: &'a [[u32; 3]],
    pub edges: &'a [[u32; 2]],
    /// Each vertex's place in the pattern (for `rest_exclusion`).
    pub pattern: &'a [Vec3],
    /// Each vertex's neighbours over a seam's weld that the pattern places apart
    /// (`LiveMesh::bridged_neighbours`, sorted; an empty slice: none).
    pub bridged: &'a [Vec<u32>],
    /// Vertices the solver moves (others are pinned or unused).
    pub free: &'a [bool],
}

impl ClothView<'_> {
    /// Whether primitives `a` and `b` (their vertices) are neighbours in the cloth at
    /// rest, nearer than `exclusion`: in the pattern, or over a weld. Such pairs carry no
    /// contact energy.
    pub(super) fn rest_near(&self, a: &[u32], b: &[u32], exclusion: f32) -> bool {
        let pattern = self.pattern;
        a.iter().any(|&i| {
            let pi = pattern[i as usize];
            b.iter()
                .any(|&j| (pi - pattern[j as usize]).length() < exclusion)
        }) || a.iter().any(|&i| {
            self.bridged
                .get(i as usize)
                .is_some_and(|near| b.iter().any(|j| near.binary_search(j).is_ok()))
        })
    }
}

impl PairCounts {
    /// The counts of `pairs`.
    pub fn of(pairs: &[Pair]) -> Self {
        let mut c = Self::default();
        for q in pairs {
            *c.of_kind(q.kind) += 1;
            c.with_energy += q.energy as usize;
        }
        c
    }

    /// The count of pairs of `kind`.
    pub(super) fn of_kind(&mut self, kind: PairKind) -> &mut usize {
        match kind {
            PairKind::VertexFace => &mut self.vertex_face,
            PairKind::EdgeEdge => &mut self.edge_edge,
            PairKind::BodyVertexFace => &mut self.body_vertex_face,
            PairKind::BodyEdgeEdge => &mut self.body_edge_edge,
            PairKind::BodyCornerFace => &mut self.body_corner_face,
            PairKind::Floor => &mut self.floor,
        }
    }
}

#[cfg(test)]
impl ProximityParams {
    /// The tests' settings: 4 mm contact, 0.1 mm separation, a 3 cm rest exclusion.
    pub(super) fn for_tests(threads: usize, floor: Option<f32>) -> Self {
        Self {
            radius: 0.004,
            delta: 1e-4,
            rest_exclusion: 0.03,
            floor,
            threads,
        }
    }
}

#[cfg(test)]
impl<'a> ClothView<'a> {
    /// A cloth with no welds, every vertex free (`free`: as many `true`s as vertices).
    pub(super) fn unwelded(
        (x, boxes): (&'a [Vec3], &'a [Aabb]),
        (tris, edges): (&'a [[u32; 3]], &'a [[u32; 2]]),
        pattern: &'a [Vec3],
        free: &'a [bool],
    ) -> Self {
        Self {
            x,
            boxes,
            tris,
            edges,
            pattern,
            bridged: &[],
            free,
        }
    }
}

/// How many pairs of each kind the last search kept.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct PairCounts {
    pub vertex_face: usize,
    pub edge_edge: usize,
    pub body_vertex_face: usize,
    pub body_edge_edge: usize,
    pub body_corner_face: usize,
    pub floor: usize,
    /// Of all those, the pairs carrying contact energy.
    pub with_energy: usize,
}

/// The closest feature of a triangle `t` from barycentric weights, as a key: a face, an
/// edge (its key) or a corner.
pub(super) fn feature_key(t: [u32; 3], tri_id: u32, w: [f32; 3]) -> u64 {
    let nz = [w[0] > 0.0, w[1] > 0.0, w[2] > 0.0];
    match nz.iter().filter(|&&b| b).count() {
        3 => (1 << 62) | tri_id as u64,
        2 => {
            let k = (0..3).find(|&k| !nz[k]).unwrap_or(0);
            (2 << 62) | edge_key(t[(k + 1) % 3], t[(k + 2) % 3])
        }
        _ => {
            let k = (0..3).find(|&k| nz[k]).unwrap_or(0);
            (3 << 62) | t[k] as u64
        }
    }
}

/// Separations under this are within what rounding the positions (f32, coordinates of a
/// metre or two) and the dot products can make of them, m: which side a primitive is on
/// is then decided exactly.
const SIDE_DOUBT: f32 = 1e-5;

/// The direction that separates the corners `ps` of one primitive from the corners `qs`
/// of another, and by how much: the direction between their closest points `p` and `q`
/// when it is well defined, otherwise the best of it and `alt` either way (a face normal,
/// or the cross product of two edges). Near touching, the closest points' difference is
/// all rounding: its direction could show a separation the primitives do not have.
///
/// And when every separation found is under [`SIDE_DOUBT`], `alt` is taken toward the
/// side `side` gives (the exact sign of `alt . (ps - qs)`; 0: not known, or in the
/// plane): in f32 either way can come out ahead there, and the wrong one lets the guard
/// keep a vertex lying on a face on the far side of it. The sewn 2 x 8k dress had a
/// vertex at a seam's T-junction lying in a welded triangle's plane, inside it; the
/// search took the face's normal toward the side away from the vertex's own triangles,
/// and the next substep the vertex went through (docs/collision.md, "A side decided
/// exactly").
pub(super) fn separating(
    ps: &[Vec3],
    qs: &[Vec3],
    (p, q): (Vec3, Vec3),
    alt: Vec3,
    side: impl FnOnce() -> i8,
) -> (Vec3, f32) {
    let sep = |n: Vec3| {
        let lo = ps.iter().map(|x| n.dot(*x)).fold(f32::INFINITY, f32::min);
        let hi = qs
            .iter()
            .map(|x| n.dot(*x))
            .fold(f32::NEG_INFINITY, f32::max);
        lo - hi
    };
    let d = p - q;
    let len = d.length();
    let mut best = (Vec3::Y, f32::NEG_INFINITY);
    if len > 0.0 {
        let n = d / len;
        let s = sep(n);
        if len >= 1e-5 && s >= 0.9 * len {
            return (n, s);
        }
        best = (n, s);
    }
    if let Some(a) = alt.try_normalize() {
        for n in [a, -a] {
            let s = sep(n);
            if s > best.1 {
                best = (n, s);
            }
        }
        if best.1 < SIDE_DOUBT {
            match side() {
                0 => {}
                s => {
                    let n = a * f32::from(s);
                    best = (n, sep(n));
                }
            }
        }
    }
    best
}

/// The sign of `((b - a) x (c - a)) . (d - a)`, exactly (the crossing count's
/// orientation predicate: det[b - a, c - a, d - a]).
pub(super) fn triple_sign(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    crate::collision::crossings::o3(b, c, d, a)
}

/// Whether the boxes of vertices `a` and those of `b` stay more than `gap` apart along
/// an axis: primitives kept in them can then never come within `gap` of each other.
#[inline]
pub(super) fn boxes_apart(boxes: &[Aabb], a: &[u32], b: &[u32], gap: f32) -> bool {
    let of = |vs: &[u32]| {
        vs.iter()
            .fold(Aabb::EMPTY, |acc, &v| acc.union(boxes[v as usize]))
    };
    !of(a).grown(gap).overlaps(&of(b))
}

pub(super) fn min_along(boxes: &[Aabb], vs: &[u32], n: Vec3) -> f32 {
    vs.iter()
        .map(|&v| boxes[v as usize].min_along(n))
        .fold(f32::INFINITY, f32::min)
}

pub(super) fn max_along(boxes: &[Aabb], vs: &[u32], n: Vec3) -> f32 {
    vs.iter()
        .map(|&v| boxes[v as usize].max_along(n))
        .fold(f32::NEG_INFINITY, f32::max)
}

/// The separation a pair keeps: `delta`, or what it has now when that is less (then it
/// may not get closer; the contact energy pushes it apart).
pub(super) fn keep(delta: f32, sep0: f32) -> f32 {
    delta.min(sep0)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::ClothView;
    use crate::collision::proximity::reach::tests::noise;

    /// Vertices 0 and 3 are 3 m apart in the pattern but neighbours over a weld; 1 is
    /// near 0 in the pattern only.
    #[test]
    fn neighbours_over_a_weld_are_near_at_rest_as_pattern_neighbours_are() {
        let pattern = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(3.0, 0.0, 0.0),
        ];
        let bridged = [vec![3], vec![], vec![], vec![0]];
        let view = ClothView {
            x: &[],
            boxes: &[],
            tris: &[],
            edges: &[],
            pattern: &pattern,
            bridged: &bridged,
            free: &[],
        };
        assert!(view.rest_near(&[0], &[2, 3], 0.5), "over the weld");
        assert!(view.rest_near(&[2, 3], &[0], 0.5), "either way round");
        assert!(!view.rest_near(&[1], &[2, 3], 0.5), "1 is 1 m from 2");
        assert!(view.rest_near(&[1], &[2], 1.5), "in the pattern");
        let none = ClothView {
            bridged: &[],
            ..view
        };
        assert!(!none.rest_near(&[0], &[3], 0.5), "without the weld");
    }

    #[test]
    fn the_exact_triple_product_has_the_sign_of_the_plain_one() {
        let mut seed = 3;
        for _ in 0..1000 {
            let mut p = || Vec3::new(noise(&mut seed), noise(&mut seed), noise(&mut seed));
            let (a, b, c, d) = (p(), p(), p(), p());
            let plain = (b - a)
                .as_dvec3()
                .cross((c - a).as_dvec3())
                .dot((d - a).as_dvec3());
            if plain.abs() > 1e-6 {
                assert_eq!(super::triple_sign(a, b, c, d), plain.signum() as i8);
            }
        }
        let o = Vec3::ZERO;
        assert_eq!(super::triple_sign(o, Vec3::X, Vec3::Y, Vec3::Y), 0);
    }

    /// A vertex a hair from a face's plane, over the face, on either side of it, the
    /// face tilted and a metre and a half up (as on a body): the direction found puts
    /// the vertex on the side it is on, exactly. In f32 alone the face's normal either
    /// way came out ahead by rounding, and the wrong way round in some of these.
    #[test]
    fn a_vertex_a_hair_from_a_face_is_kept_on_its_own_side() {
        let mut seed = 11;
        let (mut wrong_in_f32, mut decided) = (0, 0);
        for _ in 0..4000 {
            let mut n = || noise(&mut seed);
            let base = Vec3::new(0.15, 1.5, -0.02) + 0.01 * Vec3::new(n(), n(), n());
            let u = Vec3::new(n(), n(), n()).normalize() * 0.008;
            let v = Vec3::new(n(), n(), n()).normalize() * 0.008;
            let (a, b, c) = (base, base + u, base + v);
            // Inside the face, off its plane by up to 0.3 um.
            let (s, t) = (0.2 + 0.3 * n().abs(), 0.2 + 0.3 * n().abs());
            let normal = u.cross(v).normalize();
            let x = a + u * s + v * t + normal * (3e-7 * n());
            let face = [a, b, c];
            let alt = (b - a).cross(c - a);
            let exact = super::triple_sign(a, b, c, x);
            if exact == 0 {
                continue;
            }
            let on_face = a + u * s + v * t;
            let (dir, _) = super::separating(&[x], &face, (x, on_face), alt, || exact);
            let side = |d: Vec3| (d.dot(alt) > 0.0) as i8 * 2 - 1;
            assert_eq!(side(dir), exact, "the side decided exactly");
            let (plain, _) = super::separating(&[x], &face, (x, on_face), alt, || 0);
            wrong_in_f32 += usize::from(side(plain) != exact);
            decided += 1;
        }
        assert!(decided > 3000, "{decided}");
        assert!(
            wrong_in_f32 > 0,
            "f32 alone never erred here: the test shows nothing"
        );
    }
}
