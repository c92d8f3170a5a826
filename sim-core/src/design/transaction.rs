//! Applying primitive edits as transactions: an operation's list applies whole or not at
//! all (if any primitive fails, those already applied are rolled back and the error is
//! returned with the design unchanged), then goes on the history; undo applies the
//! inverses in reverse order. After applying, only what the primitives touched is brought
//! up to date: the pieces' fabrics when a piece record changed (`fabrics`), the touched
//! vertices' masses, the solver's constraints for the touched triangles and edges
//! ([`Solver::sync`](crate::solver::Solver::sync)), and the contact cache's size.

use glam::Vec3;

use super::commute;
use super::document::Design;
use super::error::EditError;
use super::history::History;
use super::parts::Seam;
use super::pieces::PieceRecord;
use super::prim::{Edit, Prim};
use crate::mesh::{Tri, edge_key, warp_of};
use crate::solver::Cloth;

/// Applies a primitive that only moves vertices (the others are left alone): to a place
/// recorded (`Move`), or by one (`Nudge`, `MoveOff`, `Unmerge`), or between others as
/// they stand (`MoveOnto`, `Merge`). Refused, changing nothing, when a vertex is not there
/// or a move is not finite.
fn move_vertices(cloth: &mut Cloth, p: &Prim) -> Result<(), EditError> {
    let n = cloth.len();
    let there = |vs: &[u32]| match vs.iter().find(|&&v| v as usize >= n) {
        Some(&v) => Err(EditError::NoVertex(v)),
        None => Ok(()),
    };
    let finite = |v: u32, ok: bool| {
        if ok {
            Ok(())
        } else {
            Err(EditError::NoVertex(v))
        }
    };
    // Checked first, so that a refused primitive changes nothing.
    match p {
        Prim::Move { vertex, new, .. } => {
            there(&[*vertex])?;
            finite(*vertex, new.0.is_finite() && new.1.is_finite())?;
        }
        Prim::MoveOnto { vertex, to, .. } => there(&[*vertex, to.a, to.b])?,
        Prim::MoveOff {
            vertex, back: d, ..
        }
        | Prim::Nudge { vertex, by: d } => {
            there(&[*vertex])?;
            finite(*vertex, d.is_finite())?;
        }
        Prim::Merge { a, b, .. } => there(&[*a, *b])?,
        Prim::Unmerge { a, b, apart, .. } => {
            there(&[*a, *b])?;
            finite(*a, apart.iter().all(|d| d.is_finite()))?;
        }
        _ => {}
    }
    let places = p.placed(|i| cloth.x.get(i as usize).copied());
    for (v, at) in places.into_iter().flatten() {
        cloth.x[v as usize] = at;
    }
    // Velocities: a move to a recorded place takes its recorded one, a merged vertex the
    // mean of the two, an unmerged one its partner's; the others keep theirs.
    match p {
        Prim::Move { vertex, new, .. } => cloth.v[*vertex as usize] = new.1,
        Prim::Merge { a, b, .. } => {
            let (ia, ib) = (*a as usize, *b as usize);
            cloth.v[ia] = (cloth.v[ia] + cloth.v[ib]) * 0.5;
        }
        Prim::Unmerge { a, b, .. } => cloth.v[*b as usize] = cloth.v[*a as usize],
        _ => {}
    }
    Ok(())
}

/// Where each vertex that `prims` move stands now, and its velocity: what a rolled-back
/// transaction puts back. (Vertices the primitives add are not there yet, and go again.)
fn moved_now(cloth: &Cloth, prims: &[Prim]) -> Vec<(u32, Vec3, Vec3)> {
    let moved = prims.iter().flat_map(|p| match p {
        Prim::Move { vertex, .. }
        | Prim::MoveOnto { vertex, .. }
        | Prim::MoveOff { vertex, .. }
        | Prim::Nudge { vertex, .. } => [Some(*vertex), None],
        Prim::Merge { a, b, .. } | Prim::Unmerge { a, b, .. } => [Some(*a), Some(*b)],
        _ => [None, None],
    });
    moved
        .flatten()
        .filter_map(|v| Some((v, *cloth.x.get(v as usize)?, *cloth.v.get(v as usize)?)))
        .collect()
}

/// What a batch of primitives touched, for the incremental update.
#[derive(Default)]
struct Touched {
    tris: Vec<u32>,
    edges: Vec<u64>,
    verts: Vec<u32>,
    /// A piece record changed (its fabric, or a piece came or went).
    pieces: bool,
    /// Vertices added, in order.
    added: Vec<u32>,
    /// Each added vertex that took another's place in a triangle (a cut's copy), with
    /// that vertex: parted after the update ([`Design::part_copies`]).
    copies: Vec<(u32, u32)>,
}

