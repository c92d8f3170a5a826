//! Carrying out the UI's commands on the design. Each answer says what happened, or why
//! nothing did (a refused command changes nothing).

use glam::{Vec2, Vec3};
use shared::command::{BodyChoice, Command, MaterialChange, Tearing};
use shared::telemetry::scene_model;
use sim_core::collision::BodyKind;
use sim_core::design::garment::{DEFAULT_FABRIC, sew};
use sim_core::design::{Design, EDITED, EditError, TearMode};
use sim_core::fabric::Library;
use sim_core::scenario::garment::SEAM_PULL;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_scene};
use sim_core::solver::{Material, ModelKind};

use crate::config::ServiceConfig;
#[cfg(test)]
use pieces::add_piece;
use pieces::{firm_if_hanging, piece_edit, piece_name};

/// "; warning: ..." when a seam's two sides' pattern lengths (m) differ by more than
/// `SEAM_MISMATCH` of the longer, else nothing.
fn mismatch_warning(la: f32, lb: f32) -> String {
    let long = la.max(lb);
    if long > 0.0 && (la - lb).abs() > sim_core::design::SEAM_MISMATCH * long {
        format!(
            "; warning: its sides differ in length by {:.0}% ({:.0} mm against {:.0} mm), \
             so the longer will gather",
            100.0 * (la - lb).abs() / long,
            1000.0 * la,
            1000.0 * lb
        )
    } else {
        String::new()
    }
}

/// Carries out a command on the design itself (not SET_TOOL, RESET, LOAD, EXPORT or
/// SET_SIMULATING, which the service handles); the message says what happened or why not.
pub fn carry_out(design: &mut Design, c: &Command) -> Result<String, String> {
    let e = |e: EditError| e.to_string();
    match c {
        Command::CutVertex { vertex, direction } => design
            .cut_vertex(*vertex, Vec3::from_array(*direction))
            .map(|n| format!("Cut: vertex {vertex} split in two, making new vertex {n}"))
            .map_err(e),
        Command::Sew { a, b } => design
            .sew(*a, *b)
            .map(|_| format!("Sew: vertices {a} and {b} joined into one"))
            .map_err(e),
        Command::Tear { a, b, split } => {
            let mode = if *split {
                TearMode::Split
            } else {
                TearMode::Delete
            };
            design
                .tear_edge(*a, *b, mode)
                .map(|_| format!("Tear: the edge between vertices {a} and {b} is torn"))
                .map_err(e)
        }
        Command::Pin { vertex, pinned } => pin_one(design, *vertex, *pinned, "").map_err(e),
        Command::FreePins => design
            .free_pins()
            .map(|n| format!("Freed {n} pin{}: the cloth hangs free again", plural(n)))
            .map_err(e),
        Command::Paint {
            point,
            radius_m,
            rgba,
        } => design
            .paint(Vec3::from_array(*point), *radius_m, *rgba)
            .map(|_| "Paint: a dab of colour on the cloth".to_string())
            .map_err(e),
        Command::RemoveRegion { min, max } => design
            .remove_region(Vec2::from_array(*min), Vec2::from_array(*max))
            .map(|n| format!("Cut away: {n} triangles removed from the pattern"))
            .map_err(e),
        Command::CutPlane { from, to } => cut_line(design, from, to),
        Command::DartPlane {
            point,
            toward,
            width_m,
        } => dart(design, point, toward, *width_m),
        Command::Seam { a, b, tolerance } => seam(design, a, b, *tolerance, false),
        Command::SeamPlane { a, b, tolerance_m } => seam(design, a, b, *tolerance_m, true),
        Command::SetMaterial { material, substeps } => set_material(design, material, *substeps),
        Command::SetFabric { name } => set_fabric(design, name),
        Command::SetPieceFabric { piece, name } => set_piece_fabric(design, *piece, name),
        Command::Undo => design.undo().map(|l| format!("Undone: {l}")).map_err(e),
        Command::Redo => {
            // A redo without its welds says so (`Design::redo`).
            let told = design.sim.notices.len();
            let redone = design.redo().map_err(e)?;
            Ok(match design.sim.notices.get(told..) {
                Some([.., said]) => said.clone(),
                _ => format!("Redone: {redone}"),
            })
        }
        Command::SetTearing(t) => set_tearing(design, *t),
        Command::SetGuard { on } => design.set_guard(*on).map_err(e),
        Command::SetStrainLimit { limit } => set_strain_limit(design, *limit),
        Command::Save { path } => design
            .refresh_png_cache()
            .and_then(|_| design.save_design_file(std::path::Path::new(path)))
            .map(|_| format!("Saved the design to {path}"))
            .map_err(|e| e.to_string()),
        Command::AddPiece { .. }
        | Command::PlacePiece { .. }
        | Command::DeletePiece { .. }
        | Command::DuplicatePiece { .. } => {
            let done = piece_edit(design, c)?;
            Ok(done + &firm_if_hanging(design, c))
        }
        Command::NameSeam { .. } | Command::NamePiece { .. } => name_one(design, c),
        Command::PressDart { seam, second } => {
            let label = sim_core::design::sewing_pattern::seam_label(*seam as usize);
            let leg = if *second { "second" } else { "first" };
            design
                .press_dart(*seam as usize, *second)
                .map(|_| {
                    format!(
                        "Dart {label} is pressed toward its {leg} leg (the arrow in the pattern \
                         view): the pattern's cut line caps its mouth that way; undo takes it back"
                    )
                })
                .map_err(e)
        }
        Command::RemoveSeam { seam } => {
            let label = sim_core::design::sewing_pattern::seam_label(*seam as usize);
            design
                .remove_seam(*seam as usize)
                .map(|r| removed(&label, r, *seam as usize >= design.seams.len()))
                .map_err(e)
        }
        Command::SetTool { .. }
        | Command::Reset { .. }
        | Command::Load { .. }
        | Command::Export { .. }
        | Command::SetSimulating { .. } => Err(format!("operation {} is the service's", c.op())),
    }
}

