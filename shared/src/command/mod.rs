//! The typed operations cloth-ui (or any client) asks of cloth-sim, and their one
//! conversion to and from the `#[repr(C)]` wire record [`ToolCommand`]: a sender builds a
//! [`Command`] and calls [`Command::to_wire`]; cloth-sim calls [`Command::from_wire`],
//! which checks the record first. Nothing else reads or writes a record's fields.

use crate::ui_to_sim::{TEXT_LEN, ToolCommand, body, op, shape};
use crate::{Checked, Header, MessageError};

/// The body of a new design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyChoice {
    Cube,
    Sphere,
    Mannequin,
    /// The mannequin with its arms held out 50 degrees below the horizontal, as
    /// GarmentCode's patterns place their sleeves (since protocol 9).
    MannequinAPose,
    /// A human figure, GarmentCode's average body, its arms held out 45 degrees below the
    /// horizontal: the body GarmentCode's patterns are cut for (since protocol 15).
    Human,
}

/// A change of material: each value given replaces the design's, each `None` keeps it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialChange {
    /// Areal density, kg/m^2.
    pub density: Option<f32>,
    /// Stretch modulus, N/m.
    pub stretch: Option<f32>,
    /// Shear modulus, N/m.
    pub shear: Option<f32>,
    /// Bending rigidity, N m.
    pub bending: Option<f32>,
    pub friction: Option<f32>,
    /// Velocity damping, 1/s.
    pub damping: Option<f32>,
    /// Shear damping time, s: the weave's internal damping in shear (CLO and Marvelous
    /// Designer call it internal damping). Since protocol 17.
    pub shear_damping: Option<f32>,
    /// Bending damping time, s: the same internal damping on the hinges. Since protocol
    /// 27.
    pub bend_damping: Option<f32>,
}

/// Automatic tearing of overstretched edges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tearing {
    Off,
    /// Edges longer than `threshold` times their rest length tear; `split` separates
    /// the material instead of deleting the two triangles.
    On {
        threshold: f32,
        split: bool,
    },
}

/// What a new piece is made from.
#[derive(Clone, Debug, PartialEq)]
pub enum PieceShape {
    /// `w` x `h` m.
    Rectangle { w: f32, h: f32 },
    /// Axes `w` and `h` m.
    Ellipse { w: f32, h: f32 },
    /// Every piece of a pattern file (SVG, DXF or GarmentCode JSON).
    File { path: String },
}

/// The seam allowance the studio's Export gives the sewing pattern unless told otherwise,
/// mm: the scenarios' (`sim_core::scenario::SCENARIO_ALLOWANCE_MM`).
pub const DEFAULT_ALLOWANCE_MM: f32 = 10.0;

