//! Closing the slit a seam leaves where its two sides have different vertex counts.
//!
//! A seam pairs the longer side's vertices each with the nearest (by arc length) of the
//! shorter side's, so some vertex of the shorter side is paired twice. Once it has
//! welded to one partner, the other partner `p` lies on the border between the welded
//! vertex `q` and the next welded vertex `r`, and the three border edges `q-p`, `p-r`
//! (one piece's) and `q-r` (the other's) bound a triangular slit that no weld can close:
//! `p` and `q` are neighbours. Zipping puts `p` into the edge `q-r`: the triangle on
//! that edge is split in two at `p`, its new corner's rest place and texture coordinate
//! taken along the edge where `p` lies. No vertex is added or removed; the longer side
//! is eased into the shorter, as a tailor eases a sleeve cap into its armhole.

use super::document::Design;
use super::prim::{Between, Prim};
use crate::mesh::NONE;

/// Where along the edge `p` may sit: not at either end (a sliver triangle).
const END_MARGIN: f32 = 0.1;

impl Design {
    /// The edit that zips `p` into the slit beside its border neighbour `q` (see the
    /// module), or `None` when `p`, `q` do not bound such a slit, or `p` lies farther than
    /// `reach` from the edge across it.
    pub(super) fn zip_prims(&self, p: u32, q: u32, reach: f32) -> Option<Vec<Prim>> {
        let live = &self.sim.cloth.live;
        let border = |a: u32, b: u32| {
            let [s0, s1] = live.edge(a, b);
            (s0 != NONE && s1 == NONE).then_some(s0)
        };
        border(p, q)?;
        // `p`'s other border edge.
        let mut others = live
            .neighbours(p)
            .into_iter()
            .filter(|&u| u != q && border(p, u).is_some());
        let r = others.next()?;
        if others.next().is_some() {
            return None;
        }
        let slot = border(q, r)?;
        let tri = *live.tri(slot)?;
        if tri.corner(p).is_some() {
            return None;
        }
        // The triangle's third corner: split at `p`, it joins `p` to that corner, which
        // must not be `p`'s neighbour already (the edge would have three or four
        // triangles: a jumpsuit's zip refused so by the mesh's check, 2026-12-07).
        let far = tri.v.into_iter().find(|&c| c != q && c != r)?;
        if live.neighbours(p).contains(&far) {
            return None;
        }
        let x = &self.sim.cloth.x;
        let (xp, xq, xr) = (x[p as usize], x[q as usize], x[r as usize]);
        let qr = xr - xq;
        let t = (xp - xq).dot(qr) / qr.length_squared();
        if !(END_MARGIN..=1.0 - END_MARGIN).contains(&t) || (xp - (xq + qr * t)).length() > reach {
            return None;
        }
        // Where `p` goes along the edge: as far as its own side puts it between `q` and
        // `r` in the pattern, so the split triangle's new sides keep the proportions of
        // the sides they are sewn to. Taken from where `p` happened to lie, a zip near an
        // end made a side of 1.2 mm sewn to one of 8 mm (the dress's hem, 2.8x its rest
        // length at the end).
        let rest_len = |a: u32, b: u32| {
            let side = live.tri(border(a, b)?)?;
            Some((side.rest[side.corner(a)?] - side.rest[side.corner(b)?]).length())
        };
        let (pq, pr) = (rest_len(p, q)?, rest_len(p, r)?);
        let t = (pq / (pq + pr)).clamp(END_MARGIN, 1.0 - END_MARGIN);
        if !t.is_finite() {
            return None;
        }
        let on_edge = xq + qr * t;
        let mut prims = vec![Prim::MoveOnto {
            vertex: p,
            to: Between { a: q, b: r, s: t },
            back: xp - on_edge,
        }];
        prims.extend(super::slit::fan(
            slot,
            tri,
            q,
            r,
            &[(t, p)],
            live.slots() as u32,
        )?);
        Some(prims)
    }

