//! Exact crossing counts: how many pairs of triangles intersect, the cloth with itself and
//! the cloth with the body. This is the judge of "the cloth never passes through", so it
//! must not err either way: every decision is the sign of an orientation determinant
//! evaluated exactly (Shewchuk's adaptive predicates, the `robust` crate) on the f32
//! positions, which convert to f64 without rounding.
//!
//! Two closed triangles intersect iff an edge of one meets the other (the intersection is
//! a compact convex set; its extreme points lie on the boundary of one of the two), so the
//! pair test is six exact segment-triangle tests. Touching counts as intersecting.
//! Pairs of cloth triangles that share a vertex are neighbours in the mesh and are not
//! counted. A triangle whose corners are exactly collinear has no inside and meets
//! nothing here.

use std::collections::HashMap;

use glam::Vec3;
use robust::{Coord, Coord3D, orient2d, orient3d};

use super::body::Body;
use super::obb::Obb;

fn c3(p: Vec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x as f64,
        y: p.y as f64,
        z: p.z as f64,
    }
}

/// The sign of the orientation of `d` against the plane through `a`, `b`, `c`, exactly:
/// of det[a - d, b - d, c - d].
pub(crate) fn o3(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> i8 {
    sign(orient3d(c3(a), c3(b), c3(c), c3(d)))
}

fn sign(v: f64) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// The 2D projection dropping axis `drop` (0, 1 or 2).
fn proj(p: Vec3, drop: usize) -> Coord<f64> {
    let (x, y) = match drop {
        0 => (p.y, p.z),
        1 => (p.z, p.x),
        _ => (p.x, p.y),
    };
    Coord {
        x: x as f64,
        y: y as f64,
    }
}

fn o2(a: Coord<f64>, b: Coord<f64>, c: Coord<f64>) -> i8 {
    sign(orient2d(a, b, c))
}

/// An axis along which the triangle projects to a non-degenerate triangle, or `None` for
/// a triangle whose corners are collinear.
fn projection_axis(t: &[Vec3; 3]) -> Option<usize> {
    (0..3).find(|&d| o2(proj(t[0], d), proj(t[1], d), proj(t[2], d)) != 0)
}

/// Closed 2D segments `pq` and `rs` share a point.
fn segments_meet_2d(p: Coord<f64>, q: Coord<f64>, r: Coord<f64>, s: Coord<f64>) -> bool {
    let (d1, d2) = (o2(p, q, r), o2(p, q, s));
    let (d3, d4) = (o2(r, s, p), o2(r, s, q));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    let within = |a: Coord<f64>, b: Coord<f64>, c: Coord<f64>| {
        c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
    };
    (d1 == 0 && within(p, q, r))
        || (d2 == 0 && within(p, q, s))
        || (d3 == 0 && within(r, s, p))
        || (d4 == 0 && within(r, s, q))
}

/// The closed 2D triangle `t` (non-degenerate) contains `p`.
fn inside_2d(t: [Coord<f64>; 3], p: Coord<f64>) -> bool {
    let s = [o2(t[0], t[1], p), o2(t[1], t[2], p), o2(t[2], t[0], p)];
    !(s.contains(&1) && s.contains(&-1))
}

/// The closed segment `pq` meets the closed, non-degenerate triangle `t` whose plane it
/// lies in, projected along `drop`.
fn coplanar_segment_meets(p: Vec3, q: Vec3, t: &[Vec3; 3], drop: usize) -> bool {
    let (p2, q2) = (proj(p, drop), proj(q, drop));
    let t2 = [proj(t[0], drop), proj(t[1], drop), proj(t[2], drop)];
    inside_2d(t2, p2)
        || inside_2d(t2, q2)
        || (0..3).any(|i| segments_meet_2d(p2, q2, t2[i], t2[(i + 1) % 3]))
}

/// The closed segment `pq` meets the closed triangle `t` (exact; `t` non-degenerate with
/// projection axis `drop`).
fn segment_meets(p: Vec3, q: Vec3, t: &[Vec3; 3], drop: usize) -> bool {
    let (sp, sq) = (o3(t[0], t[1], t[2], p), o3(t[0], t[1], t[2], q));
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        return coplanar_segment_meets(p, q, t, drop);
    }
    // pq crosses (or touches) the plane at one point; it is in the triangle iff the line
    // pq passes on no strictly different sides of the three edges.
    let s = [
        o3(p, q, t[0], t[1]),
        o3(p, q, t[1], t[2]),
        o3(p, q, t[2], t[0]),
    ];
    !(s.contains(&1) && s.contains(&-1))
}

