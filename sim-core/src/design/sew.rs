//! The paper's sew: two border vertices merged into one, halfway between them.

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;

impl Design {
    /// The paper's sew: merges border vertices `a` and `b` into `a`, placed halfway.
    /// Under the vbd model, whose cloth never crosses, it is refused when that would make
    /// the cloth cross itself or the body (the same exact check as a seam's welds: moving
    /// `a` halfway swings its triangles, and `b`'s, through whatever lies between, and two
    /// corners of one flat edge sewn lay their triangles over the cloth). The other
    /// models keep the paper's sew as it was.
    pub fn sew(&mut self, a: u32, b: u32) -> Result<(), EditError> {
        let prims = self.sew_prims(a, b)?;
        if self.sim.never_crosses() && self.edit_would_cross(&prims) {
            let x = &self.sim.cloth.x;
            return Err(EditError::SewWouldCross {
                a,
                b,
                gap_mm: (x[a as usize] - x[b as usize]).length() * 1e3,
            });
        }
        self.commit("sew", prims)
    }

    pub(super) fn sew_prims(&self, a: u32, b: u32) -> Result<Vec<Prim>, EditError> {
        self.check_vertex(a)?;
        self.check_vertex(b)?;
        if a == b {
            return Err(EditError::SewSelf(a));
        }
        for v in [a, b] {
            if !self.sim.cloth.live.is_boundary(v) {
                return Err(EditError::SewInterior(v));
            }
        }
        let live = &self.sim.cloth.live;
        if live
            .tris_of(b)
            .iter()
            .any(|&t| live.tri(t).is_some_and(|t| t.corner(a).is_some()))
        {
            return Err(EditError::SewNeighbours(a, b));
        }
        let c = &self.sim.cloth;
        let (ia, ib) = (a as usize, b as usize);
        let mut prims = vec![Prim::Move {
            vertex: a,
            old: (c.x[ia], c.v[ia]),
            new: ((c.x[ia] + c.x[ib]) * 0.5, (c.v[ia] + c.v[ib]) * 0.5),
        }];
        for &slot in live.tris_of(b) {
            if let Some(t) = live.tri(slot) {
                let mut n = *t;
                n.v = n.v.map(|i| if i == b { a } else { i });
                prims.push(Prim::Tri {
                    slot,
                    old: Some(*t),
                    new: Some(n),
                });
            }
        }
        if c.is_pinned(ib) && !c.is_pinned(ia) {
            prims.push(Prim::Pin {
                vertex: a,
                old: false,
                new: true,
            });
        }
        Ok(prims)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::design::EditError;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// Two 0.2 m squares side by side, 0.32 m apart at y = 1, and, with `wall`, a third
    /// standing between them (the plane x = 0). Returns the mesh and the two border
    /// vertices facing each other across the gap, at z = 0.
    fn across_a_gap(wall: bool) -> (ClothMesh, u32, u32) {
        let sq = ClothMesh::grid(0.2, 0.2, 2, 2, 1.0).unwrap();
        let mut mesh = sq.clone();
        for p in &mut mesh.positions {
            p.x -= 0.25;
        }
        let mut add = |m: &ClothMesh, f: &dyn Fn(Vec3) -> Vec3| {
            let n0 = mesh.positions.len() as u32;
            mesh.positions.extend(m.positions.iter().map(|&p| f(p)));
            mesh.uvs.extend(&m.uvs);
            mesh.triangles
                .extend(m.triangles.iter().map(|t| t.map(|i| i + n0)));
        };
        // The right square a little nearer, so the halfway point is not on the wall.
        add(&sq, &|p| p + Vec3::new(0.27, 0.0, 0.0));
        if wall {
            let w = ClothMesh::grid(0.3, 0.3, 2, 2, 0.0).unwrap();
            add(&w, &|p| Vec3::new(0.0, 1.0 + p.x, p.z));
        }
        let at = |x: f32| {
            mesh.positions
                .iter()
                .position(|p| (p.x - x).abs() < 1e-5 && p.z.abs() < 1e-5)
                .unwrap() as u32
        };
        let (a, b) = (at(-0.15), at(0.17));
        (mesh, a, b)
    }

    /// Under vbd and xpbd with its guard (contact that is never crossed), a sew whose
    /// halfway point lies beyond a wall of cloth is refused, and changes nothing; without
    /// the wall the same sew is done. Under plain xpbd (the paper's sew) it is done
    /// through the wall.
    #[test]
    fn a_sew_that_would_cross_is_refused_under_vbd_and_guarded_xpbd() {
        let (mesh, a, b) = across_a_gap(true);
        let mut d = crate::design::floating(mesh, ModelKind::Xpbd);
        d.sew(a, b).unwrap();
        for (model, guard) in [(ModelKind::Vbd, false), (ModelKind::Xpbd, true)] {
            refused_through_a_wall(model, guard);
        }
    }

    fn refused_through_a_wall(model: ModelKind, guard: bool) {
        let guarded = |mesh| {
            let mut d = crate::design::floating(mesh, model);
            if guard {
                assert!(d.sim.set_guard(true));
            }
            d
        };
        let (mesh, a, b) = across_a_gap(true);
        let mut d = guarded(mesh);
        let (x, tris, edits) = (
            d.sim.cloth.x.clone(),
            d.sim.cloth.live.tri_count(),
            d.history.undo_len(),
        );
        match d.sew(a, b) {
            Err(EditError::SewWouldCross { gap_mm, .. }) => {
                assert!((gap_mm - 320.0).abs() < 1.0, "{gap_mm}")
            }
            other => panic!("{model:?}: {other:?}"),
        }
        assert_eq!(d.sim.cloth.x, x);
        assert_eq!(d.sim.cloth.live.tri_count(), tris);
        assert_eq!(d.history.undo_len(), edits);

        let (mesh, a, b) = across_a_gap(false);
        let mut d = guarded(mesh);
        d.sew(a, b).unwrap();
        assert!((d.sim.cloth.x[a as usize].x - 0.01).abs() < 1e-5);
    }
}
