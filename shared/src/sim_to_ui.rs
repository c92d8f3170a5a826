//! cloth-sim -> cloth-ui: the cloth as zero-copy slices.
//!
//! - `saiho/cloth-frame`, every simulation frame: `[f32]` with the positions (3 per vertex)
//!   then the vertex normals (3 per vertex), under a [`ClothFrameHeader`].
//! - `saiho/cloth-mesh`, when the topology changes (cut, tear, sew): `[MeshCorner]`, three
//!   corners per triangle, each a vertex index, its own UV and pattern place (a sewn
//!   vertex can have two).
//!
//! Both keep the latest sample for a viewer that (re)starts.

use iceoryx2::prelude::ZeroCopySend;

use crate::{Header, MessageError};

#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::ClothFrameHeader")]
pub struct ClothFrameHeader {
    pub header: Header,
    pub frame: u64,
    /// Which mesh (`MeshHeader::topology`) these vertices belong to.
    pub topology: u64,
    pub texture_version: u64,
    /// Send time of the newest device sample that went into this frame (0: none), ns:
    /// device motion to cloth frame is `header.sent_ns - pen_sent_ns`.
    pub pen_sent_ns: u64,
    pub vertices: u32,
    /// Open seam stitches (pairs still pulling together): after the positions and
    /// normals, `3 * stitches` floats, each stitch's two vertex indices and its seam's
    /// place in the seam list (whole numbers, exact below 2^24).
    pub stitches: u32,
}

#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::MeshHeader")]
pub struct MeshHeader {
    pub header: Header,
    /// Bumped by every topology edit.
    pub topology: u64,
    pub vertices: u32,
    pub triangles: u32,
}

#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::MeshCorner")]
pub struct MeshCorner {
    pub vertex: u32,
    pub u: f32,
    pub v: f32,
    /// The corner's place in the design's pattern plane, m (x right, y up): where the
    /// pattern view draws it (UVs of pieces added later may overlap; these do not).
    pub pattern: [f32; 2],
}

/// The body the cloth drapes over (`saiho/body-mesh`, sent once, history 1). Its `[f32]`
/// payload is `3 * vertices` positions, then `3 * triangles` vertex indices stored as
/// f32 (exact below 2^24, checked).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::BodyMeshHeader")]
pub struct BodyMeshHeader {
    pub header: Header,
    pub vertices: u32,
    pub triangles: u32,
}

/// A body as positions and triangles.
pub type BodyMesh = (Vec<[f32; 3]>, Vec<[u32; 3]>);

/// Checks a received body mesh and returns its positions and triangles.
pub fn check_body(h: &BodyMeshHeader, payload: &[f32]) -> Result<BodyMesh, MessageError> {
    h.header.check()?;
    let (v, t) = (h.vertices as usize, h.triangles as usize);
    if v >= 1 << 24 || payload.len() != 3 * v + 3 * t {
        return Err(malformed(
            "body mesh",
            format!(
                "{} floats for {v} vertices and {t} triangles",
                payload.len()
            ),
        ));
    }
    let (pos, idx) = payload.split_at(3 * v);
    if pos.iter().any(|x| !x.is_finite()) {
        return Err(malformed("body mesh", "a position is not finite".into()));
    }
    let mut tris = Vec::with_capacity(t);
    for (k, c) in idx.chunks_exact(3).enumerate() {
        let mut tri = [0u32; 3];
        for (j, &f) in c.iter().enumerate() {
            if !(f >= 0.0 && f < v as f32 && f.fract() == 0.0) {
                return Err(malformed(
                    "body mesh",
                    format!("triangle {k} has index {f} (of {v} vertices)"),
                ));
            }
            tri[j] = f as u32;
        }
        tris.push(tri);
    }
    Ok((
        pos.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        tris,
    ))
}

fn malformed(what: &'static str, why: String) -> MessageError {
    MessageError::Malformed { what, why }
}