/// One operation on the design (see [`op`] for what each does on cloth-sim's side).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Split `vertex` across the cut `direction`.
    CutVertex {
        vertex: u32,
        direction: [f32; 3],
    },
    /// Merge border vertices `a` and `b`.
    Sew {
        a: u32,
        b: u32,
    },
    /// Tear edge `(a, b)`: delete its two triangles, or with `split` separate them.
    Tear {
        a: u32,
        b: u32,
        split: bool,
    },
    Pin {
        vertex: u32,
        pinned: bool,
    },
    /// Paint `rgba` within `radius_m` of the cloth point nearest to `point`.
    Paint {
        point: [f32; 3],
        radius_m: f32,
        rgba: [u8; 4],
    },
    Undo,
    Redo,
    /// Every pin of the design freed (one undoable edit).
    FreePins,
    SetTearing(Tearing),
    /// Save the design to `path`.
    Save {
        path: String,
    },
    /// The pen's tool (`sim_to_ui::tool`), paint colour and brush radius.
    SetTool {
        tool: u32,
        rgba: [u8; 4],
        brush_m: f32,
    },
    /// Remove the triangles whose pattern (UV) centre lies in the rectangle.
    RemoveRegion {
        min: [f32; 2],
        max: [f32; 2],
    },
    /// A seam between the border paths along pattern segments `a` and `b` (each from
    /// its start to its end), vertices within `tolerance` (UV units).
    Seam {
        a: [[f32; 2]; 2],
        b: [[f32; 2]; 2],
        tolerance: f32,
    },
    /// Export the design into the directory `dir` (`EXPORT`; `value` the allowance), its
    /// sewing pattern with a seam
    /// allowance of `allowance_mm` (0: cut on the sewing line; cloth-sim refuses one
    /// outside 0-100 mm, or not a number, and writes nothing).
    Export {
        dir: String,
        allowance_mm: f32,
    },
    /// A new design over `body`: `grid` cells a side (`None` keeps the current), the
    /// material changed as given, `substeps` per frame (`None`: cloth-sim's setting).
    Reset {
        body: BodyChoice,
        grid: Option<u32>,
        material: MaterialChange,
        substeps: Option<u32>,
        /// The cloth model, a [`scene_model`](crate::telemetry::scene_model) code (`None`:
        /// cloth-sim's own, its `--model`).
        model: Option<u32>,
        /// A pattern file (SVG, DXF or GarmentCode JSON) whose pieces the new design is,
        /// placed round the body and sewn, in place of a square cloth (`None`).
        pattern: Option<String>,
    },
    /// Load the design file at `path` in place of the current design.
    Load {
        path: String,
    },
    /// Change the current design's material in place, and its substeps when given.
    SetMaterial {
        material: MaterialChange,
        substeps: Option<u32>,
    },
    /// A new piece, meshed with edges of `edge_m`, started at `place`
    /// ([`place`](crate::ui_to_sim::place) codes), its top `drop_m` below the place's
    /// start.
    AddPiece {
        shape: PieceShape,
        place: u32,
        drop_m: f32,
        edge_m: f32,
    },
    /// As [`Command::Seam`], in the design's pattern plane (m).
    SeamPlane {
        a: [[f32; 2]; 2],
        b: [[f32; 2]; 2],
        tolerance_m: f32,
    },
    /// Piece `piece` (in `saiho/pieces` order) moved to `place`, its top `drop_m`
    /// below the place's start.
    PlacePiece {
        piece: u32,
        place: u32,
        drop_m: f32,
    },
    DeletePiece {
        piece: u32,
    },
    /// A copy of piece `piece` (in `saiho/pieces` order) as it is now, meshed with edges
    /// of `edge_m`, started at `place` `drop_m` lower, turned over when `mirrored`.
    DuplicatePiece {
        piece: u32,
        place: u32,
        drop_m: f32,
        mirrored: bool,
        edge_m: f32,
    },
    /// Seam `seam` (in `saiho/pieces` order) removed.
    RemoveSeam {
        seam: u32,
    },
    /// The fabric `name` (the fabric library's) for the current design, in place.
    SetFabric {
        name: String,
    },
    /// Piece `piece` (in `saiho/pieces` order) made of fabric `name`.
    SetPieceFabric {
        piece: u32,
        name: String,
    },
    /// Seam `seam` (in `saiho/pieces` order) named `name` (empty: by its letter).
    NameSeam {
        seam: u32,
        name: String,
    },
    /// Seam `seam` (in `saiho/pieces` order), a dart, pressed toward its second leg
    /// (`second`) or its first (since protocol 26).
    PressDart {
        seam: u32,
        second: bool,
    },
    /// Piece `piece` (in `saiho/pieces` order) named `name`.
    NamePiece {
        piece: u32,
        name: String,
    },
    /// The xpbd model's guard against crossing on or off.
    SetGuard {
        on: bool,
    },
    /// The xpbd model's strain limit: the most a triangle may stretch past its rest
    /// length (0.2: 1.2x; 0: none).
    SetStrainLimit {
        limit: f32,
    },
    /// Pause the simulation (`on == false`: the cloth stays where it is while edits
    /// apply) or run it again (since protocol 18).
    SetSimulating {
        on: bool,
    },
    /// Scissors along the straight line `from`-`to` in the design's pattern plane (m),
    /// on every piece it crosses (since protocol 19).
    CutPlane {
        from: [f32; 2],
        to: [f32; 2],
    },
    /// A dart `width_m` wide at the edge of the piece under `point`, from the point out
    /// along the line to `toward` (beyond the edge), in the design's pattern plane (m):
    /// the wedge cut away and its legs seamed, one undoable operation (since protocol 24).
    DartPlane {
        point: [f32; 2],
        toward: [f32; 2],
        width_m: f32,
    },
}

