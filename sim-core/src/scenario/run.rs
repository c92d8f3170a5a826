//! Running a scenario: build the scene, step it, measure, export.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec3;

use super::report::{OpsReport, Percentiles, Report};
use super::scripts;
use crate::body::{Body, BodyKind};
use crate::cloth::{Cloth, Environment, Material, ModelKind, Simulation, StepError};
use crate::error::{ConfigError, GeometryError, LoadError};
use crate::mesh::{ClothMesh, obj};

/// The scenarios `cloth-sim scenario` knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScenarioName {
    /// The paper's experiment: a square cloth dropped on the cube until it settles.
    DrapeCube,
    /// The same cloth dropped over the mannequin's head and shoulders.
    DrapeMannequin,
    /// The paper's experiment end to end: drape on the cube, cut the four hanging corners
    /// away, sew the flaps along the cube's vertical edges.
    FitCube,
    /// Drape on the cube, hold the top, pinch a corner and pull until the cloth tears.
    Tear,
    /// Drape on the cube and paint a pattern on its top; exports the texture.
    Paint,
}

impl ScenarioName {
    pub const ALL: &'static str = "drape-cube, drape-mannequin, fit-cube, tear, paint";

    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "drape-cube" => Ok(Self::DrapeCube),
            "drape-mannequin" => Ok(Self::DrapeMannequin),
            "fit-cube" => Ok(Self::FitCube),
            "tear" => Ok(Self::Tear),
            "paint" => Ok(Self::Paint),
            other => Err(ConfigError::Unknown {
                what: "scenario",
                name: other.into(),
                expected: Self::ALL,
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::DrapeCube => "drape-cube",
            Self::DrapeMannequin => "drape-mannequin",
            Self::FitCube => "fit-cube",
            Self::Tear => "tear",
            Self::Paint => "paint",
        }
    }

    /// Substeps when none are asked for: the tear scenario runs XPBD at 20, so the stretch
    /// it measures is the pull's and not Gauss-Seidel lag in the hanging cloth (at the
    /// default 5 the edges over the cube's rim stretch up to ~2.4x; see README).
    pub fn default_substeps(self, model: ModelKind) -> Option<usize> {
        (self == Self::Tear && model == ModelKind::Xpbd).then_some(20)
    }

    pub fn default_body(self) -> BodyKind {
        match self {
            Self::DrapeMannequin => BodyKind::Mannequin,
            Self::DrapeCube | Self::FitCube | Self::Tear | Self::Paint => BodyKind::Cube,
        }
    }
}

#[derive(Clone, Debug)]
pub struct ScenarioConfig {
    pub scenario: ScenarioName,
    /// Cells per side of the square cloth (N x N cells, (N+1)^2 vertices).
    pub grid: usize,
    pub model: ModelKind,
    pub frames: u64,
    pub body: BodyKind,
    pub substeps: Option<usize>,
    pub material: Material,
    /// Side of the square cloth, m.
    pub cloth_size: f32,
    /// A cloth pattern from an OBJ file instead of the square grid.
    pub cloth: Option<PathBuf>,
    pub frame_dt: f32,
    /// Print progress to stderr (once a second) while running.
    pub progress: bool,
    /// Threads for the XPBD constraint passes (1 or 2).
    pub threads: usize,
    /// The tear scenario's tearing: stretch ratio and mode.
    pub tear_threshold: f32,
    pub tear_mode: crate::edit::TearMode,
}

