//! Running a scenario: build the scene, step it (with the scenario's script at the end of
//! the drape), measure, export.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec3;

use super::config::{ScenarioConfig, ScenarioError, ScenarioName, build_scene};
use super::held::{Release, hold_pattern};
use super::report::{OpsReport, Percentiles, Report};
use super::scripts;
use crate::collision::crossings::Crossings;
use crate::collision::{Body, BodyKind};
use crate::design::Design;
use crate::design::export::{export_garment_glb, export_glb, export_obj};
use crate::design::garment::PatternSpec;
use crate::mesh::obj;
use crate::solver::{Rest, SleepRule};

/// What the frames of a run measured.
#[derive(Default)]
struct Frames {
    step_ms: Vec<f64>,
    collision_ms: Vec<f64>,
    /// The frames the cloth did not sleep through (with `--sleep`), ms.
    awake_ms: Vec<f64>,
    /// The first frame it slept through.
    first_asleep: Option<u64>,
    /// The sleep rule's watch (whether or not the cloth may sleep), and whether the last
    /// frame found the cloth still for the rule's second.
    watch: Rest,
    at_rest: bool,
    kinetic_energy_max: f64,
    ops: OpsReport,
    /// With `check_every`: the most crossings seen at a checked frame.
    crossings_max: Option<Crossings>,
}

/// The once-a-second progress line, after frame `frame` (1-based).
fn progress(cfg: &ScenarioConfig, frame: u64, step_ms: &[f64], ke: f64, contacts: usize) {
    eprintln!(
        "{}: frame {frame}/{} ({:.0}%), frame p50 {:.2} ms, kinetic energy {ke:.2e} J, {contacts} contacts",
        cfg.scenario.name(),
        cfg.frames,
        100.0 * frame as f64 / cfg.frames as f64,
        Percentiles::of(step_ms).p50,
    );
}

/// The seam allowance of the pattern every scenario writes, mm.
pub const SCENARIO_ALLOWANCE_MM: f64 = 10.0;

/// Runs a scenario and writes `out/cloth.obj`, `out/body.obj` and `out/report.json`.
pub fn run_scenario(cfg: &ScenarioConfig, out: &Path) -> Result<Report, ScenarioError> {
    let started = Instant::now();
    let (mut design, spec) = build_scene(cfg)?;
    std::fs::create_dir_all(out).map_err(write_err(out))?;
    for n in &design.sim.notices {
        eprintln!("note: {n}");
    }
    let mut frames = run_frames(cfg, &mut design, spec.as_ref())?;
    let exported = export(cfg, &design, out, &mut frames.ops)?;
    let report = report(cfg, &design, frames, exported, started);
    let report_path = out.join("report.json");
    let json = serde_json::to_string_pretty(&report).map_err(|e| ScenarioError::Write {
        path: report_path.clone(),
        source: e.into(),
    })?;
    std::fs::write(&report_path, json + "\n").map_err(write_err(&report_path))?;
    Ok(report)
}

fn write_err(path: &Path) -> impl FnOnce(std::io::Error) -> ScenarioError + use<> {
    let path = path.to_owned();
    move |source| ScenarioError::Write { path, source }
}