/// Why a command cannot be put on the wire.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CommandError {
    #[error("the path or name is {len} bytes, more than the {TEXT_LEN} a command carries")]
    PathTooLong { len: usize },
}

impl MaterialChange {
    fn to_wire(self) -> [f32; 8] {
        [
            self.density,
            self.stretch,
            self.shear,
            self.bending,
            self.friction,
            self.damping,
            self.shear_damping,
            self.bend_damping,
        ]
        .map(|v| v.unwrap_or(0.0))
    }

    /// From the wire: 0 keeps the value (negative values are refused by the check).
    fn from_wire(u: &[f32; 8]) -> Self {
        let v = |x: f32| (x > 0.0).then_some(x);
        Self {
            density: v(u[0]),
            stretch: v(u[1]),
            shear: v(u[2]),
            bending: v(u[3]),
            friction: v(u[4]),
            damping: v(u[5]),
            shear_damping: v(u[6]),
            bend_damping: v(u[7]),
        }
    }
}

fn some_nonzero(x: u32) -> Option<u32> {
    (x != 0).then_some(x)
}

fn text(c: &ToolCommand) -> String {
    c.text().unwrap_or_default().to_string()
}

/// `s` as `c`'s text, or why it cannot be.
fn set_text(c: &mut ToolCommand, s: &str) -> Result<(), CommandError> {
    if c.set_text(s) {
        Ok(())
    } else {
        Err(CommandError::PathTooLong { len: s.len() })
    }
}

impl Command {
    /// The wire op code of this command.
    pub fn op(&self) -> u32 {
        match self {
            Self::CutVertex { .. } => op::CUT_VERTEX,
            Self::Sew { .. } => op::SEW,
            Self::Tear { .. } => op::TEAR,
            Self::Pin { .. } => op::PIN,
            Self::Paint { .. } => op::PAINT,
            Self::Undo => op::UNDO,
            Self::Redo => op::REDO,
            Self::FreePins => op::FREE_PINS,
            Self::SetTearing(_) => op::SET_TEAR,
            Self::Save { .. } => op::SAVE,
            Self::SetTool { .. } => op::SET_TOOL,
            Self::RemoveRegion { .. } => op::REMOVE_REGION,
            Self::Seam { .. } => op::SEAM,
            Self::Export { .. } => op::EXPORT,
            Self::Reset { .. } => op::RESET,
            Self::Load { .. } => op::LOAD,
            Self::SetMaterial { .. } => op::SET_MATERIAL,
            Self::AddPiece { .. } => op::ADD_PIECE,
            Self::PlacePiece { .. } => op::PLACE_PIECE,
            Self::DeletePiece { .. } => op::DELETE_PIECE,
            Self::DuplicatePiece { .. } => op::DUPLICATE_PIECE,
            Self::SeamPlane { .. } => op::SEAM_PLANE,
            Self::RemoveSeam { .. } => op::REMOVE_SEAM,
            Self::SetFabric { .. } => op::SET_FABRIC,
            Self::SetPieceFabric { .. } => op::SET_PIECE_FABRIC,
            Self::NameSeam { .. } => op::NAME_SEAM,
            Self::PressDart { .. } => op::PRESS_DART,
            Self::NamePiece { .. } => op::NAME_PIECE,
            Self::SetGuard { .. } => op::SET_GUARD,
            Self::SetStrainLimit { .. } => op::SET_STRAIN_LIMIT,
            Self::SetSimulating { .. } => op::SET_SIMULATING,
            Self::CutPlane { .. } => op::CUT_PLANE,
            Self::DartPlane { .. } => op::DART_PLANE,
        }
    }