/// Checks a received frame: header, slice length `6 * vertices`, finite values.
pub fn check_frame(h: &ClothFrameHeader, payload: &[f32]) -> Result<(), MessageError> {
    h.header.check()?;
    let n = h.vertices as usize;
    let expected = 6 * n + 3 * h.stitches as usize;
    if payload.len() != expected {
        return Err(malformed(
            "cloth frame",
            format!(
                "{} floats for {n} vertices and {} stitches (expected {expected})",
                payload.len(),
                h.stitches
            ),
        ));
    }
    if let Some(i) = payload.iter().position(|v| !v.is_finite()) {
        return Err(malformed("cloth frame", format!("value {i} is not finite")));
    }
    let whole = |v: f32| v.fract() == 0.0 && v >= 0.0;
    for st in payload[6 * n..].chunks_exact(3) {
        if let Some(v) = st[..2].iter().find(|v| !(whole(**v) && (**v as usize) < n)) {
            return Err(malformed(
                "cloth frame",
                format!("stitch vertex {v} is not one of the {n} vertices"),
            ));
        }
        if !(whole(st[2]) && st[2] < (1 << 24) as f32) {
            return Err(malformed(
                "cloth frame",
                format!("stitch seam {} is not a place in a list", st[2]),
            ));
        }
    }
    Ok(())
}

/// The open stitches of a checked frame's payload: two vertices and the seam's place.
pub fn frame_stitches(h: &ClothFrameHeader, payload: &[f32]) -> Vec<[u32; 3]> {
    payload[6 * h.vertices as usize..]
        .chunks_exact(3)
        .map(|p| [p[0] as u32, p[1] as u32, p[2] as u32])
        .collect()
}

/// Checks a received mesh: header, `3 * triangles` corners, indices in range, UVs finite.
pub fn check_mesh(h: &MeshHeader, corners: &[MeshCorner]) -> Result<(), MessageError> {
    h.header.check()?;
    let t = h.triangles as usize;
    if corners.len() != 3 * t {
        return Err(malformed(
            "cloth mesh",
            format!("{} corners for {t} triangles", corners.len()),
        ));
    }
    for (k, c) in corners.iter().enumerate() {
        if c.vertex >= h.vertices {
            return Err(malformed(
                "cloth mesh",
                format!("corner {k} names vertex {} of {}", c.vertex, h.vertices),
            ));
        }
        if !(c.u.is_finite() && c.v.is_finite() && c.pattern.iter().all(|p| p.is_finite())) {
            return Err(malformed(
                "cloth mesh",
                format!("corner {k} has a non-finite UV or pattern place"),
            ));
        }
    }
    Ok(())
}

/// The tools ([`ToolState::tool`]); the pen's button 1 acts with the current one.
pub mod tool {
    /// Hold to grab the cloth and drag it.
    pub const PINCH: u32 = 0;
    /// Hold and move to cut along the path (scissors); the cut happens on release.
    pub const CUT: u32 = 1;
    /// Hold to grab and pull with tearing on.
    pub const TEAR: u32 = 2;
    /// Press on a border vertex, then on another: they are sewn.
    pub const SEW: u32 = 3;
    /// Hold to paint under the tip.
    pub const PAINT: u32 = 4;
    /// Press to pin or free the vertex under the tip.
    pub const PIN: u32 = 5;
    pub const LAST: u32 = PIN;

    /// The tool's name and what the pen's button does with it, for a status line.
    pub fn sentence(t: u32) -> &'static str {
        match t {
            PINCH => "Pinch tool: hold the pen's button to grab the cloth and pull it",
            CUT => {
                "Cut tool: hold the pen's button and draw across the cloth; it is cut along \
                 the stroke when you let go"
            }
            TEAR => "Tear tool: grab the cloth and pull; edges stretched too far come apart",
            SEW => "Sew tool: press on a border vertex, then on another, to sew them together",
            PAINT => "Paint tool: hold the pen's button to paint under its tip",
            PIN => "Pin tool: press on a vertex to pin it in place, or to free it",
            _ => "An unknown tool",
        }
    }
}

