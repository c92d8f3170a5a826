//! The cloth's live mesh: triangles in stable slots that cuts, tears and sews rewrite
//! one at a time, with the adjacency those operations and the solvers need.
//!
//! A slot keeps its index for life (a removed triangle leaves `None`; only empty slots at
//! the end are dropped, and an append takes their index again), so solvers can key
//! their per-triangle data by slot and update only what an edit touched. Every triangle
//! carries its own rest corners and UVs: after a sew, one vertex can sit at two places of
//! the pattern and of the texture.

use rustc_hash::FxHashMap as HashMap;

use glam::{Vec2, Vec3};

use super::cloth_mesh::ClothMesh;
use super::edge::{edge_ends, edge_key};
use crate::error::GeometryError;

/// One live triangle: vertex indices, and per corner its rest position and UV.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tri {
    pub v: [u32; 3],
    pub rest: [Vec3; 3],
    pub uv: [Vec2; 3],
}

impl Tri {
    pub fn rest_area(&self) -> f32 {
        let [a, b, c] = self.rest;
        0.5 * (b - a).cross(c - a).length()
    }

    /// This triangle with corner `corner` taken by vertex `v` at rest place `rest` and
    /// texture coordinate `uv` (an edge split, or a vertex put into an edge).
    pub fn with_corner(&self, corner: usize, v: u32, rest: Vec3, uv: Vec2) -> Tri {
        let mut n = *self;
        n.v[corner] = v;
        n.rest[corner] = rest;
        n.uv[corner] = uv;
        n
    }

    /// The corner holding vertex `v`.
    pub fn corner(&self, v: u32) -> Option<usize> {
        self.v.iter().position(|&i| i == v)
    }

    /// The three edges as `(a, b, opposite)`, in winding order.
    pub fn edges(&self) -> [(u32, u32, u32); 3] {
        let [a, b, c] = self.v;
        [(a, b, c), (b, c, a), (c, a, b)]
    }
}

/// No triangle on this side of an edge.
pub const NONE: u32 = u32::MAX;

#[derive(Clone, Debug, Default)]
pub struct LiveMesh {
    tris: Vec<Option<Tri>>,
    /// Triangle slots around each vertex.
    vert_tris: Vec<Vec<u32>>,
    /// Edge key -> the (at most two) triangle slots beside it.
    edges: HashMap<u64, [u32; 2]>,
    alive: usize,
    /// Whether any triangle was ever rewritten (cut, tear, sew) since the pattern.
    pub edited: bool,
    /// Bumped by every change of a triangle (so viewers know when to re-read the mesh).
    version: u64,
}

impl LiveMesh {
    /// The pattern's triangles in slots `0..t`. The pattern must already be valid.
    pub fn from_mesh(mesh: &ClothMesh) -> Self {
        let mut m = Self {
            vert_tris: vec![Vec::new(); mesh.positions.len()],
            ..Self::default()
        };
        for tri in &mesh.triangles {
            let t = Tri {
                v: *tri,
                rest: tri.map(|i| mesh.positions[i as usize]),
                uv: tri.map(|i| mesh.uvs[i as usize]),
            };
            let slot = m.tris.len() as u32;
            // A valid pattern has no third triangle on an edge, so this cannot fail.
            let _ = m.set(slot, Some(t));
        }
        m.edited = false;
        m
    }

    /// Changes with every triangle edit.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// Slots, alive or not.
    pub fn slots(&self) -> usize {
        self.tris.len()
    }

    pub fn tri_count(&self) -> usize {
        self.alive
    }

    pub fn vertex_count(&self) -> usize {
        self.vert_tris.len()
    }

    pub fn tri(&self, slot: u32) -> Option<&Tri> {
        self.tris.get(slot as usize).and_then(|t| t.as_ref())
    }

