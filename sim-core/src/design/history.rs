//! Undo and redo stacks with a memory bound: the oldest operations are forgotten first.

use std::collections::VecDeque;

use super::pieces::PieceRecord;
use super::prim::{Edit, Prim};

#[derive(Debug)]
pub struct History {
    undo: VecDeque<Edit>,
    redo: Vec<Edit>,
    /// The automatic edits on top of the undo stack made since the last undo while there
    /// is something to redo: a redo takes them back first ([`autos_over_redo`]).
    ///
    /// [`autos_over_redo`]: Self::autos_over_redo
    autos_over_redo: usize,
    bytes: usize,
    /// Most bytes the two stacks may hold together.
    pub max_bytes: usize,
    /// Most operations kept for undo.
    pub max_edits: usize,
}

impl Default for History {
    fn default() -> Self {
        Self {
            undo: VecDeque::new(),
            redo: Vec::new(),
            autos_over_redo: 0,
            bytes: 0,
            max_bytes: 256 << 20,
            max_edits: 10_000,
        }
    }
}

impl History {
    /// A new operation: it can be undone, and what was undone can no longer be redone;
    /// except after an automatic one ([`Edit::auto`], a seam's weld), which a redo takes
    /// back first: the seams left go on welding after an undo (a stalled pair closes,
    /// a pair of a seam sharing a corner with the undone one), and the redo must not be
    /// lost to that.
    pub fn push(&mut self, e: Edit) {
        if e.auto && !self.redo.is_empty() {
            self.autos_over_redo += 1;
        } else {
            for r in self.redo.drain(..) {
                self.bytes -= r.bytes();
            }
            self.autos_over_redo = 0;
        }
        self.push_after_redo(e);
    }

    /// Back on the undo stack after a redo (the rest of the redo stack stays).
    pub fn push_after_redo(&mut self, e: Edit) {
        self.bytes += e.bytes();
        self.undo.push_back(e);
        while (self.bytes > self.max_bytes || self.undo.len() > self.max_edits)
            && let Some(old) = self.undo.pop_front()
        {
            self.bytes -= old.bytes();
        }
        self.autos_over_redo = self.autos_over_redo.min(self.undo.len());
    }

    /// The newest operation off the undo stack, for the redo stack. (The automatic edits
    /// over the redo stack are not redone: [`drop_newest`](Self::drop_newest).)
    pub fn pop_undo(&mut self) -> Option<Edit> {
        self.remove_newest(0)
    }

    pub fn push_redo(&mut self, e: Edit) {
        self.bytes += e.bytes();
        self.redo.push(e);
    }

    pub fn pop_redo(&mut self) -> Option<Edit> {
        let e = self.redo.pop()?;
        self.bytes -= e.bytes();
        Some(e)
    }

    /// How many automatic edits (welds) were made since the last undo while there is
    /// something to redo: the newest on the undo stack. A redo takes them back before it
    /// redoes, so the design is again what it was before the undo.
    pub fn autos_over_redo(&self) -> usize {
        self.autos_over_redo
    }