/// Steps every frame of the scenario, running its script once the cloth has draped.
fn run_frames(
    cfg: &ScenarioConfig,
    design: &mut Design,
    spec: Option<&PatternSpec>,
) -> Result<Frames, ScenarioError> {
    // Room for the frames up front, but never more than a long run's worth at once.
    let room = cfg.frames.min(100_000) as usize;
    let mut frames = Frames {
        step_ms: Vec::with_capacity(room),
        collision_ms: Vec::with_capacity(room),
        ..Frames::default()
    };
    let mut last_print = Instant::now();
    let body0 = design.sim.body.clone();
    let ops = &mut frames.ops;
    let mut pull: Option<(Vec3, Vec3, u64)> = None;
    let mut fold = (cfg.scenario == ScenarioName::Fold).then(scripts::Fold::default);
    if let Some(spec) = spec {
        sew_pattern(cfg, design, spec, ops)?;
    }
    let mut release = Release::watching(design);
    if fold.is_some() && cfg.frames < scripts::FOLD_FRAMES {
        eprintln!(
            "note: fold: {} frames end before the second fold has settled (it needs {})",
            cfg.frames,
            scripts::FOLD_FRAMES
        );
    }
    for f in 0..cfg.frames {
        if let Some(fold) = &mut fold {
            fold.at_frame(design, f)?;
            ops.folds = Some(fold.done);
        } else if f == scripts::DRAPE_FRAMES {
            pull = run_script(cfg, design, body0.as_ref(), ops, f)?;
        }
        if let Some((start, centre, f0)) = pull {
            let t = (f - f0) as f32 * cfg.frame_dt;
            design.pinch_move(scripts::tear_target(start, centre, t));
        }
        let told = design.sim.notices.len();
        let stats = design.step()?;
        // What the frame found to tell (pairs that stopped closing), said as it happens.
        for n in design.sim.notices.get(told..).unwrap_or_default() {
            eprintln!("note: {n}");
        }
        release.after_frame(design, f + 1);
        if stats.torn > 0 && ops.first_tear_frame.is_none() && pull.is_some() {
            ops.first_tear_frame = Some(design.sim.frame);
        }
        if let Some(t) = &mut ops.tears {
            *t += stats.torn;
        }
        if ops.seams.is_some() {
            *ops.welds.get_or_insert(0) += stats.welded;
            ops.seam_pairs_welded = Some(
                design
                    .seams
                    .iter()
                    .map(|s| s.pairs.len() - s.open_pairs().count())
                    .sum(),
            );
            // A slit closed as one (`design/slit.rs`) makes a sewn pair of each of its
            // vertices: the pairs are counted as they are now.
            ops.seam_pairs = Some(design.seams.iter().map(|s| s.pairs.len()).sum());
        }
        if let Some(force) = design
            .sim
            .pinch_forces()
            .iter()
            .map(|f| f.length() as f64)
            .reduce(f64::max)
        {
            let m = ops.pinch_force_max_n.get_or_insert(0.0);
            *m = m.max(force);
        }
        // Stop pulling a while after the first tear, so the torn piece can fall away.
        if let (Some(ft), Some(_)) = (ops.first_tear_frame, pull)
            && design.sim.frame >= ft + 60
        {
            design.pinch_end();
            pull = None;
        }
        if let Some(n) = cfg.check_every
            && (f + 1) % n == 0
        {
            let c = design.sim.crossings();
            let m = frames.crossings_max.get_or_insert_with(Crossings::default);
            m.self_pairs = m.self_pairs.max(c.self_pairs);
            m.body_pairs = m.body_pairs.max(c.body_pairs);
        }
        frames.step_ms.push(stats.wall_ms);
        frames.collision_ms.push(stats.collision_ms);
        if stats.asleep {
            frames.first_asleep.get_or_insert(f + 1);
        } else {
            frames.awake_ms.push(stats.wall_ms);
        }
        let ke = design.sim.cloth.kinetic_energy();
        frames.kinetic_energy_max = frames.kinetic_energy_max.max(ke);
        let sim = &design.sim;
        let held = sim.pinch().is_some() || !sim.stitches.is_empty();
        let (x, w) = (&sim.cloth.x, &sim.cloth.inv_mass);
        frames.at_rest = frames.watch.watch(&SleepRule::default(), x, w, held);
        if cfg.progress && last_print.elapsed().as_secs_f64() >= 1.0 {
            last_print = Instant::now();
            progress(cfg, f + 1, &frames.step_ms, ke, stats.contacts);
        }
    }
    if ops.seams.is_some() {
        ops.seam_pairs_open = Some(open_pairs(design));
    }
    release.finish(design);
    Ok(frames)
}

