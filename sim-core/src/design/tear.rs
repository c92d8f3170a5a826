//! Tearing: an edge torn by hand, and overstretched edges tearing by themselves after a
//! frame when tearing is on (the paper's tear deletes the two triangles beside the edge;
//! the split mode separates the material as NVIDIA Flex does).

use super::document::Design;
use super::error::EditError;
use super::parts::TearMode;
use super::prim::Prim;

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

    /// Tears the most overstretched edges (called after each frame when tearing is on).
    /// Returns how many tore.
    pub(super) fn tear_overstretched(&mut self) -> usize {
        let s = self.tear;
        if !s.enabled || !self.sim.editable() {
            return 0;
        }
        let x = &self.sim.cloth.x;
        let mut over: Vec<(f32, u32, u32)> = Vec::new();
        for (_, t) in self.sim.cloth.live.iter() {
            for k in 0..3 {
                let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
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