/// The segment `pq` passes through triangle `t` from one side of its plane to the other,
/// inside its edges (exact): a segment lying in the plane, or grazing an edge or a
/// corner, does not. What stands between two points that must meet (`design::stalls`).
pub fn segment_pierces(p: Vec3, q: Vec3, t: &[Vec3; 3]) -> bool {
    let (sp, sq) = (o3(t[0], t[1], t[2], p), o3(t[0], t[1], t[2], q));
    if sp * sq >= 0 {
        return false;
    }
    let s = [
        o3(p, q, t[0], t[1]),
        o3(p, q, t[1], t[2]),
        o3(p, q, t[2], t[0]),
    ];
    s[0] != 0 && s[0] == s[1] && s[1] == s[2]
}

/// The segment `pq` pierces the body's surface ([`segment_pierces`]; the body's OBB
/// tree finds the candidates).
pub fn segment_pierces_body(p: Vec3, q: Vec3, body: &Body) -> bool {
    let mut near = Vec::new();
    body.tree()
        .overlap_box(&Obb::aabb(p.min(q), p.max(q)), &mut near);
    near.iter().any(|&b| {
        let t = corners(&body.vertices, body.triangles[b as usize]);
        segment_pierces(p, q, &t)
    })
}

/// Two closed triangles intersect (exact). Degenerate (collinear) triangles meet nothing.
pub fn triangles_intersect(a: &[Vec3; 3], b: &[Vec3; 3]) -> bool {
    let (Some(da), Some(db)) = (projection_axis(a), projection_axis(b)) else {
        return false;
    };
    (0..3).any(|i| segment_meets(a[i], a[(i + 1) % 3], b, db))
        || (0..3).any(|i| segment_meets(b[i], b[(i + 1) % 3], a, da))
}

fn corners(x: &[Vec3], t: [u32; 3]) -> [Vec3; 3] {
    [x[t[0] as usize], x[t[1] as usize], x[t[2] as usize]]
}

fn bounds(t: &[Vec3; 3]) -> (Vec3, Vec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

fn share_vertex(a: [u32; 3], b: [u32; 3]) -> bool {
    a.iter().any(|v| b.contains(v))
}

/// What crosses what: the cloth's intersecting triangle pairs (sharing no vertex), and its
/// triangles that intersect the body's surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Crossings {
    pub self_pairs: usize,
    pub body_triangles: usize,
    /// The (cloth triangle, body triangle) pairs behind `body_triangles`.
    pub body_pairs: usize,
}

/// The crossings of a cloth (positions `x`, triangles `tris`) with itself and the body.
pub fn count(x: &[Vec3], tris: &[[u32; 3]], body: Option<&Body>) -> Crossings {
    let (body_triangles, body_pairs) = body.map_or((0, 0), |b| count_against_body(x, tris, b));
    Crossings {
        self_pairs: count_self(x, tris),
        body_triangles,
        body_pairs,
    }
}

