//! cloth-ui -> cloth-sim: operations on the design, each answered with a reply
//! (request-response service `saiho/commands`).

use iceoryx2::prelude::ZeroCopySend;

use crate::{Checked, Header, finite3};

/// [`ToolCommand::op`] values.
pub mod op {
    /// Split vertex `a` across `vec` (the cut direction).
    pub const CUT_VERTEX: u32 = 1;
    /// Merge border vertices `a` and `b`.
    pub const SEW: u32 = 2;
    /// Tear edge `(a, b)`; `mode` 0 deletes the triangles, 1 splits.
    pub const TEAR: u32 = 3;
    /// Pin (`mode` 1) or free (`mode` 0) vertex `a`.
    pub const PIN: u32 = 4;
    /// Paint `rgba` within `value` metres of the cloth point nearest to `vec`.
    pub const PAINT: u32 = 5;
    pub const UNDO: u32 = 6;
    pub const REDO: u32 = 7;
    /// Tearing on (`mode` 1 delete, 2 split) or off (0), at stretch ratio `value`.
    pub const SET_TEAR: u32 = 8;
    /// Save the design to the UTF-8 path in `text`.
    pub const SAVE: u32 = 9;
    /// Current tool `a` (`sim_to_ui::tool`), paint colour `rgba`, brush radius `value` m.
    pub const SET_TOOL: u32 = 10;
    /// Remove the triangles whose pattern (UV) centre lies in the rectangle
    /// `uv[0..4] = (u0, v0, u1, v1)` (select on the pattern, delete).
    pub const REMOVE_REGION: u32 = 11;
    /// A seam between two boundary paths given on the pattern as UV segments
    /// `uv[0..4]` (path A from its start to its end) and `uv[4..8]` (path B): the border
    /// vertices within `value` (UV units) of each segment, past its start, in order along
    /// it, are stitched pairwise.
    pub const SEAM: u32 = 12;
    /// Export the design into the directory `text`: OBJ+MTL+PNG, GLB, the design file,
    /// the body, and `sim-report.json` (what cloth-sim measured).
    pub const EXPORT: u32 = 13;
    /// Start a new design: the scene rebuilt over body `b` (see [`body`]) with grid `a`
    /// (0 keeps the current one) and material `uv[0..8]` = (density kg/m^2, stretch N/m,
    /// shear N/m, bending N m, friction, damping 1/s, since version 17 shear damping s
    /// and since version 27 bending damping s), 0 keeping the current value, and
    /// `mode` substeps per frame (0: cloth-sim's setting), and since version 8 the cloth
    /// model `rgba[0]` (0: cloth-sim's own, its `--model`; else 1 + a
    /// [`scene_model`](crate::telemetry::scene_model) code), and since version 11 a
    /// pattern file's path in `text` (SVG, DXF or GarmentCode JSON: the new design is its
    /// pieces placed round the body and sewn; empty: a square cloth of `a` cells). The
    /// design being replaced is saved first, next to the autosave (`*.before-reset.saiho`).
    pub const RESET: u32 = 14;
    /// Load the design file at the path in `text` in place of the current design (which
    /// is saved first, as for RESET).
    pub const LOAD: u32 = 15;
    /// Change the current design's material in place, `uv[0..8]` as for RESET (0 keeps
    /// the current value), and its substeps per frame to `a` (0 keeps them). Positions,
    /// edits, seams and history stay.
    pub const SET_MATERIAL: u32 = 16;
    /// A new piece (`mode`: 0 rectangle, 1 ellipse of `vec[0]` x `vec[1]` m; 2 from the
    /// pattern file at `text`), meshed with edges of `value` m, started at place `a`
    /// (see [`place`](super::place)), its top `vec[2]` m below the place's start
    /// ([`PIECE_DROP`](super::PIECE_DROP); since protocol 22).
    pub const ADD_PIECE: u32 = 17;
    /// Piece `a` (as `saiho/pieces` lists them) moved to place `b`, its top `vec[2]` m
    /// below the place's start (since protocol 22).
    pub const PLACE_PIECE: u32 = 18;
    /// Piece `a` deleted.
    pub const DELETE_PIECE: u32 = 19;
    /// As SEAM, the segments and tolerance in the design's pattern plane (m) rather
    /// than UV: what the studio's pattern view draws.
    pub const SEAM_PLANE: u32 = 20;
    /// Seam `a` (as `saiho/pieces` lists them) removed.
    pub const REMOVE_SEAM: u32 = 21;
    /// The fabric named in `text` (as `cloth-sim fabrics` lists them) for the current
    /// design, in place: its density, stretch, shear, bending (warp, weft and bias),
    /// friction and thickness; damping and substeps stay. Every piece records it.
    pub const SET_FABRIC: u32 = 22;
    /// Piece `a` (as `saiho/pieces` lists them) made of the fabric named in `text` (the
    /// library's, or `cotton`: the design's own material), undoably; its mass, stretch,
    /// shear and bending become the fabric's, the other pieces stay as they are.
    pub const SET_PIECE_FABRIC: u32 = 23;
    /// Seam `a` (as `saiho/pieces` lists them) named `text` (UTF-8, at most 120
    /// characters; empty: it goes by its letter again), undoably.
    pub const NAME_SEAM: u32 = 24;
    /// The xpbd model's guard against crossing on (`mode` 1) or off (0), in place: with
    /// it on, the cloth never crosses itself or the body (frames cost several times
    /// more). Refused for the models without one; vbd's contact is never crossed whatever.
    pub const SET_GUARD: u32 = 25;
    /// The xpbd model's strain limit for the current design, in place: `value` is the most
    /// a triangle may stretch in any direction past its rest length (0.2: 1.2x), within
    /// [`STRAIN_LIMIT`](super::STRAIN_LIMIT), or 0 for none. Refused for the other models.
    /// Since protocol 10.
    pub const SET_STRAIN_LIMIT: u32 = 26;
    /// `mode` 0 pauses the simulation, 1 runs it again: paused, the cloth stays where it
    /// is (no frame is stepped, no stitch pulls, nothing falls) while every edit still
    /// applies, so that pieces can be placed round the body and sewn before they drape.
    /// Run again with a seam none of whose pairs has closed yet, the cloth floats while
    /// the seams pull (as a pattern's pieces do), then falls. Since protocol 18.
    pub const SET_SIMULATING: u32 = 27;
    /// Scissors in the pattern: the cloth cut along the straight line from (`uv[0]`,
    /// `uv[1]`) to (`uv[2]`, `uv[3]`) in the design's pattern plane (m), exactly along it
    /// on every piece it crosses; a line from beside a piece to beside it cuts the piece
    /// in two. Undoable. Since protocol 19.
    pub const CUT_PLANE: u32 = 28;
    /// Piece `a` (as `saiho/pieces` lists them) named `text` (UTF-8, 1 to 120
    /// characters, a name no other piece has), undoably: the list, the pattern view and
    /// the pattern out call it so. Since protocol 21.
    pub const NAME_PIECE: u32 = 29;
    /// A copy of piece `a` (as `saiho/pieces` lists them) as it is now (its outline after
    /// cuts and tears), of its fabric, meshed with edges of `value` m and started at place
    /// `b` (its top `vec[2]` m below the place's start); `mode` 1 turns it over (a mirror
    /// image: a left front from a right one), 0 not.
    /// Its seams, paint and pins are not copied. Undoable. Since protocol 22.
    pub const DUPLICATE_PIECE: u32 = 30;
    /// Every pin of the design freed, as one undoable edit. Since protocol 23.
    pub const FREE_PINS: u32 = 31;
    /// A dart `value` m wide at the edge of the piece under its point (`uv[0]`, `uv[1]`),
    /// from that point out along the line to (`uv[2]`, `uv[3]`), beyond the piece's
    /// edge, in the design's pattern plane (m): the wedge cut away and its legs seamed,
    /// as one undoable operation. Since protocol 24.
    pub const DART_PLANE: u32 = 32;
    /// Seam `a` (as `saiho/pieces` lists them), a dart, pressed toward its second leg
    /// (`mode` 1: the one its piece's outline reaches last, counter-clockwise) or its
    /// first (0), undoably: the dart cap of the pattern's cut line follows. Refused for a
    /// seam that is no dart. Since protocol 26.
    pub const PRESS_DART: u32 = 33;
    pub const LAST: u32 = PRESS_DART;
}

