//! Closing a slit between two welded pairs of a seam whose two sides put their vertices
//! at different places along it.
//!
//! A seam's pairs join its sides' vertices in order, one to one where the sides have as
//! many, by their shares of each side's length. Where a side's vertices are spaced
//! unevenly (a cut through a mesh crosses its edges where they lie), a pair can join a
//! vertex near one end of its stretch to one near the other: on a dart 1.5 cm edges, a
//! vertex 4 mm past the welded pair before it, paired with one 12 mm past it. Once the
//! pairs either side have welded, the two sides bound a slit that no weld closes: merged
//! anywhere, the vertex stretches the short side beside it to twice its rest length
//! or more, past [`ZIP_STRAIN`], and the pair waited for good (5 of 27 swept darts kept
//! 1-3 such pairs open, 7-15 mm apart).
//!
//! Closed as a zip closes a slit of one vertex (`zip.rs`), generalised: every vertex of
//! each side between the two welded ones goes into the other side's edge at its own
//! share of the stretch, that edge's triangle split into a fan, the new corners' rest
//! places and texture coordinates taken along the edge. One side's vertices move onto
//! the other side's edges; the sides' lengths and proportions are kept, no vertex is
//! added or removed, and the rest area is unchanged. The slit's pairs become one sewn
//! pair for each of its vertices, so that both sides stay marked as the seam in the
//! pattern out.
//!
//! A side may have no vertex between the welded ones (a vertex of the other paired
//! twice): that is `zip.rs`'s slit, which it closes within a weld's reach; here the
//! other side's vertices move onto its edge from as far as a zip's reach, once the seam
//! has stalled (a 3 cm dart's pair waited 21.6 mm from the edge).

use super::document::Design;
use super::prim::{Between, Prim};
use super::seam::ZIP_STRAIN;
use crate::mesh::{NONE, Tri};

/// The most open pairs between two welded ones that close as one slit.
const SLIT_PAIRS: usize = 4;

/// How near (a share of the edge) a vertex may go in to either end of the edge it goes
/// into, or to another vertex going into it: no sliver triangles.
const MARGIN: f32 = 0.1;

/// One side of a slit: its vertices from one welded end to the other, and each one's
/// share of the side's length in the pattern.
struct Side {
    path: Vec<u32>,
    share: Vec<f32>,
}

impl Design {
    /// Closes one slit of seam `si` (see the module): the first run of at most
    /// [`SLIT_PAIRS`] open pairs between two welded ones that can be closed, its
    /// vertices no farther than `reach` from where they go, the edit crossing nothing and
    /// stretching no edge past [`ZIP_STRAIN`]. An undoable edit. Whether one closed.
    pub(super) fn zip_seam_slit(&mut self, si: usize, reach: f32) -> bool {
        let pairs = self.seams[si].pairs.clone();
        let shut = |k: usize| pairs[k].0 == pairs[k].1;
        let mut k = 0;
        while k < pairs.len() {
            if !shut(k) {
                k += 1;
                continue;
            }
            let Some(j) = (k + 1..pairs.len()).find(|&j| shut(j)) else {
                break;
            };
            if (2..=SLIT_PAIRS + 1).contains(&(j - k))
                && let Some(prims) = self.slit_prims(si, k, j, reach)
                && self.commit_auto("weld", prims).is_ok()
            {
                return true;
            }
            k = j;
        }
        false
    }

