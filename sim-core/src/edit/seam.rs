//! Seams: two border paths paired vertex to vertex and pulled together by stitches of
//! bounded force, each pair welded (sewn) once closer than the cloth's thickness.

use glam::Vec3;

use super::{EditError, Prim};
use crate::cloth::Simulation;
use crate::cloth::sim::Solver;

#[derive(Clone, Debug, PartialEq)]
pub struct Seam {
    /// Stitched vertex pairs (`a == b` once welded).
    pub pairs: Vec<(u32, u32)>,
    /// Largest force one stitch pulls with, N.
    pub max_force: f32,
}

impl Seam {
    pub fn open_pairs(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.pairs.iter().copied().filter(|(a, b)| a != b)
    }
}

/// Default stitch force, N: enough to pull cotton flaps together against gravity and
/// friction, small next to what tears it.
pub const STITCH_FORCE: f32 = 0.05;

impl Simulation {
    /// Checks that `path` is a chain of border vertices joined by border edges.
    fn check_border_path(&self, path: &[u32]) -> Result<(), EditError> {
        if path.len() < 2 {
            return Err(EditError::BadValue {
                name: "seam path",
                rule: "at least 2 vertices",
                value: path.len().to_string(),
            });
        }
        for &v in path {
            self.check_vertex(v)?;
            if !self.cloth.live.is_boundary(v) {
                return Err(EditError::SewInterior(v));
            }
        }
        for w in path.windows(2) {
            let sides = self.cloth.live.edge(w[0], w[1]);
            if sides[0] == crate::mesh::live::NONE || sides[1] != crate::mesh::live::NONE {
                return Err(EditError::NotBorderEdge(w[0], w[1]));
            }
        }
        Ok(())
    }

    /// Adds a seam between border paths `a` and `b` (vertex chains along the border, in
    /// matching directions). The longer path sets the pair count; the other is resampled
    /// by arc length. Undoable.
    pub fn add_seam(&mut self, a: &[u32], b: &[u32], max_force: f32) -> Result<usize, EditError> {
        self.check_editable()?;
        self.check_border_path(a)?;
        self.check_border_path(b)?;
        if let Some(v) = a.iter().find(|v| b.contains(v)) {
            return Err(EditError::SeamOverlap(*v));
        }
        if !(max_force.is_finite() && max_force > 0.0) {
            return Err(EditError::BadValue {
                name: "stitch force",
                rule: "a positive number of newtons",
                value: max_force.to_string(),
            });
        }
        let params = |p: &[u32]| -> Vec<f32> {
            let mut s = vec![0.0f32];
            for w in p.windows(2) {
                let d = (self.cloth.x[w[1] as usize] - self.cloth.x[w[0] as usize]).length();
                s.push(s.last().copied().unwrap_or(0.0) + d);
            }
            let total = s.last().copied().unwrap_or(0.0).max(1e-12);
            s.iter().map(|t| t / total).collect()
        };
        let (ta, tb) = (params(a), params(b));
        let nearest = |ts: &[f32], t: f32| -> usize {
            ts.iter()
                .enumerate()
                .min_by(|x, y| (x.1 - t).abs().total_cmp(&(y.1 - t).abs()))
                .map_or(0, |(i, _)| i)
        };
        let pairs: Vec<(u32, u32)> = if a.len() >= b.len() {
            ta.iter()
                .enumerate()
                .map(|(i, &t)| (a[i], b[nearest(&tb, t)]))
                .collect()
        } else {
            tb.iter()
                .enumerate()
                .map(|(j, &t)| (a[nearest(&ta, t)], b[j]))
                .collect()
        };
        let seam = Seam { pairs, max_force };
        let count = seam.pairs.len();
        let index = self.seams.len() as u32;
        self.commit(
            "seam",
            vec![Prim::Seam {
                index,
                old: None,
                new: Some(seam),
            }],
        )?;
        Ok(count)
    }

    /// Hands the open stitches to the solver (before a frame).
    pub(crate) fn load_stitches(&mut self) {
        if let Solver::Xpbd(s) = &mut self.solver {
            s.stitches.clear();
            for seam in &self.seams {
                s.stitches
                    .extend(seam.open_pairs().map(|(a, b)| (a, b, seam.max_force)));
            }
        }
    }

    /// Welds stitched pairs that came within the cloth's thickness (after a frame); each
    /// weld is an undoable sew. Returns how many welded.
    pub(crate) fn weld_close_stitches(&mut self) -> usize {
        let reach = self.material.thickness;
        let mut welded = 0;
        for si in 0..self.seams.len() {
            let mut k = 0;
            while k < self.seams[si].pairs.len() {
                let (a, b) = self.seams[si].pairs[k];
                k += 1;
                if a == b || (self.cloth.x[a as usize] - self.cloth.x[b as usize]).length() > reach
                {
                    continue;
                }
                let Ok(mut prims) = self.sew_prims(a, b) else {
                    continue;
                };
                // Every seam now refers to `a` where it referred to `b`.
                for (sj, seam) in self.seams.iter().enumerate() {
                    if seam.pairs.iter().any(|&(p, q)| p == b || q == b) {
                        let mut new = seam.clone();
                        for pq in &mut new.pairs {
                            *pq = (
                                if pq.0 == b { a } else { pq.0 },
                                if pq.1 == b { a } else { pq.1 },
                            );
                        }
                        prims.push(Prim::Seam {
                            index: sj as u32,
                            old: Some(seam.clone()),
                            new: Some(new),
                        });
                    }
                }
                if self.commit("weld", prims).is_ok() {
                    welded += 1;
                }
            }
        }
        welded
    }

    /// Applies a seam primitive (`index == len` appends, `new == None` at the end pops).
    pub(crate) fn set_seam(
        &mut self,
        index: u32,
        old: &Option<Seam>,
        new: &Option<Seam>,
    ) -> Result<(), EditError> {
        let i = index as usize;
        if self.seams.get(i) != old.as_ref() {
            return Err(EditError::StaleSeam(index));
        }
        if let Some(s) = new
            && s.pairs
                .iter()
                .any(|&(a, b)| a as usize >= self.cloth.len() || b as usize >= self.cloth.len())
        {
            return Err(EditError::StaleSeam(index));
        }
        match (old, new) {
            (None, Some(s)) if i == self.seams.len() => self.seams.push(s.clone()),
            (Some(_), None) if i + 1 == self.seams.len() => {
                self.seams.pop();
            }
            (Some(_), Some(s)) => self.seams[i] = s.clone(),
            _ => return Err(EditError::StaleSeam(index)),
        }
        Ok(())
    }
}

/// A stitch step for the solver: pulls `a` and `b` together as a zero-length XPBD spring
/// of stiffness `k`, the correction bounded so the force stays under `max_force`.
pub(crate) fn stitch(
    x: &mut [Vec3],
    w: &[f32],
    (a, b, max_force): (u32, u32, f32),
    inv_h2: f32,
    k: f32,
) {
    let (a, b) = (a as usize, b as usize);
    let (Some(&wa), Some(&wb)) = (w.get(a), w.get(b)) else {
        return;
    };
    if wa + wb == 0.0 || b >= x.len() {
        return;
    }
    let d = x[b] - x[a];
    let len = d.length();
    if len < 1e-9 {
        return;
    }
    let alpha = inv_h2 / k;
    // XPBD: delta lambda in position units; force = lambda / h^2.
    let dl = (len / (wa + wb + alpha)).min(max_force / inv_h2);
    let n = d / len;
    x[a] += n * (wa * dl);
    x[b] -= n * (wb * dl);
}