/// [`ToolCommand::b`] of a RESET: the body.
pub mod body {
    pub const CUBE: u32 = 0;
    pub const SPHERE: u32 = 1;
    pub const MANNEQUIN: u32 = 2;
    /// Since protocol 9.
    pub const MANNEQUIN_APOSE: u32 = 3;
    /// Since protocol 15.
    pub const HUMAN: u32 = 4;
    pub const LAST: u32 = HUMAN;
}

/// The named places round the body a piece can start at.
pub mod place {
    pub const FRONT: u32 = 0;
    pub const BACK: u32 = 1;
    pub const LEFT_SIDE: u32 = 2;
    pub const RIGHT_SIDE: u32 = 3;
    pub const LEFT_ARM: u32 = 4;
    pub const RIGHT_ARM: u32 = 5;
    pub const LAST: u32 = RIGHT_ARM;
    /// Each place's name, by code (as `cloth-sim` and the design file spell them).
    pub const NAMES: [&str; 6] = [
        "front",
        "back",
        "left-side",
        "right-side",
        "left-arm",
        "right-arm",
    ];
}

/// The shapes of ADD_PIECE.
pub mod shape {
    pub const RECTANGLE: u32 = 0;
    pub const ELLIPSE: u32 = 1;
    pub const FILE: u32 = 2;
    pub const LAST: u32 = FILE;
}

