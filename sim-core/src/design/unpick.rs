//! Removing a seam unpicks it: what its welds sewed together comes apart again, as a
//! dressmaker unpicks a seam on the form to sew it another way. A welded vertex has a
//! place in the pattern for each side it joins (its triangles' rest corners); it is
//! split into one vertex per place, the cloth its welds folded away (`Seam::eased`) is
//! put back, and the two sides are parted as a cut's are. Before 2026-12-06 a removed
//! seam's welded pairs stayed sewn (each weld its own edit), so a dart into a sewn side
//! seam could not be freed by removing the seam; until later that day, a vertex another
//! seam also held (a dart's mouth welded into a side seam) stayed sewn whole.

use std::collections::HashSet;

use glam::{Vec2, Vec3};

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;
use super::transaction::Batch;
use crate::mesh::Tri;

/// Two corners of a vertex whose places in the pattern lie closer than this are one
/// place (the same corner in its triangles, equal to rounding), m.
const SAME_PLACE_M: f32 = 1e-3;

/// Two rest corners closer than this are one (copied, not computed), m.
const SAME_REST_M: f32 = 1e-6;

/// A vertex's triangles at one place in the pattern (or places kept together): their
/// slots and what they are.
type Place = Vec<(u32, Tri)>;

/// What removing a seam did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Removed {
    /// The seam's stitched pairs.
    pub pairs: usize,
    /// Its welded pairs taken apart.
    pub unpicked: usize,
    /// Its welded pairs left sewn: seams still listed hold both sides of their vertex
    /// (each side sewn to a third piece, or the two joined by another seam too), which
    /// unpicking would open as well. A dart's mouth welded into the seam is unpicked
    /// from the other side and stays the dart's.
    pub kept: usize,
    /// Triangles its welds had folded away (eased into it), put back.
    pub eased_back: usize,
}

/// The place in the pattern plane of a rest corner.
fn place(rest: Vec3) -> Vec2 {
    Vec2::new(rest.x, -rest.z)
}

impl Design {
    /// Removes seam `index` and unpicks it: its open stitches stop pulling, and every
    /// welded pair's vertex is split again, one vertex for each of its places in the
    /// pattern (places another seam still sews together there staying one:
    /// `unpick_groups`), with the cloth its welds eased away put back and
    /// the sides parted (a cut's 40 µm each way). One undoable edit, "remove seam".
    pub fn remove_seam(&mut self, index: usize) -> Result<Removed, EditError> {
        let count = self.seams.len();
        let Some(old) = self.seams.get(index).cloned() else {
            return Err(EditError::NoSeam { index, count });
        };
        let gone = Prim::Seam {
            index: index as u32,
            old: Some(old.clone()),
            new: None,
        };
        let welded = old.pairs.iter().filter(|(a, b)| a == b).count();
        let mut done = Removed {
            pairs: old.pairs.len(),
            ..Removed::default()
        };
        if welded == 0 {
            self.commit("remove seam", vec![gone])?;
            return Ok(done);
        }
        let mut applied = Vec::new();
        let mut batch = Batch::default();
        let unpicked = self
            .apply_unsynced(std::slice::from_ref(&gone), &mut batch)
            .and_then(|()| {
                applied.push(gone);
                self.unpick(&old.pairs, &old.eased, &mut applied, &mut batch)
            });
        match unpicked {
            Ok((unpicked, kept, eased_back)) => {
                self.record_batch("remove seam", applied, batch);
                done.unpicked = unpicked;
                done.kept = kept;
                done.eased_back = eased_back;
                Ok(done)
            }
            Err(e) => {
                self.abandon_batch(&applied, batch);
                Err(e)
            }
        }
    }