    /// The wire record of this command under `header`.
    pub fn to_wire(&self, header: Header) -> Result<ToolCommand, CommandError> {
        let mut c = ToolCommand {
            header,
            op: self.op(),
            ..ToolCommand::default()
        };
        match self {
            Self::CutVertex { vertex, direction } => (c.a, c.vec) = (*vertex, *direction),
            Self::Sew { a, b } => (c.a, c.b) = (*a, *b),
            Self::Tear { a, b, split } => (c.a, c.b, c.mode) = (*a, *b, u32::from(*split)),
            Self::Pin { vertex, pinned } => (c.a, c.mode) = (*vertex, u32::from(*pinned)),
            Self::SetGuard { on } | Self::SetSimulating { on } => c.mode = u32::from(*on),
            Self::SetStrainLimit { limit } => c.value = *limit,
            Self::Paint {
                point,
                radius_m,
                rgba,
            } => (c.vec, c.value, c.rgba) = (*point, *radius_m, *rgba),
            Self::Undo | Self::Redo | Self::FreePins => {}
            Self::SetTearing(Tearing::Off) => c.mode = 0,
            Self::SetTearing(Tearing::On { threshold, split }) => {
                (c.mode, c.value) = (if *split { 2 } else { 1 }, *threshold);
            }
            Self::Save { path } | Self::Load { path } | Self::SetFabric { name: path } => {
                set_text(&mut c, path)?;
            }
            Self::Export { dir, allowance_mm } => {
                set_text(&mut c, dir)?;
                c.value = *allowance_mm;
            }
            Self::SetPieceFabric { piece: a, name }
            | Self::NameSeam { seam: a, name }
            | Self::NamePiece { piece: a, name } => {
                c.a = *a;
                set_text(&mut c, name)?;
            }
            Self::SetTool {
                tool,
                rgba,
                brush_m,
            } => (c.a, c.rgba, c.value) = (*tool, *rgba, *brush_m),
            Self::RemoveRegion { min, max } | Self::CutPlane { from: min, to: max } => {
                c.uv[..4].copy_from_slice(&[min[0], min[1], max[0], max[1]])
            }
            Self::DartPlane {
                point,
                toward,
                width_m,
            } => {
                c.uv[..4].copy_from_slice(&[point[0], point[1], toward[0], toward[1]]);
                c.value = *width_m;
            }
            Self::Seam { a, b, tolerance }
            | Self::SeamPlane {
                a,
                b,
                tolerance_m: tolerance,
            } => {
                c.uv = [
                    a[0][0], a[0][1], a[1][0], a[1][1], b[0][0], b[0][1], b[1][0], b[1][1],
                ];
                c.value = *tolerance;
            }
            Self::Reset {
                body: which,
                grid,
                material,
                substeps,
                model,
                pattern,
            } => {
                if let Some(p) = pattern {
                    set_text(&mut c, p)?;
                }
                // 0: cloth-sim's own; a code past the byte's range stays out of range.
                c.rgba[0] = model.map_or(0, |m| m.saturating_add(1).min(255) as u8);
                c.b = match which {
                    BodyChoice::Cube => body::CUBE,
                    BodyChoice::Sphere => body::SPHERE,
                    BodyChoice::Mannequin => body::MANNEQUIN,
                    BodyChoice::MannequinAPose => body::MANNEQUIN_APOSE,
                    BodyChoice::Human => body::HUMAN,
                };
                c.a = grid.unwrap_or(0);
                c.mode = substeps.unwrap_or(0);
                c.uv = material.to_wire();
            }
            Self::SetMaterial { material, substeps } => {
                c.a = substeps.unwrap_or(0);
                c.uv = material.to_wire();
            }
            Self::AddPiece { .. } | Self::PlacePiece { .. } | Self::DuplicatePiece { .. } => {
                self.piece_to_wire(&mut c)?;
            }
            Self::DeletePiece { piece } => c.a = *piece,
            Self::RemoveSeam { seam } => c.a = *seam,
            Self::PressDart { seam, second } => (c.a, c.mode) = (*seam, u32::from(*second)),
        }
        Ok(c)
    }

