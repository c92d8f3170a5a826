//! Whether an edit would make the cloth cross itself or the body: the check that keeps
//! the vbd model's guarantee (its cloth never crosses) through the edits that move
//! vertices or put triangles back, which the solver's guard does not see: a sew or a
//! seam's weld (a vertex moved onto another), and undo and redo (a cut's triangles put
//! back across a gap that has since opened, a deleted piece back where another now lies,
//! a weld's vertex moved back where it was); and how far an edit would stretch the
//! triangles it moves (a zipped weld's bound).

use std::collections::{HashMap, HashSet};

use glam::Vec3;

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;
use crate::collision::crossings::fan_crossings;
use crate::mesh::Tri;
use crate::solver::ModelKind;

/// What an edit's primitives touch, and where they put it.
struct Touched {
    /// Moved and added vertices, where they go.
    to: HashMap<u32, Vec3>,
    /// Slots the edit changes, with the triangles there before it and after it (a slot
    /// changed twice counts once, as it was and as it ends).
    changed: HashSet<u32>,
    old: Vec<[u32; 3]>,
    new: Vec<Tri>,
    /// The moved vertices' triangles the edit leaves in place, and their slots.
    kept: Vec<Tri>,
    kept_slots: HashSet<u32>,
    /// Each vertex the edit adds in another's place in a triangle (a cut's copy of the
    /// vertex it splits), to that one: the two sides of a fresh cut lie together, and
    /// are neighbours there, not a crossing.
    origin: HashMap<u32, u32>,
}

impl Design {
    fn touched(&self, prims: &[Prim]) -> Touched {
        let live = &self.sim.cloth.live;
        let mut to = HashMap::new();
        let mut changed = HashSet::new();
        let (mut old, mut new) = (Vec::new(), Vec::<(Tri, u32)>::new());
        let mut added = HashSet::new();
        let mut origin = HashMap::new();
        for prim in prims {
            match prim {
                Prim::Move { .. }
                | Prim::MoveOnto { .. }
                | Prim::MoveOff { .. }
                | Prim::Nudge { .. }
                | Prim::Merge { .. }
                | Prim::Unmerge { .. }
                | Prim::AddVertex { .. } => {
                    // Where applying it will put them: from where they stand by then.
                    let x = &self.sim.cloth.x;
                    let now = |i: u32| to.get(&i).copied().or_else(|| x.get(i as usize).copied());
                    for (v, p) in prim.placed(now).into_iter().flatten() {
                        to.insert(v, p);
                    }
                    if let Prim::AddVertex { index, .. } = prim {
                        added.insert(*index);
                    }
                    // A weld opened in place: its two sides meet there as a cut's do.
                    if let Prim::Unmerge { a, b, apart, .. } = prim
                        && *apart == [Vec3::ZERO; 2]
                    {
                        origin.entry(*b).or_insert(*a);
                    }
                }
                Prim::Tri {
                    slot,
                    old: o,
                    new: n,
                } => {
                    if let (Some(o), Some(n)) = (o, n) {
                        for k in 0..3 {
                            let (was, now) = (o.v[k], n.v[k]);
                            if was != now && added.contains(&now) {
                                origin.entry(now).or_insert(was);
                            }
                        }
                    }
                    if changed.insert(*slot) {
                        old.extend(o.map(|t| t.v));
                    }
                    new.retain(|t| t.1 != *slot);
                    new.extend(n.map(|t| (t, *slot)));
                }
                _ => {}
            }
        }
        let (mut kept, mut kept_slots) = (Vec::new(), HashSet::new());
        for &v in to.keys() {
            for &s in live.tris_of(v) {
                if !changed.contains(&s)
                    && kept_slots.insert(s)
                    && let Some(t) = live.tri(s)
                {
                    kept.push(*t);
                }
            }
        }
        Touched {
            to,
            changed,
            old,
            new: new.into_iter().map(|t| t.0).collect(),
            kept,
            kept_slots,
            origin,
        }
    }

    /// Whether the design's contact is never crossed by choice: the xpbd model with its
    /// guard on (what the design file keeps; vbd's contact is never crossed whatever).
    pub fn guarded(&self) -> bool {
        self.sim.model == ModelKind::Xpbd && self.sim.never_crosses()
    }