/// One vertex per position: a mesh whose vertices repeat at the same position (an OBJ
/// splits them where UVs differ; a fresh cut leaves its two sides together) as positions
/// and triangles over the distinct positions, so that triangles meeting there count as
/// neighbours, not as crossing.
pub fn weld(positions: &[Vec3], tris: &[[u32; 3]]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut index: std::collections::HashMap<[u32; 3], u32> = std::collections::HashMap::new();
    let mut x = Vec::new();
    let remap: Vec<u32> = positions
        .iter()
        .map(|p| {
            *index
                .entry(p.to_array().map(f32::to_bits))
                .or_insert_with(|| {
                    x.push(*p);
                    (x.len() - 1) as u32
                })
        })
        .collect();
    let tris = tris
        .iter()
        .filter(|t| t.iter().all(|&v| (v as usize) < remap.len()))
        .map(|t| t.map(|v| remap[v as usize]))
        .collect();
    (x, tris)
}

/// Pairs of triangles of one mesh that intersect, among those sharing no vertex (exact,
/// through a uniform grid of the triangles' bounds). Triangles with a corner index out of
/// `x` are skipped.
pub fn count_self(x: &[Vec3], tris: &[[u32; 3]]) -> usize {
    let tris: Vec<[u32; 3]> = tris
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&v| (v as usize) < x.len()))
        .collect();
    let boxes: Vec<(Vec3, Vec3)> = tris.iter().map(|&t| bounds(&corners(x, t))).collect();
    if boxes
        .iter()
        .any(|(lo, hi)| !(lo.is_finite() && hi.is_finite()))
    {
        return count_self_brute(x, &tris);
    }
    // Cells as large as the typical triangle: most triangles fall in 1-8 cells.
    let mut extents: Vec<f32> = boxes
        .iter()
        .map(|(lo, hi)| (*hi - *lo).max_element())
        .collect();
    extents.sort_by(f32::total_cmp);
    let cell = extents
        .get(extents.len() / 2)
        .copied()
        .unwrap_or(0.0)
        .max(1.0e-6)
        * 2.0;
    let key = |p: Vec3| {
        let c = (p / cell).floor();
        (c.x as i32, c.y as i32, c.z as i32)
    };
    let mut grid: HashMap<(i32, i32, i32), Vec<u32>> = HashMap::new();
    for (i, (lo, hi)) in boxes.iter().enumerate() {
        let (a, b) = (key(*lo), key(*hi));
        // A triangle far larger than the cells (a stray vertex) is tested against all.
        // In i64: far-flung corners saturate the i32 cell keys, whose difference would
        // overflow.
        let span = |lo: i32, hi: i32| (hi as i64 - lo as i64 + 1).max(0);
        let n = span(a.0, b.0)
            .saturating_mul(span(a.1, b.1))
            .saturating_mul(span(a.2, b.2));
        if n > 4096 {
            return count_self_brute(x, &tris);
        }
        for cx in a.0..=b.0 {
            for cy in a.1..=b.1 {
                for cz in a.2..=b.2 {
                    grid.entry((cx, cy, cz)).or_default().push(i as u32);
                }
            }
        }
    }
    let mut count = 0;
    for (cellkey, list) in &grid {
        for (k, &i) in list.iter().enumerate() {
            for &j in &list[k + 1..] {
                let ((alo, ahi), (blo, bhi)) = (boxes[i as usize], boxes[j as usize]);
                if alo.cmpgt(bhi).any() || blo.cmpgt(ahi).any() {
                    continue;
                }
                // Each pair once: in the cell holding the low corner of the boxes' overlap.
                if key(alo.max(blo)) != *cellkey {
                    continue;
                }
                let (ti, tj) = (tris[i as usize], tris[j as usize]);
                if !share_vertex(ti, tj) && triangles_intersect(&corners(x, ti), &corners(x, tj)) {
                    count += 1;
                }
            }
        }
    }
    count
}

