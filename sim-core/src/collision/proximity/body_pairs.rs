//! The cloth against the body: its vertices against the body's triangles, its edges
//! against the body's creases, its triangles against the body's crease corners, each
//! found through the body's hashes (`body_side.rs`), one cloth primitive at a time so
//! that a search can split them over threads and an update can look from a few.

use glam::Vec3;

use super::cloth_side::Part;
use super::distance::{point_triangle, segment_segment};
use super::grid::Aabb;
use super::pair::{
    ClothView, NONE, Pair, PairKind, ProximityParams, feature_key, keep, min_along, separating,
};
use crate::collision::body::Body;
use crate::mesh::edge_key;

/// What a body pair is found as: its kind, and a corner-face pair's body vertex.
#[derive(Clone, Copy)]
struct Found(PairKind, u32);

/// A pair of cloth vertices `vs` (weights `w`) with the body, closest points `on_cloth`
/// and `on_body`; `corners` are the body primitive's corners. Listed in `out` unless the
/// boxes cannot bring them within the contact distance.
#[allow(clippy::too_many_arguments)]
fn push(
    out: &mut Vec<Pair>,
    c: &ClothView<'_>,
    vs: &[u32],
    w: &[f32],
    (on_cloth, on_body): (Vec3, Vec3),
    corners: &[Vec3],
    fallback: Vec3,
    energy: bool,
    found: Found,
    p: &ProximityParams,
) {
    let mut cloth_pts = [Vec3::ZERO; 3];
    for (k, &v) in vs.iter().enumerate().take(3) {
        cloth_pts[k] = c.x[v as usize];
    }
    let cloth_pts = &cloth_pts[..vs.len().min(3)];
    // The body's side is its own (outward): no exact side asked.
    let (n, sep0) = separating(cloth_pts, corners, (on_cloth, on_body), fallback, || 0);
    let body_bound = corners
        .iter()
        .map(|b| n.dot(*b))
        .fold(f32::NEG_INFINITY, f32::max);
    let gap_max = min_along(c.boxes, vs, n) - body_bound;
    if gap_max >= p.radius {
        return;
    }
    let mut pair = Pair {
        v: [NONE; 4],
        w: [0.0; 4],
        side: [0; 4],
        n,
        offset: -n.dot(on_body),
        body_bound,
        delta: keep(p.delta, sep0),
        energy,
        kind: found.0,
        body_vertex: found.1,
    };
    for (k, (&v, &wk)) in vs.iter().zip(w).enumerate() {
        pair.v[k] = v;
        pair.w[k] = wk;
        pair.side[k] = 1;
    }
    out.push(pair);
}

/// Cloth vertex `i` against the body's triangles near it, nearest first, so the feature
/// the vertex is over gets the energy.
pub(super) fn vertex_face(
    c: &ClothView<'_>,
    body: &Body,
    p: &ProximityParams,
    reach: f32,
    part: &mut Part,
    i: usize,
) {
    let at = |i: u32| body.vertices[i as usize];
    let b = c.boxes[i];
    if !c.free[i] || !b.is_finite() {
        return;
    }
    let Part {
        pairs,
        found,
        near,
        seen,
        ..
    } = part;
    found.clear();
    body.grids
        .triangles
        .query(&b.grown(reach), |t| found.push(t));
    let xi = c.x[i];
    near.clear();
    near.extend(found.iter().map(|&t| {
        let [a, bb, cc] = body.triangles[t as usize].map(at);
        let (q, w) = point_triangle(xi, a, bb, cc);
        ((xi - q).length(), t, q, w)
    }));
    near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    seen.clear();
    for &(_, t, q, w) in near.iter() {
        let tri = body.triangles[t as usize];
        let key = feature_key(tri, t, w);
        let energy = !seen.contains(&key);
        let before = pairs.len();
        let found = Found(PairKind::BodyVertexFace, NONE);
        let (corners, normal) = (tri.map(at), body.face_normal(t));
        push(
            pairs,
            c,
            &[i as u32],
            &[1.0],
            (xi, q),
            &corners,
            normal,
            energy,
            found,
            p,
        );
        if energy && pairs.len() > before {
            seen.push(key);
        }
    }
}