    /// Turns the xpbd model's guard against crossing on or off, in place (positions,
    /// edits and history stay); the sentence says what the contact is now. Under vbd it
    /// is always on; the paper's model and the implicit reference have none. A cloth
    /// that already crosses keeps those crossings when the guard comes on (it keeps each
    /// pair from crossing further, it does not untangle), and the sentence counts them.
    pub fn set_guard(&mut self, on: bool) -> Result<String, EditError> {
        match self.sim.model {
            ModelKind::Xpbd => {}
            ModelKind::Vbd if on => {
                return Ok("The vbd model's contact is never crossed already".into());
            }
            ModelKind::Vbd => return Err(EditError::GuardBuiltIn),
            m => return Err(EditError::NoGuard(m.name())),
        }
        if !on {
            self.sim.set_guard(false);
            return Ok(
                "The cloth may cross itself and the body's edges again (the guard is \
                       off: frames are faster)"
                    .into(),
            );
        }
        if self.guarded() {
            return Ok(
                "The guard is on already: the cloth never crosses itself or the body".into(),
            );
        }
        let crossed = self.sim.crossings();
        self.sim.set_guard(true);
        Ok(if crossed.self_pairs + crossed.body_pairs == 0 {
            "The guard is on: from now the cloth never crosses itself or the body".into()
        } else {
            format!(
                "The guard is on, but the cloth already crosses itself in {} triangle pairs \
                 and the body in {}: those stay (a new scene with the guard on has none)",
                crossed.self_pairs, crossed.body_pairs
            )
        })
    }

    /// Whether applying `prims` would leave the triangles they touch (those they put in
    /// place, and those of the vertices they move) crossing the rest of the cloth, each
    /// other or the body in more pairs than the same triangles do now. Such an edit is
    /// refused or waits (a seam's stitch keeps pulling, and the pair closes once it can
    /// without a new crossing). Under the vbd model, whose cloth crosses nothing, any
    /// crossing is new.
    pub(super) fn edit_would_cross(&self, prims: &[Prim]) -> bool {
        self.new_crossings(prims) > 0
    }

