//! The pause: the simulation held or run again (SET_SIMULATING), and held for a piece
//! added, copied or moved while the cloth runs, which would otherwise fall before the
//! designer can sew it; and the cloth afloat while a seam made as it runs pulls together.

use shared::command::Command;

use super::Service;
use crate::commands::{STITCHED_PULL, carry_out};

/// What an answer starts with when the edit paused the simulation: first, where a
/// reply's 200 bytes cannot cut it off (the same words as a new scene's).
pub(super) const PAUSED_FOR_IT: &str = "Paused (simulate to drape it). ";

impl Service<'_> {
    /// Pauses the simulation or runs it again; the sentence says what that means.
    pub(super) fn set_simulating(&mut self, on: bool) -> String {
        self.tel_due = true;
        match (on, self.paused) {
            (false, true) => "Paused already: edits apply, the cloth stays where it is".into(),
            (false, false) => {
                self.paused = true;
                "Paused: the cloth stays where it is while you place, cut and sew pieces; \
                 nothing falls and no stitch pulls until you simulate again"
                    .into()
            }
            (true, false) => "Simulating already".into(),
            (true, true) => {
                self.paused = false;
                // Seams made while paused close before their pieces fall, as a pattern's
                // do (`Design::float_while_sewing`).
                let fresh = (self.design.seams.iter())
                    .any(|s| !s.pairs.is_empty() && s.pairs.iter().all(|(a, b)| a != b));
                if fresh {
                    self.design.float_while_sewing();
                    "Simulating: the new seams pull their pieces together before they fall \
                     (at most a second)"
                        .into()
                } else {
                    "Simulating".into()
                }
            }
        }
    }

    /// A piece added, copied or moved (`c`): while the cloth runs, the simulation pauses
    /// with it, so that the piece waits where it was placed, as a designer places and
    /// sews pieces before draping them (a piece added to a running cloth fell to the
    /// floor before its seam could be picked). Paused already, or refused, nothing else
    /// changes.
    pub(super) fn hold_for_piece(&mut self, c: &Command) -> Result<String, String> {
        let done = carry_out(&mut self.design, c)?;
        if self.paused {
            return Ok(done);
        }
        self.paused = true;
        self.tel_due = true;
        Ok(format!("{PAUSED_FOR_IT}{done}"))
    }

    /// A seam made while the cloth runs (SEAM, SEAM_PLANE): the cloth floats, without
    /// gravity, while the new pairs pull together, as the seams made while paused do
    /// once it is simulated again (`Design::float_while_sewing`: at most a second, and
    /// not once every seam has closed). A sleeve seamed into a draped dress's armholes
    /// closed 0 and 16 of 24 pairs a side over the shoulder without it, and all of them
    /// with it (docs/garments.md). Paused, nothing changes: the float waits for Simulate.
    pub(super) fn float_new_seam(&mut self, c: &Command) -> Result<String, String> {
        let done = carry_out(&mut self.design, c)?;
        if self.paused {
            return Ok(done);
        }
        self.design.float_while_sewing();
        Ok(done.replacen(
            STITCHED_PULL,
            "stitched; they pull together (the cloth afloat, at most 1 s)",
            1,
        ))
    }
}