/// The current tool and its settings, owned by cloth-sim (so a restarted UI and the pen's
/// buttons see the same), with the undo and redo depth.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
#[type_name("saiho::ToolState")]
pub struct ToolState {
    pub header: Header,
    pub tool: u32,
    pub rgba: [u8; 4],
    /// Paint brush radius, m.
    pub brush_m: f32,
    pub undo_depth: u32,
    pub redo_depth: u32,
    /// The vertex picked by the first press of a sew, or u32::MAX.
    pub sew_first: u32,
    /// Since version 19: how many operations of the pen's button (a cut stroke, a sew or
    /// pin by the pen) cloth-sim has answered since it started, the last one's answer
    /// (1 done, 0 refused) and its message (the first `pen_message_len` bytes), so that
    /// the studio says what a stroke of the mouse did or why it was refused.
    pub pen_said: u32,
    pub pen_ok: u32,
    pub pen_message_len: u32,
    pub pen_message: [u8; PEN_MESSAGE_LEN],
    /// Explicit padding: every byte of a message is a field.
    pub _pad: u32,
}

/// Bytes of [`ToolState::pen_message`] (a longer message is cut at a character).
pub const PEN_MESSAGE_LEN: usize = 160;

impl Default for ToolState {
    fn default() -> Self {
        Self {
            header: Header::default(),
            tool: 0,
            rgba: [0; 4],
            brush_m: 0.0,
            undo_depth: 0,
            redo_depth: 0,
            sew_first: 0,
            pen_said: 0,
            pen_ok: 0,
            pen_message_len: 0,
            pen_message: [0; PEN_MESSAGE_LEN],
            _pad: 0,
        }
    }
}

/// Checks a received tool state and returns the pen's last answer (`None` before the
/// first): whether it was done, and its message.
pub fn check_tool_state(s: &ToolState) -> Result<Option<(bool, String)>, MessageError> {
    s.header.check()?;
    let bad = |why: String| Err(malformed("tool state", why));
    if s.pen_ok > 1 {
        return bad(format!("the pen's answer is {} (0 or 1)", s.pen_ok));
    }
    let Some(text) = text_in(&s.pen_message, s.pen_message_len) else {
        return bad(format!(
            "the pen's message ({} bytes) is not UTF-8 text",
            s.pen_message_len
        ));
    };
    Ok((s.pen_said > 0).then(|| (s.pen_ok == 1, text.to_string())))
}

/// Most pieces a [`PieceList`] carries; a design with more lists the first ones and says
/// how many there are.
pub const MAX_LISTED: usize = 32;
/// Bytes of a listed piece's name and fabric (longer ones are cut at a character).
pub const PIECE_NAME_LEN: usize = 48;
pub const FABRIC_NAME_LEN: usize = 24;
/// Bytes of a listed seam's name (a longer one is cut at a character).
pub const SEAM_NAME_LEN: usize = 32;

/// One piece as the list carries it.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
#[type_name("saiho::PieceEntry")]
pub struct PieceEntry {
    pub name_len: u32,
    pub name: [u8; PIECE_NAME_LEN],
    pub fabric_len: u32,
    pub fabric: [u8; FABRIC_NAME_LEN],
    pub vertices: u32,
    pub triangles: u32,
    /// One corner of the piece (`anchor_vertex == u32::MAX`: none): the piece is the
    /// mesh's triangles joined to it in the pattern (by shared vertex and UV).
    pub anchor_vertex: u32,
    pub anchor_uv: [f32; 2],
}

impl Default for PieceEntry {
    fn default() -> Self {
        Self {
            name_len: 0,
            name: [0; PIECE_NAME_LEN],
            fabric_len: 0,
            fabric: [0; FABRIC_NAME_LEN],
            vertices: 0,
            triangles: 0,
            anchor_vertex: u32::MAX,
            anchor_uv: [0.0; 2],
        }
    }
}

/// One seam as the list carries it.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::SeamEntry")]
pub struct SeamEntry {
    /// Its label in the pattern out ("A", "B", ... "AA": its place in the list).
    pub label: [u8; 4],
    pub label_len: u32,
    pub pairs: u32,
    /// Pairs still pulling (not yet welded).
    pub open: u32,
    /// Its two sides' lengths in the pattern, m.
    pub lengths: [f32; 2],
    /// What the designer calls it (empty: nothing but its label).
    pub name_len: u32,
    pub name: [u8; SEAM_NAME_LEN],
    /// Of the open pairs, those that stopped closing (since version 16): none has come a
    /// millimetre nearer for three seconds; their stitches still pull.
    pub stalled: u32,
    /// The least and the most distance between a stalled pair's two vertices, m (0 when
    /// none is stalled).
    pub stalled_gap: [f32; 2],
    /// Whether the pattern finds the seam closing a dart, and which way its intake is
    /// pressed (since version 26): [`dart`]`::NONE`, `FIRST` or `SECOND` (its legs in the
    /// order the piece's outline reaches them, counter-clockwise).
    pub dart: u32,
}