    /// The edit closing the slit between welded pairs `k` and `j` of seam `si`, or
    /// `None` where it is no such slit or cannot be closed (see
    /// [`Design::zip_seam_slit`]).
    fn slit_prims(&self, si: usize, k: usize, j: usize, reach: f32) -> Option<Vec<Prim>> {
        let pairs = &self.seams[si].pairs;
        let (w0, w1) = (pairs[k].0, pairs[j].0);
        let side = |pick: fn(&(u32, u32)) -> u32| -> Option<Side> {
            let mut path = vec![w0];
            for p in &pairs[k + 1..j] {
                let v = pick(p);
                if path.last() != Some(&v) {
                    path.push(v);
                }
            }
            path.push(w1);
            self.slit_side(path)
        };
        let (a, b) = (side(|p| p.0)?, side(|p| p.1)?);
        if a.path.len() + b.path.len() < 5 {
            // No vertex between the ends on either side: nothing to close.
            return None;
        }
        if a.path[1..a.path.len() - 1]
            .iter()
            .any(|v| b.path.contains(v))
        {
            return None;
        }
        // One side's vertices onto the other's edges; the other way if that will not do.
        let seam = self.slit_seam(si, k, j, &a, &b);
        // (A side with none between its ends cannot move: its one edge does not lie
        // along the other side, whose vertices go into it.)
        let moves = [(&a, &b), (&b, &a)]
            .into_iter()
            .filter(|(m, _)| m.path.len() > 2);
        moves.into_iter().find_map(|(mover, stay)| {
            let mut prims = self.slit_moves(mover, stay, reach)?;
            // New triangles take the slots after the last, the second side's after the
            // first's.
            let first = self.sim.cloth.live.slots() as u32;
            let splits = self.slit_splits(mover, stay, first)?;
            let added = splits
                .iter()
                .filter(|p| matches!(p, Prim::Tri { old: None, .. }));
            let then = first + added.count() as u32;
            prims.extend(splits);
            prims.extend(self.slit_splits(stay, mover, then)?);
            let ok = self.stretch_after(&prims) <= ZIP_STRAIN && !self.edit_would_cross(&prims);
            ok.then(|| {
                // Undone, the slit opens where it stands, each moved vertex parted off its
                // edge as a cut's sides are (as a zip's).
                for p in &mut prims {
                    if let Prim::MoveOnto { back, .. } = p {
                        *back = back.normalize_or_zero() * super::cut::PART_M;
                    }
                }
                prims.push(seam.clone());
                prims
            })
        })
    }

    /// `path` as a slit's side: from one welded end to another, each vertex a border
    /// vertex, each step a border edge.
    fn slit_side(&self, path: Vec<u32>) -> Option<Side> {
        let live = &self.sim.cloth.live;
        if path.len() < 2 || path[0] == path[path.len() - 1] {
            return None;
        }
        let border = |w: &[u32]| {
            let [s0, s1] = live.edge(w[0], w[1]);
            s0 != NONE && s1 == NONE
        };
        if !path.windows(2).all(border) || !path.iter().all(|&v| live.is_boundary(v)) {
            return None;
        }
        let mut share = vec![0.0f32];
        for w in path.windows(2) {
            share.push(share[share.len() - 1] + self.pattern_edge(w[0], w[1]));
        }
        let total = share[share.len() - 1];
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        share.iter_mut().for_each(|s| *s /= total);
        Some(Side { path, share })
    }

    /// Each vertex of `mover` between its ends moved onto the edge of `stay` at its
    /// share; `None` if one lies farther than `reach` from there.
    fn slit_moves(&self, mover: &Side, stay: &Side, reach: f32) -> Option<Vec<Prim>> {
        let x = &self.sim.cloth.x;
        let mut prims = Vec::new();
        for (i, &v) in mover
            .path
            .iter()
            .enumerate()
            .take(mover.path.len() - 1)
            .skip(1)
        {
            let (e, t) = on_edge(&stay.share, mover.share[i])?;
            let (a, b) = (stay.path[e], stay.path[e + 1]);
            let to = x[a as usize].lerp(x[b as usize], t);
            if x[v as usize].distance(to) > reach {
                return None;
            }
            prims.push(Prim::MoveOnto {
                vertex: v,
                to: Between { a, b, s: t },
                back: x[v as usize] - to,
            });
        }
        Some(prims)
    }

    /// The triangles on `side`'s edges split into fans at the other side's vertices
    /// (`into`), each at its share. `None` where a vertex would go in too near an end of
    /// its edge or another vertex (a sliver). New triangles take slots from `next_slot`.
    fn slit_splits(&self, side: &Side, into: &Side, mut next_slot: u32) -> Option<Vec<Prim>> {
        let live = &self.sim.cloth.live;
        let mut prims = Vec::new();
        for e in 0..side.path.len() - 1 {
            let (u, v) = (side.path[e], side.path[e + 1]);
            let mut ins: Vec<(f32, u32)> = Vec::new();
            for i in 1..into.path.len() - 1 {
                // (At a vertex's own share it goes in nowhere: no slit of that kind.)
                let (f, t) = on_edge(&side.share, into.share[i])?;
                if f == e {
                    ins.push((t, into.path[i]));
                }
            }
            if ins.is_empty() {
                continue;
            }
            let ts: Vec<f32> = std::iter::once(0.0)
                .chain(ins.iter().map(|p| p.0))
                .chain(std::iter::once(1.0))
                .collect();
            if ts.windows(2).any(|w| w[1] - w[0] < MARGIN) {
                return None;
            }
            let slot = live.edge(u, v)[0];
            let split = fan(slot, *live.tri(slot)?, u, v, &ins, next_slot)?;
            next_slot += ins.len() as u32;
            prims.extend(split);
        }
        Some(prims)
    }

