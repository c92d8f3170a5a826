//! Which of the welds made after a designer's operation depend on it: an undo takes back
//! the operation with those, and leaves the others where they are (undoing one of a
//! dress's seams used to open every seam welded since, all of them, sewn together).
//!
//! Two edits commute when neither reads or writes what the other does: their vertices,
//! triangle slots and seams are apart, and at most one of them adds or removes vertices
//! (which always happens at the end of the list). A piece record or a paint patch is
//! taken to touch everything, so edits with those never commute.

use std::collections::HashSet;

use super::prim::{Edit, Prim};

/// What an edit reads and writes.
#[derive(Default)]
struct Footprint {
    vertices: HashSet<u32>,
    slots: HashSet<u32>,
    seams: HashSet<u32>,
    /// The lowest index at which a seam is put in or taken out (the seams from there on
    /// change places).
    seams_from: Option<u32>,
    /// Adds or removes a vertex (the vertex count).
    count: bool,
    /// Touches what is not told apart here (pieces, paint).
    everything: bool,
}

impl Footprint {
    fn of(prims: &[Prim]) -> Self {
        let mut f = Footprint::default();
        for p in prims {
            f.add(p);
        }
        f
    }

    fn add(&mut self, p: &Prim) {
        let v = &mut self.vertices;
        match p {
            Prim::Tri { slot, old, new } => {
                self.slots.insert(*slot);
                v.extend(old.iter().chain(new).flat_map(|t| t.v));
            }
            Prim::Uv { slot, .. } => {
                self.slots.insert(*slot);
            }
            Prim::AddVertex { index, from, .. } | Prim::RemoveVertex { index, from, .. } => {
                self.count = true;
                v.insert(*index);
                v.extend(from.iter().flat_map(|f| [f.a, f.b]));
            }
            Prim::Move { vertex, .. } | Prim::Nudge { vertex, .. } | Prim::Pin { vertex, .. } => {
                v.insert(*vertex);
            }
            Prim::Merge { a, b, .. } | Prim::Unmerge { a, b, .. } => v.extend([*a, *b]),
            Prim::MoveOnto { vertex, to, .. } | Prim::MoveOff { vertex, to, .. } => {
                v.extend([*vertex, to.a, to.b]);
            }
            Prim::Seam { index, old, new } => {
                self.seams.insert(*index);
                if old.is_none() || new.is_none() {
                    self.seams_from = Some(self.seams_from.map_or(*index, |f| f.min(*index)));
                }
                for s in old.iter().chain(new) {
                    v.extend(s.pairs.iter().flat_map(|&(a, b)| [a, b]));
                }
            }
            Prim::Paint(_) | Prim::Piece { .. } => self.everything = true,
            // Welds do not depend on it.
            Prim::Substeps { .. } => {}
        }
    }

    /// Whether the two touch anything in common.
    fn meets(&self, o: &Footprint) -> bool {
        let shifts = |a: &Footprint, b: &Footprint| {
            a.seams_from
                .is_some_and(|f| b.seams_from.is_some() || b.seams.iter().any(|&s| s >= f))
        };
        self.everything
            || o.everything
            || (self.count && o.count)
            || shifts(self, o)
            || shifts(o, self)
            || !self.vertices.is_disjoint(&o.vertices)
            || !self.slots.is_disjoint(&o.slots)
            || !self.seams.is_disjoint(&o.seams)
    }

    fn absorb(&mut self, o: Footprint) {
        self.vertices.extend(o.vertices);
        self.slots.extend(o.slots);
        self.seams.extend(o.seams);
        self.seams_from = match (self.seams_from, o.seams_from) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self.count |= o.count;
        self.everything |= o.everything;
    }
}

/// For `edits`, oldest first, the first of them the designer's operation: which must be
/// undone with it (`true` for itself). An edit depends on it when it touches what the
/// operation, or an edit depending on it, touched before; the others commute with all of
/// those, so they can stay applied while those are undone, and stay under them when they
/// are redone.
pub(super) fn dependents(edits: &[&Edit]) -> Vec<bool> {
    let Some((first, rest)) = edits.split_first() else {
        return Vec::new();
    };
    let mut taken = Footprint::of(&first.prims);
    let mut out = vec![true];
    for e in rest {
        let f = Footprint::of(&e.prims);
        let depends = taken.meets(&f);
        if depends {
            taken.absorb(f);
        }
        out.push(depends);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::parts::Seam;
    use glam::Vec3;

    fn edit(prims: Vec<Prim>) -> Edit {
        Edit {
            label: "weld",
            auto: true,
            prims,
        }
    }

    fn merge(a: u32, b: u32) -> Prim {
        Prim::Merge {
            a,
            b,
            at: crate::design::prim::MergeAt::Middle,
            apart: [Vec3::ZERO; 2],
        }
    }

    fn seam(index: u32, pairs: &[(u32, u32)], new: bool) -> Prim {
        let s = Seam {
            pairs: pairs.to_vec(),
            max_force: 1.0,
            name: String::new(),
            eased: Vec::new(),
            press_second: false,
        };
        let (old, new) = if new {
            (None, Some(s))
        } else {
            (Some(s.clone()), Some(s))
        };
        Prim::Seam { index, old, new }
    }

    #[test]
    fn a_seams_own_welds_depend_on_it_and_another_seams_do_not() {
        // Seam 2 made over vertices 10-13; seams 0 and 1 weld elsewhere, then seam 2 welds,
        // then seam 0 welds a pair that shares vertex 12 with seam 2.
        let made = edit(vec![seam(2, &[(10, 11), (12, 13)], true)]);
        let other = edit(vec![merge(1, 2), seam(0, &[(1, 1)], false)]);
        let other1 = edit(vec![merge(5, 6), seam(1, &[(5, 5)], false)]);
        let own = edit(vec![merge(10, 11), seam(2, &[(10, 10), (12, 13)], false)]);
        let corner = edit(vec![merge(3, 12), seam(0, &[(1, 1), (3, 3)], false)]);
        let after = edit(vec![merge(7, 8), seam(0, &[(1, 1), (3, 3), (7, 7)], false)]);
        let edits = [&made, &other, &other1, &own, &corner, &after];
        // The corner weld touches seam 2's vertex 12; the weld after it is on seam 0,
        // whose record the corner weld changed.
        assert_eq!(dependents(&edits), [true, false, false, true, true, true]);
        // A seam put in at index 0 shifts every seam after it: all depend on it.
        let first = edit(vec![seam(0, &[(20, 21)], true)]);
        assert_eq!(dependents(&[&first, &other1]), [true, true]);
        // A vertex added (a cut) and a weld apart from it commute; paint commutes with
        // nothing.
        let cut = edit(vec![Prim::AddVertex {
            index: 30,
            x: Vec3::ZERO,
            v: Vec3::ZERO,
            from: None,
        }]);
        assert_eq!(dependents(&[&cut, &other1]), [true, false]);
        let paint = edit(vec![Prim::Paint(crate::design::texture::PaintPatch {
            x0: 0,
            y0: 0,
            w: 0,
            h: 0,
            old: Vec::new(),
            new: Vec::new(),
        })]);
        assert_eq!(dependents(&[&paint, &other1]), [true, true]);
    }
}