    /// Alive triangles with their slots.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &Tri)> + '_ {
        self.tris
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.as_ref().map(|t| (i as u32, t)))
    }

    /// Each of `n` vertices' place in the pattern (its first alive triangle's rest
    /// corner; infinite for a vertex no triangle uses).
    pub fn pattern_places(&self, n: usize) -> Vec<Vec3> {
        let mut places = vec![Vec3::splat(f32::INFINITY); n];
        for (_, t) in self.iter() {
            for k in 0..3 {
                if let Some(p) = places.get_mut(t.v[k] as usize)
                    && !p.is_finite()
                {
                    *p = t.rest[k];
                }
            }
        }
        places
    }

    /// The mean rest length of the alive triangles' sides (0 with none).
    pub fn mean_rest_side(&self) -> f32 {
        let (mut sum, mut k) = (0.0f32, 0usize);
        for (_, t) in self.iter() {
            for j in 0..3 {
                sum += (t.rest[j] - t.rest[(j + 1) % 3]).length();
                k += 1;
            }
        }
        if k == 0 { 0.0 } else { sum / k as f32 }
    }

    /// Alive triangles' vertex indices, in slot order.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.iter().map(|(_, t)| t.v).collect()
    }

    pub fn tris_of(&self, v: u32) -> &[u32] {
        self.vert_tris.get(v as usize).map_or(&[], |t| &t[..])
    }

    /// A vertex is alive while some triangle uses it.
    pub fn vertex_alive(&self, v: u32) -> bool {
        !self.tris_of(v).is_empty()
    }

    /// The triangle slots beside edge `(a, b)` (`NONE` for a missing side).
    pub fn edge(&self, a: u32, b: u32) -> [u32; 2] {
        self.edges
            .get(&edge_key(a, b))
            .copied()
            .unwrap_or([NONE; 2])
    }

    /// Whether `v` lies on the cloth's border (some edge of it has one triangle).
    pub fn is_boundary(&self, v: u32) -> bool {
        self.tris_of(v).iter().any(|&t| {
            self.tri(t).is_some_and(|tri| {
                tri.edges()
                    .iter()
                    .filter(|(a, b, _)| *a == v || *b == v)
                    .any(|(a, b, _)| self.edge(*a, *b)[1] == NONE)
            })
        })
    }

    /// Whether `a` and `b` are neighbours or share one.
    pub fn meet(&self, a: u32, b: u32) -> bool {
        let nb = self.neighbours(b);
        nb.contains(&a) || self.neighbours(a).iter().any(|u| nb.contains(u))
    }

    /// Vertices joined to `v` by an edge.
    pub fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for &t in self.tris_of(v) {
            if let Some(tri) = self.tri(t) {
                for &u in &tri.v {
                    if u != v && !out.contains(&u) {
                        out.push(u);
                    }
                }
            }
        }
        out
    }

    /// Keys of the edges with two triangles, sorted (a deterministic order).
    pub fn hinge_keys(&self) -> Vec<u64> {
        let mut k: Vec<u64> = self
            .edges
            .iter()
            .filter(|(_, e)| e[1] != NONE)
            .map(|(k, _)| *k)
            .collect();
        k.sort_unstable();
        k
    }

    /// The hinge on edge `key`: vertices `[a, b, c, d]` (triangles `a b c` and `a b d`)
    /// and each triangle's rest corners for `a, b, c` and `a, b, d`.
    pub fn hinge(&self, key: u64) -> Option<([u32; 4], [Vec3; 3], [Vec3; 3])> {
        let e = self.edges.get(&key)?;
        let (t0, t1) = (self.tri(e[0])?, self.tri(e[1])?);
        let (a, b) = edge_ends(key);
        let corners = |t: &Tri| -> Option<(u32, [Vec3; 3])> {
            let (ca, cb) = (t.corner(a)?, t.corner(b)?);
            let cc = 3 - ca - cb;
            Some((t.v[cc], [t.rest[ca], t.rest[cb], t.rest[cc]]))
        };
        let (c, r0) = corners(t0)?;
        let (d, r1) = corners(t1)?;
        (c != d).then_some(([a, b, c, d], r0, r1))
    }

    /// The warp direction at the hinge of edge `key` (its first triangle's, at rest).
    pub fn hinge_warp(&self, key: u64) -> Option<Vec3> {
        let t = self.tri(self.edges.get(&key)?[0])?;
        Some(warp_of(t.rest, t.uv))
    }

    /// Adds an isolated vertex slot (it becomes alive when a triangle uses it).
    pub fn push_vertex(&mut self) -> u32 {
        self.vert_tris.push(Vec::new());
        (self.vert_tris.len() - 1) as u32
    }

    /// Removes the last vertex slot; it must be unused.
    pub fn pop_vertex(&mut self) -> bool {
        match self.vert_tris.last() {
            Some(t) if t.is_empty() => {
                self.vert_tris.pop();
                true
            }
            _ => false,
        }
    }

    /// Whether `tri` could be placed in `slot` (replacing what is there) keeping every
    /// edge in at most two triangles and every index in range and distinct.
    pub fn can_set(&self, slot: u32, tri: &Tri) -> Result<(), GeometryError> {
        let n = self.vert_tris.len();
        if tri.v.iter().any(|&i| i as usize >= n) {
            return Err(GeometryError::IndexOutOfRange {
                triangle: slot as usize,
                vertices: n,
            });
        }
        if tri.v[0] == tri.v[1] || tri.v[1] == tri.v[2] || tri.v[0] == tri.v[2] {
            return Err(GeometryError::Degenerate {
                triangle: slot as usize,
            });
        }
        for (a, b, _) in tri.edges() {
            let [s0, s1] = self.edge(a, b);
            let others = [s0, s1].iter().filter(|&&s| s != NONE && s != slot).count();
            if others >= 2 {
                return Err(GeometryError::NonManifoldEdge { a, b, count: 3 });
            }
        }
        Ok(())
    }

    /// Puts `tri` (or nothing) in `slot` and returns what was there. A slot past the end
    /// (`slots()` or beyond: empty slots at the end are dropped, so an undo may put back
    /// the last ones in any order) extends the slots. Fails, changing nothing, when an
    /// edge would get a third triangle or an index is bad.
    pub fn set(&mut self, slot: u32, tri: Option<Tri>) -> Result<Option<Tri>, GeometryError> {
        let s = slot as usize;
        if s > self.tris.len() + 2 * super::MAX_VERTICES {
            return Err(GeometryError::IndexOutOfRange {
                triangle: s,
                vertices: self.vert_tris.len(),
            });
        }
        if let Some(t) = &tri {
            self.can_set(slot, t)?;
        }
        if s >= self.tris.len() {
            if tri.is_none() {
                return Ok(None);
            }
            self.tris.resize(s + 1, None);
        }
        let old = self.tris[s].take();
        if let Some(o) = &old {
            self.alive -= 1;
            for &v in &o.v {
                self.vert_tris[v as usize].retain(|&x| x != slot);
            }
            for (a, b, _) in o.edges() {
                let key = edge_key(a, b);
                if let Some(e) = self.edges.get_mut(&key) {
                    if e[0] == slot {
                        *e = [e[1], NONE];
                    } else if e[1] == slot {
                        e[1] = NONE;
                    }
                    if e[0] == NONE {
                        self.edges.remove(&key);
                    }
                }
            }
        }
        if let Some(t) = &tri {
            self.alive += 1;
            for &v in &t.v {
                self.vert_tris[v as usize].push(slot);
            }
            for (a, b, _) in t.edges() {
                let e = self.edges.entry(edge_key(a, b)).or_insert([NONE; 2]);
                if e[0] == NONE {
                    e[0] = slot;
                } else {
                    e[1] = slot;
                }
            }
        }
        self.tris[s] = tri;
        // Empty slots at the end go (an undone new piece leaves thousands): the next
        // append reuses their indices, as a redo does.
        while self.tris.last().is_some_and(Option::is_none) {
            self.tris.pop();
        }
        self.edited = true;
        self.version += 1;
        Ok(old)
    }

    /// Gives the triangle in `slot` new texture coordinates, its corners and rest shape
    /// as they are; returns the old ones. Fails, changing nothing, without a triangle
    /// there or with a UV outside [0, 1].
    pub fn set_uv(&mut self, slot: u32, uv: [Vec2; 3]) -> Result<[Vec2; 3], GeometryError> {
        let t = self
            .tris
            .get_mut(slot as usize)
            .and_then(|t| t.as_mut())
            .ok_or(GeometryError::Degenerate {
                triangle: slot as usize,
            })?;
        if uv
            .iter()
            .any(|u| !u.is_finite() || u.min_element() < 0.0 || u.max_element() > 1.0)
        {
            return Err(GeometryError::BadUv {
                vertex: t.v[0] as usize,
            });
        }
        let old = std::mem::replace(&mut t.uv, uv);
        self.version += 1;
        Ok(old)
    }

    /// Checks the invariants the solvers rely on against positions `x`: indices in range,
    /// no repeated index or zero-area triangle, every edge in at most two triangles,
    /// finite positions of live vertices, UVs finite and within [0, 1].
    pub fn validate(&self, x: &[Vec3]) -> Result<(), GeometryError> {
        if self.alive == 0 {
            return Err(GeometryError::Empty);
        }
        let n = x.len().min(self.vert_tris.len());
        let mut count: HashMap<u64, usize> =
            HashMap::with_capacity_and_hasher(self.alive * 2, Default::default());
        for (slot, t) in self.iter() {
            let triangle = slot as usize;
            if t.v.iter().any(|&i| i as usize >= n) {
                return Err(GeometryError::IndexOutOfRange {
                    triangle,
                    vertices: n,
                });
            }
            if t.v[0] == t.v[1] || t.v[1] == t.v[2] || t.v[0] == t.v[2] || t.rest_area() <= 0.0 {
                return Err(GeometryError::Degenerate { triangle });
            }
            for &i in &t.v {
                if !x[i as usize].is_finite() {
                    return Err(GeometryError::NonFinite { vertex: i as usize });
                }
            }
            if t.uv
                .iter()
                .any(|u| !u.is_finite() || u.min_element() < 0.0 || u.max_element() > 1.0)
            {
                return Err(GeometryError::BadUv {
                    vertex: t.v[0] as usize,
                });
            }
            for (a, b, _) in t.edges() {
                let c = count.entry(edge_key(a, b)).or_insert(0);
                *c += 1;
                if *c > 2 {
                    return Err(GeometryError::NonManifoldEdge { a, b, count: *c });
                }
            }
        }
        Ok(())
    }
}