/// [`SeamEntry::dart`].
pub mod dart {
    /// The seam closes no dart.
    pub const NONE: u32 = 0;
    /// A dart pressed toward its first leg.
    pub const FIRST: u32 = 1;
    /// A dart pressed toward its second leg.
    pub const SECOND: u32 = 2;
}

/// Most seam segments a [`PieceList`] carries.
pub const MAX_SEAM_SEGMENTS: usize = 2048;

/// One outline edge of a listed seam, in the design's pattern plane (rest x and -z), m:
/// how the studio's pattern view draws each seam in its own colour.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::SeamSegment")]
pub struct SeamSegment {
    /// The seam's place in `seams`.
    pub seam: u32,
    pub a: [f32; 2],
    pub b: [f32; 2],
    /// 0: the whole seam; `k` (up to [`MAX_SEAM_STRETCH`]): its `k`-th stretch, labelled
    /// "B1", "B2" where its sides run over more than two pieces (since version 20).
    pub stretch: u32,
}

/// The highest stretch number a [`SeamSegment`] carries.
pub const MAX_SEAM_STRETCH: u32 = 99;

impl SeamSegment {
    /// Its label in the pattern: the seam's, and its stretch's number if any ("B2").
    pub fn label(&self, seam_label: &str) -> String {
        match self.stretch {
            0 => seam_label.to_string(),
            k => format!("{seam_label}{k}"),
        }
    }
}

/// Most pattern outline segments a [`PieceList`] carries (a 1 m square cut at 5 mm edges
/// has 800 along its border).
pub const MAX_OUTLINE_SEGMENTS: usize = 8192;

/// What an [`OutlineSegment`] draws.
pub mod outline {
    /// The sewing line: the piece's outline (outer loop and holes).
    pub const SEWING_LINE: u32 = 0;
    /// A balance notch: a slit from the sewing line into the piece.
    pub const NOTCH: u32 = 1;
    /// The grain line (the warp's direction).
    pub const GRAIN: u32 = 2;
    /// A drill hole (a sewn dart's point, marked a little inside it): a point, `a == b`.
    pub const DRILL: u32 = 3;
    /// A dart's press mark: from the middle of its mouth toward the leg its intake is
    /// pressed to (since version 26).
    pub const PRESS: u32 = 4;
    pub const LAST: u32 = PRESS;
}

/// One line of the pattern as cloth-sim's pattern out makes it, in the design's pattern
/// plane (rest x and -z), m: the studio's pattern view draws these, so it shows what an
/// export writes (the cloth a weld eased into a seam included).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::OutlineSegment")]
pub struct OutlineSegment {
    /// The piece's place in `entries`, or `u32::MAX` for a piece past [`MAX_LISTED`].
    pub piece: u32,
    /// [`outline`]`::SEWING_LINE`, `NOTCH`, `GRAIN`, `DRILL` or `PRESS`.
    pub kind: u32,
    pub a: [f32; 2],
    pub b: [f32; 2],
}

