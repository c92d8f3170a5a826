//! What a design holds besides its cloth and its paint: seams (the stitched pairs and
//! how hard they pull) and the tearing settings. Plain data; the operations on them are
//! in `seam` and `tear`.

use glam::Vec3;

use crate::solver::{ClosingWatch, Stitch};

#[derive(Clone, Debug, PartialEq)]
pub struct Seam {
    /// Stitched vertex pairs (`a == b` once welded).
    pub pairs: Vec<(u32, u32)>,
    /// Largest force one stitch pulls with, N.
    pub max_force: f32,
    /// What the designer calls it ("left side seam"); empty: it goes by its letter.
    pub name: String,
    /// The triangles (their rest corners) its welds folded away: where one side has more
    /// vertices than the other, two neighbours of that side are welded to one partner in
    /// turn and the triangle between them collapses, its cloth eased into the seam. It is
    /// still cloth of its piece: the pattern out draws the piece with it
    /// (`sewing_pattern`).
    pub eased: Vec<[Vec3; 3]>,
    /// Where the seam closes a dart (its two sides meet at a point on one piece): its
    /// intake is pressed toward the dart's second leg, the one the piece's outline
    /// reaches last going counter-clockwise, rather than its first. The pattern out's
    /// dart cap follows (`sewing_pattern::dart`); nothing in 3D does.
    pub press_second: bool,
}

/// Seams of at least this many pairs sew their two end pairs last while the garment
/// floats (`Design::float_while_sewing`, damped or not): a pair at either end is pulled
/// only once the pair beside it has welded (`Seam::pulled_pairs`), or the float is over.
/// A seam's end is a free corner of each piece; pulled from the start by its own stitch,
/// it was drawn in ahead of the seam, folded, and threaded round the other piece's edge
/// or the body: the 5k dress sewn in the air, damped, lost the neck end of a shoulder
/// seam in every run (88, 87, 88 of 90 welded), and sewn undamped with the cotton held
/// under 1.2x (the studio's way) in two runs of three. Drawn in by the seam welded beside
/// it, the end arrives edge to edge (90 of 90 in every run, both ways). (docs/garments.md,
/// "Every pair of both dresses welded, at rest" and "A seam's ends sewn last in every
/// float".)
pub const ENDS_WAIT_FROM: usize = 4;

/// The seams' stitches the solver pulls now: each seam's open pairs, but with
/// `ends_wait` a seam's end pairs only once the pair beside them has welded
/// ([`ENDS_WAIT_FROM`]).
pub fn open_stitches(seams: &[Seam], ends_wait: bool) -> impl Iterator<Item = Stitch> + '_ {
    seams.iter().flat_map(move |seam| {
        seam.pulled_pairs(ends_wait).map(|(a, b)| Stitch {
            a,
            b,
            max_force: seam.max_force,
        })
    })
}

impl Seam {
    pub fn open_pairs(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.pairs.iter().copied().filter(|(a, b)| a != b)
    }

    /// Whether pair `k` is an end pair still waiting for the pair beside it to weld
    /// ([`ENDS_WAIT_FROM`]).
    pub fn end_waits(&self, k: usize) -> bool {
        let n = self.pairs.len();
        let shut = |j: usize| self.pairs.get(j).is_some_and(|p| p.0 == p.1);
        let open = self.pairs.get(k).is_some_and(|p| p.0 != p.1);
        open && n >= ENDS_WAIT_FROM && ((k == 0 && !shut(1)) || (k + 1 == n && !shut(n - 2)))
    }

    /// The open pairs whose stitches pull now: all of them, but with `ends_wait` the end
    /// pairs still waiting ([`Seam::end_waits`]).
    pub fn pulled_pairs(&self, ends_wait: bool) -> impl Iterator<Item = (u32, u32)> + '_ {
        (self.pairs.iter().enumerate())
            .filter(move |&(k, &(a, b))| a != b && !(ends_wait && self.end_waits(k)))
            .map(|(_, &p)| p)
    }
}