/// Cloth edge `e` against the body's creases near it.
pub(super) fn edge_edge(
    c: &ClothView<'_>,
    body: &Body,
    p: &ProximityParams,
    reach: f32,
    part: &mut Part,
    e: usize,
) {
    let at = |i: u32| body.vertices[i as usize];
    let grids = &*body.grids;
    let e = &c.edges[e];
    if !c.free[e[0] as usize] && !c.free[e[1] as usize] {
        return;
    }
    let eb = c.boxes[e[0] as usize].union(c.boxes[e[1] as usize]);
    if !eb.is_finite() {
        return;
    }
    part.found.clear();
    grids
        .edge_grid
        .query(&eb.grown(reach), |f| part.found.push(f));
    for &f in &part.found {
        let [q0, q1] = grids.edges[f as usize].map(at);
        let [p0, p1] = e.map(|v| c.x[v as usize]);
        let (s, t) = segment_segment(p0, p1, q0, q1);
        let interior = s > 1e-4 && s < 1.0 - 1e-4 && t > 1e-4 && t < 1.0 - 1e-4;
        let fallback = (p1 - p0).cross(q1 - q0);
        let closest = (p0.lerp(p1, s), q0.lerp(q1, t));
        let found = Found(PairKind::BodyEdgeEdge, NONE);
        let w = [1.0 - s, s];
        push(
            &mut part.pairs,
            c,
            e,
            &w,
            closest,
            &[q0, q1],
            fallback,
            interior,
            found,
            p,
        );
    }
}

/// Cloth triangle `ti` against the body's corners near it. A corner against one cloth
/// edge is found from both the edge's triangles: [`one_energy_per_corner`] then keeps
/// one energy.
pub(super) fn corner_face(
    c: &ClothView<'_>,
    body: &Body,
    p: &ProximityParams,
    reach: f32,
    part: &mut Part,
    ti: usize,
) {
    let grids = &*body.grids;
    let t = &c.tris[ti];
    if t.iter().all(|&v| !c.free[v as usize]) {
        return;
    }
    let tb = t
        .iter()
        .fold(Aabb::EMPTY, |b, &v| b.union(c.boxes[v as usize]));
    if !tb.is_finite() {
        return;
    }
    part.found.clear();
    grids
        .vertices
        .query(&tb.grown(reach), |b| part.found.push(b));
    for &slot in &part.found {
        let bv = grids.corners[slot as usize];
        let b = body.vertices[bv as usize];
        let [x0, x1, x2] = t.map(|v| c.x[v as usize]);
        let (q, w) = point_triangle(b, x0, x1, x2);
        // A body corner against a cloth corner is the cloth vertex's contact.
        let corner_of_cloth = w.iter().filter(|&&wk| wk > 0.0).count() <= 1;
        let fallback = (x1 - x0).cross(x2 - x0);
        let found = Found(PairKind::BodyCornerFace, bv);
        push(
            &mut part.pairs,
            c,
            t,
            &w,
            (q, b),
            &[b],
            fallback,
            !corner_of_cloth,
            found,
            p,
        );
    }
}

/// One energy per (body corner, cloth edge) among the corner-face pairs of `pairs`: the
/// pair from the triangle whose corners, in order, come first keeps it, whatever order
/// the pairs are in (an update appends its pairs at the end).
pub(super) fn one_energy_per_corner(
    pairs: &mut [Pair],
    keys: &mut Vec<(u32, u64, [u32; 3], u32)>,
    flips: &mut Vec<(u32, bool)>,
) {
    keys.clear();
    for (k, q) in pairs.iter().enumerate() {
        if q.kind != PairKind::BodyCornerFace {
            continue;
        }
        let (mut on, mut m) = ([NONE; 3], 0);
        for j in 0..3 {
            if q.w[j] > 0.0 {
                on[m] = q.v[j];
                m += 1;
            }
        }
        if let (2, [a, b, _]) = (m, on) {
            let mut tri = [q.v[0], q.v[1], q.v[2]];
            tri.sort_unstable();
            keys.push((q.body_vertex, edge_key(a, b), tri, k as u32));
        }
    }
    keys.sort_unstable();
    for k in 0..keys.len() {
        let first = k == 0 || (keys[k - 1].0, keys[k - 1].1) != (keys[k].0, keys[k].1);
        let q = &mut pairs[keys[k].3 as usize];
        if q.energy != first {
            flips.push((keys[k].3, q.energy));
            q.energy = first;
        }
    }
}