/// The answer to a seam removed: what was unpicked, and what stays sewn (`last`: no
/// seam came after it).
fn removed(label: &str, r: sim_core::design::Removed, last: bool) -> String {
    let mut said = format!("Removed seam {label} ({} pairs)", r.pairs);
    if r.unpicked > 0 {
        said += &format!("; {} sewn pair{} unpicked", r.unpicked, plural(r.unpicked));
        if r.eased_back > 0 {
            said += &format!(
                ", the cloth eased into it back ({} triangle{})",
                r.eased_back,
                plural(r.eased_back)
            );
        }
    }
    if r.kept > 0 {
        said += &format!(
            "; {} sewn pair{} stay{} sewn where other seams hold the cloth on both sides (remove them too to open {})",
            r.kept,
            plural(r.kept),
            if r.kept == 1 { "s" } else { "" },
            if r.kept == 1 { "it" } else { "them" }
        );
    }
    if !last {
        said += "; the seams after it move up a letter";
    }
    said
}

/// "s" unless `n` is 1.
fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Pins or frees vertex `v` (`how`: " by the pen", or nothing for the mouse); the answer
/// names the piece and counts the design's pins, so a designer knows what holds the cloth.
pub(crate) fn pin_one(
    design: &mut Design,
    v: u32,
    pinned: bool,
    how: &str,
) -> Result<String, EditError> {
    design.set_pin(v, pinned)?;
    let piece = design
        .piece_name_of(v)
        .unwrap_or_else(|| "the cloth".into());
    let n = design.pinned_vertices().len();
    Ok(if pinned {
        let hold = if n == 1 { "holds" } else { "hold" };
        format!(
            "Pin: {piece} pinned here{how}; {n} pin{} {hold} the cloth (shift-click a pin to \
             free it, or Free pins in the Tools panel)",
            plural(n)
        )
    } else {
        format!("Pin: {piece} freed here{how}; {n} pin{} left", plural(n))
    })
}

/// What a reply that stitched seams adds when the xpbd model runs without its strain
/// limit: the cloth stretches where it hangs, and the shipped dress's shoulder seams
/// then stay open at the neck (docs/garments.md). Empty otherwise.
pub(crate) fn seam_tip(design: &Design) -> &'static str {
    if design.sim.model == ModelKind::Xpbd && design.sim.material.strain_limit == 0.0 {
        "; tip: if a seam stays open, try Hold stretch under (the scene panel): the shipped \
         dress closes every seam with it"
    } else {
        ""
    }
}