    /// The seam with the slit's open pairs, `k + 1 .. j`, replaced by one sewn pair for
    /// each vertex of either side between its ends, in order along the seam.
    fn slit_seam(&self, si: usize, k: usize, j: usize, a: &Side, b: &Side) -> Prim {
        let old = self.seams[si].clone();
        let mut inner: Vec<(f32, u32)> = [a, b]
            .iter()
            .flat_map(|s| (1..s.path.len() - 1).map(|i| (s.share[i], s.path[i])))
            .collect();
        inner.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut new = old.clone();
        new.pairs = (old.pairs[..=k].iter().copied())
            .chain(inner.iter().map(|&(_, v)| (v, v)))
            .chain(old.pairs[j..].iter().copied())
            .collect();
        Prim::Seam {
            index: si as u32,
            old: Some(old),
            new: Some(new),
        }
    }
}

/// Triangle `tri` in `slot` split into a fan at the vertices `ins` (each with its share
/// of the way from `u` to `v`, in order) on its side `u`-`v`: each piece the triangle with
/// its `u` corner moved to the piece's first end and its `v` corner to its last, the new
/// corners' rest places and texture coordinates taken along the side. The first piece
/// keeps `slot`; the others take slots from `next_slot` on. `None` if `tri` has no such
/// side.
pub(super) fn fan(
    slot: u32,
    tri: Tri,
    u: u32,
    v: u32,
    ins: &[(f32, u32)],
    next_slot: u32,
) -> Option<Vec<Prim>> {
    let (cu, cv) = (tri.corner(u)?, tri.corner(v)?);
    let at = |t: f32| {
        (
            tri.rest[cu].lerp(tri.rest[cv], t),
            tri.uv[cu].lerp(tri.uv[cv], t),
        )
    };
    let ends: Vec<(f32, u32)> = std::iter::once((0.0, u))
        .chain(ins.iter().copied())
        .chain(std::iter::once((1.0, v)))
        .collect();
    let pieces = ends.windows(2).enumerate().map(|(m, w)| {
        let mut piece = tri;
        if m > 0 {
            let (r, uv) = at(w[0].0);
            piece = piece.with_corner(cu, w[0].1, r, uv);
        }
        if m + 2 < ends.len() {
            let (r, uv) = at(w[1].0);
            piece = piece.with_corner(cv, w[1].1, r, uv);
        }
        let (slot, old) = match m {
            0 => (slot, Some(tri)),
            _ => (next_slot + m as u32 - 1, None),
        };
        Prim::Tri {
            slot,
            old,
            new: Some(piece),
        }
    });
    Some(pieces.collect())
}

