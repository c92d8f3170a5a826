//! The piece edits of the command set: a piece added (a rectangle, an ellipse, a
//! pattern file's pieces), moved, deleted or copied, where it starts, and the substeps a
//! piece that hangs below the shoulders needs under xpbd.

use shared::command::{Command, PieceShape};
use sim_core::design::garment::{
    Landmarks, PieceSpec, Place, Placement, Start, holds, load_pattern, sew,
};
use sim_core::design::{Design, EditError};
use sim_core::mesh::mesher::Outline;
use sim_core::scenario::FIRM_SUBSTEPS;
use sim_core::scenario::garment::SEAM_PULL;
use sim_core::solver::ModelKind;

use super::{design_fabric, seam_tip};

/// A piece added, moved, deleted or copied.
pub(super) fn piece_edit(design: &mut Design, c: &Command) -> Result<String, String> {
    let e = |e: EditError| e.to_string();
    match c {
        Command::AddPiece {
            shape,
            place,
            drop_m,
            edge_m,
        } => add_piece(design, shape, start_of(*place, *drop_m)?, *edge_m),
        Command::PlacePiece {
            piece,
            place,
            drop_m,
        } => {
            let at = start_of(*place, *drop_m)?;
            let name = piece_name(design, *piece);
            design.place_piece(*piece as usize, at).map_err(e)?;
            let r = design.pieces.iter().position(|r| r.name == name);
            Ok(format!(
                "Placed {name} at the {}{}",
                where_(at),
                started_note(design, r, at)
            ))
        }
        Command::DeletePiece { piece } => {
            let name = piece_name(design, *piece);
            let seams = design.seams.len();
            let n = design.delete_piece(*piece as usize).map_err(e)?;
            Ok(match seams.saturating_sub(design.seams.len()) {
                0 => format!("Deleted {name} ({n} triangles)"),
                k => format!(
                    "Deleted {name} ({n} triangles) and the {k} seam(s) left with nothing to \
                     sew; the seams after them move up a letter"
                ),
            })
        }
        Command::DuplicatePiece {
            piece,
            place,
            drop_m,
            mirrored,
            edge_m,
        } => {
            let at = start_of(*place, *drop_m)?;
            let was = piece_name(design, *piece);
            design
                .duplicate_piece(*piece as usize, at, *mirrored, *edge_m)
                .map(|(name, n)| {
                    let how = if *mirrored { ", turned over" } else { "" };
                    let r = design.pieces.len().checked_sub(1);
                    format!(
                        "Copied {was} as {name} at the {} ({n} vertices{how}){}; sew it as \
                         any piece (undo takes it away)",
                        where_(at),
                        started_note(design, r, at)
                    )
                })
                .map_err(e)
        }
        _ => Err(format!("operation {} is not a piece's", c.op())),
    }
}

/// How far below the shoulders a piece must start to hang from the waist or hips, m: the
/// mannequin's chest is 0.2-0.3 m down, its waist 0.42.
const HANGS_BELOW: f32 = 0.25;

/// Under xpbd at fewer than [`FIRM_SUBSTEPS`], a piece added, copied or moved
/// [`HANGS_BELOW`] or more below the shoulders (not on an arm) raises the design's
/// substeps to it and says so: at 5 a skirt of two pieces sewn at the sides slid off
/// the mannequin's hips to the floor, at 20 it stayed at the waist, as a pattern's
/// garment that hangs from its waist runs (docs/garments.md), and its undo puts them back.
/// Otherwise nothing.
pub(super) fn firm_if_hanging(design: &mut Design, c: &Command) -> String {
    let (Command::AddPiece { place, drop_m, .. }
    | Command::PlacePiece { place, drop_m, .. }
    | Command::DuplicatePiece { place, drop_m, .. }) = c
    else {
        return String::new();
    };
    let on_arm = matches!(
        *place,
        shared::ui_to_sim::place::LEFT_ARM | shared::ui_to_sim::place::RIGHT_ARM
    );
    let was = design.sim.substeps;
    if *drop_m < HANGS_BELOW
        || on_arm
        || design.sim.model != ModelKind::Xpbd
        || was >= FIRM_SUBSTEPS
    {
        return String::new();
    }
    // Undone with the piece (a skirt added and undone left the dress at 20).
    design.firm_with_last_edit(FIRM_SUBSTEPS);
    format!("; xpbd now runs {FIRM_SUBSTEPS} substeps, not {was} (a skirt slid off at {was})")
}

/// The start a wire place code and drop name.
fn start_of(code: u32, drop: f32) -> Result<Start, String> {
    let place = shared::ui_to_sim::place::NAMES
        .get(code as usize)
        .and_then(|n| Place::parse(n))
        .ok_or_else(|| format!("no place {code}"))?;
    Ok(Start { place, drop })
}