/// A seam between the border paths along two segments, in UV or (`plane`) in the
/// design's pattern plane, with a warning when their lengths do not match.
/// Scissors along a line in the pattern plane; the reply says how many pieces the cloth
/// is now.
fn cut_line(design: &mut Design, from: &[f32; 2], to: &[f32; 2]) -> Result<String, String> {
    let n = (design.cut_line(Vec2::from_array(*from), Vec2::from_array(*to)))
        .map_err(|x| x.to_string())?;
    let pieces = match design.piece_list().len() {
        1 => "1 piece".to_string(),
        k => format!("{k} pieces"),
    };
    Ok(format!(
        "Cut: {n} vertices split along the line; the cloth is {pieces} now"
    ))
}

// The studio offers the widths the design takes.
const _: () = assert!(
    shared::ui_to_sim::DART_WIDTH.0 == *sim_core::design::DART_WIDTH_M.start()
        && shared::ui_to_sim::DART_WIDTH.1 == *sim_core::design::DART_WIDTH_M.end()
);

fn dart(
    design: &mut Design,
    point: &[f32; 2],
    toward: &[f32; 2],
    width: f32,
) -> Result<String, String> {
    let (p, q) = (Vec2::from_array(*point), Vec2::from_array(*toward));
    let pairs = design
        .dart_on_plane(p, q, width)
        .map_err(|x| x.to_string())?;
    let k = design.seams.len() - 1;
    let label = sim_core::design::sewing_pattern::seam_label(k);
    // A dart into a seam already sewn: the cloth sewn to it has to gather the intake.
    let sewn = if design.dart_mouth_sewn(k) == Some(true) {
        "; its mouth is on a seam already sewn, whose other side must gather the intake: \
         the pairs at the mouth may stay open (the seam list tells); undo, Remove that \
         seam (it is unpicked), take the dart and sew the seam again"
    } else {
        ""
    };
    // Which way its intake lies: a tailor's way where the body tells one.
    let tailors = design.tailors_press(k);
    let press = match (design.pressed_legs(k), tailors) {
        (Some([to, _]), Some((way, rule))) if to == way => match rule {
            sim_core::design::TailorsPress::TowardMiddle => {
                "; pressed toward the body's middle, as a dart up the body is"
            }
            sim_core::design::TailorsPress::Down => "; pressed down, as a dart round the body is",
        },
        (Some(_), _) => "; pressed toward its first leg",
        (None, _) => "",
    };
    Ok(format!(
        "Dart: {:.0} mm wide, its legs seam {label} of {pairs} pairs{press}; it closes as the cloth is simulated{sewn}",
        width * 1e3
    ))
}

/// What a new seam's pairs do, as its answer says (a seam made while the cloth runs
/// adds that the cloth floats meanwhile: `Service::float_new_seam`).
pub(crate) const STITCHED_PULL: &str = "of border vertices stitched; they pull together";

fn seam(
    design: &mut Design,
    a: &[[f32; 2]; 2],
    b: &[[f32; 2]; 2],
    tol: f32,
    plane: bool,
) -> Result<String, String> {
    let seg = |s: &[[f32; 2]; 2]| s.map(Vec2::from_array);
    let (sa, sb) = (seg(a), seg(b));
    // The two sides' pattern lengths, for a warning when they do not match.
    let (pa, pb) = design.seam_sides(sa, sb, tol, plane);
    let (la, lb) = (design.pattern_length(&pa), design.pattern_length(&pb));
    let done = if plane {
        design.seam_on_plane(sa, sb, tol)
    } else {
        design.seam_on_pattern(sa, sb, tol)
    };
    done.map(|n| {
        format!(
            "Seam: {n} pairs {STITCHED_PULL} and are sewn as they meet{}",
            mismatch_warning(la, lb)
        )
    })
    .map_err(|e| e.to_string())
}

