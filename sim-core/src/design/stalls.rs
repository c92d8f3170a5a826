//! Stitched pairs that stopped closing, told to the designer.
//!
//! A pair the cloth cannot bring together (held apart by the body, or by what a weld
//! there would cross) stays open while its stitch pulls on: on the 2 x 8k dress, seam A's
//! three pairs at a shoulder's neck end stay 2-4 cm open in every run. Nothing said so
//! until the report at the end. So once no open pair has come a millimetre nearer for
//! [`STALL_TOLD_AFTER`] frames (`ClosingWatch`: the xpbd model's links have gone back to
//! their straight distances by then and had a second to draw the pairs in), the designer
//! is told once which pairs stopped closing and how far apart they are (a notice, said by
//! the scenario and the service as it happens); the report marks them `stalled`. An edit
//! (a cut, a sew, an undo, the weld of another pair) or the pen's pinch starts the watch
//! afresh.
//!
//! Stalled stitches no longer keep the cloth awake: once the pairs have stalled, a cloth
//! that has come to rest may sleep (`solver::rest`) with them open, where before it was
//! simulated every frame for nothing (cloth-sim took 70% of a core and the studio beside
//! it drew 2 frames a second). Sleep moves nothing, and the edit or pinch that may help
//! the pairs wakes it.
//!
//! The stitches keep pulling, as a sewing line that cannot close does in CLO and
//! Marvelous Designer. Letting them go was tried (docs/garments.md): the open corner
//! sprang back, and the shipped dress at density 0.15001 was no longer at rest at frame
//! 600.

use super::document::Design;
use super::sewing_pattern::seam_label;

/// Frames without a pair closing after which the open pairs count as stalled: three
/// seconds at 60 Hz (the xpbd links tighten over the first two, `xpbd::sewing`).
pub const STALL_TOLD_AFTER: u32 = 180;

impl Design {
    /// Watches the open pairs for a frame, and tells the designer once when they have
    /// stalled (the module's doc).
    pub(super) fn watch_stalls(&mut self) {
        if self.sim.pinch().is_some() {
            self.stalls.reset();
            return;
        }
        let open = self.seams.iter().flat_map(|s| s.open_pairs());
        self.stalls.quiet = self.stalls.closing.observe(open, &self.sim.cloth.x);
        if self.stitches_stalled() && !self.stalls.told {
            self.stalls.told = true;
            let said = self.stalled_pairs();
            let one = self.seams.iter().flat_map(|s| s.open_pairs()).count() == 1;
            let (its, pull) = match one {
                true => ("its stitch still pulls", "it"),
                false => ("their stitches still pull", "them"),
            };
            self.sim.notices.push(format!(
                "frame {}: {said} stopped closing; {its} (an edit or a pinch may help {pull})",
                self.sim.frame
            ));
        }
    }

    /// Whether the open pairs have stopped closing: none has come a millimetre nearer
    /// for [`STALL_TOLD_AFTER`] frames.
    pub fn stitches_stalled(&self) -> bool {
        self.stalls.quiet >= STALL_TOLD_AFTER
    }

    /// Seam `seam`'s stalled pairs: how many, and the least and the most distance
    /// between a pair's two vertices, m; `None` while the pairs are closing (or the seam
    /// has none open).
    pub fn stalled_in(&self, seam: usize) -> Option<(usize, f32, f32)> {
        if !self.stitches_stalled() {
            return None;
        }
        let x = &self.sim.cloth.x;
        let gap = |(a, b): (u32, u32)| match (x.get(a as usize), x.get(b as usize)) {
            (Some(p), Some(q)) => p.distance(*q),
            _ => 0.0,
        };
        let gaps = self.seams.get(seam)?.open_pairs().map(gap);
        let (n, lo, hi) = gaps.fold((0, f32::MAX, 0.0f32), |(n, lo, hi), g| {
            (n + 1, lo.min(g), hi.max(g))
        });
        (n > 0).then_some((n, lo, hi))
    }

