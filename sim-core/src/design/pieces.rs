//! Pieces as a designer names them. A design built from a pattern keeps one
//! [`PieceRecord`] per piece: its name, fabric, grain, where it was placed, and its
//! outline where it lies in the design's pattern plane (pieces side by side along x, so
//! each owns a band of x there). The cloth's triangles are the truth of what a piece is
//! now: `piece_list` names the cloth's connected parts by these records.

use glam::Vec2;
use serde::{Deserialize, Serialize};

use super::garment::Placement;
use crate::mesh::mesher::Outline;

/// Longest piece or fabric name, characters.
pub const MAX_NAME: usize = 120;

/// A piece as the design keeps it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PieceRecord {
    pub name: String,
    /// The fabric's name (the fabric library names them).
    pub fabric: String,
    /// The warp's direction in the piece's pattern, radians from its x axis.
    pub grain: f32,
    /// Where the piece started in 3D.
    pub placement: Option<Placement>,
    /// Where the piece's own pattern coordinates lie in the design's pattern plane (its
    /// x and -z), m.
    pub offset: Vec2,
    /// The piece's outline as made, in its own coordinates, m.
    pub outline: Outline,
}

impl PieceRecord {
    /// The band of the design's pattern x this piece owns.
    pub(super) fn band(&self) -> (f32, f32) {
        let (lo, hi) = crate::mesh::bounds2(self.outline.loops.first().map_or(&[], |l| &l[..]));
        (lo.x + self.offset.x, hi.x + self.offset.x)
    }

    /// Checks a record read from a file: a name, finite numbers, loops of 3 points.
    pub fn check(&self) -> Result<(), String> {
        if self.name.trim().is_empty() || self.name.chars().count() > MAX_NAME {
            return Err(format!(
                "a piece's name must have 1 to {MAX_NAME} characters, got {:?}",
                self.name
            ));
        }
        if self.fabric.chars().count() > MAX_NAME {
            return Err(format!(
                "piece {}: the fabric's name is too long",
                self.name
            ));
        }
        let finite = self.grain.is_finite()
            && self.offset.is_finite()
            && self.outline.loops.iter().flatten().all(|p| p.is_finite());
        if !finite {
            return Err(format!("piece {}: a number is NaN or infinite", self.name));
        }
        if self.outline.loops.is_empty() || self.outline.loops.iter().any(|l| l.len() < 3) {
            return Err(format!(
                "piece {}: an outline needs loops of 3 points or more",
                self.name
            ));
        }
        Ok(())
    }
}
