//! A design's frame: its seams' stitches handed to the solver, one simulation frame, then
//! what the frame did to the design as edits (tears of overstretched edges, welds of
//! stitches that closed).

use std::time::Instant;

use super::document::Design;
use super::parts::open_stitches;
use crate::solver::{FrameStats, PenPath, StepError};

impl Design {
    /// Steps one frame. On divergence the error says so; the state is then not usable.
    pub fn step(&mut self) -> Result<FrameStats, StepError> {
        self.step_with(&mut |_, _, _| None)
    }

    /// Steps one frame, asking `pen(substep, substeps, held)` before each substep where the
    /// pinch's pointer is and how hard it may pull (`None`: unchanged); then tears what
    /// is overstretched (when tearing is on) and welds stitches that closed, each as an
    /// undoable edit.
    pub fn step_with(&mut self, pen: &mut PenPath<'_>) -> Result<FrameStats, StepError> {
        let t0 = Instant::now();
        self.sim.stitches.clear();
        self.sim.stitches.extend(open_stitches(&self.seams));
        // With tearing on, the strain limit lets every side stretch past the tear
        // threshold (a quarter beyond it: a side no longer than the limit never passes
        // it): held under 1.2x, a cloth pulled by the pen followed it and never tore.
        self.sim.stretch_floor = if self.tear.enabled {
            1.25 * self.tear.threshold
        } else {
            0.0
        };
        let mut stats = self.sim.step_with(pen)?;
        stats.torn = self.tear_overstretched();
        stats.welded = self.weld_close_stitches();
        stats.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        Ok(stats)
    }
}