    /// The stalled pairs, seam by seam: "3 pairs of seam A (15-41 mm apart)".
    fn stalled_pairs(&self) -> String {
        let said: Vec<String> = (0..self.seams.len())
            .filter_map(|i| {
                let (n, lo, hi) = self.stalled_in(i)?;
                let (lo, hi, label) = (lo * 1e3, hi * 1e3, seam_label(i));
                Some(match n {
                    1 => format!("1 pair of seam {label} ({hi:.0} mm apart)"),
                    n => format!("{n} pairs of seam {label} ({lo:.0}-{hi:.0} mm apart)"),
                })
            })
            .collect();
        said.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    /// A 0.5 m cloth of 8 x 8 cells at y = 1, its two top corners pinned 0.5 m apart and
    /// stitched together: a pair that can never close.
    fn pinned_stitch() -> crate::design::Design {
        let n = 8u32;
        let mesh = ClothMesh::grid(0.5, 0.5, n as usize, n as usize, 1.0).unwrap();
        let mut d = crate::design::floating(mesh, ModelKind::Xpbd);
        d.sim.env.gravity = Vec3::new(0.0, -9.81, 0.0);
        d.sim.pin(0);
        d.sim.pin(n as usize);
        d.add_seam(&[0, 1], &[n, n - 1], 0.5).unwrap();
        d
    }

    #[test]
    fn pairs_that_stop_closing_are_told_once_and_an_edit_watches_them_afresh() {
        let mut d = pinned_stitch();
        let mut stalled_at = None;
        for f in 0..super::STALL_TOLD_AFTER + 240 {
            d.step().unwrap();
            if d.stitches_stalled() {
                stalled_at.get_or_insert(f);
            }
        }
        let at = stalled_at.expect("the pairs never stalled");
        assert!(at >= super::STALL_TOLD_AFTER, "stalled at frame {at}");
        // Told once, and the stitches still pull.
        assert_eq!(d.sim.notices.len(), 1, "{:?}", d.sim.notices);
        let n = &d.sim.notices[0];
        assert!(
            n.contains("2 pairs of seam A (") && n.contains("mm apart) stopped closing"),
            "{n}"
        );
        assert_eq!(d.sim.stitches.len(), 2);
        assert!(d.sim.stitches.iter().all(|s| s.max_force == 0.5));
        // The studio's seam list reads the same pairs: two, the pinned corners' 0.5 m
        // apart the farthest.
        let (n, lo, hi) = d.stalled_in(0).expect("seam A's pairs are stalled");
        assert_eq!(n, 2);
        assert!(0.0 < lo && lo <= hi && (hi - 0.5).abs() < 1e-3, "{lo} {hi}");
        assert_eq!(d.stalled_in(1), None, "there is no seam B");
        // An edit elsewhere: watched afresh, not told again at once.
        d.cut_vertex(40, Vec3::X).unwrap();
        assert!(!d.stitches_stalled());
        assert_eq!(d.stalled_in(0), None);
        d.step().unwrap();
        assert!(!d.stitches_stalled());
        assert_eq!(d.sim.notices.len(), 1);
    }

    #[test]
    fn a_cloth_at_rest_with_stalled_pairs_sleeps_and_an_edit_wakes_it() {
        let mut d = pinned_stitch();
        d.sim.sleep = Some(crate::solver::SleepRule::default());
        let mut first = None;
        for f in 0..super::STALL_TOLD_AFTER + 600 {
            let stats = d.step().unwrap();
            if stats.asleep && first.is_none() {
                first = Some(f);
                // Never before its pairs were told stalled, and they are still open.
                assert!(d.stitches_stalled(), "asleep at frame {f} before the stall");
                assert_eq!(d.sim.stitches.len(), 2);
            }
        }
        let f = first.expect("a cloth at rest with stalled pairs never slept");
        assert!(f >= super::STALL_TOLD_AFTER, "asleep at frame {f}");
        assert!(d.sim.asleep());
        let x = d.sim.cloth.x.clone();
        d.step().unwrap();
        assert_eq!(d.sim.cloth.x, x, "a sleeping cloth moved");
        // An edit wakes it and watches the pairs afresh: simulated again.
        d.cut_vertex(40, Vec3::X).unwrap();
        assert!(!d.step().unwrap().asleep);
        assert!(!d.stitches_stalled());
    }
}