/// How many (fan triangle, other triangle) pairs intersect, exactly, where `fan`'s
/// triangles are tested against `others` (those sharing a vertex with them skipped) and
/// the body's surface, with each vertex where `at` puts it (`None`: skip the triangle).
/// A weld asks this of its vertex's triangles before and after it would move them, and
/// a piece added or placed asks it of its triangles where they would start: the contact
/// guard keeps the solver's moves uncrossed, and edits are not solver moves.
pub fn fan_crossings(
    at: impl Fn(u32) -> Option<Vec3>,
    fan: &[[u32; 3]],
    others: &[[u32; 3]],
    body: Option<&Body>,
) -> usize {
    // A weld's dozen triangles against the cloth: one pass over it beats building a grid
    // (each frame, for every stitch close enough to weld).
    let grid = fan.len().saturating_mul(others.len()) > GRID_ABOVE;
    fan_crossings_by(at, fan, others, body, grid)
}

/// Pairs to test past which [`fan_crossings`] puts the other triangles in a grid.
const GRID_ABOVE: usize = 200_000;

fn fan_crossings_by(
    at: impl Fn(u32) -> Option<Vec3>,
    fan: &[[u32; 3]],
    others: &[[u32; 3]],
    body: Option<&Body>,
    use_grid: bool,
) -> usize {
    let tri = |t: [u32; 3]| Some([at(t[0])?, at(t[1])?, at(t[2])?]);
    // Each other triangle: its vertices, corners and bounds, in a uniform grid of cells
    // twice the typical triangle (a piece of 14,000 triangles against a dress of 2,700
    // took 170 ms pair by pair).
    type Placed = ([u32; 3], [Vec3; 3], (Vec3, Vec3));
    let other: Vec<Placed> = others
        .iter()
        .filter_map(|&o| tri(o).map(|c| (o, c, bounds(&c))))
        .filter(|(_, _, (lo, hi))| lo.is_finite() && hi.is_finite())
        .collect();
    let cell = if use_grid {
        let mut extents: Vec<f32> = other
            .iter()
            .map(|(_, _, (lo, hi))| (*hi - *lo).max_element())
            .collect();
        extents.sort_by(f32::total_cmp);
        2.0 * extents
            .get(extents.len() / 2)
            .copied()
            .unwrap_or(1.0)
            .max(1e-4)
    } else {
        1.0
    };
    let key = |p: Vec3| {
        let c = (p / cell).floor();
        (c.x as i32, c.y as i32, c.z as i32)
    };
    let cells = |lo: Vec3, hi: Vec3| {
        let (a, b) = (key(lo), key(hi));
        (a.0..=b.0)
            .flat_map(move |x| (a.1..=b.1).flat_map(move |y| (a.2..=b.2).map(move |z| (x, y, z))))
    };
    let mut grid: HashMap<(i32, i32, i32), Vec<u32>> = HashMap::new();
    let mut huge = Vec::new();
    for (i, (_, _, (lo, hi))) in other.iter().enumerate().filter(|_| use_grid) {
        // A triangle far larger than the cells (a stray vertex) is tested against all.
        if ((*hi - *lo) / cell).max_element() > 16.0 {
            huge.push(i as u32);
            continue;
        }
        for c in cells(*lo, *hi) {
            grid.entry(c).or_default().push(i as u32);
        }
    }
    let mut seen = vec![usize::MAX; other.len()];
    let mut near = Vec::new();
    let mut count = 0;
    for (n, &f) in fan.iter().enumerate() {
        let Some(c) = tri(f) else {
            continue;
        };
        let (lo, hi) = bounds(&c);
        let candidates: Box<dyn Iterator<Item = u32>> =
            if !(use_grid && lo.is_finite() && hi.is_finite())
                || ((hi - lo) / cell).max_element() > 16.0
            {
                Box::new(0..other.len() as u32)
            } else {
                Box::new(
                    cells(lo, hi)
                        .filter_map(|k| grid.get(&k))
                        .flatten()
                        .copied()
                        .chain(huge.iter().copied()),
                )
            };
        for i in candidates {
            if std::mem::replace(&mut seen[i as usize], n) == n {
                continue;
            }
            let (o, d, (olo, ohi)) = &other[i as usize];
            if lo.cmpgt(*ohi).any() || olo.cmpgt(hi).any() || share_vertex(f, *o) {
                continue;
            }
            count += usize::from(triangles_intersect(&c, d));
        }
        if let Some(b) = body {
            near.clear();
            b.tree().overlap_box(&Obb::aabb(lo, hi), &mut near);
            count += near
                .iter()
                .filter(|&&k| {
                    triangles_intersect(&c, &corners(&b.vertices, b.triangles[k as usize]))
                })
                .count();
        }
    }
    count
}