    /// Zips every open pair of a seam whose ends are border neighbours bounding a slit
    /// (see the module) and lie within `reach` of closing; each zip is an undoable edit
    /// that marks the pair sewn. Returns how many.
    pub(super) fn zip_seam_slits(&mut self, reach: f32) -> usize {
        let mut zipped = 0;
        for si in 0..self.seams.len() {
            for k in 0..self.seams[si].pairs.len() {
                let (a, b) = self.seams[si].pairs[k];
                if a == b {
                    continue;
                }
                let found = [(a, b), (b, a)].into_iter().find_map(|(p, q)| {
                    let prims = self.zip_prims(p, q, reach)?;
                    (!self.edit_would_cross(&prims)).then_some((p, prims))
                });
                let Some((p, mut prims)) = found else {
                    continue;
                };
                // Undone, a zip opens where it stands, the vertex parted off the edge as a
                // cut's sides are: put back as far off as it lay, from where the edge is
                // once the garment has turned, it could go through the layers round the
                // seam (as a seam's welds did: docs/design-file.md).
                for prim in &mut prims {
                    if let Prim::MoveOnto { back, .. } = prim {
                        *back = back.normalize_or_zero() * super::cut::PART_M;
                    }
                }
                let old = self.seams[si].clone();
                let mut new = old.clone();
                new.pairs[k] = (p, p);
                prims.push(Prim::Seam {
                    index: si as u32,
                    old: Some(old),
                    new: Some(new),
                });
                if self.commit_auto("weld", prims).is_ok() {
                    zipped += 1;
                }
            }
        }
        zipped
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::design::Design;
    use crate::design::prim::Prim;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// Two 0.2 m strips meeting along z = 0, the far one 5 mm higher (within the weld's
    /// reach): the near one with 5 vertices on that edge, the far one with 3, sewn there
    /// (so the far side's middle vertex is paired twice). Returns the design and the
    /// near side's 5 vertices.
    fn uneven_seam(model: ModelKind) -> (Design, Vec<u32>) {
        let near = ClothMesh::grid(0.2, 0.1, 4, 2, 1.0).unwrap();
        let far = ClothMesh::grid(0.2, 0.1, 2, 2, 1.005).unwrap();
        let n0 = near.positions.len() as u32;
        let mut mesh = near.clone();
        for p in &mut mesh.positions {
            p.z -= 0.05;
        }
        mesh.positions
            .extend(far.positions.iter().map(|p| *p + Vec3::new(0.0, 0.0, 0.05)));
        mesh.uvs.extend(&far.uvs);
        mesh.triangles
            .extend(far.triangles.iter().map(|t| t.map(|i| i + n0)));
        let mut d = crate::design::floating(mesh, model);
        let a: Vec<u32> = (10..15).collect();
        let b: Vec<u32> = (n0..n0 + 3).collect();
        assert_eq!(d.add_seam(&a, &b, 0.5).unwrap(), 5);
        (d, a)
    }

    /// The near side's two vertices paired with an already welded far vertex are zipped
    /// into the far side's edges: every pair sewn, no border left along the seam, the
    /// cloth's rest area unchanged, the design valid and stepping; undo takes it all back.
    #[test]
    fn a_seam_with_fewer_vertices_on_one_side_closes() {
        for model in [ModelKind::Xpbd, ModelKind::Vbd] {
            let (mut d, a) = uneven_seam(model);
            let live = &d.sim.cloth.live;
            let (tris, edits) = (live.tri_count(), d.history.undo_len());
            let area =
                |d: &Design| -> f32 { d.sim.cloth.live.iter().map(|(_, t)| t.rest_area()).sum() };
            let area0 = area(&d);
            assert_eq!(d.weld_close_stitches(), 5, "{model:?}");
            assert!(
                d.seams[0].pairs.iter().all(|(p, q)| p == q),
                "{:?}",
                d.seams[0]
            );
            let live = &d.sim.cloth.live;
            assert_eq!(live.tri_count(), tris + 2, "one triangle split at each zip");
            for &v in &a[1..4] {
                assert!(
                    !live.is_boundary(v),
                    "{model:?}: vertex {v} still on a border"
                );
            }
            assert!((area(&d) - area0).abs() < 1e-6 * area0);
            d.validate().unwrap();
            for _ in 0..5 {
                d.step().unwrap();
            }
            // One undo takes back the seam with its five welds and zips.
            assert_eq!(d.undo().unwrap(), "seam");
            assert_eq!(d.history.undo_len(), edits - 1);
            assert_eq!(d.sim.cloth.live.tri_count(), tris);
            assert!(d.seams.is_empty());
            assert_eq!(d.history.redo_steps(), 1);
            d.validate().unwrap();
        }
    }

    /// A zip undone after the cloth has moved opens where the vertex stands, parted off
    /// the edge by a cut's parting (before 2026-11-28, where the zip had found it: with
    /// the whole cloth 0.3 m away since, 0.3 m off its triangles; until 2026-12-03, as far
    /// off the edge as it had lain, from where it stands); redone, onto the edge as it
    /// stands.
    #[test]
    fn a_zip_undone_or_redone_after_the_cloth_moved_stays_with_it() {
        let (mut d, a) = uneven_seam(ModelKind::Xpbd);
        let p = a[1] as usize;
        let before = d.sim.cloth.x.clone();
        d.weld_close_stitches();
        assert!(!d.sim.cloth.live.is_boundary(a[1]), "not zipped");
        let shift = Vec3::new(0.3, -0.1, 0.05);
        let moved = |d: &mut Design| d.sim.cloth.x.iter_mut().for_each(|x| *x += shift);
        moved(&mut d);
        let on_edge = d.sim.cloth.x[p];
        // Undo the seam with its welds and the zip, the cloth moved since: the vertex
        // leaves the edge by a parting, where it is (it lay 5 mm off it when zipped).
        while !d.sim.cloth.live.is_boundary(a[1]) {
            d.undo().unwrap();
        }
        let off = d.sim.cloth.x[p].distance(on_edge);
        assert!(
            off > 0.0 && off <= 1.01 * crate::design::cut::PART_M,
            "{off}"
        );
        // Not back where it lay, 5 mm off the edge.
        assert!(d.sim.cloth.x[p].distance(before[p] + shift) > 1e-3);
        moved(&mut d);
        while d.redo().is_ok() {}
        // (Within the 40 µm by which the undone welds' sides were parted, as a cut's.)
        let x = &d.sim.cloth.x;
        assert!(
            x[p].distance(on_edge + shift) < 2.0 * crate::design::cut::PART_M,
            "{} {}",
            x[p],
            on_edge + shift
        );
    }

    /// A zip or a weld that the mesh refuses changes nothing: its vertices stay where they
    /// were, at the speed they had. Its moves are recorded to be undone parted off the
    /// seam, and rolled back so, a refused zip left its vertex on the edge it was to go
    /// into, 40 µm off it, from a stitch's length away: a jumpsuit's zip that would have
    /// given an edge a third triangle left 2 crossing pairs (2026-12-07).
    #[test]
    fn a_zip_or_weld_the_mesh_refuses_moves_nothing() {
        use crate::design::prim::{Between, MergeAt};
        let (mut d, a) = uneven_seam(ModelKind::Xpbd);
        let far = d.seams[0].pairs[4].1;
        let (p, m) = (a[1], a[3]);
        d.sim.cloth.x[p as usize].y -= 0.005;
        for (k, v) in d.sim.cloth.v.iter_mut().enumerate() {
            *v = Vec3::new(0.01 * k as f32, -0.02, 0.03);
        }
        let (x0, v0) = (d.sim.cloth.x.clone(), d.sim.cloth.v.clone());
        let part = Vec3::Y * crate::design::cut::PART_M;
        let prims = vec![
            Prim::MoveOnto {
                vertex: p,
                to: Between {
                    a: a[0],
                    b: a[2],
                    s: 0.5,
                },
                back: part,
            },
            Prim::Merge {
                a: m,
                b: far,
                at: MergeAt::Middle,
                apart: [Vec3::ZERO; 2],
            },
            // Stale: slot 0 holds a triangle.
            Prim::Tri {
                slot: 0,
                old: None,
                new: None,
            },
        ];
        let edits = d.history.undo_len();
        assert!(d.commit_auto("weld", prims).is_err());
        assert_eq!(d.history.undo_len(), edits);
        for (k, (x, v)) in d.sim.cloth.x.iter().zip(&d.sim.cloth.v).enumerate() {
            assert_eq!((*x, *v), (x0[k], v0[k]), "vertex {k}");
        }
    }

    /// A vertex farther than the reach from the edge across the slit waits.
    #[test]
    fn a_slit_wider_than_the_reach_waits() {
        let (mut d, a) = uneven_seam(ModelKind::Xpbd);
        d.sim.cloth.x[a[1] as usize].y -= 0.01;
        assert_eq!(d.weld_close_stitches(), 4);
        assert_eq!(d.seams[0].pairs.iter().filter(|(p, q)| p != q).count(), 1);
        assert!(d.sim.cloth.live.is_boundary(a[1]));
    }

    /// A vertex is zipped in where its own side puts it in the pattern (halfway between
    /// its welded neighbours here), not where it happens to lie: moved 3 cm toward one
    /// end, it made the split triangle's side 2 cm long at rest, sewn to a side of 5.
    #[test]
    fn a_zip_keeps_the_proportions_of_the_side_it_eases_in() {
        let (mut d, a) = uneven_seam(ModelKind::Xpbd);
        d.sim.cloth.x[a[1] as usize].x -= 0.03;
        d.weld_close_stitches();
        assert!(!d.sim.cloth.live.is_boundary(a[1]), "not zipped");
        let q = d.seams[0].pairs[0].0;
        let live = &d.sim.cloth.live;
        let sides: Vec<f32> = live
            .tris_of(a[1])
            .iter()
            .filter_map(|&t| live.tri(t))
            .filter_map(|t| Some((t.rest[t.corner(a[1])?] - t.rest[t.corner(q)?]).length()))
            .collect();
        assert!(sides.len() >= 2, "{sides:?}");
        assert!(
            sides.iter().all(|&l| (l - 0.05).abs() < 1e-4),
            "rest lengths of the side to the welded end: {sides:?}"
        );
    }
}
