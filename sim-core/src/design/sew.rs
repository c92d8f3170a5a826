//! The paper's sew: two border vertices merged into one, halfway between them.

use super::document::Design;
use super::error::EditError;
use super::prim::{MergeAt, Prim};
use crate::mesh::NONE;

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
        self.check_sewable(a, b)?;
        let live = &self.sim.cloth.live;
        if live
            .tris_of(b)
            .iter()
            .any(|&t| live.tri(t).is_some_and(|t| t.corner(a).is_some()))
        {
            return Err(EditError::SewNeighbours(a, b));
        }
        Ok(self.merge_prims(a, b, NONE))
    }

    /// A seam's weld of `a` and `b`: [`Design::sew_prims`], or, where the two are the
    /// ends of a border side, that side collapsed. A zip eases a vertex into the edge
    /// across its slit by splitting that edge's triangle, and a pair of the seam can then
    /// be joined by a side of one of the halves; welding it removes that half (its rest
    /// area goes with it: small where the zip eased the vertex in beside its partner), the
    /// other triangles keeping their own rest shapes, `b` taken to `a`. Only a
    /// border side with one triangle `(a, b, c)` whose two ends have no neighbour but
    /// `c` in common: anything else would pinch the cloth (`SewNeighbours`, as before).
    pub(super) fn weld_prims(&self, a: u32, b: u32) -> Result<Vec<Prim>, EditError> {
        let live = &self.sim.cloth.live;
        let [slot, other] = live.edge(a, b);
        if slot == NONE {
            return self.sew_prims(a, b);
        }
        self.check_sewable(a, b)?;
        let third = live
            .tri(slot)
            .and_then(|t| t.v.iter().copied().find(|&v| v != a && v != b));
        let Some(c) = third.filter(|_| other == NONE) else {
            return Err(EditError::SewNeighbours(a, b));
        };
        let na = live.neighbours(a);
        if live.neighbours(b).iter().any(|u| *u != c && na.contains(u)) {
            return Err(EditError::SewNeighbours(a, b));
        }
        Ok(self.merge_prims(a, b, slot))
    }

    /// Both vertices alive, two of them, on the border.
    fn check_sewable(&self, a: u32, b: u32) -> Result<(), EditError> {
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
        Ok(())
    }

    /// `b` merged into `a` halfway between them, triangle slot `gone` (if any) removed.
    fn merge_prims(&self, a: u32, b: u32, gone: u32) -> Vec<Prim> {
        let live = &self.sim.cloth.live;
        let c = &self.sim.cloth;
        let (ia, ib) = (a as usize, b as usize);
        let at = MergeAt::Middle;
        let to = at.of(c.x[ia], c.x[ib]);
        let mut prims = vec![Prim::Merge {
            a,
            b,
            at,
            apart: [c.x[ia] - to, c.x[ib] - to],
        }];
        // The collapsed side's triangle goes first, so that no edge has three on the way.
        if let Some(t) = live.tri(gone) {
            prims.push(Prim::Tri {
                slot: gone,
                old: Some(*t),
                new: None,
            });
        }
        for &slot in live.tris_of(b).iter().filter(|&&s| s != gone) {
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
        prims
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::design::EditError;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// A seam's pair joined by one border side (as the half of a triangle a zip split
    /// leaves one) welds by collapsing that side, its triangle going with it; the paper's
    /// sew still refuses it, and a side inside the cloth stays refused. Undo restores it.
    #[test]
    fn a_pair_on_one_border_side_welds_by_collapsing_it() {
        for model in [ModelKind::Xpbd, ModelKind::Vbd] {
            // 2 x 1 cells of 0.1 m: vertices 0-2 along one border, 3-5 along the other;
            // triangles (0 3 1), (1 3 4), (1 4 5), (1 5 2).
            let mesh = ClothMesh::grid(0.2, 0.1, 2, 1, 1.0).unwrap();
            let mut d = crate::design::floating(mesh, model);
            assert!(matches!(d.sew(0, 1), Err(EditError::SewNeighbours(0, 1))));
            assert!(matches!(
                d.weld_prims(1, 3),
                Err(EditError::SewNeighbours(1, 3))
            ));
            // The side 0-1 drawn in to 4 mm, within a weld's reach, and sewn by a seam.
            d.sim.cloth.x[1] = d.sim.cloth.x[0] + Vec3::X * 0.004;
            // (The seam's other pair, 3 with 2, stays 0.2 m apart.)
            assert_eq!(d.add_seam(&[0, 3], &[1, 2], 0.5).unwrap(), 2);
            let (tris, edits) = (d.sim.cloth.live.tri_count(), d.history.undo_len());
            assert_eq!(d.weld_close_stitches(), 1, "{model:?}");
            assert_eq!(d.seams[0].pairs, vec![(0, 0), (3, 2)]);
            let live = &d.sim.cloth.live;
            assert_eq!(live.tri_count(), tris - 1, "the side's triangle goes");
            assert!(!live.vertex_alive(1));
            assert_eq!(live.tris_of(0).len(), 3);
            d.validate().unwrap();
            d.step().unwrap();
            // The weld is undone with the seam that made it; redone with it.
            assert_eq!(d.undo().unwrap(), "seam");
            assert_eq!(d.history.undo_len(), edits - 1);
            assert_eq!(d.sim.cloth.live.tri_count(), tris);
            assert!(d.seams.is_empty());
            assert_eq!(d.redo().unwrap(), "seam");
            assert_eq!(d.history.undo_len(), edits + 1);
            assert_eq!(d.seams[0].pairs, vec![(0, 0), (3, 2)]);
            assert_eq!(d.sim.cloth.live.tri_count(), tris - 1);
        }
    }

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

    /// A sew across 32 cm leaves the sides around the joined vertex far past their rest
    /// length. The cloth takes that up without flying off: before the settling frames
    /// (`solver::xpbd::settle`), XPBD turned the stretch into speed: 25 m/s here, and
    /// pieces flew 20 m in the random-edits test. Weightless, so any speed is the sew's
    /// (now 0.002 m/s under xpbd; vbd's implicit steps pull the halves in at 1.2 m/s).
    #[test]
    fn a_sew_across_a_gap_pulls_the_cloth_in_without_flinging_it() {
        for model in [ModelKind::Xpbd, ModelKind::Vbd] {
            let (mesh, a, b) = across_a_gap(false);
            let mut d = crate::design::floating(mesh, model);
            d.sew(a, b).unwrap();
            let mut fastest = 0.0f32;
            for _ in 0..60 {
                d.step().unwrap();
                let v = d.sim.cloth.v.iter().map(|v| v.length()).fold(0.0, f32::max);
                fastest = fastest.max(v);
            }
            assert!(fastest < 2.0, "{model:?}: {fastest} m/s");
            // The stretch was taken up: the sides by the joined vertex began over 0.2 m;
            // now none is much past a diagonal's rest length (0.141 m).
            let c = &d.sim.cloth;
            let worst = c
                .live
                .iter()
                .flat_map(|(_, t)| t.edges().map(|(i, j, _)| (i, j)))
                .map(|(i, j)| (c.x[i as usize] - c.x[j as usize]).length())
                .fold(0.0f32, f32::max);
            assert!(worst < 0.16, "{model:?}: a side of {worst} m");
        }
    }
}