/// `count_self` by testing every pair: the reference, and the fallback for meshes the
/// grid does not suit.
pub fn count_self_brute(x: &[Vec3], tris: &[[u32; 3]]) -> usize {
    let mut count = 0;
    for (i, &a) in tris.iter().enumerate() {
        for &b in &tris[i + 1..] {
            if !share_vertex(a, b) && triangles_intersect(&corners(x, a), &corners(x, b)) {
                count += 1;
            }
        }
    }
    count
}

/// Triangles of a mesh that intersect the body's surface, and the pairs (exact; the
/// body's OBB tree finds the candidates). A cloth triangle wholly inside a closed body
/// is not counted here: that is penetration, measured apart.
pub fn count_against_body(x: &[Vec3], tris: &[[u32; 3]], body: &Body) -> (usize, usize) {
    let (mut crossing_tris, mut pairs) = (0, 0);
    let mut near = Vec::new();
    for &t in tris {
        if t.iter().any(|&v| v as usize >= x.len()) {
            continue;
        }
        let c = corners(x, t);
        let (lo, hi) = bounds(&c);
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        near.clear();
        body.tree().overlap_box(&Obb::aabb(lo, hi), &mut near);
        let n = near
            .iter()
            .filter(|&&b| {
                triangles_intersect(&c, &corners(&body.vertices, body.triangles[b as usize]))
            })
            .count();
        pairs += n;
        crossing_tris += usize::from(n > 0);
    }
    (crossing_tris, pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [Vec3; 3] {
        [Vec3::from(a), Vec3::from(b), Vec3::from(c)]
    }

    /// A segment pierces a triangle only by passing through its inside from one side to
    /// the other: ending on it, grazing an edge or a corner, or lying in its plane does not.
    #[test]
    fn a_segment_pierces_a_triangle_only_through_its_inside() {
        let tri = t([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let through = (v(0.2, 1.0, 0.2), v(0.2, -1.0, 0.2));
        assert!(segment_pierces(through.0, through.1, &tri));
        assert!(
            segment_pierces(through.1, through.0, &tri),
            "either way round"
        );
        // Beside it, short of it, ending on it.
        assert!(!segment_pierces(v(0.8, 1.0, 0.8), v(0.8, -1.0, 0.8), &tri));
        assert!(!segment_pierces(v(0.2, 1.0, 0.2), v(0.2, 0.1, 0.2), &tri));
        assert!(!segment_pierces(v(0.2, 1.0, 0.2), v(0.2, 0.0, 0.2), &tri));
        // Through an edge and through a corner: touching, not piercing.
        assert!(!segment_pierces(v(0.5, 1.0, 0.0), v(0.5, -1.0, 0.0), &tri));
        assert!(!segment_pierces(v(0.0, 1.0, 0.0), v(0.0, -1.0, 0.0), &tri));
        // In its plane, across it.
        assert!(!segment_pierces(v(-1.0, 0.0, 0.2), v(2.0, 0.0, 0.2), &tri));
    }

    /// A damaged design's far-flung vertex (its cell keys saturate) is counted, not a
    /// panic (a mutated design file once overflowed the cell span).
    #[test]
    fn far_flung_vertices_do_not_overflow_the_grid() {
        let x = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(-3.0e38, 0.0, 0.0),
            Vec3::new(3.0e38, 1.0, 0.0),
            Vec3::new(0.0, -3.0e38, 1.0),
        ];
        assert_eq!(count_self(&x, &[[0, 1, 2], [3, 4, 5]]), 1);
    }

    #[test]
    fn crossing_touching_and_apart() {
        let a = t([0., 0., 0.], [1., 0., 0.], [0., 1., 0.]);
        // Pierces a's inside.
        assert!(triangles_intersect(
            &a,
            &t([0.2, 0.2, -1.], [0.2, 0.2, 1.], [0.3, 0.5, 1.])
        ));
        // Above it.
        assert!(!triangles_intersect(
            &a,
            &t([0.2, 0.2, 0.1], [0.9, 0.2, 1.], [0.3, 0.5, 1.])
        ));
        // A corner exactly on a's inside: touching counts.
        assert!(triangles_intersect(
            &a,
            &t([0.25, 0.25, 0.], [0.9, 0.2, 1.], [0.3, 0.5, 1.])
        ));
        // Coplanar and overlapping, coplanar and apart, coplanar and contained.
        assert!(triangles_intersect(
            &a,
            &t([0.5, 0.5, 0.], [-0.5, 0.2, 0.], [0.2, -0.5, 0.])
        ));
        assert!(!triangles_intersect(
            &a,
            &t([2., 2., 0.], [3., 2., 0.], [2., 3., 0.])
        ));
        assert!(triangles_intersect(
            &a,
            &t([0.1, 0.1, 0.], [0.2, 0.1, 0.], [0.1, 0.2, 0.])
        ));
        // Just beside the hypotenuse, by one float step: apart.
        let e = 0.5 + f32::EPSILON;
        assert!(!triangles_intersect(
            &a,
            &t([e, e, -1.], [e, e, 1.], [2., 2., 0.])
        ));
        // Degenerate: meets nothing.
        assert!(!triangles_intersect(
            &a,
            &t([0., 0., -1.], [0., 0., 0.5], [0., 0., 1.])
        ));
    }

    #[test]
    fn a_flat_grid_does_not_cross_itself_and_a_fold_through_it_does() {
        let n = 10;
        let mut x = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                x.push(Vec3::new(i as f32 * 0.1, 0.0, j as f32 * 0.1));
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = (j * (n + 1) + i) as u32;
                let w = v + n as u32 + 1;
                tris.push([v, v + 1, w]);
                tris.push([v + 1, w + 1, w]);
            }
        }
        assert_eq!(count_self(&x, &tris), 0);
        // A triangle standing through the sheet crosses exactly the triangles it pierces.
        let base = x.len() as u32;
        x.extend([
            Vec3::new(0.33, -0.5, 0.33),
            Vec3::new(0.37, 0.5, 0.33),
            Vec3::new(0.35, 0.5, 0.37),
        ]);
        tris.push([base, base + 1, base + 2]);
        let fast = count_self(&x, &tris);
        assert!(fast >= 1);
        assert_eq!(fast, count_self_brute(&x, &tris));
    }

    /// An independent exact reference on integer corners: the separating axis theorem.
    /// Two closed triangles are apart iff some axis among the normals, the in-plane edge
    /// normals and the edge-edge cross products strictly separates their projections.
    fn sat_intersect(a: &[[i64; 3]; 3], b: &[[i64; 3]; 3]) -> bool {
        let sub = |p: [i64; 3], q: [i64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let cross = |u: [i64; 3], v: [i64; 3]| {
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        let dot = |u: [i64; 3], v: [i64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        let edges = |t: &[[i64; 3]; 3]| [sub(t[1], t[0]), sub(t[2], t[1]), sub(t[0], t[2])];
        let (ea, eb) = (edges(a), edges(b));
        let (na, nb) = (cross(ea[0], ea[1]), cross(eb[0], eb[1]));
        let mut axes = vec![na, nb];
        for i in 0..3 {
            axes.push(cross(na, ea[i]));
            axes.push(cross(nb, eb[i]));
            for j in 0..3 {
                axes.push(cross(ea[i], eb[j]));
            }
        }
        let range = |t: &[[i64; 3]; 3], ax: [i64; 3]| {
            let d = t.map(|p| dot(p, ax));
            (*d.iter().min().unwrap(), *d.iter().max().unwrap())
        };
        !axes.into_iter().filter(|ax| *ax != [0, 0, 0]).any(|ax| {
            let ((alo, ahi), (blo, bhi)) = (range(a, ax), range(b, ax));
            ahi < blo || bhi < alo
        })
    }

    fn small_triangle() -> impl proptest::strategy::Strategy<Value = [[i64; 3]; 3]> {
        use proptest::prelude::*;
        proptest::array::uniform3(proptest::array::uniform3(0i64..5)).prop_filter(
            "not degenerate",
            |t| {
                let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
                let v = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
                u[1] * v[2] != u[2] * v[1]
                    || u[2] * v[0] != u[0] * v[2]
                    || u[0] * v[1] != u[1] * v[0]
            },
        )
    }

    fn to_f32(t: &[[i64; 3]; 3]) -> [Vec3; 3] {
        t.map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

        /// On a small integer lattice touching, shared edges and coplanar overlaps are
        /// common: the exact test agrees with the integer SAT on every pair.
        #[test]
        fn the_exact_test_agrees_with_integer_sat(a in small_triangle(), b in small_triangle()) {
            proptest::prop_assert_eq!(
                triangles_intersect(&to_f32(&a), &to_f32(&b)),
                sat_intersect(&a, &b)
            );
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// Random soups: the grid's count equals the count over every pair by SAT.
        #[test]
        fn the_grid_count_equals_brute_force_on_soups(
            soup in proptest::collection::vec(small_triangle(), 2..40),
            shift in proptest::collection::vec(proptest::array::uniform3(0i64..4), 40),
        ) {
            let soup: Vec<[[i64; 3]; 3]> = soup
                .iter()
                .zip(&shift)
                .map(|(t, s)| t.map(|p| [p[0] + s[0], p[1] + s[1], p[2] + s[2]]))
                .collect();
            let x: Vec<Vec3> = soup.iter().flat_map(to_f32).collect();
            let tris: Vec<[u32; 3]> =
                (0..soup.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            let mut reference = 0;
            for i in 0..soup.len() {
                for j in i + 1..soup.len() {
                    reference += usize::from(sat_intersect(&soup[i], &soup[j]));
                }
            }
            proptest::prop_assert_eq!(count_self(&x, &tris), reference);
            proptest::prop_assert_eq!(count_self_brute(&x, &tris), reference);
        }

        /// The fan count, through its grid or pair by pair, equals the pairs by SAT
        /// between the soup's first `k` triangles and the rest.
        #[test]
        fn the_fan_count_equals_brute_force_on_soups(
            soup in proptest::collection::vec(small_triangle(), 2..40),
            shift in proptest::collection::vec(proptest::array::uniform3(0i64..4), 40),
            k in 1usize..20,
        ) {
            let soup: Vec<[[i64; 3]; 3]> = soup
                .iter()
                .zip(&shift)
                .map(|(t, s)| t.map(|p| [p[0] + s[0], p[1] + s[1], p[2] + s[2]]))
                .collect();
            let k = k.min(soup.len() - 1);
            let x: Vec<Vec3> = soup.iter().flat_map(to_f32).collect();
            let tris: Vec<[u32; 3]> =
                (0..soup.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            let mut reference = 0;
            for i in 0..k {
                for j in k..soup.len() {
                    reference += usize::from(sat_intersect(&soup[i], &soup[j]));
                }
            }
            let at = |v: u32| x.get(v as usize).copied();
            for grid in [false, true] {
                proptest::prop_assert_eq!(
                    fan_crossings_by(at, &tris[..k], &tris[k..], None, grid),
                    reference
                );
            }
        }
    }
}