/// The warp direction of a triangle, in 3D at rest: where U grows across its UVs,
/// projected into its plane (the first side when the UVs are degenerate).
pub fn warp_of(rest: [Vec3; 3], uv: [Vec2; 3]) -> Vec3 {
    let [x0, x1, x2] = rest;
    let [t0, t1, t2] = uv;
    let (e1, e2) = (x1 - x0, x2 - x0);
    let n = e1.cross(e2).normalize_or(Vec3::Y);
    let (du1, du2) = (t1 - t0, t2 - t0);
    let det = du1.x * du2.y - du2.x * du1.y;
    let mut tangent = if det.abs() > 1e-12 {
        (e1 * du2.y - e2 * du1.y) / det
    } else {
        e1
    };
    tangent -= n * n.dot(tangent);
    tangent
        .try_normalize()
        .unwrap_or_else(|| e1.normalize_or(Vec3::X))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_keeps_adjacency_and_refuses_a_third_triangle() {
        let m = ClothMesh::grid(1.0, 1.0, 2, 2, 0.0).unwrap();
        let mut live = LiveMesh::from_mesh(&m);
        assert!(!live.edited);
        assert_eq!(live.tri_count(), 8);
        let t0 = *live.tri(0).unwrap();
        let [a, b, _] = t0.v;
        assert_ne!(live.edge(a, b)[0], NONE);
        // A third triangle on an interior edge is refused and changes nothing.
        let interior = live
            .iter()
            .flat_map(|(_, t)| t.edges())
            .find(|(a, b, _)| live.edge(*a, *b)[1] != NONE)
            .unwrap();
        let far = (0..9u32)
            .find(|v| *v != interior.0 && *v != interior.1 && *v != interior.2)
            .unwrap();
        let extra = Tri {
            v: [interior.0, interior.1, far],
            ..t0
        };
        let slots = live.slots() as u32;
        assert!(live.set(slots, Some(extra)).is_err());
        assert_eq!(live.slots(), 8);
        // Removing a triangle frees its edges' sides.
        live.set(0, None).unwrap();
        assert_eq!(live.tri_count(), 7);
        assert!(live.edited);
        assert!(!live.tris_of(a).contains(&0));
        // The corner vertex lost its only triangle; the others are now on the border.
        assert!(!live.vertex_alive(a));
        assert!(t0.v[1..].iter().all(|&v| live.is_boundary(v)));
        live.set(0, Some(t0)).unwrap();
        assert_eq!(live.tri_count(), 8);
        live.validate(&m.positions).unwrap();
        // Empty slots at the end go; the last ones come back in any order.
        let (t6, t7) = (*live.tri(6).unwrap(), *live.tri(7).unwrap());
        live.set(6, None).unwrap();
        assert_eq!(live.slots(), 8);
        live.set(7, None).unwrap();
        assert_eq!(live.slots(), 6);
        live.set(7, Some(t7)).unwrap();
        assert_eq!((live.slots(), live.tri_count()), (8, 7));
        live.set(6, Some(t6)).unwrap();
        assert_eq!((live.slots(), live.tri_count()), (8, 8));
        live.validate(&m.positions).unwrap();
    }
}