/// Default pull of a seam, N per metre of seam (each stitched pair its share,
/// [`Design::pair_pull`](super::Design::pair_pull)): enough to pull cotton flaps together
/// against gravity and friction, small next to what tears it. 0.05 N a pair at
/// fit-cube's 15.6 mm grid, the force per pair it replaced.
pub const STITCH_PULL: f32 = 3.2;

/// What an overstretched edge does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TearMode {
    /// The paper's: the two triangles beside the edge are removed.
    Delete,
    /// The material separates at the edge: one end is split in two across the edge, the
    /// triangles stay (as NVIDIA Flex tears).
    Split,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TearSettings {
    /// Tearing happens at all.
    pub enabled: bool,
    /// An edge tears when longer than this times its rest length.
    pub threshold: f32,
    pub mode: TearMode,
    /// Most tears per frame (the most stretched first).
    pub max_per_frame: usize,
    /// Tear only within this distance of the pinched vertex, and nothing while nothing is
    /// pinched (`None`: anywhere). A tear by the pen sets it: a designer tears where the
    /// hand pulls, not wherever a seam happens to be stretched most. Not saved.
    pub near_pinch: Option<f32>,
}

impl Default for TearSettings {
    fn default() -> Self {
        Self {
            enabled: false,
            threshold: 1.6,
            mode: TearMode::Delete,
            max_per_frame: 16,
            near_pinch: None,
        }
    }
}

/// The design's watch over its open stitched pairs (`stalls`).
#[derive(Clone, Debug, Default)]
pub(super) struct Stalls {
    pub(super) closing: ClosingWatch,
    /// Frames since an open pair last closed.
    pub(super) quiet: u32,
    /// The designer has been told of these stalled pairs.
    pub(super) told: bool,
}

impl Stalls {
    /// Forgets what it saw: the pairs are watched afresh.
    pub(super) fn reset(&mut self) {
        self.closing.reset();
        self.quiet = 0;
        self.told = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seam(pairs: &[(u32, u32)]) -> Seam {
        Seam {
            pairs: pairs.to_vec(),
            max_force: 0.5,
            name: String::new(),
            eased: Vec::new(),
            press_second: false,
        }
    }

    #[test]
    fn a_seams_end_pairs_wait_for_the_pair_beside_them() {
        let mut s = seam(&[(0, 10), (1, 11), (2, 12), (3, 13), (4, 14)]);
        let pulled = |s: &Seam, wait| s.pulled_pairs(wait).collect::<Vec<_>>();
        assert_eq!(pulled(&s, true), [(1, 11), (2, 12), (3, 13)]);
        assert!(s.end_waits(0) && s.end_waits(4) && !s.end_waits(2));
        // Not waiting, every open pair pulls.
        assert_eq!(pulled(&s, false).len(), 5);
        // The pair beside the first end welded: that end pulls, the other still waits.
        s.pairs[1] = (1, 1);
        assert_eq!(pulled(&s, true), [(0, 10), (2, 12), (3, 13)]);
        // A welded end does not wait (nor pull).
        s.pairs[4] = (4, 4);
        assert!(!s.end_waits(4));
        assert_eq!(pulled(&s, true), [(0, 10), (2, 12), (3, 13)]);
        // Shorter seams pull every pair from the start.
        let short = seam(&[(0, 10), (1, 11), (2, 12)]);
        assert_eq!(pulled(&short, true).len(), 3);
        assert_eq!(ENDS_WAIT_FROM, 4);
        // The design's stitches.
        let both = [seam(&[(0, 10), (1, 11), (2, 12), (3, 13)]), short];
        assert_eq!(open_stitches(&both, true).count(), 2 + 3);
        assert_eq!(open_stitches(&both, false).count(), 4 + 3);
    }
}
