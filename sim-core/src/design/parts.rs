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

/// The seams' open stitches, as the solver pulls them.
pub fn open_stitches(seams: &[Seam]) -> impl Iterator<Item = Stitch> + '_ {
    seams.iter().flat_map(|seam| {
        seam.open_pairs().map(|(a, b)| Stitch {
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