    /// A new, moved or copied piece's fields into `c`.
    fn piece_to_wire(&self, c: &mut ToolCommand) -> Result<(), CommandError> {
        match self {
            Self::AddPiece {
                shape: s,
                place,
                drop_m,
                edge_m,
            } => {
                (c.a, c.value) = (*place, *edge_m);
                match s {
                    PieceShape::Rectangle { w, h } => {
                        (c.mode, c.vec) = (shape::RECTANGLE, [*w, *h, *drop_m])
                    }
                    PieceShape::Ellipse { w, h } => {
                        (c.mode, c.vec) = (shape::ELLIPSE, [*w, *h, *drop_m])
                    }
                    PieceShape::File { path } => {
                        (c.mode, c.vec[2]) = (shape::FILE, *drop_m);
                        set_text(c, path)?;
                    }
                }
            }
            Self::PlacePiece {
                piece,
                place,
                drop_m,
            } => (c.a, c.b, c.vec[2]) = (*piece, *place, *drop_m),
            Self::DuplicatePiece {
                piece,
                place,
                drop_m,
                mirrored,
                edge_m,
            } => {
                (c.a, c.b, c.mode, c.value) = (*piece, *place, u32::from(*mirrored), *edge_m);
                c.vec[2] = *drop_m;
            }
            _ => {}
        }
        Ok(())
    }

    /// The command a received record carries, after checking it ([`Checked`]): nothing
    /// from another process is used unchecked.
    pub fn from_wire(c: &ToolCommand) -> Result<Self, MessageError> {
        c.check()?;
        let u = &c.uv;
        Ok(match c.op {
            op::CUT_VERTEX => Self::CutVertex {
                vertex: c.a,
                direction: c.vec,
            },
            op::SEW => Self::Sew { a: c.a, b: c.b },
            op::TEAR => Self::Tear {
                a: c.a,
                b: c.b,
                split: c.mode == 1,
            },
            op::PIN => Self::Pin {
                vertex: c.a,
                pinned: c.mode == 1,
            },
            op::PAINT => Self::Paint {
                point: c.vec,
                radius_m: c.value,
                rgba: c.rgba,
            },
            op::UNDO => Self::Undo,
            op::REDO => Self::Redo,
            op::FREE_PINS => Self::FreePins,
            op::SET_TEAR => Self::SetTearing(tearing_from_wire(c)),
            op::SAVE => Self::Save { path: text(c) },
            op::SET_TOOL => Self::SetTool {
                tool: c.a,
                rgba: c.rgba,
                brush_m: c.value,
            },
            op::REMOVE_REGION => Self::RemoveRegion {
                min: [u[0], u[1]],
                max: [u[2], u[3]],
            },
            op::SEAM => Self::Seam {
                a: [[u[0], u[1]], [u[2], u[3]]],
                b: [[u[4], u[5]], [u[6], u[7]]],
                tolerance: c.value,
            },
            op::EXPORT => Self::Export {
                dir: text(c),
                allowance_mm: c.value,
            },
            op::RESET => reset_from_wire(c),
            op::LOAD => Self::Load { path: text(c) },
            op::SET_MATERIAL => Self::SetMaterial {
                material: MaterialChange::from_wire(u),
                substeps: some_nonzero(c.a),
            },
            op::ADD_PIECE | op::PLACE_PIECE | op::DUPLICATE_PIECE => piece_from_wire(c),
            op::DELETE_PIECE => Self::DeletePiece { piece: c.a },
            op::REMOVE_SEAM => Self::RemoveSeam { seam: c.a },
            op::SET_FABRIC => Self::SetFabric { name: text(c) },
            op::SET_PIECE_FABRIC => Self::SetPieceFabric {
                piece: c.a,
                name: text(c),
            },
            op::NAME_SEAM => Self::NameSeam {
                seam: c.a,
                name: text(c),
            },
            op::PRESS_DART => Self::PressDart {
                seam: c.a,
                second: c.mode == 1,
            },
            op::NAME_PIECE => Self::NamePiece {
                piece: c.a,
                name: text(c),
            },
            op::SET_GUARD => Self::SetGuard { on: c.mode == 1 },
            op::SET_SIMULATING => Self::SetSimulating { on: c.mode == 1 },
            op::SET_STRAIN_LIMIT => Self::SetStrainLimit { limit: c.value },
            op::CUT_PLANE => Self::CutPlane {
                from: [u[0], u[1]],
                to: [u[2], u[3]],
            },
            op::DART_PLANE => Self::DartPlane {
                point: [u[0], u[1]],
                toward: [u[2], u[3]],
                width_m: c.value,
            },
            op::SEAM_PLANE => Self::SeamPlane {
                a: [[u[0], u[1]], [u[2], u[3]]],
                b: [[u[4], u[5]], [u[6], u[7]]],
                tolerance_m: c.value,
            },
            other => {
                return Err(MessageError::Malformed {
                    what: ToolCommand::WHAT,
                    why: format!("unknown operation {other}"),
                });
            }
        })
    }
}

