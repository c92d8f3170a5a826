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
//! The notice says what stands between a stalled pair's two ends, where something does
//! ([`Design::between`]): the body, or cloth. Cloth between them means the pair is
//! threaded round a fold the wrong way (on the 2 x 8k dress, the back's seam end lies
//! under a fold of the front's); no pull along the pair closes that without a
//! crossing (nor did a pen lifting the fold and carrying it across, docs/garments.md).
//!
//! The stitches keep pulling, as a sewing line that cannot close does in CLO and
//! Marvelous Designer. Letting them go was tried (docs/garments.md): the open corner
//! sprang back, and the shipped dress at density 0.15001 was no longer at rest at frame
//! 600.

use super::document::Design;
use super::sewing_pattern::seam_label;
use crate::collision::crossings::{segment_pierces, segment_pierces_body};

/// What lies across the straight line between a stitched pair's two ends (`Design::between`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Across {
    /// Nothing: the pair is held apart by the cloth's own pull, or friction.
    Nothing,
    /// The body's surface.
    Body,
    /// Cloth of the piece named (a fold the pair is threaded round).
    Cloth(String),
}

impl Across {
    /// The report's word for it: "nothing", "body" or "cloth".
    pub fn word(&self) -> &'static str {
        match self {
            Self::Nothing => "nothing",
            Self::Body => "body",
            Self::Cloth(_) => "cloth",
        }
    }
}

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
            let (said, folded) = self.stalled_pairs();
            let one = self.seams.iter().flat_map(|s| s.open_pairs()).count() == 1;
            let (its, pull) = match one {
                true => ("its stitch still pulls", "it"),
                false => ("their stitches still pull", "them"),
            };
            let hint = match folded {
                true => {
                    "; cloth between a pair means it is threaded round a fold, which no pull brings it through"
                }
                false => "",
            };
            self.sim.notices.push(format!(
                "frame {}: {said} stopped closing; {its} (an edit or a pinch may help {pull}){hint}",
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

    /// The stalled pairs, seam by seam, and what lies between them: "3 pairs of seam A
    /// (15-41 mm apart, cloth of the front between 2)"; and whether cloth lies between
    /// any of them.
    fn stalled_pairs(&self) -> (String, bool) {
        let mut folded = false;
        let said: Vec<String> = (0..self.seams.len())
            .filter_map(|i| {
                let (n, lo, hi) = self.stalled_in(i)?;
                let (lo, hi, label) = (lo * 1e3, hi * 1e3, seam_label(i));
                let why: Vec<Across> = (self.seams[i].open_pairs())
                    .map(|(a, b)| self.between(a, b))
                    .collect();
                folded |= why.iter().any(|w| matches!(w, Across::Cloth(_)));
                let why = said_between(why, n);
                Some(match n {
                    1 => format!("1 pair of seam {label} ({hi:.0} mm apart{why})"),
                    n => format!("{n} pairs of seam {label} ({lo:.0}-{hi:.0} mm apart{why})"),
                })
            })
            .collect();
        (said.join(", "), folded)
    }

    /// What lies across the straight line between vertices `a` and `b` (a stitched
    /// pair's ends): cloth not next to either end that the line passes through (the
    /// first such triangle's piece), else the body's surface, else nothing. Touching or
    /// lying along a triangle is not passing through it.
    pub fn between(&self, a: u32, b: u32) -> Across {
        let x = &self.sim.cloth.x;
        let (Some(&p), Some(&q)) = (x.get(a as usize), x.get(b as usize)) else {
            return Across::Nothing;
        };
        let (lo, hi) = (p.min(q), p.max(q));
        let live = &self.sim.cloth.live;
        for t in live.iter().map(|(_, t)| t.v) {
            if t.contains(&a) || t.contains(&b) || t.iter().any(|&v| v as usize >= x.len()) {
                continue;
            }
            let c = t.map(|v| x[v as usize]);
            let (tlo, thi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
            if tlo.cmpgt(hi).any() || thi.cmplt(lo).any() {
                continue;
            }
            if segment_pierces(p, q, &c) {
                return Across::Cloth(self.piece_name_of(t[0]).unwrap_or_default());
            }
        }
        match self.sim.body.as_ref() {
            Some(body) if segment_pierces_body(p, q, body) => Across::Body,
            _ => Across::Nothing,
        }
    }
}

/// The notice's words for what lies between a seam's `n` stalled pairs: ", cloth of the
/// front between 2", ", the body between them"; empty where nothing does.
fn said_between(why: Vec<Across>, n: usize) -> String {
    let cloth: Vec<&str> = why
        .iter()
        .filter_map(|w| match w {
            Across::Cloth(name) => Some(name.as_str()),
            _ => None,
        })
        .collect();
    let body = why.iter().filter(|w| **w == Across::Body).count();
    let of = |k: usize| match (k == n, n) {
        (true, 1) => "it".to_string(),
        (true, _) => "them".to_string(),
        (false, _) => k.to_string(),
    };
    let mut out = String::new();
    if !cloth.is_empty() {
        let mut names: Vec<&str> = cloth.iter().copied().filter(|s| !s.is_empty()).collect();
        names.sort_unstable();
        names.dedup();
        let whose = match names.is_empty() {
            true => String::new(),
            false => format!(" of the {}", names.join(" and the ")),
        };
        out += &format!(", cloth{whose} between {}", of(cloth.len()));
    }
    if body > 0 {
        out += &format!(", the body between {}", of(body));
    }
    out
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
        // Nothing lies between them (the line runs along the grid's border).
        assert!(!n.contains("between") && !n.contains("fold"), "{n}");
        assert_eq!(d.between(0, 8), super::Across::Nothing);
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

    /// What lies between a pair's ends: the grid's own cloth when one end is folded over
    /// it and the other under it, the body when a sphere stands between them, and the
    /// notice's words for a seam's pairs.
    #[test]
    fn what_lies_between_a_pairs_ends_is_named() {
        let mut d = pinned_stitch();
        // The grid lies at y = 1 from (0, 0) to (0.5, 0.5) in x and z (8 x 8 cells).
        let (lo, hi) = crate::mesh::bounds(&d.sim.cloth.x);
        let mid = 0.5 * (lo + hi);
        let (a, b) = (0u32, 80u32);
        d.sim.cloth.x[a as usize] = mid + Vec3::new(0.01, 0.1, 0.02);
        d.sim.cloth.x[b as usize] = mid + Vec3::new(0.01, -0.1, 0.02);
        let name = d.piece_name_of(40).unwrap_or_default();
        assert_eq!(d.between(a, b), super::Across::Cloth(name));
        assert_eq!(d.between(b, a), d.between(a, b), "either way round");
        // Beside the grid: nothing.
        // (Off the sphere's axis below: a line through its pole only touches a corner.)
        d.sim.cloth.x[a as usize] = hi + Vec3::new(0.113, 0.1, 0.007);
        d.sim.cloth.x[b as usize] = hi + Vec3::new(0.113, -0.1, 0.007);
        assert_eq!(d.between(a, b), super::Across::Nothing);
        // A sphere between them, beside the grid: the body.
        let c = hi + Vec3::new(0.1, 0.0, 0.0);
        d.sim.body = Some(crate::collision::body::sphere(c, 0.05, 3).unwrap());
        assert_eq!(d.between(a, b), super::Across::Body);
        // A line passing above the sphere: nothing.
        d.sim.cloth.x[a as usize] = c + Vec3::new(0.0, 0.2, 0.0);
        d.sim.cloth.x[b as usize] = c + Vec3::new(0.06, 0.2, 0.0);
        assert_eq!(d.between(a, b), super::Across::Nothing);
        use super::{Across::*, said_between};
        let front = || Cloth("front".into());
        assert_eq!(said_between(vec![Nothing, Nothing], 2), "");
        assert_eq!(
            said_between(vec![front()], 1),
            ", cloth of the front between it"
        );
        assert_eq!(
            said_between(vec![front(), Body, Cloth("back".into())], 3),
            ", cloth of the back and the front between 2, the body between 1"
        );
        assert_eq!(said_between(vec![Body, Body], 2), ", the body between them");
        assert_eq!(
            said_between(vec![Cloth(String::new())], 1),
            ", cloth between it"
        );
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
