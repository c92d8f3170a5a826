//! The paper's sew: two border vertices merged into one, halfway between them.

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;

impl Design {
    /// The paper's sew: merges border vertices `a` and `b` into `a`, placed halfway.
    pub fn sew(&mut self, a: u32, b: u32) -> Result<(), EditError> {
        let prims = self.sew_prims(a, b)?;
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