fn set_material(
    design: &mut Design,
    change: &MaterialChange,
    substeps: Option<u32>,
) -> Result<String, String> {
    let old = design.sim.material;
    let mut m = old;
    apply_material(&mut m, change);
    // Mass and stiffness set by hand are the whole design's: every piece hangs as them
    // (damping and friction are the design's whatever the pieces' fabrics).
    let hangs_otherwise = (m.density, m.stretch, m.shear, m.bending)
        != (old.density, old.stretch, old.shear, old.bending);
    design
        .sim
        .set_material(m, substeps.map(|n| n as usize))
        .map_err(|e| format!("Material not changed: {e}"))?;
    let mut said = String::new();
    if hangs_otherwise {
        // The pieces no longer hang as their fabric measured: their list says so.
        design.rename_fabrics(|f| {
            if f.ends_with(EDITED) {
                f.to_string()
            } else {
                format!("{f}{EDITED}")
            }
        });
        said = fabric_notes(design.apply_fabrics());
    }
    Ok(format!(
        "Material: density {} kg/m², stretch {} N/m, shear {} N/m, bending {} N m, \
         friction {}, damping {}/s, shear damping {} ms, bending damping {} ms; {} \
         substeps{said}",
        m.density,
        m.stretch,
        m.shear,
        m.bending,
        m.friction,
        m.damping,
        // To a ten-thousandth of a ms: 20 ms from the studio is 0.020000001 s.
        (f64::from(m.shear_damping) * 1e7).round() / 1e4,
        (f64::from(m.bend_damping) * 1e7).round() / 1e4,
        design.sim.substeps
    ))
}

/// The xpbd model's strain limit for the design, in place (0: none).
pub fn set_strain_limit(design: &mut Design, limit: f32) -> Result<String, String> {
    if design.sim.model != ModelKind::Xpbd {
        return Err(format!(
            "Strain limit not changed: the {} model has none (the xpbd model's is a hard \
             limit on each triangle's stretch)",
            design.sim.model.name()
        ));
    }
    let m = Material {
        strain_limit: limit,
        ..design.sim.material
    };
    design
        .sim
        .set_material(m, None)
        .map_err(|e| format!("Strain limit not changed: {e}"))?;
    Ok(if limit == 0.0 {
        "Strain limit off: triangles stretch as far as the solver leaves them".into()
    } else {
        format!(
            "Strain limit on: no triangle stretches past {:.2}x its rest length in any \
             direction (frames cost 30-100% more)",
            1.0 + limit
        )
    })
}

/// What applying the pieces' fabrics said, as "; note: ..." parts.
fn fabric_notes(r: Result<Vec<String>, sim_core::error::ConfigError>) -> String {
    match r {
        Ok(notes) => notes.iter().map(|n| format!("; note: {n}")).collect(),
        Err(e) => format!("; the pieces' own fabrics were not applied: {e}"),
    }
}

/// Piece `piece` made of the library's fabric `name` (or the design's material).
/// A seam or a piece named (`NAME_SEAM`, `NAME_PIECE`), with the reply that says so.
fn name_one(design: &mut Design, c: &Command) -> Result<String, String> {
    let e = |x: EditError| x.to_string();
    match c {
        Command::NameSeam { seam, name } => {
            let label = sim_core::design::sewing_pattern::seam_label(*seam as usize);
            design
                .name_seam(*seam as usize, name)
                .map(|_| match name.trim() {
                    "" => format!("Seam {label} goes by its letter again"),
                    n => format!("Seam {label} is now called \"{n}\" (undo takes it back)"),
                })
                .map_err(e)
        }
        Command::NamePiece { piece, name } => {
            let was = piece_name(design, *piece);
            design
                .name_piece(*piece as usize, name)
                .map(|_| format!("{was} is now called {} (undo takes it back)", name.trim()))
                .map_err(e)
        }
        _ => Err("not a name".into()),
    }
}

