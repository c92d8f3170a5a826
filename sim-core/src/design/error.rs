//! Why an edit of the design was refused.

use crate::error::GeometryError;

/// Why an operation was refused. The design is unchanged when one is returned.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EditError {
    #[error("operations need the xpbd model (this simulation runs {0})")]
    Model(&'static str),
    #[error("vertex {0} does not exist")]
    NoVertex(u32),
    #[error("vertex {0} was removed (no triangle uses it any more)")]
    RemovedVertex(u32),
    #[error("cannot sew vertex {0} to itself")]
    SewSelf(u32),
    #[error("vertex {0} is inside the cloth; only vertices on its border can be sewn")]
    SewInterior(u32),
    #[error("vertices {0} and {1} already share a triangle")]
    SewNeighbours(u32, u32),
    #[error(
        "sewing vertices {a} and {b} now ({gap_mm:.0} mm apart) would pass the cloth through \
         itself or the body; bring them together first, or make a seam between the two \
         edges, which pulls them together and joins them once it can"
    )]
    SewWouldCross { a: u32, b: u32, gap_mm: f32 },
    #[error(
        "{doing} \"{label}\" now would pass the cloth through itself or the body ({crossings} \
         new crossing pairs: the cloth has moved since); move it clear and try again{hint}. \
         It stays on the list to {again}"
    )]
    HistoryWouldCross {
        doing: &'static str,
        label: &'static str,
        crossings: usize,
        again: &'static str,
        /// What else will do (a seam unpicked: sewing it again).
        hint: &'static str,
    },
    #[error("nothing to cut at vertex {0}: all its triangles lie on one side of the cut")]
    NothingToCut(u32),
    #[error("the cut direction is zero or not finite")]
    BadDirection,
    #[error("the stroke runs over no cloth (none within its radius of it), so nothing was cut")]
    EmptyStroke,
    #[error("no cloth within {radius} m of the pointer")]
    NothingNear { radius: f32 },
    #[error("edge ({0}, {1}) does not exist")]
    NoEdge(u32, u32),
    #[error("{name} must be {rule}, got {value}")]
    BadValue {
        name: &'static str,
        rule: &'static str,
        value: String,
    },
    #[error("the edit would break the mesh: {0}")]
    Geometry(#[from] GeometryError),
    #[error("({0}, {1}) is not an edge on the cloth's border")]
    NotBorderEdge(u32, u32),
    #[error(
        "the seam's two sides are one border (vertex {0} is on both): take the second side along another border"
    )]
    SeamOverlap(u32),
    #[error("the design changed underneath this edit (seam {0})")]
    StaleSeam(u32),
    #[error("the design changed underneath this edit (triangle slot {0})")]
    Stale(u32),
    #[error("no {what} on the pattern there")]
    NothingOnPattern { what: &'static str },
    #[error("there is no seam {index} (the design has {count}, counted from 0)")]
    NoSeam { index: usize, count: usize },
    #[error("there is no piece {index} (the design has {count}, counted from 0)")]
    NoPiece { index: usize, count: usize },
    #[error(
        "seam {label} is no dart: a dart's two sides run into one piece from its edge and meet at a point"
    )]
    NotADart { label: String },
    #[error("{0}")]
    Piece(String),
    #[error(
        "piece {piece} would start crossing the cloth or the body ({crossings} crossing triangle pairs); try another place"
    )]
    PieceWouldCross { piece: String, crossings: usize },
    #[error(
        "the edit would remove all of the cloth; a design keeps at least one piece (start a new design instead)"
    )]
    LastCloth,
    #[error(
        "the {0} model has no guard against crossing (xpbd has one; vbd's contact never crosses \
         on its own)"
    )]
    NoGuard(&'static str),
    #[error(
        "the vbd model's contact is never crossed and cannot be turned off (the xpbd model \
         without its guard is the one that may cross)"
    )]
    GuardBuiltIn,
    #[error("nothing to undo")]
    NothingToUndo,
    #[error(
        "nothing to undo but the seams' own welds, which would close again at once (Remove a seam in the Seams list to stop it sewing)"
    )]
    OnlyWeldsToUndo,
    #[error("nothing to redo")]
    NothingToRedo,
    #[error("no pin to free: nothing holds the cloth in place")]
    NoPins,
    #[error("already pinned there")]
    AlreadyPinned,
    #[error("no pin there to free (shift-click a pin's head)")]
    NoPinThere,
}