    /// Splits the welded vertices of `pairs` (a seam already out of the list) by their
    /// places and puts `eased` back; returns the welded pairs taken apart, those kept
    /// (another seam holds their vertex) and the triangles put back.
    fn unpick(
        &mut self,
        pairs: &[(u32, u32)],
        eased: &[[Vec3; 3]],
        applied: &mut Vec<Prim>,
        batch: &mut Batch,
    ) -> Result<(usize, usize, usize), EditError> {
        let mut split: HashSet<u32> = HashSet::new();
        let mut welded: Vec<u32> = (pairs.iter())
            .filter(|(a, b)| a == b)
            .map(|p| p.0)
            .collect();
        welded.sort_unstable();
        welded.dedup();
        let first_new = self.sim.cloth.len() as u32;
        for v in welded {
            if !self.sim.cloth.live.vertex_alive(v) {
                continue;
            }
            let Some(groups) = self.unpick_groups(v) else {
                continue;
            };
            if groups.len() < 2 {
                continue;
            }
            for moving in &groups[1..] {
                let prims = self.split_off_prims(v, moving)?;
                self.apply_unsynced(&prims, batch)?;
                applied.extend(prims);
            }
            split.insert(v);
        }
        let mut near: Vec<u32> = (split.iter().copied())
            .chain(first_new..self.sim.cloth.len() as u32)
            .collect();
        let ring: Vec<u32> = (near.iter())
            .flat_map(|&v| self.sim.cloth.live.neighbours(v))
            .collect();
        near.extend(ring);
        near.sort_unstable();
        near.dedup();
        let mut eased_back = 0;
        for rest in eased {
            let Some(tri) = self.eased_tri(rest, &near) else {
                continue;
            };
            let prims = [Prim::Tri {
                slot: self.sim.cloth.live.slots() as u32,
                old: None,
                new: Some(tri),
            }];
            // One that no longer fits (an edge with two triangles already) stays out.
            if self.apply_unsynced(&prims, batch).is_ok() {
                applied.extend(prims);
                eased_back += 1;
            }
        }
        let count = |set: &HashSet<u32>| {
            (pairs.iter())
                .filter(|(a, b)| a == b && set.contains(a))
                .count()
        };
        let sewn: HashSet<u32> = (pairs.iter())
            .filter(|&&(a, b)| {
                a == b
                    && !split.contains(&a)
                    && self.sim.cloth.live.vertex_alive(a)
                    && self.place_groups(a).len() > 1
            })
            .map(|p| p.0)
            .collect();
        Ok((count(&split), count(&sewn), eased_back))
    }

    /// Vertex `v`'s triangles as unpicking parts them: one group for each of its places
    /// in the pattern, except that places a seam still listed sews together at `v` stay
    /// one group (a dart's two legs where their mouth was welded into the side seam being
    /// unpicked). A listed seam sews together the places from which an edge runs to a
    /// vertex of its pair on either side of the pairs at `v`. The group the listed seams
    /// hold comes first, to stay on `v` (their pairs name it); None when they hold two
    /// groups apart (a vertex between two other seams), which could not both stay.
    fn unpick_groups(&self, v: u32) -> Option<Vec<Place>> {
        let places = self.place_groups(v);
        let mut root: Vec<usize> = (0..places.len()).collect();
        fn find(root: &mut [usize], mut i: usize) -> usize {
            while root[i] != i {
                root[i] = root[root[i]];
                i = root[i];
            }
            i
        }
        let mut held = vec![false; places.len()];
        for seam in &self.seams {
            for (i, &(a, b)) in seam.pairs.iter().enumerate() {
                if a != v && b != v {
                    continue;
                }
                // The pairs beside it either way, past any more pairs of `v` alone (a
                // vertex paired twice).
                let other = |&&(p, q): &&(u32, u32)| p != v || q != v;
                let before = seam.pairs[..i].iter().rev().find(other);
                let after = seam.pairs[i + 1..].iter().find(other);
                let ends: Vec<u32> = (before.into_iter().chain(after))
                    .flat_map(|&(p, q)| [p, q])
                    .filter(|&u| u != v)
                    .collect();
                let joined: Vec<usize> = (0..places.len())
                    .filter(|&g| {
                        (places[g].iter()).any(|(_, t)| ends.iter().any(|u| t.v.contains(u)))
                    })
                    .collect();
                // A seam at `v` whose places cannot be told: all stay together.
                let joined = if joined.is_empty() {
                    (0..places.len()).collect()
                } else {
                    joined
                };
                for &g in &joined {
                    held[g] = true;
                    let (r, s) = (find(&mut root, joined[0]), find(&mut root, g));
                    root[s] = r;
                }
            }
        }
        let mut groups: Vec<(usize, bool, Place)> = Vec::new();
        for (g, tris) in places.into_iter().enumerate() {
            let r = find(&mut root, g);
            match groups.iter_mut().find(|(q, _, _)| *q == r) {
                Some((_, h, all)) => {
                    *h |= held[g];
                    all.extend(tris);
                }
                None => groups.push((r, held[g], tris)),
            }
        }
        if groups.iter().filter(|(_, h, _)| *h).count() > 1 {
            return None;
        }
        // Stable: the held group first, the others in the order met.
        groups.sort_by_key(|(_, h, _)| !*h);
        Some(groups.into_iter().map(|(_, _, tris)| tris).collect())
    }