fn set_piece_fabric(design: &mut Design, piece: u32, name: &str) -> Result<String, String> {
    let name = name.trim();
    let records = design.pieces.len();
    let piece_name = design
        .set_piece_fabric(piece as usize, name)
        .map_err(|e| format!("Fabric not changed: {e}; `cloth-sim fabrics` lists them"))?;
    let piece_name = if design.pieces.len() > records {
        format!(
            "{piece_name}, a piece of its own now (a fabric is a whole pattern piece's; \
             the pattern view has it on the right),"
        )
    } else {
        piece_name
    };
    if name == DEFAULT_FABRIC {
        return Ok(format!("Fabric: {piece_name} is the design's own material"));
    }
    let lib = Library::builtin();
    let f = lib.get(name).map_err(|e| e.to_string())?;
    let m = f.material();
    Ok(format!(
        "Fabric: {piece_name} is {} ({:.0} g/m², bending {:.1e} N m warp, {:.1e} weft); the \
         other pieces stay as they are; undo takes it back",
        f.name,
        m.density * 1e3,
        m.bending,
        m.bending * m.bending_weft
    ))
}

/// The library's fabric `name` for the whole design, in place: its measured values
/// replace the material's, damping and the solver's settings stay.
fn set_fabric(design: &mut Design, name: &str) -> Result<String, String> {
    let lib = Library::builtin();
    let f = lib
        .get(name.trim())
        .map_err(|e| format!("Fabric not changed: {e}; `cloth-sim fabrics` lists them"))?;
    let m = f.material_over(&design.sim.material);
    design
        .sim
        .set_material(m, None)
        .map_err(|e| format!("Fabric not changed: {e}"))?;
    design.rename_fabrics(|_| f.name.clone());
    let said = fabric_notes(design.apply_fabrics());
    let held = match (design.sim.model, m.strain_limit) {
        (ModelKind::Xpbd, l) if l > 0.0 => format!(", held under {:.2}x", 1.0 + l),
        (ModelKind::Xpbd, _) => ", no stretch limit".into(),
        _ => String::new(),
    };
    Ok(format!(
        "Fabric: {} ({:.0} g/m², bending {:.1e} N m warp, {:.1e} weft{held}) for the whole \
         design; source: {}{said}",
        f.name,
        m.density * 1e3,
        m.bending,
        m.bending * m.bending_weft,
        f.source
    ))
}

/// The fabric a new piece gets: the one every piece of the design has, else the default.
fn design_fabric(design: &Design) -> String {
    match design.pieces.first() {
        Some(p) if design.pieces.iter().all(|q| q.fabric == p.fabric) => p.fabric.clone(),
        _ => DEFAULT_FABRIC.into(),
    }
}

fn set_tearing(design: &mut Design, t: Tearing) -> Result<String, String> {
    match t {
        Tearing::Off => {
            design.tear.enabled = false;
            design.tear.mode = TearMode::Delete;
            Ok("Tearing off".into())
        }
        Tearing::On { threshold, split } => {
            if threshold <= 1.0 {
                return Err(format!(
                    "The tear threshold must be above 1, got {threshold}"
                ));
            }
            design.tear.enabled = true;
            design.tear.mode = if split {
                TearMode::Split
            } else {
                TearMode::Delete
            };
            design.tear.threshold = threshold;
            Ok(format!(
                "Tearing on: edges tear past {threshold} times their rest length"
            ))
        }
    }
}

/// The material with a command's changes: each value given replaces the one in `m`.
fn apply_material(m: &mut Material, c: &MaterialChange) {
    let set = |field: &mut f32, v: Option<f32>| {
        if let Some(v) = v {
            *field = v;
        }
    };
    set(&mut m.density, c.density);
    set(&mut m.stretch, c.stretch);
    set(&mut m.shear, c.shear);
    set(&mut m.bending, c.bending);
    set(&mut m.friction, c.friction);
    set(&mut m.damping, c.damping);
    set(&mut m.shear_damping, c.shear_damping);
    set(&mut m.bend_damping, c.bend_damping);
}

/// The model a [`scene_model`](shared::telemetry::scene_model) code names: the code is
/// the place of the model's `--model` name in `scene_model::NAMES`.
pub(crate) fn model_of(code: u32) -> Result<ModelKind, String> {
    let name = scene_model::NAMES
        .get(code as usize)
        .ok_or_else(|| format!("unknown model {code}"))?;
    ModelKind::parse(name).map_err(|e| e.to_string())
}

/// The [`scene_model`](shared::telemetry::scene_model) code of `kind` (the inverse of
/// [`model_of`]).
pub(crate) fn model_code(kind: ModelKind) -> u32 {
    scene_model::NAMES
        .iter()
        .position(|n| *n == kind.name())
        .unwrap_or(scene_model::NAMES.len()) as u32
}