/// What primitives applied without the incremental update touched
/// ([`Design::apply_unsynced`]), until [`Design::record_batch`] or
/// [`Design::abandon_batch`].
#[derive(Default)]
pub(super) struct Batch(Touched);

impl Touched {
    fn tri(&mut self, slot: u32, t: Option<&Tri>) {
        self.tris.push(slot);
        if let Some(t) = t {
            for (a, b, _) in t.edges() {
                self.edges.push(edge_key(a, b));
            }
            self.verts.extend_from_slice(&t.v);
        }
    }
}

impl Design {
    pub(super) fn check_editable(&self) -> Result<(), EditError> {
        if self.sim.editable() {
            Ok(())
        } else {
            Err(EditError::Model(self.sim.model.name()))
        }
    }

    /// A vertex that exists and is still part of the cloth.
    pub fn check_vertex(&self, v: u32) -> Result<(), EditError> {
        if v as usize >= self.sim.cloth.len() {
            Err(EditError::NoVertex(v))
        } else if !self.sim.cloth.live.vertex_alive(v) {
            Err(EditError::RemovedVertex(v))
        } else {
            Ok(())
        }
    }

    /// Applies one primitive to the cloth, recording what it touched.
    fn apply_prim(&mut self, p: &Prim, touched: &mut Touched) -> Result<(), EditError> {
        let cloth = &mut self.sim.cloth;
        match p {
            Prim::Tri { slot, old, new } => {
                if cloth.live.tri(*slot) != old.as_ref() {
                    return Err(EditError::Stale(*slot));
                }
                cloth.live.set(*slot, *new)?;
                touched.tri(*slot, old.as_ref());
                touched.tri(*slot, new.as_ref());
                if let (Some(o), Some(n)) = (old, new) {
                    for (&was, &now) in o.v.iter().zip(&n.v) {
                        if was != now && touched.added.contains(&now) {
                            touched.copies.push((now, was));
                        }
                    }
                }
            }
            Prim::Uv { slot, old, new } => {
                let Some(t) = cloth.live.tri(*slot) else {
                    return Err(EditError::Stale(*slot));
                };
                // Only a move that keeps the warp direction leaves the models as they
                // are (they are not told of it).
                let (w0, w1) = (warp_of(t.rest, *old), warp_of(t.rest, *new));
                if t.uv != *old || w0.dot(w1) < 1.0 - 1e-4 {
                    return Err(EditError::Stale(*slot));
                }
                cloth.live.set_uv(*slot, *new)?;
            }
            Prim::AddVertex { index, x, v, from } => {
                let placed = from.and_then(|f| f.place(&cloth.x, &cloth.v));
                let (x, v) = placed.unwrap_or((*x, *v));
                if *index as usize != cloth.len() || !x.is_finite() || !v.is_finite() {
                    return Err(EditError::NoVertex(*index));
                }
                cloth.live.push_vertex();
                cloth.x.push(x);
                cloth.v.push(v);
                cloth.mass.push(0.0);
                cloth.inv_mass.push(0.0);
                cloth.pinned.push(false);
                touched.added.push(*index);
            }
            Prim::RemoveVertex { index, .. } => {
                if *index as usize + 1 != cloth.len() || !cloth.live.pop_vertex() {
                    return Err(EditError::NoVertex(*index));
                }
                cloth.x.pop();
                cloth.v.pop();
                cloth.mass.pop();
                cloth.inv_mass.pop();
                // `sync` drops touched vertices past the end (a retain here cost O(n)
                // per vertex: seconds to undo a large added piece).
                cloth.pinned.pop();
                touched.added.retain(|&a| a != *index);
                touched.copies.retain(|c| c.0 != *index && c.1 != *index);
            }
            Prim::Move { .. }
            | Prim::MoveOnto { .. }
            | Prim::MoveOff { .. }
            | Prim::Merge { .. }
            | Prim::Unmerge { .. }
            | Prim::Nudge { .. } => {
                move_vertices(cloth, p)?;
                // A weld opened in place: its two sides parted as a fresh cut's.
                if let Prim::Unmerge { a, b, apart, .. } = p
                    && *apart == [glam::Vec3::ZERO; 2]
                {
                    touched.copies.push((*b, *a));
                }
            }
            Prim::Pin { vertex, new, .. } => {
                let i = *vertex as usize;
                if i >= cloth.len() {
                    return Err(EditError::NoVertex(*vertex));
                }
                cloth.set_pinned(i, *new);
                touched.verts.push(*vertex);
            }
            Prim::Paint(patch) => self.texture.apply(patch, false),
            Prim::Seam { index, old, new } => self.set_seam(*index, old, new)?,
            Prim::Piece { index, old, new } => {
                self.set_piece(*index, old, new)?;
                touched.pieces = true;
            }
            Prim::Substeps { new, .. } => self.sim.substeps = *new as usize,
        }
        Ok(())
    }