/// The edge of a side (by its vertices' `shares`) that `s` falls on, and where along
/// it; `None` at a vertex's own share or outside the side.
fn on_edge(shares: &[f32], s: f32) -> Option<(usize, f32)> {
    let e = shares.windows(2).position(|w| w[0] < s && s < w[1])?;
    Some((e, (s - shares[e]) / (shares[e + 1] - shares[e])))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::seam::ZIP_AFTER;
    use crate::design::Design;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// Two 0.1 x 0.05 m strips meeting along z = 0, the far one 5 mm higher (within the
    /// weld's reach), each with three vertices on that edge, sewn there one to one: the
    /// near side's middle vertex 10 mm from its first end, the far side's 10 mm from its
    /// last. Returns the design and the two middle vertices.
    fn skewed_seam(model: ModelKind) -> (Design, [u32; 2]) {
        let strip = |y: f32, dz: f32, mid_x: f32| {
            let mut m = ClothMesh::grid(0.1, 0.05, 2, 1, y).unwrap();
            for (i, p) in m.positions.iter_mut().enumerate() {
                p.z += dz;
                if i % 3 == 1 {
                    p.x = mid_x;
                }
            }
            m
        };
        let near = strip(1.0, -0.025, -0.04);
        let far = strip(1.005, 0.025, 0.04);
        let n0 = near.positions.len() as u32;
        let mut mesh = near;
        mesh.positions.extend(&far.positions);
        mesh.uvs.extend(&far.uvs);
        mesh.triangles
            .extend(far.triangles.iter().map(|t| t.map(|i| i + n0)));
        let mut d = crate::design::floating(mesh, model);
        assert_eq!(
            d.add_seam(&[3, 4, 5], &[n0, n0 + 1, n0 + 2], 0.5).unwrap(),
            3
        );
        (d, [4, n0 + 1])
    }

    /// The seam's ends weld; its middle pair, merged anywhere, would stretch a 10 mm side
    /// to several times its length, and waited for good. Closed as a slit: each middle
    /// vertex in the other side's edge at its own share, every pair sewn (one for each
    /// vertex), no border left along the seam, the rest area unchanged, the design valid
    /// and stepping; one undo takes the seam back with it.
    #[test]
    fn a_pair_that_no_weld_can_close_between_welded_ones_closes_as_a_slit() {
        for model in [ModelKind::Xpbd, ModelKind::Vbd] {
            let (mut d, mids) = skewed_seam(model);
            let live = &d.sim.cloth.live;
            let (tris, edits) = (live.tri_count(), d.history.undo_len());
            let area =
                |d: &Design| -> f32 { d.sim.cloth.live.iter().map(|(_, t)| t.rest_area()).sum() };
            let area0 = area(&d);
            assert_eq!(d.weld_close_stitches(), 2, "{model:?}: the ends");
            let mut welded = 0;
            for _ in 0..2 * ZIP_AFTER {
                welded += d.weld_close_stitches();
            }
            assert_eq!(welded, 1, "{model:?}: the slit, once");
            let pairs = &d.seams[0].pairs;
            assert_eq!(pairs.len(), 4, "{pairs:?}");
            assert!(pairs.iter().all(|(p, q)| p == q), "{pairs:?}");
            assert_eq!((pairs[1].0, pairs[2].0), (mids[0], mids[1]), "in order");
            let live = &d.sim.cloth.live;
            assert_eq!(live.tri_count(), tris + 2, "a triangle split on each side");
            for v in mids {
                assert!(!live.is_boundary(v), "{model:?}: vertex {v} on a border");
            }
            assert!((area(&d) - area0).abs() < 1e-6 * area0);
            // The near side's middle vertex went into the far side's edge, 1/9 along it
            // from the welded end: 10 mm of its 90.
            let x = &d.sim.cloth.x;
            let (end, far_mid) = (x[d.seams[0].pairs[0].0 as usize], x[mids[1] as usize]);
            let on = end.lerp(far_mid, 1.0 / 9.0);
            assert!(x[mids[0] as usize].distance(on) < 1e-5, "{model:?}");
            d.validate().unwrap();
            for _ in 0..5 {
                d.step().unwrap();
            }
            assert!(d.sim.cloth.x.iter().all(|p| p.is_finite()));
            assert_eq!(d.undo().unwrap(), "seam");
            assert_eq!(d.history.undo_len(), edits - 1);
            assert_eq!(d.sim.cloth.live.tri_count(), tris);
            assert!(d.seams.is_empty());
            d.validate().unwrap();
        }
    }

    /// A slit whose vertices lie farther than the reach from where they would go waits.
    #[test]
    fn a_slit_wider_than_the_reach_waits() {
        let (mut d, mids) = skewed_seam(ModelKind::Xpbd);
        d.weld_close_stitches();
        d.sim.cloth.x[mids[0] as usize] += Vec3::new(0.0, 0.5, 0.0);
        d.sim.cloth.x[mids[1] as usize] += Vec3::new(0.0, -0.5, 0.0);
        for _ in 0..2 * ZIP_AFTER {
            d.weld_close_stitches();
        }
        assert_eq!(d.seams[0].pairs.iter().filter(|(p, q)| p != q).count(), 1);
        assert!(mids.iter().all(|&v| d.sim.cloth.live.is_boundary(v)));
    }
}