/// The design's pieces and seams now (`saiho/pieces`, history 1): sent when they
/// change, in the order cloth-sim numbers them for PLACE_PIECE, DELETE_PIECE and
/// REMOVE_SEAM.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
#[type_name("saiho::PieceList")]
pub struct PieceList {
    pub header: Header,
    /// The mesh (`MeshHeader::topology`) the anchors refer to.
    pub topology: u64,
    /// How many pieces the design has (more than `entries` when over [`MAX_LISTED`]).
    pub total: u32,
    /// How many of `entries` are filled.
    pub count: u32,
    pub entries: [PieceEntry; MAX_LISTED],
    /// How many seams the design has, and how many of `seams` are filled.
    pub seam_total: u32,
    pub seam_count: u32,
    pub seams: [SeamEntry; MAX_LISTED],
    /// The listed seams' outline edges (both sides of each), the first
    /// `segment_count`; a design with more draws the first [`MAX_SEAM_SEGMENTS`].
    pub segment_count: u32,
    pub segments: [SeamSegment; MAX_SEAM_SEGMENTS],
    /// The pattern's lines (every piece's sewing line, notches and grain line): how many
    /// there are, and how many of `outline` are filled (fewer when over
    /// [`MAX_OUTLINE_SEGMENTS`]: a viewer then draws the outline of its own mesh).
    pub outline_total: u32,
    pub outline_count: u32,
    pub outline: [OutlineSegment; MAX_OUTLINE_SEGMENTS],
    /// The pattern file the design was made from (a RESET's, or `--pattern` at start),
    /// the first `source_len` bytes ([`check_source`]); empty for a square cloth, a
    /// loaded design or one resumed from its autosave. Since protocol 18: the studio's
    /// Scene panel shows it, so that New scene makes that design again.
    pub source_len: u32,
    pub source: [u8; SOURCE_LEN],
    /// The pinned vertices of the cloth's pieces (since protocol 23): how many there
    /// are, and the first `pin_count` of them, each once, in increasing order. The studio
    /// draws a pin at each, so a designer sees what holds the cloth and where to free it.
    pub pin_total: u32,
    pub pin_count: u32,
    pub pins: [u32; MAX_PINS],
}

/// Most pinned vertices a [`PieceList`] carries (a design with more shows the first).
pub const MAX_PINS: usize = 1024;

/// Bytes of [`PieceList::source`]: a command's path (RESET's text, `ui_to_sim::TEXT_LEN`,
/// which checks the two agree).
pub const SOURCE_LEN: usize = 240;

/// The first `len` bytes of `buf` as text (`None`: past the buffer, or not UTF-8).
fn text_in(buf: &[u8], len: u32) -> Option<&str> {
    buf.get(..len as usize)
        .and_then(|t| std::str::from_utf8(t).ok())
}

/// Checks a received list's pattern file and returns it.
pub fn check_source(l: &PieceList) -> Result<String, MessageError> {
    text_in(&l.source, l.source_len)
        .map(str::to_string)
        .ok_or_else(|| {
            malformed(
                "piece list",
                format!(
                    "its pattern file ({} bytes) is not UTF-8 text",
                    l.source_len
                ),
            )
        })
}

impl Default for PieceList {
    fn default() -> Self {
        Self {
            header: Header::default(),
            topology: 0,
            total: 0,
            count: 0,
            entries: [PieceEntry::default(); MAX_LISTED],
            seam_total: 0,
            seam_count: 0,
            seams: [SeamEntry::default(); MAX_LISTED],
            segment_count: 0,
            segments: [SeamSegment::default(); MAX_SEAM_SEGMENTS],
            outline_total: 0,
            outline_count: 0,
            outline: [OutlineSegment::default(); MAX_OUTLINE_SEGMENTS],
            source_len: 0,
            source: [0; SOURCE_LEN],
            pin_total: 0,
            pin_count: 0,
            pins: [0; MAX_PINS],
        }
    }
}

/// A piece of a checked [`PieceList`].
#[derive(Clone, Debug, PartialEq)]
pub struct ListedPiece {
    pub name: String,
    pub fabric: String,
    pub vertices: u32,
    pub triangles: u32,
    pub anchor: Option<(u32, [f32; 2])>,
}

/// Copies `s` into `buf` up to its length, cut at a character; returns the length.
pub fn put_text(buf: &mut [u8], s: &str) -> u32 {
    let mut n = s.len().min(buf.len());
    while !s.is_char_boundary(n) {
        n -= 1;
    }
    buf[..n].copy_from_slice(&s.as_bytes()[..n]);
    n as u32
}

impl SeamEntry {
    /// The label (checked to be UTF-8 by [`check_seams`]).
    pub fn label(&self) -> &str {
        text_in(&self.label, self.label_len).unwrap_or("?")
    }