/// A new piece's size, each side, m, and its mesh's edge length, m.
pub const PIECE_SIZE: (f32, f32) = (0.01, 3.0);
pub const PIECE_EDGE: (f32, f32) = (0.005, 0.5);
/// How far below its place's own start (the shoulders; for an arm, the shoulder, down
/// the arm) a piece's top may start, m: ADD_PIECE's, PLACE_PIECE's and DUPLICATE_PIECE's
/// `vec[2]`. Since protocol 22 (0 before: the place's own start).
pub const PIECE_DROP: f32 = 1.0;

/// A dart's width at the edge DART_PLANE makes, m (the design refuses others). Since
/// protocol 24.
pub const DART_WIDTH: (f32, f32) = (0.002, 0.5);

/// The strain limits SET_STRAIN_LIMIT accepts besides 0 (the material's own range).
pub const STRAIN_LIMIT: (f32, f32) = (0.01, 10.0);
pub const TEXT_LEN: usize = 240;
// A design's pattern file comes back in its piece list whole.
const _: () = assert!(TEXT_LEN == crate::sim_to_ui::SOURCE_LEN);
pub const MESSAGE_LEN: usize = 200;

#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
#[type_name("saiho::ToolCommand")]
pub struct ToolCommand {
    pub header: Header,
    pub op: u32,
    pub a: u32,
    pub b: u32,
    pub mode: u32,
    pub vec: [f32; 3],
    pub value: f32,
    pub rgba: [u8; 4],
    /// Pattern coordinates for REMOVE_REGION, SEAM, SEAM_PLANE, CUT_PLANE and DART_PLANE.
    pub uv: [f32; 8],
    pub text_len: u32,
    pub text: [u8; TEXT_LEN],
}

impl Default for ToolCommand {
    fn default() -> Self {
        Self {
            header: Header::default(),
            op: 0,
            a: 0,
            b: 0,
            mode: 0,
            vec: [0.0; 3],
            value: 0.0,
            rgba: [0; 4],
            uv: [0.0; 8],
            text_len: 0,
            text: [0; TEXT_LEN],
        }
    }
}

impl ToolCommand {
    /// The text field (a path), if valid UTF-8 within its length.
    pub fn text(&self) -> Option<&str> {
        let n = self.text_len as usize;
        (n <= TEXT_LEN)
            .then(|| std::str::from_utf8(&self.text[..n]).ok())
            .flatten()
    }

