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
    /// Names the designer gave parts a cut left of the piece (none in files written
    /// before parts could be named): the part that holds a name's point is called so,
    /// the piece's other parts by its own name.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<PartName>,
    /// The bounds its placement is measured from, `[lo.x, lo.y, hi.x, hi.y]` in its own
    /// coordinates, m, where they are not its outline's: a piece read from a pattern that
    /// saved its start (its outline since cut or sewn), which starts where it started.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// (Boxed: a record is carried twice in every undo step that changes it.)
    pub frame: Option<Box<[f32; 4]>>,
}

/// A name one part of a cut piece has of its own.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartName {
    /// Points spread over the part, in the piece's own pattern coordinates, m: the part
    /// that holds the most of them has the name. The pattern does not move as the cloth
    /// does, and a cut or a region cut away leaves some of them in one part.
    pub points: Vec<Vec2>,
    pub name: String,
}

/// Most points a part's name keeps.
pub(super) const PART_POINTS: usize = 16;
/// Most named parts one piece may carry.
pub(super) const MAX_PART_NAMES: usize = 1_000;

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
            && self.outline.loops.iter().flatten().all(|p| p.is_finite())
            && self.frame.iter().all(|f| f.iter().all(|v| v.is_finite()));
        if !finite {
            return Err(format!("piece {}: a number is NaN or infinite", self.name));
        }
        if self.outline.loops.is_empty() || self.outline.loops.iter().any(|l| l.len() < 3) {
            return Err(format!(
                "piece {}: an outline needs loops of 3 points or more",
                self.name
            ));
        }
        if self.parts.len() > MAX_PART_NAMES {
            return Err(format!(
                "piece {}: {} named parts (at most {MAX_PART_NAMES})",
                self.name,
                self.parts.len()
            ));
        }
        for part in &self.parts {
            if part.name.trim().is_empty() || part.name.chars().count() > MAX_NAME {
                return Err(format!(
                    "piece {}: a part's name must have 1 to {MAX_NAME} characters, got {:?}",
                    self.name, part.name
                ));
            }
            let points = 1..=PART_POINTS;
            if !points.contains(&part.points.len()) || part.points.iter().any(|p| !p.is_finite()) {
                return Err(format!(
                    "piece {}: part {} needs 1 to {PART_POINTS} finite points",
                    self.name, part.name
                ));
            }
        }
        Ok(())
    }
}
