//! Each piece hangs as its own fabric: the pieces' fabric names looked up in the fabric
//! library and handed to the simulation as material zones, one per piece's band of the
//! pattern plane (`solver::MaterialZones`).
//!
//! A piece whose fabric the library names hangs with that fabric's mass, stretch, shear
//! and bending (with its weft and bias shares) over the design's material; one named
//! [`DEFAULT_FABRIC`], or whose fabric was edited by hand (`", edited"`), hangs as the
//! design's material. Damping, drag, friction and the contact thickness are the design's
//! for every piece. A name the library does not have (a file from another library)
//! hangs as the design's material too, with a notice.

use super::document::Design;
use super::error::EditError;
use super::garment::DEFAULT_FABRIC;
use super::pieces::PieceRecord;
use crate::error::ConfigError;
use crate::fabric::Library;
use crate::solver::{Material, MaterialZones, Zone};

/// What a fabric's name gains when its values are changed by hand.
pub const EDITED: &str = ", edited";

/// The material a piece of fabric `name` hangs with over the design's `base`: the
/// library's fabric, or `None` for the design's own material (with why, when the name is
/// not one the design gives).
fn piece_material(name: &str, base: &Material, lib: &Library) -> Result<Material, Option<String>> {
    if name.is_empty() || name == DEFAULT_FABRIC || name.ends_with(EDITED) {
        return Err(None);
    }
    lib.get(name).map(|f| f.material_over(base)).map_err(|_| {
        Some(format!(
            "the fabric library has no {name:?}: those pieces hang as the design's material"
        ))
    })
}

/// The zones of `records` over the design's material `base`, and notices for fabrics
/// the library does not have.
pub fn fabric_zones(
    records: &[PieceRecord],
    base: &Material,
) -> Result<(MaterialZones, Vec<String>), ConfigError> {
    let lib = Library::builtin();
    let mut notes: Vec<String> = Vec::new();
    let mut zones = Vec::with_capacity(records.len());
    for r in records {
        let material = match piece_material(&r.fabric, base, &lib) {
            Ok(m) => m,
            Err(note) => {
                if let Some(n) = note.filter(|n| !notes.contains(n)) {
                    notes.push(n);
                }
                *base
            }
        };
        let (lo, hi) = r.band();
        zones.push(Zone { lo, hi, material });
    }
    Ok((MaterialZones::new(zones, base)?, notes))
}

impl Design {
    /// Hands each piece's fabric to the simulation (after the pieces or the design's
    /// material changed); returns notices about fabrics the library does not have.
    pub fn apply_fabrics(&mut self) -> Result<Vec<String>, ConfigError> {
        let (zones, notes) = fabric_zones(&self.pieces, &self.sim.material)?;
        self.sim.set_zones(zones)?;
        Ok(notes)
    }

    /// Every piece's fabric named anew by `rename` (a whole-design fabric, or values
    /// set by hand: `", edited"`), in the undo history's piece records too. Not an
    /// operation of its own (the design's material is not undone either), but the
    /// records the history holds must match the pieces, or undoing the piece that came
    /// before the change would find its record stale and lose the whole history.
    /// The fabrics are not applied here ([`Design::apply_fabrics`]).
    pub fn rename_fabrics(&mut self, mut rename: impl FnMut(&str) -> String) {
        let mut relabel = |r: &mut PieceRecord| r.fabric = rename(&r.fabric);
        self.pieces.iter_mut().for_each(&mut relabel);
        self.history.relabel_pieces(relabel);
    }

    /// Piece `index` (in [`Design::piece_list`] order) made of the library's fabric
    /// `name`, or of the design's material with [`DEFAULT_FABRIC`]; undoable. A part a
    /// cut left of a piece becomes a piece of its own, of that fabric (a fabric belongs
    /// to a whole pattern piece; see [`Design::separated`]). Returns the piece's name.
    pub fn set_piece_fabric(&mut self, index: usize, name: &str) -> Result<String, EditError> {
        let (k, list) = self.own_record(
            index,
            "no fabric of its own; set the design's fabric instead",
        )?;
        let name = name.trim();
        if name != DEFAULT_FABRIC {
            Library::builtin()
                .get(name)
                .map_err(|e| EditError::Piece(e.to_string()))?;
        }
        let old = &self.pieces[k];
        if old.fabric == name {
            return Ok(list[index].name.clone());
        }
        if list.iter().filter(|p| p.record == Some(k)).count() > 1 {
            let prims = self.separated(k, index, name)?;
            self.commit("piece fabric", prims)?;
            return Ok(list[index].name.clone());
        }
        let new = PieceRecord {
            fabric: name.to_string(),
            ..old.clone()
        };
        self.replace_record("piece fabric", k, new)
    }
}