    pub fn set_text(&mut self, s: &str) -> bool {
        if s.len() > TEXT_LEN {
            return false;
        }
        self.text[..s.len()].copy_from_slice(s.as_bytes());
        self.text_len = s.len() as u32;
        true
    }
}

impl Checked for ToolCommand {
    const WHAT: &'static str = "tool command";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        if self.op == 0 || self.op > op::LAST {
            return Err(format!("unknown operation {}", self.op));
        }
        finite3("vector", &self.vec)?;
        if !self.value.is_finite() {
            return Err("value is not finite".into());
        }
        if self.op == op::SET_TOOL
            && (self.a > crate::sim_to_ui::tool::LAST || !(self.value > 0.0 && self.value < 1.0))
        {
            return Err(format!(
                "tool {} with brush {} m (tools 0..={}, brush between 0 and 1 m)",
                self.a,
                self.value,
                crate::sim_to_ui::tool::LAST
            ));
        }
        if !self.uv.iter().all(|c| c.is_finite()) {
            return Err("pattern coordinates are not finite".into());
        }
        self.check_texts()?;
        if self.op == op::SET_SIMULATING && self.mode > 1 {
            return Err(format!("simulating {} (0 paused, 1 running)", self.mode));
        }
        if self.op == op::PRESS_DART && self.mode > 1 {
            return Err(format!(
                "a dart pressed toward leg {} (0 its first, 1 its second)",
                self.mode
            ));
        }
        if self.op == op::SET_GUARD && self.mode > 1 {
            return Err(format!("guard {} (0 off, 1 on)", self.mode));
        }
        if self.op == op::SET_STRAIN_LIMIT
            && self.value != 0.0
            && !(STRAIN_LIMIT.0..=STRAIN_LIMIT.1).contains(&self.value)
        {
            return Err(format!(
                "strain limit {} (0 for none, else {} to {})",
                self.value, STRAIN_LIMIT.0, STRAIN_LIMIT.1
            ));
        }
        if self.op == op::SET_MATERIAL {
            if self.a > 100 {
                return Err(format!("substeps {} (1 to 100, 0 keeps them)", self.a));
            }
            if self.uv.iter().any(|v| *v < 0.0) {
                return Err("material values must not be negative".into());
            }
        }
        if self.op == op::RESET {
            if self.b > body::LAST {
                return Err(format!(
                    "unknown body {} (0 cube, 1 sphere, 2 mannequin)",
                    self.b
                ));
            }
            if self.mode > 100 {
                return Err(format!("substeps {} (1 to 100, 0 keeps them)", self.mode));
            }
            if self.a != 0 && !(2..=256).contains(&self.a) {
                return Err(format!("grid {} (2 to 256 cells a side)", self.a));
            }
            if u32::from(self.rgba[0]) > crate::telemetry::scene_model::LAST + 1 {
                return Err(format!(
                    "unknown model {} (0 cloth-sim's own, 1 xpbd, 2 vbd, 3 seed, 4 implicit)",
                    self.rgba[0]
                ));
            }
            if self.uv.iter().any(|v| *v < 0.0) {
                return Err("material values must not be negative".into());
            }
        }
        if matches!(
            self.op,
            op::ADD_PIECE | op::PLACE_PIECE | op::DUPLICATE_PIECE
        ) {
            self.check_piece()?;
        }
        if matches!(self.op, op::SEAM | op::SEAM_PLANE)
            && self.value.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
        {
            return Err(format!(
                "a seam needs a positive tolerance, got {}",
                self.value
            ));
        }
        Ok(())
    }
}