/// Where a piece starts, as the answer says it: "front", "left arm, 0.10 m lower".
fn where_(at: Start) -> String {
    let place = at.place.name().replace('-', " ");
    if at.drop > 0.0 {
        format!("{place}, {:.2} m lower", at.drop)
    } else {
        place
    }
}

/// What an answer adds when piece record `r` started further from `at` than asked, to
/// clear the cloth there (a layer out, or down an arm: `Design::add_piece`), or nothing.
fn started_note(design: &Design, r: Option<usize>, at: Start) -> String {
    let placement = r
        .and_then(|r| design.pieces.get(r))
        .and_then(|p| p.placement);
    let (lower, out) = match placement {
        Some(Placement::Arm { down, room, .. }) => (down - at.drop, room),
        Some(Placement::Around { out, .. }) => (0.0, out),
        _ => (0.0, 0.0),
    };
    let (lower, out) = ((lower * 100.0).round(), (out * 1000.0).round());
    match (lower > 0.0, out > 0.0) {
        (false, false) => String::new(),
        (true, false) => format!(", {lower:.0} cm down the arm to clear the cloth"),
        (false, true) => format!(", {out:.0} mm out to clear the cloth"),
        (true, true) => {
            format!(", {lower:.0} cm down the arm and {out:.0} mm out to clear the cloth")
        }
    }
}

/// Piece `index`'s name as the list has it, or its number.
pub(super) fn piece_name(design: &Design, index: u32) -> String {
    design
        .piece_list()
        .get(index as usize)
        .map_or_else(|| format!("piece {index}"), |p| p.name.clone())
}

/// Adds a rectangle, an ellipse or every piece of a pattern file (its seams sewn).
pub(super) fn add_piece(
    design: &mut Design,
    shape: &PieceShape,
    at: Start,
    edge: f32,
) -> Result<String, String> {
    let fabric = design_fabric(design);
    let piece = |name: &str, outline: Outline| PieceSpec {
        name: name.into(),
        outline,
        fabric: fabric.clone(),
        grain: 0.0,
        placement: None,
        start: None,
        fallback: None,
    };
    let one = |design: &mut Design, p: PieceSpec| {
        let n = design.add_piece(&p, at, edge).map_err(|e| e.to_string())?;
        let r = design.pieces.len().checked_sub(1);
        // Its name as the list has it ("rectangle (2)" beside another rectangle).
        let name = r.map_or(p.name.as_str(), |r| design.pieces[r].name.as_str());
        Ok(format!(
            "Added {name} at the {} ({n} vertices){}",
            where_(at),
            started_note(design, r, at)
        ))
    };
    match shape {
        PieceShape::Rectangle { w, h } => {
            one(design, piece("rectangle", Outline::rectangle(*w, *h)))
        }
        PieceShape::Ellipse { w, h } => one(
            design,
            piece("ellipse", Outline::ellipse(0.5 * w, 0.5 * h, edge)),
        ),
        PieceShape::File { path } => {
            let marks = Landmarks::of(design.sim.body.as_ref());
            let (mut spec, notes) =
                load_pattern(std::path::Path::new(path), &marks).map_err(|e| e.to_string())?;
            if spec.pieces.len() == 1 && spec.seams.is_empty() && spec.holds.is_empty() {
                // One piece goes where the designer asked, not where its name says (a
                // circle skirt cut in one piece, sewn to itself and held at the waist,
                // goes where its fan does, below).
                spec.pieces[0].placement = None;
                spec.pieces[0].fallback = None;
                return one(design, spec.pieces.remove(0));
            }
            let base = design.pieces.len();
            let mut added = 0;
            for p in &spec.pieces {
                if let Err(e) = design.add_piece(p, at, edge) {
                    return Err(format!(
                        "{e} ({added} of the file's {} pieces were added; undo takes them back)",
                        spec.pieces.len()
                    ));
                }
                added += 1;
            }
            for s in &mut spec.seams {
                s.a.piece += base;
                s.b.piece += base;
            }
            for h in &mut spec.holds {
                h.edge.piece += base;
            }
            let sewn = sew(design, &spec, SEAM_PULL).map_err(|e| e.to_string())?;
            let pieces = if added == 1 {
                "the piece".to_string()
            } else {
                format!("the {added} pieces")
            };
            let mut msg = format!(
                "Added {pieces} of {path}, {} seams stitched ({} pairs)",
                sewn.seams, sewn.pairs
            );
            // A skirt's waist held at the body's while it settles, as the scenarios hold it.
            let held = holds(design, &spec);
            if !held.is_empty() {
                msg += &format!(
                    "; its waist ({} vertices) held for the first {} frames",
                    held.len(),
                    sim_core::design::HOLD_FRAMES
                );
                design.hold_while_draping(held);
            }
            for n in notes.iter().chain(&sewn.open) {
                msg += &format!("; note: {n}");
            }
            if sewn.seams > 0 {
                msg += seam_tip(design);
            }
            Ok(msg)
        }
    }
}