    /// How many more crossing pairs the triangles `prims` touch would have after it than
    /// now (0 when fewer or as many).
    pub(super) fn new_crossings(&self, prims: &[Prim]) -> usize {
        let t = self.touched(prims);
        if t.to.is_empty() && t.new.is_empty() {
            return 0;
        }
        let kept = t.kept.iter().map(|k| k.v);
        let now: Vec<[u32; 3]> = t.old.iter().copied().chain(kept.clone()).collect();
        let mut others: Vec<[u32; 3]> = self
            .sim
            .cloth
            .live
            .iter()
            .filter(|(s, _)| !t.changed.contains(s) && !t.kept_slots.contains(s))
            .map(|(_, t)| t.v)
            .collect();
        let (x, body) = (&self.sim.cloth.x, self.sim.body.as_ref());
        let now_at = |v: u32| x.get(v as usize).copied();
        let then_at = |v: u32| t.to.get(&v).copied().or_else(|| now_at(v));
        // Only the triangles near the edit's can cross them. The others touch no vertex
        // the edit moves, so they lie where they lie now, before and after: those outside
        // the box round the edit's triangles (as they are and as they would be) are left
        // out before the count puts them in its grid (undoing a 20-vertex stroke on a
        // 16k-vertex cloth spent 10 ms gridding every triangle of the cloth).
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let fans = t
            .old
            .iter()
            .chain(t.kept.iter().chain(&t.new).map(|k| &k.v));
        for p in fans
            .flatten()
            .flat_map(|&v| [now_at(v), then_at(v)])
            .flatten()
        {
            if p.is_finite() {
                (lo, hi) = (lo.min(p), hi.max(p));
            }
        }
        let near_fan = |o: &[u32; 3]| {
            let c = o.map(|v| now_at(v).unwrap_or(Vec3::NAN));
            let (olo, ohi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
            // A corner not finite is kept for the count to judge.
            !(olo.is_finite() && ohi.is_finite()) || (olo.cmple(hi).all() && ohi.cmpge(lo).all())
        };
        others.retain(near_fan);
        // A cut's copies as the vertices they split, where they lie: the cut's two sides
        // meet there as neighbours (a copy's place is its origin's; until 2026-11-30
        // every cut undone under the guard could not be redone, "would make 2
        // crossings").
        let canon = |v: u32| {
            let mut v = v;
            for _ in 0..64 {
                match t.origin.get(&v) {
                    Some(&o) if then_at(v) == then_at(o) => v = o,
                    _ => break,
                }
            }
            v
        };
        let then: Vec<[u32; 3]> = t.new.iter().map(|n| n.v.map(canon)).chain(kept).collect();
        // Each touched triangle against the rest and the body, and against the other
        // touched ones (a pair among them counted twice, alike before and after).
        let count = |at: &dyn Fn(u32) -> Option<Vec3>, fan: &[[u32; 3]]| {
            fan_crossings(at, fan, &others, body) + fan_crossings(at, fan, fan, None)
        };
        count(&then_at, &then).saturating_sub(count(&now_at, &now))
    }

    /// The most any edge of the triangles `prims` touch would be stretched after it, as a
    /// share of its rest length.
    pub(super) fn stretch_after(&self, prims: &[Prim]) -> f32 {
        let t = self.touched(prims);
        let x = &self.sim.cloth.x;
        let at = |v: u32| t.to.get(&v).copied().or_else(|| x.get(v as usize).copied());
        t.new
            .iter()
            .chain(&t.kept)
            .flat_map(|tri| {
                (0..3).filter_map(move |k| {
                    let (a, b) = (at(tri.v[k])?, at(tri.v[(k + 1) % 3])?);
                    let rest = (tri.rest[k] - tri.rest[(k + 1) % 3]).length();
                    Some((a - b).length() / rest.max(1e-9) - 1.0)
                })
            })
            .fold(0.0, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::design::{EditError, floating};
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// The guard's pairs outlive an edit: the frame after a cut, a tear or an undo
    /// updates the pairs of the vertices the edit touched instead of searching the whole
    /// cloth again (which cost 157 ms against a 44 ms frame on the 16k-vertex drape).
    #[test]
    fn the_frame_after_an_edit_updates_the_guards_pairs() {
        let mut d = floating(
            ClothMesh::grid(0.4, 0.4, 16, 16, 1.0).unwrap(),
            ModelKind::Xpbd,
        );
        d.set_guard(true).unwrap();
        d.step().unwrap();
        let stats = |d: &crate::design::Design| d.sim.solver.contact_stats().unwrap();
        assert_eq!(stats(&d).searches, 1, "the first frame searches in full");
        d.step().unwrap();
        assert_eq!(
            (stats(&d).searches, stats(&d).updates),
            (0, 0),
            "nothing moved"
        );
        d.cut_vertex(140, Vec3::X).unwrap();
        d.step().unwrap();
        assert_eq!(
            (stats(&d).searches, stats(&d).updates),
            (0, 1),
            "after a cut"
        );
        d.tear_edge(20, 21, crate::design::TearMode::Split).unwrap();
        d.undo().unwrap();
        d.step().unwrap();
        assert_eq!(
            (stats(&d).searches, stats(&d).updates),
            (0, 1),
            "after an undo"
        );
    }

    /// A 0.4 m cloth at y = 1 with its right half (x > 0) cut away, then its left half
    /// stood up as a wall at x = 0.1, through where the right half lay.
    fn cut_then_moved(model: ModelKind) -> crate::design::Design {
        let mut d = floating(ClothMesh::grid(0.4, 0.4, 8, 8, 1.0).unwrap(), model);
        let right: Vec<u32> = d
            .sim
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                t.v.iter()
                    .map(|&v| d.sim.cloth.x[v as usize].x)
                    .sum::<f32>()
                    > 0.0
            })
            .map(|(s, _)| s)
            .collect();
        d.remove_triangles(&right).unwrap();
        for i in 0..d.sim.cloth.len() {
            let p = d.sim.cloth.x[i];
            if d.sim.cloth.live.vertex_alive(i as u32) {
                d.sim.cloth.x[i] = Vec3::new(0.1, 0.9 - p.x, p.z);
            }
        }
        d
    }

    #[test]
    fn an_undo_that_would_cross_is_refused_under_vbd_and_kept() {
        let mut d = cut_then_moved(ModelKind::Vbd);
        let tris = d.sim.cloth.live.tri_count();
        match d.undo() {
            Err(EditError::HistoryWouldCross {
                label, crossings, ..
            }) => {
                assert_eq!(label, "cut away");
                assert!(crossings > 0);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(d.sim.cloth.live.tri_count(), tris, "nothing changed");
        assert_eq!(d.history.undo_len(), 1, "the cut can still be undone");
        // Laid flat again, where it was: the cut's triangles go back.
        for i in 0..d.sim.cloth.len() {
            let p = d.sim.cloth.x[i];
            if d.sim.cloth.live.vertex_alive(i as u32) {
                d.sim.cloth.x[i] = Vec3::new(0.9 - p.y, 1.0, p.z);
            }
        }
        assert_eq!(d.undo(), Ok("cut away"));
        assert!(d.sim.cloth.live.tri_count() > tris);
        // XPBD restores what was, crossed or not; with its guard on, its contact is
        // never crossed as vbd's, and its undo is refused too.
        let mut x = cut_then_moved(ModelKind::Xpbd);
        assert_eq!(x.undo(), Ok("cut away"));
        let mut x = cut_then_moved(ModelKind::Xpbd);
        assert!(x.sim.set_guard(true));
        assert!(matches!(x.undo(), Err(EditError::HistoryWouldCross { .. })));
    }

    #[test]
    fn a_redo_that_would_cross_is_refused_under_vbd_and_kept() {
        let mut d = floating(
            ClothMesh::grid(0.4, 0.4, 8, 8, 1.0).unwrap(),
            ModelKind::Vbd,
        );
        // Cells as (column, row) from the -x, -z corner, 5 cm each; vertex (i, j) is
        // `9 j + i`. Away: the column between x = 0 and 5 cm, and the three cells round the
        // first, which is left on its own.
        let away: Vec<u32> = d
            .sim
            .cloth
            .live
            .iter()
            .filter(|(_, t)| {
                let c = t.v.iter().map(|&v| d.sim.cloth.x[v as usize]).sum::<Vec3>() / 3.0;
                let cell = ((c.x / 0.4 + 0.5) * 8.0).floor() as i32;
                let row = ((c.z / 0.4 + 0.5) * 8.0).floor() as i32;
                cell == 4 || (cell <= 1 && row <= 1 && (cell, row) != (0, 0))
            })
            .map(|(s, _)| s)
            .collect();
        d.remove_triangles(&away).unwrap();
        // Across the gap, 5 cm: the sew joins them halfway, and is undone.
        let (a, b) = (4 + 9 * 4, 5 + 9 * 4);
        d.sew(a, b).unwrap();
        d.undo().unwrap();
        // The lone cell stood up in the gap, across where the sew puts `a`.
        let m = Vec3::new(0.025, 1.0, 0.0);
        for (v, at) in [
            (0, (-0.03, -0.03)),
            (1, (-0.03, 0.03)),
            (9, (0.03, -0.03)),
            (10, (0.03, 0.03)),
        ] {
            d.sim.cloth.x[v] = m + Vec3::new(0.0, at.1, at.0);
        }
        assert!(matches!(
            d.redo(),
            Err(EditError::HistoryWouldCross { label: "sew", .. })
        ));
        assert_eq!(d.history.redo_len(), 1, "the sew can still be redone");
        // The cell laid back: it goes through.
        for v in [0usize, 1, 9, 10] {
            d.sim.cloth.x[v].x -= 0.5;
        }
        assert_eq!(d.redo(), Ok("sew"));
    }
}

#[cfg(test)]
mod guard_tests {
    use glam::Vec3;

    use crate::design::{Design, EditError, floating};
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    fn sheet(model: ModelKind) -> Design {
        floating(ClothMesh::grid(0.4, 0.4, 8, 8, 1.0).unwrap(), model)
    }

    #[test]
    fn the_guard_is_switched_in_place_and_the_design_file_keeps_it() {
        let mut d = sheet(ModelKind::Xpbd);
        assert!(!d.guarded());
        let bytes = d.save_design().unwrap();
        assert!(!Design::load_design(&bytes).unwrap().guarded());
        let m = d.set_guard(true).unwrap();
        assert!(m.contains("never crosses"), "{m}");
        assert!(d.guarded() && d.sim.never_crosses());
        let again = Design::load_design(&d.save_design().unwrap()).unwrap();
        assert!(again.guarded(), "the file keeps the guard");
        assert!(d.set_guard(false).is_ok());
        assert!(!d.guarded() && !d.sim.never_crosses());
        assert!(
            !Design::load_design(&d.save_design().unwrap())
                .unwrap()
                .guarded()
        );
    }

    /// The guard switched on over a cloth that crosses already counts the pairs; it adds
    /// none (here a step frees 4 of the 23), and does not untangle the rest.
    #[test]
    fn the_guard_on_over_crossings_names_them() {
        // A 0.4 m square at y = 1 and a wall of the same through it at x = 0.
        let mut mesh = ClothMesh::grid(0.4, 0.4, 5, 5, 1.0).unwrap();
        let wall = ClothMesh::grid(0.4, 0.4, 5, 5, 0.0).unwrap();
        let n0 = mesh.positions.len() as u32;
        mesh.positions.extend(
            wall.positions
                .iter()
                .map(|p| Vec3::new(0.0, 1.0 + p.x, p.z)),
        );
        mesh.uvs.extend(&wall.uvs);
        mesh.triangles
            .extend(wall.triangles.iter().map(|t| t.map(|i| i + n0)));
        let mut d = floating(mesh, ModelKind::Xpbd);
        let crossed = d.sim.crossings().self_pairs;
        assert!(crossed > 0);
        let m = d.set_guard(true).unwrap();
        assert!(
            m.contains(&format!(
                "already crosses itself in {crossed} triangle pairs"
            )),
            "{m}"
        );
        assert!(d.guarded());
        d.step().unwrap();
        let now = d.sim.crossings().self_pairs;
        assert!(now > 0 && now <= crossed, "{now} of {crossed}: none added");
    }

    /// A material change rebuilds the xpbd solver; the guard goes on with it (it once
    /// went with the old solver, and the studio's Apply or a fabric choice let the cloth
    /// cross again while the panel still said it never would).
    #[test]
    fn a_material_change_keeps_the_guard() {
        let mut d = sheet(ModelKind::Xpbd);
        d.set_guard(true).unwrap();
        let mut m = d.sim.material;
        m.density *= 1.5;
        m.strain_limit = 0.3;
        d.sim.set_material(m, Some(7)).unwrap();
        assert!(d.guarded(), "kept through a material change");
        d.step().unwrap();
        assert!(d.guarded());
        let crossed = d.sim.crossings();
        assert_eq!(crossed.self_pairs + crossed.body_pairs, 0);
    }

    #[test]
    fn the_models_without_a_switch_say_why() {
        for model in [ModelKind::Seed, ModelKind::Implicit] {
            let mut d = sheet(model);
            assert_eq!(d.set_guard(true), Err(EditError::NoGuard(model.name())));
            assert!(!d.sim.never_crosses());
        }
        let mut v = sheet(ModelKind::Vbd);
        assert!(v.set_guard(true).is_ok());
        assert_eq!(v.set_guard(false), Err(EditError::GuardBuiltIn));
        assert!(v.sim.never_crosses());
    }

    #[test]
    fn a_cloth_that_already_crosses_keeps_its_crossings_and_is_told_so() {
        let mut d = sheet(ModelKind::Xpbd);
        // One corner pushed down through the sheet's middle.
        let mid = 4 + 9 * 4;
        let under = d.sim.cloth.x[mid] - Vec3::Y * 0.05;
        for (v, off) in [
            (0usize, Vec3::ZERO),
            (1, Vec3::X * 0.05),
            (9, Vec3::Z * 0.05),
        ] {
            d.sim.cloth.x[v] = under + off;
        }
        let lifted = d.sim.cloth.x[0] + Vec3::Y * 0.1;
        d.sim.cloth.x[10] = lifted;
        let crossed = d.sim.crossings().self_pairs;
        assert!(crossed > 0);
        let m = d.set_guard(true).unwrap();
        assert!(
            m.contains(&format!("itself in {crossed} triangle pairs")),
            "{m}"
        );
        assert!(d.guarded());
    }
}