impl ToolCommand {
    /// ADD_PIECE's, PLACE_PIECE's and DUPLICATE_PIECE's own fields.
    fn check_piece(&self) -> Result<(), String> {
        if !(0.0..=PIECE_DROP).contains(&self.vec[2]) {
            return Err(format!(
                "a piece's top {} m below its place's start (0 to {PIECE_DROP} m)",
                self.vec[2]
            ));
        }
        if matches!(self.op, op::ADD_PIECE | op::DUPLICATE_PIECE)
            && !(PIECE_EDGE.0..=PIECE_EDGE.1).contains(&self.value)
        {
            return Err(format!(
                "edge length {} m (between {} and {} m)",
                self.value, PIECE_EDGE.0, PIECE_EDGE.1
            ));
        }
        if self.op == op::ADD_PIECE {
            if self.mode > shape::LAST || self.a > place::LAST {
                return Err(format!(
                    "shape {} at place {} (shapes 0 rectangle, 1 ellipse, 2 file; places 0..={})",
                    self.mode,
                    self.a,
                    place::LAST
                ));
            }
            let sized = |v: f32| (PIECE_SIZE.0..=PIECE_SIZE.1).contains(&v);
            if self.mode != shape::FILE && !(sized(self.vec[0]) && sized(self.vec[1])) {
                return Err(format!(
                    "a piece of {} x {} m (each side between {} and {} m)",
                    self.vec[0], self.vec[1], PIECE_SIZE.0, PIECE_SIZE.1
                ));
            }
            if self.mode == shape::FILE && self.text().is_none_or(str::is_empty) {
                return Err("a piece from a file needs a UTF-8 path".into());
            }
        }
        if self.op == op::PLACE_PIECE && self.b > place::LAST {
            return Err(format!("place {} (0..={})", self.b, place::LAST));
        }
        if self.op == op::DUPLICATE_PIECE && (self.b > place::LAST || self.mode > 1) {
            return Err(format!(
                "a copy at place {} turned over {} (places 0..={}; 0 as it is, 1 turned over)",
                self.b,
                self.mode,
                place::LAST
            ));
        }
        Ok(())
    }

    /// The paths and names a command's `text` must carry.
    fn check_texts(&self) -> Result<(), String> {
        if matches!(self.op, op::SAVE | op::EXPORT | op::LOAD)
            && self.text().is_none_or(str::is_empty)
        {
            return Err("save, load and export need a UTF-8 path".into());
        }
        if self.op == op::NAME_SEAM && self.text().is_none() {
            return Err("a seam's name must be UTF-8 text".into());
        }
        if self.op == op::NAME_PIECE && self.text().is_none_or(|t| t.trim().is_empty()) {
            return Err("a piece's name must be UTF-8 text, not empty".into());
        }
        if matches!(self.op, op::SET_FABRIC | op::SET_PIECE_FABRIC)
            && self.text().is_none_or(|t| t.trim().is_empty())
        {
            return Err("a fabric needs a UTF-8 name".into());
        }
        Ok(())
    }
}

/// The answer to one command.
#[derive(Clone, Copy, Debug, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
#[type_name("saiho::CommandReply")]
pub struct CommandReply {
    pub header: Header,
    /// The command's `header.seq`.
    pub request_seq: u64,
    /// 1 done, 0 refused (the design is unchanged; `message` says why).
    pub ok: u32,
    /// Operations that can be undone after this one.
    pub undo_depth: u32,
    pub message_len: u32,
    pub message: [u8; MESSAGE_LEN],
    /// Explicit padding (was implicit): every byte of a message is a field.
    pub _pad: u32,
}

impl CommandReply {
    pub fn new(header: Header, request_seq: u64, ok: bool, undo_depth: usize, msg: &str) -> Self {
        let mut message = [0u8; MESSAGE_LEN];
        // Truncate on a character boundary.
        let mut n = msg.len().min(MESSAGE_LEN);
        while !msg.is_char_boundary(n) {
            n -= 1;
        }
        message[..n].copy_from_slice(&msg.as_bytes()[..n]);
        Self {
            header,
            request_seq,
            ok: u32::from(ok),
            undo_depth: undo_depth as u32,
            message_len: n as u32,
            message,
            _pad: 0,
        }
    }

    pub fn message(&self) -> &str {
        let n = (self.message_len as usize).min(MESSAGE_LEN);
        std::str::from_utf8(&self.message[..n]).unwrap_or("(reply message is not UTF-8)")
    }
}

impl Checked for CommandReply {
    const WHAT: &'static str = "command reply";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        if self.ok > 1 || self.message_len as usize > MESSAGE_LEN {
            return Err("bad reply fields".into());
        }
        Ok(())
    }
}