/// An ADD_PIECE, PLACE_PIECE or DUPLICATE_PIECE record's command (checked already).
fn piece_from_wire(c: &ToolCommand) -> Command {
    match c.op {
        op::ADD_PIECE => Command::AddPiece {
            shape: match c.mode {
                shape::RECTANGLE => PieceShape::Rectangle {
                    w: c.vec[0],
                    h: c.vec[1],
                },
                shape::ELLIPSE => PieceShape::Ellipse {
                    w: c.vec[0],
                    h: c.vec[1],
                },
                _ => PieceShape::File { path: text(c) },
            },
            place: c.a,
            drop_m: c.vec[2],
            edge_m: c.value,
        },
        op::PLACE_PIECE => Command::PlacePiece {
            piece: c.a,
            place: c.b,
            drop_m: c.vec[2],
        },
        _ => Command::DuplicatePiece {
            piece: c.a,
            place: c.b,
            drop_m: c.vec[2],
            mirrored: c.mode == 1,
            edge_m: c.value,
        },
    }
}

/// A SET_TEAR record's tearing (checked already).
fn tearing_from_wire(c: &ToolCommand) -> Tearing {
    match c.mode {
        0 => Tearing::Off,
        m => Tearing::On {
            threshold: c.value,
            split: m == 2,
        },
    }
}

/// A RESET record's new scene (checked already).
fn reset_from_wire(c: &ToolCommand) -> Command {
    Command::Reset {
        body: match c.b {
            body::SPHERE => BodyChoice::Sphere,
            body::MANNEQUIN => BodyChoice::Mannequin,
            body::MANNEQUIN_APOSE => BodyChoice::MannequinAPose,
            body::HUMAN => BodyChoice::Human,
            _ => BodyChoice::Cube,
        },
        grid: some_nonzero(c.a),
        material: MaterialChange::from_wire(&c.uv),
        substeps: some_nonzero(c.mode),
        model: u32::from(c.rgba[0]).checked_sub(1),
        pattern: Some(text(c)).filter(|t| !t.is_empty()),
    }
}

#[cfg(test)]
mod tests;
