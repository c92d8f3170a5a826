//! Seams: two border paths paired vertex to vertex and pulled together by stitches of
//! bounded force, each pair welded (sewn) once closer than the cloth's thickness.

use super::document::Design;

/// Sides of a seam whose pattern lengths differ by more than this share of the longer
/// are worth a warning (not a refusal: easing a longer side in is a tailor's choice).
pub const SEAM_MISMATCH: f32 = 0.2;
use super::error::EditError;
use super::parts::Seam;
use super::prim::Prim;

impl Design {
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
            if !self.sim.cloth.live.is_boundary(v) {
                return Err(EditError::SewInterior(v));
            }
        }
        for w in path.windows(2) {
            let sides = self.sim.cloth.live.edge(w[0], w[1]);
            if sides[0] == crate::mesh::NONE || sides[1] != crate::mesh::NONE {
                return Err(EditError::NotBorderEdge(w[0], w[1]));
            }
        }
        Ok(())
    }

    /// The length of a vertex path in the pattern (the rest length of each of its edges,
    /// as the triangle holding the edge has it; the present distance where no triangle
    /// holds both ends), m. Two sides to be sewn should match: a designer is told when
    /// they differ by more than [`SEAM_MISMATCH`].
    pub fn pattern_length(&self, path: &[u32]) -> f32 {
        let live = &self.sim.cloth.live;
        path.windows(2)
            .map(|w| {
                live.tris_of(w[0])
                    .iter()
                    .filter_map(|&t| live.tri(t))
                    .find_map(|t| {
                        let (i, j) = (t.corner(w[0])?, t.corner(w[1])?);
                        Some((t.rest[i] - t.rest[j]).length())
                    })
                    .unwrap_or_else(|| {
                        let x = &self.sim.cloth.x;
                        match (x.get(w[0] as usize), x.get(w[1] as usize)) {
                            (Some(a), Some(b)) => (*a - *b).length(),
                            _ => 0.0,
                        }
                    })
            })
            .sum()
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
                let d =
                    (self.sim.cloth.x[w[1] as usize] - self.sim.cloth.x[w[0] as usize]).length();
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
        let seam = Seam {
            pairs,
            max_force,
            name: String::new(),
        };
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

    /// Names seam `index` (`name` trimmed; empty: it goes by its letter again). Undoable.
    /// A name longer than [`MAX_NAME`](super::MAX_NAME) characters is refused.
    pub fn name_seam(&mut self, index: usize, name: &str) -> Result<(), EditError> {
        let count = self.seams.len();
        let Some(old) = self.seams.get(index).cloned() else {
            return Err(EditError::NoSeam { index, count });
        };
        let name = name.trim();
        if name.chars().count() > super::MAX_NAME || name.chars().any(char::is_control) {
            return Err(EditError::BadValue {
                name: "seam name",
                rule: "at most 120 characters, none of them control characters",
                value: format!("{} characters", name.chars().count()),
            });
        }
        if old.name == name {
            return Ok(());
        }
        let new = Seam {
            name: name.to_string(),
            ..old.clone()
        };
        self.commit(
            "name seam",
            vec![Prim::Seam {
                index: index as u32,
                old: Some(old),
                new: Some(new),
            }],
        )
    }

    /// Removes seam `index` (its open stitches stop pulling; pairs already welded stay
    /// sewn, each weld being its own edit). Undoable. Returns how many pairs it had.
    pub fn remove_seam(&mut self, index: usize) -> Result<usize, EditError> {
        let count = self.seams.len();
        let Some(old) = self.seams.get(index).cloned() else {
            return Err(EditError::NoSeam { index, count });
        };
        let n = old.pairs.len();
        self.commit(
            "remove seam",
            vec![Prim::Seam {
                index: index as u32,
                old: Some(old),
                new: None,
            }],
        )?;
        Ok(n)
    }

    /// Each seam's two sides' pattern lengths (the A side's vertices, then the B side's,
    /// each in order without repeats), m.
    pub fn seam_lengths(&self, seam: &Seam) -> (f32, f32) {
        let side = |pick: fn(&(u32, u32)) -> u32| {
            let mut path: Vec<u32> = seam.pairs.iter().map(pick).collect();
            path.dedup();
            self.pattern_length(&path)
        };
        (side(|p| p.0), side(|p| p.1))
    }

    /// Welds stitched pairs that came within 1.5 x the cloth's thickness (after a frame);
    /// each weld is an undoable sew. Returns how many welded. (Not within the thickness:
    /// under penetration-free contact two pieces' edges meet at the contact distance,
    /// which is the thickness, and would never weld.)
    pub(super) fn weld_close_stitches(&mut self) -> usize {
        let reach = 1.5 * self.sim.material.thickness;
        let mut welded = 0;

        for si in 0..self.seams.len() {
            let mut k = 0;
            while k < self.seams[si].pairs.len() {
                let (a, b) = self.seams[si].pairs[k];
                k += 1;
                if a == b
                    || (self.sim.cloth.x[a as usize] - self.sim.cloth.x[b as usize]).length()
                        > reach
                {
                    continue;
                }
                let Ok(mut prims) = self.sew_prims(a, b) else {
                    continue;
                };
                if self.edit_would_cross(&prims) {
                    continue;
                }
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
        welded + self.zip_seam_slits(reach)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::collision::Body;
    use crate::design::Design;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// A 0.5 m cloth at y = 1 cut in two along x, the far half raised 5 mm (within the
    /// weld's reach of 6 mm), a seam joining the cut's two sides.
    fn cut_and_sewn() -> Design {
        let n = 8;
        let mesh = ClothMesh::grid(0.5, 0.5, n, n, 1.0).unwrap();
        let mut d = crate::design::floating(mesh, ModelKind::Xpbd);
        let z = 0.0021;
        d.cut_stroke(&[Vec3::new(-0.3, 1.0, z), Vec3::new(0.3, 1.0, z)], 0.015)
            .unwrap();
        let row = (n / 2 * (n + 1)) as u32;
        let a: Vec<u32> = (row..row + n as u32 + 1).collect();
        let x = d.sim.cloth.x.clone();
        let b: Vec<u32> = a
            .iter()
            .map(|&v| {
                (0..x.len() as u32)
                    .rev()
                    .find(|&u| u != v && x[u as usize] == x[v as usize])
                    .unwrap()
            })
            .collect();
        for i in 0..x.len() {
            if x[i].z > 0.0 || b.contains(&(i as u32)) {
                d.sim.cloth.x[i].y += 0.005;
            }
        }
        d.add_seam(&a, &b, 0.05).unwrap();
        d
    }

    /// A closed box, outward wound, from `lo` to `hi`.
    fn plate(lo: Vec3, hi: Vec3) -> Body {
        let v: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { lo.x } else { hi.x },
                    if i & 2 == 0 { lo.y } else { hi.y },
                    if i & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        Body::new("plate", v, t, None).unwrap()
    }

    /// A weld moves its vertices by up to 4.5 mm outside the contact guard: one that
    /// would leave the cloth through something waits.
    #[test]
    fn a_weld_that_would_cross_the_body_waits() {
        let mut open = cut_and_sewn();
        let pairs = open.seams[0].pairs.len();
        assert_eq!(
            open.weld_close_stitches(),
            pairs,
            "with nothing between, all weld"
        );

        let mut blocked = cut_and_sewn();
        // A 2 mm plate between the two sides, where the welded vertices would meet.
        blocked.sim.body = Some(plate(
            Vec3::new(-0.4, 1.0015, -0.05),
            Vec3::new(0.4, 1.0035, 0.05),
        ));
        let before = blocked.sim.cloth.x.clone();
        assert_eq!(blocked.weld_close_stitches(), 0);
        assert_eq!(blocked.sim.cloth.x, before, "nothing moved");
        assert!(blocked.seams[0].pairs.iter().all(|(p, q)| p != q));
    }
}
