//! Pins: a vertex held where it is (inverse mass 0), set or freed as an undoable edit.

use super::document::Design;
use super::error::EditError;
use super::prim::Prim;

impl Design {
    /// Pins or frees vertex `v` (undoable).
    pub fn set_pin(&mut self, v: u32, pinned: bool) -> Result<(), EditError> {
        self.check_vertex(v)?;
        let old = self.sim.cloth.is_pinned(v as usize);
        self.commit(
            "pin",
            vec![Prim::Pin {
                vertex: v,
                old,
                new: pinned,
            }],
        )
    }
}
