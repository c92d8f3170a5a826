//! Pins: a vertex held where it is (inverse mass 0), set or freed as an undoable edit.

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;

impl Design {
    /// Pins or frees vertex `v` (undoable); pinning a pinned vertex or freeing a free
    /// one is refused (no empty step in the history).
    pub fn set_pin(&mut self, v: u32, pinned: bool) -> Result<(), EditError> {
        self.check_vertex(v)?;
        let old = self.sim.cloth.is_pinned(v as usize);
        match (old, pinned) {
            (true, true) => return Err(EditError::AlreadyPinned),
            (false, false) => return Err(EditError::NoPinThere),
            _ => {}
        }
        self.commit(
            "pin",
            vec![Prim::Pin {
                vertex: v,
                old,
                new: pinned,
            }],
        )
    }

    /// The pinned vertices of the cloth, in increasing order: those some triangle uses
    /// (a deleted piece's pins wait with it for an undo).
    pub fn pinned_vertices(&self) -> Vec<u32> {
        let cloth = &self.sim.cloth;
        (0..cloth.pinned.len() as u32)
            .filter(|&v| cloth.pinned[v as usize] && cloth.live.vertex_alive(v))
            .collect()
    }

    /// Frees every pin of [`Design::pinned_vertices`] as one undoable edit; returns how
    /// many. None to free is refused ([`EditError::NoPins`]).
    pub fn free_pins(&mut self) -> Result<usize, EditError> {
        let prims: Vec<Prim> = (self.pinned_vertices().into_iter())
            .map(|vertex| Prim::Pin {
                vertex,
                old: true,
                new: false,
            })
            .collect();
        if prims.is_empty() {
            return Err(EditError::NoPins);
        }
        let n = prims.len();
        self.commit("free pins", prims)?;
        Ok(n)
    }

    /// The name of the listed piece vertex `v` belongs to (the first, for a vertex a
    /// seam welded into two pieces); `None` for a vertex no triangle uses.
    pub fn piece_name_of(&self, v: u32) -> Option<String> {
        let slots = self.sim.cloth.live.tris_of(v);
        (self.listed().into_iter())
            .find(|(_, tris)| tris.iter().any(|t| slots.contains(t)))
            .map(|(info, _)| info.name)
    }
}