    /// Applies `prims` as one transaction and brings masses, solver and contacts up to
    /// date. On failure, rolls back and returns the error: nothing changed.
    pub(super) fn apply_prims(&mut self, prims: &[Prim]) -> Result<(), EditError> {
        self.check_editable()?;
        let before = moved_now(&self.sim.cloth, prims);
        let mut touched = Touched::default();
        for (k, p) in prims.iter().enumerate() {
            if let Err(e) = self.apply_prim(p, &mut touched) {
                let mut ignore = Touched::default();
                for q in prims[..k].iter().rev() {
                    // The inverse of an applied primitive always applies.
                    let _ = self.apply_prim(&q.inverse(), &mut ignore);
                }
                // An inverse puts a vertex where an undo wants it, which need not be where
                // it was (a zip or a weld undone opens parted off the seam, where it was
                // zipped from a stitch's length away): put back, and nothing parted.
                let cloth = &mut self.sim.cloth;
                for &(v, x, vel) in &before {
                    cloth.x[v as usize] = x;
                    cloth.v[v as usize] = vel;
                }
                ignore.copies.clear();
                self.sync(&mut ignore);
                return Err(e);
            }
        }
        self.sync(&mut touched);
        // The cloth changed: a weld refused before may go now.
        self.weld_refused.clear();
        Ok(())
    }

    /// Applies `prims` whole or not at all, like [`Design::apply_prims`], but leaves the
    /// incremental update to [`Design::record_batch`]: for an edit that reads the mesh
    /// between its steps (an exact cut splits an edge, then finds the next crossing), so
    /// the solver and the guard are brought up to date once, not at every step.
    pub(super) fn apply_unsynced(
        &mut self,
        prims: &[Prim],
        batch: &mut Batch,
    ) -> Result<(), EditError> {
        self.check_editable()?;
        for (k, p) in prims.iter().enumerate() {
            if let Err(e) = self.apply_prim(p, &mut batch.0) {
                for q in prims[..k].iter().rev() {
                    // The inverse of an applied primitive always applies.
                    let _ = self.apply_prim(&q.inverse(), &mut batch.0);
                }
                return Err(e);
            }
        }
        Ok(())
    }

    /// Takes back `applied` (applied through [`Design::apply_unsynced`] into `batch`),
    /// last first, and brings the solver and contact up to date: nothing changed.
    pub(super) fn abandon_batch(&mut self, applied: &[Prim], mut batch: Batch) {
        for q in applied.iter().rev() {
            // The inverse of an applied primitive always applies.
            let _ = self.apply_prim(&q.inverse(), &mut batch.0);
        }
        self.sync_batch(batch);
    }

    /// Brings the solver and contact up to date for a batch applied whole, and records
    /// `applied` (with the parting of any fresh cut it made) as one operation.
    pub(super) fn record_batch(
        &mut self,
        label: &'static str,
        mut applied: Vec<Prim>,
        batch: Batch,
    ) {
        self.sync_batch(batch);
        applied.append(&mut self.parting);
        self.history.push(Edit {
            label,
            prims: applied,
            auto: false,
        });
    }

    /// The incremental update for everything a batch touched.
    fn sync_batch(&mut self, mut batch: Batch) {
        self.sync(&mut batch.0);
        self.weld_refused.clear();
    }

    fn sync(&mut self, touched: &mut Touched) {
        // The cloth changed: stalled pairs may close now (`stalls`).
        self.stalls.reset();
        if touched.pieces {
            // Each piece's fabric first: the masses and elements below are its.
            let said = match self.apply_fabrics() {
                Ok(notes) => notes,
                Err(e) => vec![format!("the pieces' fabrics were not applied: {e}")],
            };
            // Every piece edit looks the fabrics up again: say each thing once.
            for n in said {
                if !self.sim.notices.contains(&n) {
                    self.sim.notices.push(n);
                }
            }
        }
        self.part_copies(&touched.copies);
        touched.verts.sort_unstable();
        touched.verts.dedup();
        touched
            .verts
            .retain(|&v| (v as usize) < self.sim.cloth.len());
        touched.edges.sort_unstable();
        touched.edges.dedup();
        touched.tris.sort_unstable();
        touched.tris.dedup();
        self.sim
            .cloth_edited(&touched.tris, &touched.edges, &touched.verts);
    }

