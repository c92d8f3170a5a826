//! Cutting: the paper's cut (a vertex split across the cut direction) and cutting pieces
//! away (triangles removed); scissors along a stroke are in `stroke.rs`, exact cuts along
//! a pattern outline in `trim.rs`.

use glam::Vec3;

use super::document::Design;
use super::error::EditError;
use super::prim::{Between, Prim};
use crate::mesh::Tri;

/// How far a cut moves each of its two sides off the line it was made along, across
/// the cloth, m: 40 µm, under the guard's least separation (0.1 mm), so that no side
/// is moved into other cloth the guard keeps apart.
pub(super) const PART_M: f32 = 4e-5;

/// How far a side of a fresh cut at `x` is moved: [`PART_M`] toward the middle of its
/// own triangles (their corners, `fan`), along the cloth (off their area-weighted
/// normal). `None` with no triangles, or no such direction.
pub(super) fn parting(x: Vec3, fan: impl Iterator<Item = [Vec3; 3]>) -> Option<Vec3> {
    let (mut centre, mut normal, mut n) = (Vec3::ZERO, Vec3::ZERO, 0usize);
    for [a, b, c] in fan {
        centre += (a + b + c) / 3.0;
        normal += (b - a).cross(c - a);
        n += 1;
    }
    if n == 0 {
        return None;
    }
    let inward = centre / n as f32 - x;
    let normal = normal.normalize_or_zero();
    let along = (inward - normal * normal.dot(inward)).try_normalize()?;
    Some(along * PART_M)
}

impl Design {
    /// Moves the two sides of a fresh cut apart: every copy that lies (within
    /// [`PART_M`]) where the vertex it was made from lies, and that vertex, each
    /// [`PART_M`] into its own triangles, along the cloth. Lying together, the sides
    /// have no direction between them but the cloth's normal, so the guard kept them
    /// apart along it only, and they could slide into each other in the cloth's plane
    /// (2 crossing pairs on a flat cloth cut along a slanted stroke, up to 25 while the
    /// trim's moved vertices pulled the cloth). Apart, the guard keeps each pair of
    /// sides from crossing the line between them. The moves are kept in `parting` for
    /// the edit to record (undone, the sides come back by as much). A pinned vertex is
    /// moved too (its copy is pinned with it, and a pin holds a vertex where it is): left
    /// together, a pinned cut's two sides met at one point, which the exact count finds
    /// as 1-6 touching triangle pairs on a cloth hanging from it.
    pub(super) fn part_copies(&mut self, copies: &[(u32, u32)]) {
        let cloth = &self.sim.cloth;
        let n = cloth.len();
        let mut sides: Vec<u32> = Vec::new();
        for &(c, o) in copies {
            let (ci, oi) = (c as usize, o as usize);
            if ci < n && oi < n && (cloth.x[ci] - cloth.x[oi]).length() < PART_M {
                sides.extend([c, o]);
            }
        }
        sides.sort_unstable();
        sides.dedup();
        // Every direction from the positions as the edit left them, then the moves.
        let x = &cloth.x;
        let moves: Vec<(usize, Vec3)> = sides
            .iter()
            .filter_map(|&v| {
                let fan = (cloth.live.tris_of(v).iter())
                    .filter_map(|&t| cloth.live.tri(t))
                    .map(|t| t.v.map(|i| x[i as usize]));
                Some((v as usize, parting(x[v as usize], fan)?))
            })
            .collect();
        self.parting.clear();
        for (v, by) in moves {
            self.sim.cloth.x[v] += by;
            self.parting.push(Prim::Nudge {
                vertex: v as u32,
                by,
            });
        }
    }

    fn centroid(&self, t: &Tri) -> Vec3 {
        t.v.iter()
            .map(|&i| self.sim.cloth.x[i as usize])
            .sum::<Vec3>()
            / 3.0
    }

    /// Primitives that split `v` in two: the triangles whose centre lies on the positive
    /// side of the plane through `v` with normal `plane` move to a new vertex.
    pub(super) fn split_prims(&self, v: u32, plane: Vec3) -> Result<Vec<Prim>, EditError> {
        if !plane.is_finite() || plane.length_squared() < 1e-20 {
            return Err(EditError::BadDirection);
        }
        let xv = self.sim.cloth.x[v as usize];
        let tris: Vec<(u32, Tri)> = self
            .sim
            .cloth
            .live
            .tris_of(v)
            .iter()
            .filter_map(|&t| self.sim.cloth.live.tri(t).map(|tri| (t, *tri)))
            .collect();
        let moving: Vec<(u32, Tri)> = tris
            .iter()
            .filter(|(_, t)| (self.centroid(t) - xv).dot(plane) > 0.0)
            .copied()
            .collect();
        if moving.len() == tris.len() {
            return Err(EditError::NothingToCut(v));
        }
        self.split_off_prims(v, &moving)
    }