/// Sews a garment scenario's pattern into `design` (its seams' stitches), says what was
/// sewn, and for drape-pattern lets the pieces float while the seams pull.
fn sew_pattern(
    cfg: &ScenarioConfig,
    design: &mut Design,
    spec: &PatternSpec,
    ops: &mut OpsReport,
) -> Result<(), ScenarioError> {
    let sewn = crate::design::garment::sew(design, spec, super::garment::SEAM_PULL)?;
    ops.seams = Some(sewn.seams);
    ops.seam_pairs = Some(sewn.pairs);
    ops.seam_length_mismatch_m = Some(sewn.mismatch_m as f64);
    eprintln!(
        "{}: {} pieces, {} seams of {} stitched pairs",
        cfg.scenario.name(),
        spec.pieces.len(),
        sewn.seams,
        sewn.pairs
    );
    for n in sewn.open {
        eprintln!("note: {n}");
        design.sim.notices.push(n);
    }
    // Both sew in the air: dress-mannequin damped (`SEW_DAMPING`), drape-pattern
    // undamped, unless `--sew-damping` says otherwise; at 0 dress-mannequin sews as it
    // falls, as it did until 2026-12-07 (docs/garments.md).
    if cfg.sew_damping() > 0.0 {
        design.float_while_sewing_damped(cfg.sew_damping());
    } else if cfg.scenario == ScenarioName::DrapePattern {
        design.float_while_sewing();
    }
    if cfg.scenario == ScenarioName::DrapePattern {
        let before = design.sim.notices.len();
        if let Some(said) = hold_pattern(design, spec, cfg.substeps) {
            eprintln!("{}: {said}", cfg.scenario.name());
        }
        for n in &design.sim.notices[before..] {
            eprintln!("note: {n}");
        }
        ops.held_vertices = Some(design.held().0.len());
    }
    Ok(())
}

/// The design's stitched pairs still open, seam by seam.
fn open_pairs(design: &Design) -> Vec<super::report::OpenPair> {
    let x = &design.sim.cloth.x;
    let mut open = Vec::new();
    for (i, seam) in design.seams.iter().enumerate() {
        for (k, &(a, b)) in seam.pairs.iter().enumerate() {
            if let (true, Some(&xa), Some(&xb)) = (a != b, x.get(a as usize), x.get(b as usize)) {
                open.push(super::report::OpenPair {
                    seam: crate::design::sewing_pattern::seam_label(i),
                    pair: k,
                    gap_m: (xa - xb).length(),
                    at: xa.to_array(),
                    stalled: design.stitches_stalled(),
                    between: design.between(a, b).word(),
                });
            }
        }
    }
    open
}

/// The scenario's script at frame `f`, the end of the drape. For the tear, returns the
/// pull: where the grip started, the point it pulls away from, and the frame it began.
fn run_script(
    cfg: &ScenarioConfig,
    design: &mut Design,
    body0: Option<&Body>,
    ops: &mut OpsReport,
    f: u64,
) -> Result<Option<(Vec3, Vec3, u64)>, ScenarioError> {
    // The scenarios that act on a body were refused without one (`needs_body`).
    let Some(body0) = body0 else {
        return Ok(None);
    };
    match cfg.scenario {
        ScenarioName::FitCube => {
            let fit = scripts::fit_cube(design, body0, cfg.grid)?;
            ops.cuts = Some(fit.cuts);
            ops.seams = Some(fit.seams);
            ops.seam_pairs = Some(fit.pairs);
            eprintln!(
                "{}: cut {} corners away, {} seams of {} stitched pairs",
                cfg.scenario.name(),
                fit.cuts,
                fit.seams,
                fit.pairs
            );
        }
        ScenarioName::Tear => {
            let v = scripts::tear_setup(design, body0)?;
            design.tear.threshold = cfg.tear_threshold;
            design.tear.mode = cfg.tear_mode;
            let (mn, mx) = body0.bounds();
            ops.tears = Some(0);
            return Ok(Some((design.sim.cloth.x[v as usize], (mn + mx) * 0.5, f)));
        }
        ScenarioName::Paint => {
            ops.paint_strokes = Some(scripts::paint_pattern(design, body0));
        }
        ScenarioName::DressMannequin => {
            let n = super::garment::cut_neckline(design)?;
            ops.cuts = Some(1);
            eprintln!(
                "{}: cut the front's neckline away ({n} triangles)",
                cfg.scenario.name()
            );
        }
        ScenarioName::DrapeCube
        | ScenarioName::DrapeMannequin
        | ScenarioName::Fold
        | ScenarioName::DrapePattern => {}
    }
    Ok(None)
}