impl ScenarioConfig {
    pub fn new(scenario: ScenarioName) -> Self {
        Self {
            scenario,
            grid: 64,
            model: ModelKind::Xpbd,
            frames: 600,
            body: scenario.default_body(),
            substeps: None,
            material: Material::default(),
            cloth_size: 1.0,
            cloth: None,
            frame_dt: 1.0 / 60.0,
            progress: false,
            threads: 1,
            tear_threshold: crate::edit::TearSettings::default().threshold,
            tear_mode: crate::edit::TearMode::Delete,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("body: {0}")]
    Body(#[from] LoadError),
    #[error("cloth: {0}")]
    Cloth(#[from] GeometryError),
    #[error("cloth: {0}")]
    ClothFile(LoadError),
    #[error(transparent)]
    Step(#[from] StepError),
    #[error("{0}")]
    Edit(#[from] crate::edit::EditError),
    #[error(transparent)]
    Export(#[from] crate::edit::export::ExportError),
    #[error(transparent)]
    Design(#[from] crate::edit::design::DesignError),
    #[error("cannot write {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// Builds the scene of a scenario: the body, and the cloth centred 5 cm above it.
pub fn build_simulation(cfg: &ScenarioConfig) -> Result<Simulation, ScenarioError> {
    if cfg.grid == 0 || cfg.grid > 2000 {
        return Err(ConfigError::OutOfRange {
            name: "grid",
            rule: "between 1 and 2000 cells",
            value: cfg.grid.to_string(),
        }
        .into());
    }
    if cfg.frames == 0 {
        return Err(ConfigError::OutOfRange {
            name: "frames",
            rule: ">= 1",
            value: "0".into(),
        }
        .into());
    }
    crate::error::check_positive("cloth size", cfg.cloth_size)?;
    if !(cfg.tear_threshold.is_finite() && cfg.tear_threshold > 1.0) {
        return Err(ConfigError::OutOfRange {
            name: "tear threshold",
            rule: "a stretch ratio above 1",
            value: cfg.tear_threshold.to_string(),
        }
        .into());
    }
    cfg.material.validate()?;
    let body = cfg.body.build()?;
    let (_, top) = body.bounds();
    let (mn, mx) = body.bounds();
    let cx = (mn.x + mx.x) * 0.5;
    let cz = (mn.z + mx.z) * 0.5;
    let mut mesh = match &cfg.cloth {
        None => ClothMesh::grid(cfg.cloth_size, cfg.cloth_size, cfg.grid, cfg.grid, 0.0)?,
        Some(path) => obj::load_obj(path).map_err(ScenarioError::ClothFile)?,
    };
    // Centre the cloth over the body, its lowest point 5 cm above the body's top.
    let (cmin, cmax) = crate::mesh::bounds(&mesh.positions);
    let shift = Vec3::new(
        cx - (cmin.x + cmax.x) * 0.5,
        top.y + 0.05 - cmin.y,
        cz - (cmin.z + cmax.z) * 0.5,
    );
    for p in &mut mesh.positions {
        *p += shift;
    }
    let cloth = Cloth::new(mesh, &cfg.material)?;
    let env = Environment {
        frame_dt: cfg.frame_dt,
        ..Environment::default()
    };
    let mut sim = Simulation::new(
        cloth,
        Some(body),
        cfg.model,
        cfg.material,
        env,
        cfg.substeps.or(cfg.scenario.default_substeps(cfg.model)),
    )?;
    sim.set_threads(cfg.threads);
    Ok(sim)
}

/// Runs a scenario and writes `out/cloth.obj`, `out/body.obj` and `out/report.json`.
pub fn run_scenario(cfg: &ScenarioConfig, out: &Path) -> Result<Report, ScenarioError> {
    let started = Instant::now();
    let mut sim = build_simulation(cfg)?;
    let write_err = |path: &Path| {
        let path = path.to_owned();
        move |source| ScenarioError::Write { path, source }
    };
    std::fs::create_dir_all(out).map_err(write_err(out))?;
    for n in &sim.notices {
        eprintln!("note: {n}");
    }
    let mut step_ms = Vec::with_capacity(cfg.frames as usize);
    let mut coll_ms = Vec::with_capacity(cfg.frames as usize);
    let mut ke_max = 0.0f64;
    let mut last_print = Instant::now();
    let body0 = sim.body.clone().ok_or(GeometryError::Empty)?;
    let mut ops = OpsReport::default();
    let mut pull: Option<(Vec3, Vec3, u64)> = None;
    for f in 0..cfg.frames {
        if f == scripts::DRAPE_FRAMES {
            match cfg.scenario {
                ScenarioName::FitCube => {
                    let fit = scripts::fit_cube(&mut sim, &body0, cfg.grid)?;
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
                    let v = scripts::tear_setup(&mut sim, &body0)?;
                    sim.tear.threshold = cfg.tear_threshold;
                    sim.tear.mode = cfg.tear_mode;
                    let (mn, mx) = body0.bounds();
                    pull = Some((sim.cloth.x[v as usize], (mn + mx) * 0.5, f));
                    ops.tears = Some(0);
                }
                ScenarioName::Paint => {
                    ops.paint_strokes = Some(scripts::paint_pattern(&mut sim, &body0));
                }
                _ => {}
            }
        }
        if let Some((start, centre, f0)) = pull {
            let t = (f - f0) as f32 * cfg.frame_dt;
            sim.pinch_move(scripts::tear_target(start, centre, t));
        }
        let stats = sim.step()?;
        if stats.torn > 0 && ops.first_tear_frame.is_none() && pull.is_some() {
            ops.first_tear_frame = Some(sim.frame);
        }
        if let Some(t) = &mut ops.tears {
            *t += stats.torn;
        }
        if ops.seams.is_some() {
            *ops.welds.get_or_insert(0) += stats.welded;
        }
        if let Some(force) = sim
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
            && sim.frame >= ft + 60
        {
            sim.pinch_end();
            pull = None;
        }
        step_ms.push(stats.wall_ms);
        coll_ms.push(stats.collision_ms);
        ke_max = ke_max.max(sim.cloth.kinetic_energy());
        if cfg.progress && last_print.elapsed().as_secs_f64() >= 1.0 {
            last_print = Instant::now();
            let p = Percentiles::of(&step_ms);
            eprintln!(
                "{}: frame {}/{} ({:.0}%), frame p50 {:.2} ms, kinetic energy {:.2e} J, {} contacts",
                cfg.scenario.name(),
                f + 1,
                cfg.frames,
                100.0 * (f + 1) as f64 / cfg.frames as f64,
                p.p50,
                sim.cloth.kinetic_energy(),
                stats.contacts
            );
        }
    }
    let body = sim.body.as_ref().ok_or(GeometryError::Empty)?;
    let max_pen = sim
        .cloth
        .x
        .iter()
        .map(|&p| body.penetration(p) as f64)
        .fold(0.0, f64::max);
    let mesh_valid = sim.validate().is_ok();
    let (strain_mean, strain_max) = sim.cloth.strain();
    let ke = sim.cloth.kinetic_energy();
    let top_face_gap = (cfg.scenario == ScenarioName::DrapeCube && cfg.body == BodyKind::Cube)
        .then(|| top_face_gap(&sim, body));
    // "Settled": RMS speed under 1 cm/s.
    let total_mass: f64 = sim.cloth.mass.iter().map(|&m| m as f64).sum();
    let settled = ke <= 0.5 * total_mass * 0.01f64.powi(2);
    let mut exported = crate::edit::export::export_obj(&sim, out, "cloth")?;
    exported.push(crate::edit::export::export_glb(&sim, out, "cloth")?);
    let design_path = out.join("design.saiho");
    sim.save_design_file(&design_path)?;
    if matches!(
        cfg.scenario,
        ScenarioName::FitCube | ScenarioName::DrapeCube
    ) && cfg.body == BodyKind::Cube
    {
        let (mean, max) = scripts::fit_gap(&sim, body);
        ops.fit_gap_mean_m = Some(mean);
        ops.fit_gap_max_m = Some(max);
    }
    if cfg.scenario == ScenarioName::Paint {
        let base = [235u8, 235, 230, 255];
        ops.texels_painted = Some(
            sim.texture
                .rgba
                .chunks_exact(4)
                .filter(|t| *t != base)
                .count(),
        );
    }
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
    let report = Report {
        scenario: cfg.scenario.name().into(),
        model: cfg.model.name().into(),
        body: cfg.body.name(),
        grid: cfg.grid,
        vertices: sim.cloth.len(),
        triangles: sim.cloth.live.tri_count(),
        constraints: sim.constraint_count(),
        frames: sim.frame,
        frame_dt_s: cfg.frame_dt as f64,
        substeps: sim.substeps,
        step_ms: Percentiles::of(&step_ms),
        collision_ms: Percentiles::of(&coll_ms),
        threads: sim.threads(),
        max_penetration_m: max_pen,
        thickness_m: sim.material.thickness as f64,
        kinetic_energy_final_j: ke,
        kinetic_energy_max_j: ke_max,
        mesh_valid,
        strain_mean,
        strain_max,
        top_face_gap_max_m: top_face_gap,
        stable_step_s: sim.stable_step,
        settled,
        ops,
        exported: exported
            .iter()
            .chain(std::iter::once(&design_path))
            .map(|p| p.display().to_string())
            .collect(),
        wall_s: started.elapsed().as_secs_f64(),
        notices: sim.notices.clone(),
    };
    let report_path = out.join("report.json");
    let json = serde_json::to_string_pretty(&report).map_err(|e| ScenarioError::Write {
        path: report_path.clone(),
        source: e.into(),
    })?;
    std::fs::write(&report_path, json + "\n").map_err(write_err(&report_path))?;
    Ok(report)
}

/// For the cube: over the cloth vertices above the top face (inset 2 cm from its edges),
/// the largest distance from the plane they should rest on.
fn top_face_gap(sim: &Simulation, body: &Body) -> f64 {
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

/// The largest square grid (from a fixed ladder) whose median frame time stays within
/// the frame period, for drape-cube with `model`. Returns `(grid, p50_ms)` for each size
/// tried, in order; the search stops at the first size that misses real time.
///
/// With `matched_seed`, the seed model's k is set per grid so each unit-mass spring has
/// the default cotton's stiffness-to-mass ratio (`k = stretch / (density * cell^2)`): the
/// same material at every resolution, so its stable step shrinks as the grid refines,
/// which is the paper's stated limit. Without it the seed model keeps its default k and
/// unit masses, a sheet whose stiffness-to-mass ratio does not change with resolution.
pub fn max_realtime_grid(
    model: ModelKind,
    frames: u64,
    matched_seed: bool,
    mut log: impl FnMut(usize, f64, usize),
) -> Result<Vec<(usize, f64)>, ScenarioError> {
    let ladder = [
        8usize, 12, 16, 24, 32, 48, 64, 96, 128, 160, 192, 256, 320, 384,
    ];
    let mut tried = Vec::new();
    for &grid in &ladder {
        let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
        cfg.grid = grid;
        cfg.model = model;
        if matched_seed {
            let cell = cfg.cloth_size / grid as f32;
            cfg.material.seed_stiffness =
                cfg.material.stretch / (cfg.material.density * cell * cell);
        }
        cfg.frames = frames;
        let mut sim = build_simulation(&cfg)?;
        let mut ms = Vec::new();
        for _ in 0..frames {
            ms.push(sim.step()?.wall_ms);
        }
        // Skip the first frames (cold caches, first contacts).
        let p50 = Percentiles::of(&ms[ms.len() / 4..]).p50;
        log(grid, p50, sim.substeps);
        tried.push((grid, p50));
        if p50 > cfg.frame_dt as f64 * 1e3 {
            break;
        }
    }
    Ok(tried)
}