    /// The newest `k` operations on the undo stack, newest first (the automatic ones over
    /// the redo stack: [`autos_over_redo`](Self::autos_over_redo)).
    pub fn newest(&self, k: usize) -> impl Iterator<Item = &Edit> + '_ {
        self.undo.iter().rev().take(k)
    }

    /// Drops the newest operation on the undo stack, taken back and never to be redone (an
    /// automatic edit over the redo stack: it followed from an undo, and what is redone
    /// later must find the design as that undo left it).
    pub fn drop_newest(&mut self) -> Option<Edit> {
        self.remove_newest(0)
    }

    /// Takes the `n`-th newest operation (0: the newest) off the undo stack, the others
    /// keeping their order: an undo takes a designer's operation with the welds that
    /// depend on it, and leaves those that commute with them (`commute`).
    pub fn remove_newest(&mut self, n: usize) -> Option<Edit> {
        let at = self.undo.len().checked_sub(n + 1)?;
        let e = self.undo.remove(at)?;
        self.bytes -= e.bytes();
        if n < self.autos_over_redo {
            self.autos_over_redo -= 1;
        }
        Some(e)
    }

    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
        self.autos_over_redo = 0;
        self.bytes = 0;
    }

    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }

    pub fn redo_len(&self) -> usize {
        self.redo.len()
    }

    /// The designer's operations that can be undone, each an undo step (with the
    /// automatic edits over it: [`Edit::auto`]).
    pub fn undo_steps(&self) -> usize {
        self.undo.iter().filter(|e| !e.auto).count()
    }

    /// The operations that can be redone, each a redo step (with the automatic edits that
    /// follow it).
    pub fn redo_steps(&self) -> usize {
        self.redo.iter().filter(|e| !e.auto).count()
    }

    /// Whether the newest operation on the undo stack is automatic.
    pub fn undo_top_is_auto(&self) -> bool {
        self.undo.back().is_some_and(|e| e.auto)
    }

    /// How many operations one undo takes back: the automatic ones on top and the
    /// designer's under them (all of them, automatic, when there is none).
    pub fn undo_group(&self) -> usize {
        let autos = self.undo.iter().rev().take_while(|e| e.auto).count();
        (autos + 1).min(self.undo.len())
    }

    /// How many operations one redo brings back: the next one and the automatic ones
    /// after it.
    pub fn redo_group(&self) -> usize {
        let autos = self
            .redo
            .iter()
            .rev()
            .skip(1)
            .take_while(|e| e.auto)
            .count();
        (autos + 1).min(self.redo.len())
    }

    /// The newest `k` operations on the undo stack, newest first; the last is the
    /// designer's when `k` is an [`undo_group`](Self::undo_group) that holds one, and
    /// none is yielded for a group of automatic operations alone.
    pub fn undo_edits(&self, k: usize) -> impl Iterator<Item = &Edit> + Clone + '_ {
        let group = self.undo.iter().rev().take(k);
        let designers = group.clone().any(|e| !e.auto);
        group.filter(move |_| designers)
    }

    /// The next `k` operations on the redo stack, in the order they are redone.
    pub fn redo_edits(&self, k: usize) -> impl Iterator<Item = &Edit> + '_ {
        self.redo.iter().rev().take(k)
    }

    /// Labels of the operations that can be undone, oldest first.
    pub fn labels(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.undo.iter().map(|e| e.label)
    }

    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// Applies `f` to every piece record the operations hold, on both stacks: what the
    /// design's pieces went through outside the history (a whole-design material or
    /// fabric, which relabels every piece) their records must follow, or undoing an
    /// earlier piece edit finds its record stale and the history is lost. A piece
    /// record's size does not count toward the memory bound, so the bound holds.
    pub fn relabel_pieces(&mut self, mut f: impl FnMut(&mut PieceRecord)) {
        for e in self.undo.iter_mut().chain(self.redo.iter_mut()) {
            for p in &mut e.prims {
                if let Prim::Piece { old, new, .. } = p {
                    old.iter_mut().chain(new.iter_mut()).for_each(&mut f);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Prim;
    use glam::Vec3;

    fn edit(n: usize) -> Edit {
        Edit {
            label: "move",
            auto: false,
            prims: vec![
                Prim::Move {
                    vertex: 0,
                    old: (Vec3::ZERO, Vec3::ZERO),
                    new: (Vec3::ONE, Vec3::ZERO),
                };
                n
            ],
        }
    }

    #[test]
    fn memory_bound_forgets_the_oldest() {
        let mut h = History {
            max_bytes: edit(10).bytes() * 3,
            ..History::default()
        };
        for _ in 0..5 {
            h.push(edit(10));
        }
        assert_eq!(h.undo_len(), 3);
        assert!(h.bytes() <= h.max_bytes);
        let e = h.pop_undo().unwrap();
        h.push_redo(e);
        assert_eq!(h.redo_len(), 1);
        // A new edit drops the redo stack.
        h.push(edit(1));
        assert_eq!(h.redo_len(), 0);
        assert_eq!(h.undo_len(), 3);
        assert_eq!(h.bytes(), 2 * edit(10).bytes() + edit(1).bytes());
    }

    #[test]
    fn an_undo_takes_the_automatic_edits_on_top_with_the_designers_under_them() {
        let mut h = History::default();
        let op = |label, auto| Edit {
            auto,
            label,
            ..edit(1)
        };
        h.push(op("weld", true));
        assert_eq!((h.undo_group(), h.undo_edits(1).count()), (1, 0));
        h.push(op("cut", false));
        h.push(op("weld", true));
        h.push(op("weld", true));
        assert_eq!((h.undo_len(), h.undo_steps()), (4, 1));
        assert_eq!(h.undo_group(), 3);
        let labels: Vec<_> = h.undo_edits(3).map(|e| e.label).collect();
        assert_eq!(labels, ["weld", "weld", "cut"]);
        for _ in 0..3 {
            let e = h.pop_undo().unwrap();
            h.push_redo(e);
        }
        assert_eq!((h.redo_group(), h.redo_steps()), (3, 1));
        assert_eq!(h.redo_edits(3).next().unwrap().label, "cut");
        // Only automatic edits left: nothing of the designer's to undo.
        assert_eq!((h.undo_group(), h.undo_edits(1).count()), (1, 0));
        // A weld after the undo keeps the redo stack, and is counted for the redo to take
        // back; a designer's edit clears both.
        h.push(op("weld", true));
        h.push(op("weld", true));
        assert_eq!((h.redo_steps(), h.autos_over_redo()), (1, 2));
        assert_eq!(h.newest(2).count(), 2);
        assert!(h.drop_newest().is_some());
        assert_eq!((h.autos_over_redo(), h.undo_len()), (1, 2));
        h.push(op("cut", false));
        assert_eq!((h.redo_len(), h.autos_over_redo()), (0, 0));
        let bytes: usize = h.newest(h.undo_len()).map(Edit::bytes).sum();
        assert_eq!(h.bytes(), bytes);
    }
}