/// Writes the cloth (OBJ + MTL + PNG, GLB), the design file and the body; measures what
/// the scenario's operations left (fit gap, painted texels). Returns the files written.
fn export(
    cfg: &ScenarioConfig,
    design: &Design,
    out: &Path,
    ops: &mut OpsReport,
) -> Result<Vec<PathBuf>, ScenarioError> {
    let mut exported = export_obj(design, out, "cloth")?;
    exported.push(export_glb(design, out, "cloth")?);
    if !design.pieces.is_empty() {
        exported.push(export_garment_glb(design, out)?);
    }
    exported.extend(crate::design::sewing_pattern::export_pattern(
        design,
        out,
        SCENARIO_ALLOWANCE_MM,
    )?);
    let design_path = out.join("design.saiho");
    design.save_design_file(&design_path)?;
    if matches!(
        cfg.scenario,
        ScenarioName::FitCube | ScenarioName::DrapeCube
    ) && cfg.body == Some(BodyKind::Cube)
        && let Some(body) = &design.sim.body
    {
        let (mean, max) = scripts::fit_gap(design, body);
        ops.fit_gap_mean_m = Some(mean);
        ops.fit_gap_max_m = Some(max);
    }
    if matches!(
        cfg.scenario,
        ScenarioName::DressMannequin | ScenarioName::DrapePattern
    ) {
        ops.pieces = Some(design.piece_list().len());
        if let Some(body) = &design.sim.body {
            let (mn, mx) = body.bounds();
            let axis = glam::Vec2::new(0.5 * (mn.x + mx.x), 0.5 * (mn.z + mx.z));
            ops.torso_coverage = Some(super::garment::torso_coverage(design, axis));
        }
        ops.fit = crate::design::garment::fit::of_design(design);
    }
    if cfg.scenario == ScenarioName::Fold {
        let l = scripts::layers(design);
        ops.layers = Some(l.mode);
        ops.layers_max = Some(l.max);
        ops.layer_gap_min_m = l.gap_min_m.is_finite().then_some(l.gap_min_m);
        ops.height_max_m = Some(l.height_max_m);
    }
    if cfg.scenario == ScenarioName::Paint {
        let base = crate::design::CLOTH_COLOUR;
        ops.texels_painted = Some(
            design
                .texture
                .rgba
                .chunks_exact(4)
                .filter(|t| *t != base)
                .count(),
        );
    }
    if let Some(body) = &design.sim.body {
        let body_path = out.join("body.obj");
        obj::write_obj(
            &body_path,
            &body.name,
            &body.vertices,
            None,
            &body.triangles,
            None,
        )
        .map_err(write_err(&body_path))?;
    }
    exported.push(design_path);
    Ok(exported)
}