    /// Primitives that give the triangles `moving` (some of `v`'s, not none) a new vertex
    /// of their own in `v`'s place.
    pub(super) fn split_off_prims(
        &self,
        v: u32,
        moving: &[(u32, Tri)],
    ) -> Result<Vec<Prim>, EditError> {
        if moving.is_empty() {
            return Err(EditError::NothingToCut(v));
        }
        let xv = self.sim.cloth.x[v as usize];
        let new = self.sim.cloth.len() as u32;
        let mut prims = vec![Prim::AddVertex {
            index: new,
            x: xv,
            v: self.sim.cloth.v[v as usize],
            from: Some(Between { a: v, b: v, s: 0.0 }),
        }];
        for (slot, t) in moving {
            let mut n = *t;
            n.v = n.v.map(|i| if i == v { new } else { i });
            prims.push(Prim::Tri {
                slot: *slot,
                old: Some(*t),
                new: Some(n),
            });
        }
        if self.sim.cloth.is_pinned(v as usize) {
            prims.push(Prim::Pin {
                vertex: new,
                old: false,
                new: true,
            });
        }
        Ok(prims)
    }

    /// The paper's cut: splits vertex `v` in two, its triangles divided by the plane that
    /// contains the cut direction `dir` and the surface normal. Returns the new vertex.
    pub fn cut_vertex(&mut self, v: u32, dir: Vec3) -> Result<u32, EditError> {
        self.check_vertex(v)?;
        let plane = dir.cross(self.sim.cloth.vertex_normal(v));
        let new = self.sim.cloth.len() as u32;
        let prims = self.split_prims(v, plane)?;
        self.commit("cut", prims)?;
        Ok(new)
    }

    /// Shortest edge path from `a` to `b` of at most `limit` edges (just `[a, b]` if none).
    pub(super) fn mesh_path(&self, a: u32, b: u32, limit: usize) -> Vec<u32> {
        let mut prev: std::collections::HashMap<u32, u32> = std::collections::HashMap::new();
        let mut frontier = vec![a];
        prev.insert(a, a);
        for _ in 0..limit {
            let mut next = Vec::new();
            for &u in &frontier {
                for w in self.sim.cloth.live.neighbours(u) {
                    if let std::collections::hash_map::Entry::Vacant(e) = prev.entry(w) {
                        e.insert(u);
                        next.push(w);
                    }
                }
            }
            if prev.contains_key(&b) {
                let mut path = vec![b];
                let mut c = b;
                while c != a {
                    c = prev[&c];
                    path.push(c);
                }
                path.reverse();
                return path;
            }
            frontier = next;
        }
        vec![a, b]
    }

    /// Cuts a piece away: removes the triangles in `slots` (alive ones; at least one) as
    /// one undoable operation, with the seams none of whose pairs has cloth left at both
    /// ends (a seam of a deleted piece: it could never close, and the list would go on
    /// showing it). Returns how many triangles went.
    pub fn remove_triangles(&mut self, slots: &[u32]) -> Result<usize, EditError> {
        self.remove_labelled("cut away", slots)
    }

    /// The removal of each seam none of whose pairs would keep cloth at both ends once the
    /// triangles in `going` are gone, the last seam first (each index still valid as the
    /// primitives apply in order, and undo puts them back in order).
    fn seams_left_without_cloth(&self, going: &std::collections::HashSet<u32>) -> Vec<Prim> {
        let live = &self.sim.cloth.live;
        let mut kept = vec![false; self.sim.cloth.len()];
        for (slot, t) in live.iter() {
            if !going.contains(&slot) {
                for v in t.v {
                    kept[v as usize] = true;
                }
            }
        }
        let has = |v: u32| kept.get(v as usize).copied().unwrap_or(false);
        (0..self.seams.len())
            .rev()
            .filter(|&i| !self.seams[i].pairs.iter().any(|&(a, b)| has(a) && has(b)))
            .map(|i| Prim::Seam {
                index: i as u32,
                old: Some(self.seams[i].clone()),
                new: None,
            })
            .collect()
    }

    /// [`Design::remove_triangles`] under the history label `label`.
    pub(super) fn remove_labelled(
        &mut self,
        label: &'static str,
        slots: &[u32],
    ) -> Result<usize, EditError> {
        self.check_editable()?;
        let mut seen = std::collections::HashSet::new();
        let mut prims: Vec<Prim> = slots
            .iter()
            .filter(|s| seen.insert(**s))
            .filter_map(|&s| {
                self.sim.cloth.live.tri(s).map(|t| Prim::Tri {
                    slot: s,
                    old: Some(*t),
                    new: None,
                })
            })
            .collect();
        if prims.is_empty() {
            return Err(EditError::NothingNear { radius: 0.0 });
        }
        let n = prims.len();
        prims.extend(self.seams_left_without_cloth(&seen));
        self.commit(label, prims)?;
        Ok(n)
    }
}