/// A new design from `scene`; with `scene.pattern` (whatever its scenario) that pattern's
/// pieces placed round the body and sewn, as drape-pattern builds them, and what was
/// stitched ("4 seams stitched (122 pairs)", with the notes of the file's reader and of
/// the seams left unsewn).
pub fn new_design(scene: &ScenarioConfig) -> Result<(Design, Option<String>), String> {
    let mut scene = scene.clone();
    if scene.pattern.is_some() {
        scene.scenario = ScenarioName::DrapePattern;
        scene.cloth = None;
        scene.piece = None;
    }
    let (mut d, spec) = build_scene(&scene).map_err(|e| e.to_string())?;
    let Some(spec) = spec else {
        return Ok((d, None));
    };
    let sewn = sew(&mut d, &spec, SEAM_PULL).map_err(|e| e.to_string())?;
    d.float_while_sewing();
    let mut said = format!("{} seams stitched ({} pairs)", sewn.seams, sewn.pairs);
    if let Some(held) = sim_core::scenario::hold_pattern(&mut d, &spec, scene.substeps) {
        said += &format!("; {held}");
    }
    for n in d.sim.notices.iter().chain(&sewn.open) {
        said += &format!("; note: {n}");
    }
    Ok((d, Some(said)))
}

/// The design that replaces the current one for a RESET or LOAD command, what it is, and
/// where the current one was saved first (next to the autosave, so a reset loses
/// nothing).
pub(crate) fn replacement(
    design: &mut Design,
    c: &Command,
    cfg: &ServiceConfig,
) -> Result<(Design, String, std::path::PathBuf), String> {
    let next = match c {
        Command::Load { path } => {
            let path = std::path::PathBuf::from(path);
            let d = Design::load_design_file(&path).map_err(|e| e.to_string())?;
            let mut msg = format!("Loaded the design {}", path.display());
            for n in &d.sim.notices {
                msg += &format!("; note: {n}");
            }
            (d, msg)
        }
        Command::Reset {
            body,
            grid,
            material,
            substeps,
            model,
            pattern,
        } => {
            let mut scene = cfg.scene.clone();
            if let Some(m) = model {
                scene.model = model_of(*m)?;
            }
            let kind = match body {
                BodyChoice::Sphere => BodyKind::Sphere,
                BodyChoice::Mannequin => BodyKind::Mannequin,
                BodyChoice::Cube => BodyKind::Cube,
                BodyChoice::MannequinAPose => BodyKind::MannequinAPose,
                BodyChoice::Human => BodyKind::Human,
            };
            let name = kind.name();
            scene.body = Some(kind);
            if let Some(g) = grid {
                scene.grid = *g as usize;
            }
            apply_material(&mut scene.material, material);
            if let Some(n) = substeps {
                scene.substeps = Some(*n as usize);
            }
            // A square cloth, or the garment scenarios' design: the pattern's pieces
            // placed round the body (their tops above its shoulders) and sewn.
            scene.scenario = ScenarioName::DrapeCube;
            scene.pattern = pattern.as_ref().map(Into::into);
            let (d, sewn) = new_design(&scene)?;
            let msg = match (pattern, sewn) {
                (Some(path), Some(sewn)) => format!(
                    "New design: the {} pieces of {path} round the {name}, {sewn} ({} model)",
                    d.pieces.len(),
                    scene.model.name()
                ),
                _ => format!(
                    "New design: a {}x{} cloth over the {} ({} model)",
                    scene.grid,
                    scene.grid,
                    name,
                    scene.model.name()
                ),
            };
            (d, msg)
        }
        other => {
            return Err(format!(
                "operation {} does not replace the design",
                other.op()
            ));
        }
    };
    let backup = cfg.autosave.with_extension("before-reset.saiho");
    design
        .refresh_png_cache()
        .and_then(|_| design.save_design_file(&backup))
        .map_err(|e| {
            format!("The current design could not be saved first ({e}); nothing changed")
        })?;
    Ok((next.0, next.1, backup))
}

mod pieces;
#[cfg(test)]
mod tests;