/// The report of a finished run.
fn report(
    cfg: &ScenarioConfig,
    design: &Design,
    frames: Frames,
    exported: Vec<PathBuf>,
    started: Instant,
) -> Report {
    let sim = &design.sim;
    let max_pen = sim.body.as_ref().map_or(0.0, |body| {
        // Vertices in no triangle (what welds merged away) are no cloth.
        (0..sim.cloth.len())
            .filter(|&i| sim.cloth.live.vertex_alive(i as u32))
            .map(|i| body.penetration(sim.cloth.x[i]) as f64)
            .fold(0.0, f64::max)
    });
    let (strain_mean, strain_max) = sim.cloth.strain();
    let threads = sim.cloth.thread_stretch();
    let crossings = sim.crossings();
    let seen = cfg.check_every.map(|_| {
        let m = frames.crossings_max.unwrap_or_default();
        (
            m.self_pairs.max(crossings.self_pairs),
            m.body_pairs.max(crossings.body_pairs),
        )
    });
    let ke = sim.cloth.kinetic_energy();
    let top_face_gap = match &sim.body {
        Some(body)
            if cfg.scenario == ScenarioName::DrapeCube && cfg.body == Some(BodyKind::Cube) =>
        {
            Some(top_face_gap(design, body))
        }
        _ => None,
    };
    // "Settled": RMS speed under 1 cm/s.
    let total_mass: f64 = sim.cloth.mass.iter().map(|&m| m as f64).sum();
    Report {
        scenario: cfg.scenario.name().into(),
        model: cfg.model.name().into(),
        guard: cfg.guard && cfg.model == crate::solver::ModelKind::Xpbd,
        strain_limit: match sim.model {
            crate::solver::ModelKind::Xpbd => sim.material.strain_limit,
            _ => 0.0,
        },
        sew_damping: cfg.sew_damping(),
        body: cfg.body.as_ref().map_or("floor".into(), BodyKind::name),
        grid: cfg.grid,
        vertices: sim.cloth.len(),
        triangles: sim.cloth.live.tri_count(),
        constraints: sim.constraint_count(),
        frames: sim.frame,
        frame_dt_s: cfg.frame_dt as f64,
        substeps: sim.substeps,
        step_ms: Percentiles::of(&frames.step_ms),
        collision_ms: Percentiles::of(&frames.collision_ms),
        sleep: cfg.sleep,
        frames_asleep: sim.frames_asleep(),
        first_frame_asleep: frames.first_asleep,
        step_ms_awake: cfg.sleep.then(|| Percentiles::of(&frames.awake_ms)),
        frame_ms: frames
            .step_ms
            .iter()
            .map(|t| (t * 100.0).round() / 100.0)
            .collect(),
        threads: sim.threads(),
        max_penetration_m: max_pen,
        thickness_m: sim.material.thickness as f64,
        kinetic_energy_final_j: ke,
        kinetic_energy_max_j: frames.kinetic_energy_max,
        mesh_valid: design.validate().is_ok(),
        strain_mean,
        strain_max,
        strain_max_at: sim
            .cloth
            .worst_side()
            .map(|(a, b, _)| ((sim.cloth.x[a as usize] + sim.cloth.x[b as usize]) / 2.0).into()),
        thread_stretch_p50: threads.p50,
        thread_stretch_p90: threads.p90,
        thread_stretch_max: threads.max,
        crossings_self: crossings.self_pairs,
        crossings_body: crossings.body_pairs,
        self_contacts: sim.self_contacts(),
        crossings_body_triangles: crossings.body_triangles,
        crossings_self_max: seen.map(|s| s.0),
        crossings_body_max: seen.map(|s| s.1),
        check_every: cfg.check_every,
        top_face_gap_max_m: top_face_gap,
        stable_step_s: sim.stable_step,
        settled: ke <= 0.5 * total_mass * 0.01f64.powi(2),
        at_rest: frames.at_rest,
        ops: frames.ops,
        exported: exported.iter().map(|p| p.display().to_string()).collect(),
        wall_s: started.elapsed().as_secs_f64(),
        notices: sim.notices.clone(),
    }
}

/// For the cube: over the cloth vertices above the top face (inset 2 cm from its edges),
/// the largest distance from the plane they should rest on.
fn top_face_gap(design: &Design, body: &Body) -> f64 {
    let sim = &design.sim;
    let (mn, mx) = body.bounds();
    let rest_y = mx.y + sim.material.thickness;
    sim.cloth
        .x
        .iter()
        .filter(|p| {
            p.x > mn.x + 0.02
                && p.x < mx.x - 0.02
                && p.z > mn.z + 0.02
                && p.z < mx.z - 0.02
                && p.y > mn.y
        })
        .map(|p| (p.y - rest_y).abs() as f64)
        .fold(0.0, f64::max)
}
