//! Tearing: an edge torn by hand, and overstretched edges tearing by themselves after a
//! frame when tearing is on (the paper's tear deletes the two triangles beside the edge;
//! the split mode separates the material as NVIDIA Flex does).

use glam::Vec3;

use super::document::Design;
use super::error::EditError;
use super::parts::TearMode;
use super::prim::Prim;
use crate::solver::StretchFloor;

impl Design {
    /// Tears edge `(a, b)` by hand, in `mode`.
    pub fn tear_edge(&mut self, a: u32, b: u32, mode: TearMode) -> Result<(), EditError> {
        let prims = self.tear_prims(a, b, mode)?;
        self.commit("tear", prims)
    }

    fn tear_prims(&self, a: u32, b: u32, mode: TearMode) -> Result<Vec<Prim>, EditError> {
        self.check_vertex(a)?;
        self.check_vertex(b)?;
        let sides = self.sim.cloth.live.edge(a, b);
        if sides[0] == crate::mesh::NONE {
            return Err(EditError::NoEdge(a, b));
        }
        match mode {
            TearMode::Delete => Ok(sides
                .iter()
                .filter_map(|&s| {
                    self.sim.cloth.live.tri(s).map(|t| Prim::Tri {
                        slot: s,
                        old: Some(*t),
                        new: None,
                    })
                })
                .collect()),
            TearMode::Split => {
                let d = self.sim.cloth.x[b as usize] - self.sim.cloth.x[a as usize];
                self.split_prims(a, d).or_else(|_| self.split_prims(b, -d))
            }
        }
    }

    /// Where tearing may happen this frame: everywhere (`None`), within a distance of a
    /// point, or nowhere (tearing off, or a tear near the pinch with nothing pinched).
    fn tear_zone(&self) -> Option<Option<(Vec3, f32)>> {
        let s = self.tear;
        if !s.enabled || !self.sim.editable() {
            return None;
        }
        match s.near_pinch {
            None => Some(None),
            Some(r) => {
                let v = self.sim.pinch()?.vertex as usize;
                Some(Some((*self.sim.cloth.x.get(v)?, r)))
            }
        }
    }

    /// The strain limit's floor this frame: with tearing on, a side may stretch past the
    /// tear threshold where tearing may happen (a quarter beyond it: a side no longer
    /// than the limit never passes it; held under 1.2x, a cloth pulled by the pen
    /// followed it and never tore); elsewhere each triangle keeps its own limit.
    pub(super) fn tear_floor(&self) -> StretchFloor {
        match self.tear_zone() {
            None => StretchFloor::NONE,
            Some(within) => StretchFloor {
                ratio: 1.25 * self.tear.threshold,
                within,
            },
        }
    }

    /// Tears the most overstretched edges where tearing may happen (called after each
    /// frame when tearing is on). Returns how many tore.
    pub(super) fn tear_overstretched(&mut self) -> usize {
        let s = self.tear;
        let Some(zone) = self.tear_zone() else {
            return 0;
        };
        let x = &self.sim.cloth.x;
        let near = |a: u32, b: u32| {
            zone.is_none_or(|(c, r)| {
                [a, b]
                    .iter()
                    .any(|&i| x[i as usize].distance_squared(c) <= r * r)
            })
        };
        let mut over: Vec<(f32, u32, u32)> = Vec::new();
        for (_, t) in self.sim.cloth.live.iter() {
            for k in 0..3 {
                let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
                if !near(a, b) {
                    continue;
                }
                let rest = (t.rest[k] - t.rest[(k + 1) % 3]).length();
                let r = (x[a as usize] - x[b as usize]).length() / rest.max(1e-12);
                if r > s.threshold {
                    over.push((r, a.min(b), a.max(b)));
                }
            }
        }
        over.sort_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));
        over.dedup_by_key(|e| (e.1, e.2));
        let mut torn = 0;
        for (_, a, b) in over {
            if torn >= s.max_per_frame {
                break;
            }
            if self.tear_edge(a, b, s.mode).is_ok() {
                torn += 1;
            }
        }
        torn
    }
}