    /// Vertex `v`'s live triangles grouped by the place in the pattern of their corner
    /// at `v`, in the order first met.
    pub(super) fn place_groups(&self, v: u32) -> Vec<Vec<(u32, Tri)>> {
        let live = &self.sim.cloth.live;
        let mut groups: Vec<(Vec2, Vec<(u32, Tri)>)> = Vec::new();
        for &slot in live.tris_of(v) {
            let Some(t) = live.tri(slot) else { continue };
            let Some(c) = t.corner(v) else { continue };
            let p = place(t.rest[c]);
            match groups
                .iter_mut()
                .find(|(q, _)| q.distance(p) < SAME_PLACE_M)
            {
                Some((_, g)) => g.push((slot, *t)),
                None => groups.push((p, vec![(slot, *t)])),
            }
        }
        groups.into_iter().map(|(_, g)| g).collect()
    }

    /// The triangle eased away with rest corners `rest`, on the vertices among `near`
    /// that have those corners now (with their texture coordinates); None unless all
    /// three are found, three of them.
    fn eased_tri(&self, rest: &[Vec3; 3], near: &[u32]) -> Option<Tri> {
        let live = &self.sim.cloth.live;
        let corner = |r: Vec3| {
            near.iter().find_map(|&u| {
                live.tris_of(u).iter().find_map(|&slot| {
                    let t = live.tri(slot)?;
                    let c = t.corner(u)?;
                    (t.rest[c].distance(r) < SAME_REST_M).then_some((u, t.uv[c]))
                })
            })
        };
        let [a, b, c] = [corner(rest[0])?, corner(rest[1])?, corner(rest[2])?];
        (a.0 != b.0 && b.0 != c.0 && a.0 != c.0).then_some(Tri {
            v: [a.0, b.0, c.0],
            rest: *rest,
            uv: [a.1, b.1, c.1],
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    /// The draping a dart into a sewn side seam asks for: the dress at 3 cm, sewn and
    /// draped, its left side seam (D) removed: every welded pair comes apart, one vertex
    /// for each place, nothing crossing, and undo sews it again. Removed again, a dart
    /// taken into the open side closes whole, and the side sewn again welds whole over
    /// it. Before unpicking, the removed seam's 19 vertices kept both places.
    #[test]
    fn a_removed_seam_comes_apart_and_a_dart_then_closes_before_it_is_sewn_again() {
        let mut d = crate::design::tests::sewn_dress(0.03, 240);
        let welded = |d: &super::Design, k: usize| {
            let s = &d.seams[k];
            (s.pairs.iter().filter(|p| p.0 == p.1).count(), s.pairs.len())
        };
        let (w, n) = welded(&d, 3);
        assert_eq!(w, n, "seam D is not sewn");
        let vertices = d.sim.cloth.len();
        let side: Vec<u32> = d.seams[3].pairs.iter().map(|p| p.0).collect();
        let r = d.remove_seam(3).unwrap();
        assert_eq!((r.pairs, r.unpicked, r.kept, r.eased_back), (n, n, 0, 0));
        assert_eq!(d.seams.len(), 3);
        assert_eq!(d.sim.cloth.len(), vertices + n);
        for v in &side {
            assert_eq!(d.place_groups(*v).len(), 1, "vertex {v} is still sewn");
        }
        let crossed = d.sim.crossings();
        assert_eq!((crossed.self_pairs, crossed.body_pairs), (0, 0));
        assert_eq!(d.undo().unwrap(), "remove seam");
        assert_eq!((d.seams.len(), d.sim.cloth.len()), (4, vertices));
        assert!(side.iter().all(|&v| d.place_groups(v).len() == 2));
        // Unpicked, the dart into the side closes, and the side sews again over it.
        d.remove_seam(3).unwrap();
        let (lo, hi) = crate::mesh::bounds2(&d.pieces[0].outline.loops[0]);
        let off = d.pieces[0].offset;
        let at = |x: f32, below: f32| Vec2::new(lo.x + x, hi.y - below) + off;
        d.dart_on_plane(at(0.12, 0.38), at(-0.06, 0.40), 0.04)
            .unwrap();
        assert_eq!(d.dart_mouth_sewn(3), Some(false));
        let (blo, bhi) = crate::mesh::bounds2(&d.pieces[1].outline.loops[0]);
        let boff = d.pieces[1].offset;
        for _ in 0..200 {
            d.step().unwrap();
        }
        let (w, n) = welded(&d, 3);
        assert_eq!(w, n, "the dart");
        let front = [hi.y - 0.22, lo.y].map(|y| Vec2::new(lo.x, y) + off);
        let back = [bhi.y - 0.22, blo.y].map(|y| Vec2::new(bhi.x, y) + boff);
        d.seam_on_plane(front, back, 0.01).unwrap();
        for _ in 0..400 {
            d.step().unwrap();
        }
        for k in [3, 4] {
            let (w, n) = welded(&d, k);
            assert_eq!(w, n, "seam {k}");
        }
        let crossed = d.sim.crossings();
        assert_eq!((crossed.self_pairs, crossed.body_pairs), (0, 0));
        // Its pattern out reads back whole, the dart and the side seam over its mouth
        // sewn as two, from the SVG and from the DXF (whose seam texts stood once per
        // label). Before 2026-12-06 the dart went unmarked here: its mouth's vertex, paired
        // twice and welded into the side seam, was on the back too.
        let dir = std::env::temp_dir().join(format!("saiho-unpick-{}", std::process::id()));
        crate::design::sewing_pattern::export_pattern(&d, &dir, 10.0).unwrap();
        let svg = crate::mesh::svg::load_svg(&dir.join("pattern.svg")).unwrap();
        let dxf = crate::mesh::dxf::load_dxf(&dir.join("pattern.dxf")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        for read in [svg, dxf] {
            let (spec, notices) = crate::design::garment::pattern_from_outlines(read);
            let labels: Vec<&str> = spec.seams.iter().map(|s| s.label.as_str()).collect();
            assert_eq!(labels, ["A", "B", "C", "D", "E", "E"], "{notices:?}");
            assert!(notices.iter().all(|n| !n.contains("unsewn")), "{notices:?}");
        }
        // The side unpicked again over the sewn dart: the dart's mouth, welded into the
        // side, leaves the back and stays one vertex with the dart's two legs (before
        // 2026-12-06, later, it stayed sewn to the back: "kept").
        let dart: Vec<u32> = d.seams[3].pairs.iter().map(|p| p.0).collect();
        let side: Vec<u32> = d.seams[4].pairs.iter().map(|p| p.0).collect();
        let mouth: Vec<u32> = side.iter().copied().filter(|v| dart.contains(v)).collect();
        assert!(
            !mouth.is_empty(),
            "the side seam runs over the dart's mouth"
        );
        assert!(mouth.iter().all(|&v| d.place_groups(v).len() == 3));
        let dart_places: Vec<usize> = dart.iter().map(|&v| d.place_groups(v).len()).collect();
        let r = d.remove_seam(4).unwrap();
        assert_eq!((r.unpicked, r.kept), (side.len(), 0));
        assert_eq!(
            welded(&d, 3),
            (dart.len(), dart.len()),
            "the dart stays sewn"
        );
        for &v in &side {
            let places = if mouth.contains(&v) { 2 } else { 1 };
            assert_eq!(d.place_groups(v).len(), places, "vertex {v}");
        }
        for (&v, &was) in dart.iter().zip(&dart_places) {
            let now = d.place_groups(v).len();
            assert_eq!(
                now,
                if mouth.contains(&v) { 2 } else { was },
                "dart vertex {v}"
            );
        }
        let crossed = d.sim.crossings();
        assert_eq!((crossed.self_pairs, crossed.body_pairs), (0, 0));
    }

    /// Undone once its sides have fallen apart (the dress's shoulder seam unpicked and
    /// the front slid off the shoulder), the unpick would weld them back through the
    /// cloth: refused, kept on the list, and the answer says a seam sews them again.
    #[test]
    fn an_unpick_undone_after_the_sides_fell_apart_says_to_sew_them_again() {
        let mut d = crate::design::tests::sewn_dress(0.04, 240);
        d.remove_seam(0).unwrap();
        for _ in 0..30 {
            d.step().unwrap();
        }
        let e = d.undo().unwrap_err().to_string();
        assert!(
            e.contains("undoing \"remove seam\"") && e.contains("sew the two edges again"),
            "{e}"
        );
        assert_eq!(d.seams.len(), 3, "nothing changed");
    }
}