    /// Applies an operation's primitives and records it for undo.
    pub(super) fn commit(
        &mut self,
        label: &'static str,
        prims: Vec<Prim>,
    ) -> Result<(), EditError> {
        self.commit_as(label, prims, false)
    }

    /// [`commit`](Self::commit) for an edit the design makes itself (a seam's weld):
    /// undone and redone with the designer's operation under it ([`Edit::auto`]).
    pub(super) fn commit_auto(
        &mut self,
        label: &'static str,
        prims: Vec<Prim>,
    ) -> Result<(), EditError> {
        self.commit_as(label, prims, true)
    }

    fn commit_as(
        &mut self,
        label: &'static str,
        prims: Vec<Prim>,
        auto: bool,
    ) -> Result<(), EditError> {
        let mut prims = prims;
        self.apply_prims(&prims)?;
        prims.append(&mut self.parting);
        if self.sim.cloth.live.tri_count() == 0 {
            // A design with no cloth cannot be saved and loaded again: refuse, as if
            // nothing happened (the inverse of applied primitives always applies).
            let inverse: Vec<Prim> = prims.iter().rev().map(Prim::inverse).collect();
            let _ = self.apply_prims(&inverse);
            return Err(EditError::LastCloth);
        }
        self.history.push(Edit { label, prims, auto });
        Ok(())
    }