    /// The designer's name for it (checked to be UTF-8 by [`check_seams`]).
    pub fn name(&self) -> &str {
        text_in(&self.name, self.name_len).unwrap_or("")
    }
}

/// How many of a list's `max` places are filled (`count` of `total`), checked: no more
/// than fit and no more than the total.
fn listed_count(count: u32, total: u32, max: usize, what: &str) -> Result<usize, MessageError> {
    if count as usize > max || total < count {
        return Err(malformed(
            "piece list",
            format!("{count} of {total} {what} (at most {max})"),
        ));
    }
    Ok(count as usize)
}

/// Checks a received list's seams and returns them.
pub fn check_seams(l: &PieceList) -> Result<Vec<SeamEntry>, MessageError> {
    let n = listed_count(l.seam_count, l.seam_total, MAX_LISTED, "seams")?;
    let seams = &l.seams[..n];
    if seams.iter().any(|s| {
        s.open > s.pairs
            || s.stalled > s.open
            || !s.lengths.iter().all(|v| v.is_finite() && *v >= 0.0)
            || !s.stalled_gap.iter().all(|v| v.is_finite() && *v >= 0.0)
            || text_in(&s.label, s.label_len).is_none()
            || text_in(&s.name, s.name_len).is_none()
            || s.dart > dart::SECOND
    }) {
        return Err(malformed(
            "piece list",
            "a seam's counts or lengths are impossible".into(),
        ));
    }
    Ok(seams.to_vec())
}

/// Checks a received piece list and returns its pieces.
pub fn check_pieces(l: &PieceList) -> Result<Vec<ListedPiece>, MessageError> {
    l.header.check()?;
    let n = listed_count(l.count, l.total, MAX_LISTED, "pieces")?;
    let text = |b: &[u8], len: u32, what: &str| -> Result<String, MessageError> {
        text_in(b, len)
            .map(str::to_string)
            .ok_or_else(|| malformed("piece list", format!("a piece's {what} is not UTF-8 text")))
    };
    l.entries[..n]
        .iter()
        .map(|e| {
            if !e.anchor_uv.iter().all(|c| c.is_finite()) {
                return Err(malformed("piece list", "an anchor UV is not finite".into()));
            }
            Ok(ListedPiece {
                name: text(&e.name, e.name_len, "name")?,
                fabric: text(&e.fabric, e.fabric_len, "fabric")?,
                vertices: e.vertices,
                triangles: e.triangles,
                anchor: (e.anchor_vertex != u32::MAX).then_some((e.anchor_vertex, e.anchor_uv)),
            })
        })
        .collect()
}

/// One square of the cloth's texture (`saiho/texture`, `[u8]` RGBA rows under this
/// header). Changed tiles go out at once; all tiles are also re-sent round-robin, so a
/// viewer that starts late has the whole texture within a refresh cycle.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::TextureTile")]
pub struct TextureTile {
    pub header: Header,
    pub texture_version: u64,
    /// The whole texture's size, texels.
    pub width: u32,
    pub height: u32,
    /// This tile's rectangle, texels.
    pub x0: u32,
    pub y0: u32,
    pub w: u32,
    pub h: u32,
}

/// Checks a received tile: header, rectangle inside the texture, `4 * w * h` bytes.
pub fn check_tile(t: &TextureTile, payload: &[u8]) -> Result<(), MessageError> {
    t.header.check()?;
    let inside = t.width > 0
        && t.height > 0
        && t.width <= 16384
        && t.height <= 16384
        && t.x0.checked_add(t.w).is_some_and(|e| e <= t.width)
        && t.y0.checked_add(t.h).is_some_and(|e| e <= t.height);
    if !inside {
        return Err(malformed(
            "texture tile",
            format!("rectangle {t:?} is outside the texture"),
        ));
    }
    if payload.len() != 4 * t.w as usize * t.h as usize {
        return Err(malformed(
            "texture tile",
            format!("{} bytes for {} x {} texels", payload.len(), t.w, t.h),
        ));
    }
    Ok(())
}

mod lines;
pub use lines::{check_outline, check_pins, check_seam_segments};

#[cfg(test)]
mod tests;