    /// Undoes the designer's last operation, and first the welds made since that depend
    /// on it (its own seam's, and those sharing their vertices or seams: undone alone, a
    /// weld closes again in the next frame, so a designer's undo seemed to do nothing
    /// while a seam zipped); the welds of other seams stay (`commute`). Returns its label.
    /// Refused, the operation kept for a later undo, when that would make a vbd cloth cross
    /// itself or the body. With only welds to undo (a pattern's seams closing on their
    /// own), nothing is undone.
    pub fn undo(&mut self) -> Result<&'static str, EditError> {
        let group = self.history.undo_group();
        let Some(label) = self.history.undo_edits(group).last().map(|e| e.label) else {
            return Err(if self.history.undo_len() > 0 {
                EditError::OnlyWeldsToUndo
            } else {
                EditError::NothingToUndo
            });
        };
        // What goes, newest first: the welds made since the last undo (taken back and not
        // redone: a redo further down the stack must find the design as that undo left
        // it), then the operation and the welds that depend on it.
        let dropped = self.history.autos_over_redo().min(group - 1);
        let mut older: Vec<&Edit> = self.history.newest(group).skip(dropped).collect();
        older.reverse();
        let goes: Vec<bool> = std::iter::repeat_n(true, dropped)
            .chain(commute::dependents(&older).into_iter().rev())
            .collect();
        // All of it is checked before any of it is undone, newest first.
        let inverse: Vec<Prim> = (self.history.newest(group).zip(&goes))
            .filter(|(_, go)| **go)
            .flat_map(|(e, _)| e.prims.iter().rev().map(Prim::inverse))
            .collect();
        self.history_check(&inverse, ["undoing", "undo"], label)?;
        let going = (0..goes.len()).filter(|&i| goes[i]);
        // Each one removed moves those under it one place up.
        for (removed, i) in going.enumerate() {
            let Some(edit) = self.history.remove_newest(i - removed) else {
                break;
            };
            let inverse: Vec<Prim> = edit.prims.iter().rev().map(Prim::inverse).collect();
            if let Err(e) = self.apply_prims(&inverse) {
                self.history.clear();
                return Err(e);
            }
            if i >= dropped {
                self.history.push_redo(edit);
            }
        }
        // A garment's waist held while it settles (an imported skirt's) may be what was
        // undone: the holds of vertices gone with it go too, so that a piece added later
        // in their places is not held.
        let live = &self.sim.cloth.live;
        self.holds.retain(|h| live.vertex_alive(h.vertex));
        Ok(label)
    }

    /// Under the vbd model, whose cloth never crosses, refuses applying `prims` (undoing or
    /// redoing `label`, `[doing, again]` naming which) when that would make new crossings
    /// (`no_cross`); the other models' undo and redo restore what was, crossed or not.
    fn history_check(
        &self,
        prims: &[Prim],
        [doing, again]: [&'static str; 2],
        label: &'static str,
    ) -> Result<(), EditError> {
        if !self.sim.never_crosses() {
            return Ok(());
        }
        match self.new_crossings(prims) {
            0 => Ok(()),
            crossings => Err(EditError::HistoryWouldCross {
                doing,
                label,
                crossings,
                again,
                // An unpicked seam whose sides have fallen apart is sewn again by a seam,
                // which pulls them together first.
                hint: if label == "remove seam" && again == "undo" {
                    ", or sew the two edges again (a seam pulls them together and joins them \
                     as they meet)"
                } else {
                    ""
                },
            }),
        }
    }

    /// Redoes the last undone operation, and the welds undone with it; returns its
    /// label. The welds made since the undo (a stalled pair of another seam closing) are
    /// taken back first, so the operation finds the design as it was undone, and the
    /// whole is checked before any of it is applied. Where its welds would now cross (the
    /// cloth has moved since: a seam's two sides hang apart) and nothing older waits to be
    /// redone, the operation is redone without them, and a notice says so: a seam pulls
    /// its sides together again and welds them as they meet.
    pub fn redo(&mut self) -> Result<&'static str, EditError> {
        let group = self.history.redo_group();
        let Some(label) = self.history.redo_edits(group).next().map(|e| e.label) else {
            return Err(EditError::NothingToRedo);
        };
        let since = self.history.autos_over_redo();
        let prims = |h: &History, k: usize| -> Vec<Prim> {
            (h.newest(since))
                .flat_map(|e| e.prims.iter().rev().map(Prim::inverse))
                .chain((h.redo_edits(k)).flat_map(|e| e.prims.iter().cloned()))
                .collect()
        };
        let mut redone = group;
        if let Err(e) = self.history_check(&prims(&self.history, group), ["redoing", "redo"], label)
        {
            // Without the welds, when no older redo needs the design as they left it.
            if group == 1 || group < self.history.redo_len() {
                return Err(e);
            }
            self.history_check(&prims(&self.history, 1), ["redoing", "redo"], label)?;
            redone = 1;
        }
        for _ in 0..since {
            let Some(edit) = self.history.drop_newest() else {
                break;
            };
            let inverse: Vec<Prim> = edit.prims.iter().rev().map(Prim::inverse).collect();
            if let Err(e) = self.apply_prims(&inverse) {
                self.history.clear();
                return Err(e);
            }
        }
        for i in 0..group {
            let Some(edit) = self.history.pop_redo() else {
                break;
            };
            if i >= redone {
                continue;
            }
            if let Err(e) = self.apply_prims(&edit.prims) {
                self.history.clear();
                return Err(e);
            }
            self.history.push_after_redo(edit);
        }
        if redone < group {
            self.sim.notices.push(format!(
                "Redone: {label}, but not its {} welds (the cloth has moved since the \
                 undo): the stitches pull the sides together and weld them again",
                group - redone
            ));
        }
        Ok(label)
    }

    /// Applies a seam primitive: `old == None` inserts at `index` (up to the end),
    /// `new == None` removes the seam there, both replace it.
    pub(super) fn set_seam(
        &mut self,
        index: u32,
        old: &Option<Seam>,
        new: &Option<Seam>,
    ) -> Result<(), EditError> {
        let i = index as usize;
        if old.is_some() && self.seams.get(i) != old.as_ref() {
            return Err(EditError::StaleSeam(index));
        }
        if let Some(s) = new
            && s.pairs.iter().any(|&(a, b)| {
                a as usize >= self.sim.cloth.len() || b as usize >= self.sim.cloth.len()
            })
        {
            return Err(EditError::StaleSeam(index));
        }
        // A seam comes and goes at its place in the list (the later ones move up one,
        // and back on undo).
        match (old, new) {
            (None, Some(s)) if i <= self.seams.len() => self.seams.insert(i, s.clone()),
            (Some(_), None) if i < self.seams.len() => {
                self.seams.remove(i);
            }
            (Some(_), Some(s)) => self.seams[i] = s.clone(),
            _ => return Err(EditError::StaleSeam(index)),
        }
        Ok(())
    }

    /// Piece record `index` from `old` to `new` (appending and removing at the end).
    fn set_piece(
        &mut self,
        index: u32,
        old: &Option<PieceRecord>,
        new: &Option<PieceRecord>,
    ) -> Result<(), EditError> {
        let i = index as usize;
        let stale = || {
            EditError::Piece(format!(
                "the design changed underneath this edit (piece record {index})"
            ))
        };
        if self.pieces.get(i) != old.as_ref() {
            return Err(stale());
        }
        match (old, new) {
            (None, Some(r)) if i == self.pieces.len() => self.pieces.push(r.clone()),
            (Some(_), None) if i + 1 == self.pieces.len() => {
                self.pieces.pop();
            }
            (Some(_), Some(r)) => self.pieces[i] = r.clone(),
            _ => return Err(stale()),
        }
        Ok(())
    }
}
