//! What a scenario is: its name, its settings, its errors, and the scene it builds.

use std::path::PathBuf;

use glam::Vec3;

use crate::collision::{BodyKind, crossings};
use crate::design::garment::PatternSpec;
use crate::design::{Design, TearMode, TearSettings};
use crate::error::{ConfigError, GeometryError, LoadError, check_range};
use crate::mesh::mesher::{self, EDGE_RANGE, Outline};
use crate::mesh::svg;
use crate::mesh::{ClothMesh, obj};
use crate::solver::{
    Cloth, Environment, MAX_FRAME_SUBSTEPS, Material, ModelKind, Simulation, SleepRule,
};

pub use super::error::ScenarioError;

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
    /// A cloth lying on the floor folded twice, corner to corner and then across: four
    /// layers that must lie flat without crossing.
    Fold,
    /// A garment: a front and a back panel placed round the mannequin and sewn at the
    /// shoulders and sides, draped.
    DressMannequin,
    /// Any pattern file (SVG, DXF or GarmentCode JSON, `--pattern`) placed round the
    /// body, sewn at its seams and draped.
    DrapePattern,
}

impl ScenarioName {
    pub const ALL: &'static str =
        "drape-cube, drape-mannequin, fit-cube, tear, paint, fold, dress-mannequin, drape-pattern";

    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "drape-cube" => Ok(Self::DrapeCube),
            "drape-mannequin" => Ok(Self::DrapeMannequin),
            "fit-cube" => Ok(Self::FitCube),
            "tear" => Ok(Self::Tear),
            "paint" => Ok(Self::Paint),
            "fold" => Ok(Self::Fold),
            "dress-mannequin" => Ok(Self::DressMannequin),
            "drape-pattern" => Ok(Self::DrapePattern),
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
            Self::Fold => "fold",
            Self::DressMannequin => "dress-mannequin",
            Self::DrapePattern => "drape-pattern",
        }
    }

    /// Substeps when none are asked for: the tear scenario runs XPBD at 20, so the stretch
    /// it measures is the pull's and not Gauss-Seidel lag in the hanging cloth (at the
    /// default 5 the edges over the cube's rim stretch up to ~2.4x; see docs/models.md).
    pub fn default_substeps(self, model: ModelKind) -> Option<usize> {
        (self == Self::Tear && model == ModelKind::Xpbd).then_some(20)
    }

    /// The body the scenario drapes over; `None`: the floor alone.
    pub fn default_body(self) -> Option<BodyKind> {
        match self {
            Self::DrapeMannequin | Self::DressMannequin | Self::DrapePattern => {
                Some(BodyKind::Mannequin)
            }
            Self::DrapeCube | Self::FitCube | Self::Tear | Self::Paint => Some(BodyKind::Cube),
            Self::Fold => None,
        }
    }

    /// Whether the scenario's operations need a body (they act on the cube).
    pub fn needs_body(self) -> bool {
        matches!(
            self,
            Self::FitCube | Self::Tear | Self::Paint | Self::DressMannequin
        )
    }
}

#[derive(Clone, Debug)]
pub struct ScenarioConfig {
    pub scenario: ScenarioName,
    /// Cells per side of the square cloth (N x N cells, (N+1)^2 vertices).
    pub grid: usize,
    pub model: ModelKind,
    pub frames: u64,
    /// The body; `None`: the floor alone.
    pub body: Option<BodyKind>,
    pub substeps: Option<usize>,
    pub material: Material,
    /// Side of the square cloth, m.
    pub cloth_size: f32,
    /// A cloth pattern from an OBJ file instead of the square grid.
    pub cloth: Option<PathBuf>,
    /// The pattern drape-pattern drapes (SVG, DXF or GarmentCode JSON).
    pub pattern: Option<PathBuf>,
    /// A pattern piece meshed from its outline instead of the square grid, with
    /// triangles of about `piece_edge` m a side.
    pub piece: Option<PieceShape>,
    pub piece_edge: f32,
    pub frame_dt: f32,
    /// Print progress to stderr (once a second) while running.
    pub progress: bool,
    /// Threads for the XPBD constraint passes (1 or 2).
    pub threads: usize,
    /// The tear scenario's tearing: stretch ratio and mode.
    pub tear_threshold: f32,
    pub tear_mode: TearMode,
    /// Count the crossings every this many frames too (the report keeps the most seen).
    pub check_every: Option<u64>,
    /// The library fabric `material` came from, which the pattern's pieces are then
    /// named as (`None`: the design's own material, [`crate::design::garment::DEFAULT_FABRIC`]).
    pub fabric: Option<String>,
    /// Pieces of the pattern made of another fabric: (piece name, library fabric).
    pub piece_fabrics: Vec<(String, String)>,
    /// Garment scenarios: sew in the air with the cloth's motion damped at this rate,
    /// 1/s, until the seams close (`Design::float_while_sewing_damped`); 0: dress-mannequin
    /// sews as it falls, drape-pattern in the air undamped. `None`: the scenario's own
    /// ([`ScenarioConfig::sew_damping`]).
    pub sew_damping: Option<f32>,
    /// XPBD with its guard: contact that is never crossed (`solver/xpbd/guard.rs`). On
    /// by default; the other models ignore it (vbd's contact is always guarded, the
    /// paper's model and the implicit reference have none).
    pub guard: bool,
    /// Let the cloth fall asleep once it has come to rest, as cloth-sim's service does
    /// (`solver::rest`, [`SleepRule::default`]). Off by default here: a scenario measures
    /// every frame's work.
    pub sleep: bool,
}

/// A pattern piece by its outline's shape and size, m, or the pieces of an SVG file.
#[derive(Clone, Debug, PartialEq)]
pub enum PieceShape {
    Rectangle { width: f32, height: f32 },
    Ellipse { width: f32, height: f32 },
    Svg(PathBuf),
}

impl PieceShape {
    /// Parses `rect:WxH` or `ellipse:WxH` (metres; an ellipse by its two diameters), or
    /// a path ending in `.svg`.
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        if s.to_ascii_lowercase().ends_with(".svg") {
            return Ok(Self::Svg(PathBuf::from(s)));
        }
        let bad = || ConfigError::OutOfRange {
            name: "piece",
            rule: "rect:WxH or ellipse:WxH, sizes in metres between 0.01 and 10 (e.g. ellipse:0.8x0.5), or FILE.svg",
            value: s.into(),
        };
        let (kind, size) = s.split_once(':').ok_or_else(bad)?;
        let (w, h) = size.split_once(['x', 'X']).ok_or_else(bad)?;
        let (width, height): (f32, f32) = (
            w.trim().parse().map_err(|_| bad())?,
            h.trim().parse().map_err(|_| bad())?,
        );
        if !((0.01..=10.0).contains(&width) && (0.01..=10.0).contains(&height)) {
            return Err(bad());
        }
        match kind {
            "rect" | "rectangle" => Ok(Self::Rectangle { width, height }),
            "ellipse" => Ok(Self::Ellipse { width, height }),
            _ => Err(bad()),
        }
    }

    /// The outlines (one for a shape, centred on the origin; an SVG's pieces where the
    /// file puts them).
    pub fn outlines(&self, edge: f32) -> Result<Vec<Outline>, ScenarioError> {
        Ok(match self {
            Self::Rectangle { width, height } => {
                let mut o = Outline::rectangle(*width, *height);
                for p in &mut o.loops[0] {
                    *p -= glam::Vec2::new(*width, *height) * 0.5;
                }
                vec![o]
            }
            Self::Ellipse { width, height } => {
                vec![Outline::ellipse(0.5 * width, 0.5 * height, edge)]
            }
            Self::Svg(path) => svg::load_svg(path)
                .map_err(|e| ScenarioError::PieceFile {
                    path: path.clone(),
                    reason: e.to_string(),
                })?
                .into_iter()
                .map(|p| p.outline)
                .collect(),
        })
    }

    /// Every piece meshed with triangles of about `edge` m, in one cloth.
    pub fn mesh(&self, edge: f32) -> Result<ClothMesh, ScenarioError> {
        Ok(mesher::mesh_pieces(&self.outlines(edge)?, edge)?)
    }
}

/// Largest grid: (1999 + 1)^2 vertices is `MAX_VERTICES`.
pub const MAX_GRID: usize = 1999;

/// How fast dress-mannequin's pieces' motion dies away while they are sewn in the air,
/// 1/s (`--sew-damping`). At 30, with a seam's ends sewn last and the cloth's flutter
/// damped, the 5k dress and the 2 x 8k dress weld every pair and come to rest in every
/// run; sewn as it falls, the 2 x 8k dress left three pairs open and took 20-30 ms a
/// frame (docs/garments.md, "Every pair of both dresses welded, at rest").
pub const SEW_DAMPING: f32 = 30.0;
/// Most frames a scenario runs (4.6 hours of 1/60 s frames).
pub const MAX_FRAMES: u64 = 1_000_000;
/// Most threads the XPBD passes split across (the solver's two halves).
pub const MAX_THREADS: usize = 2;

impl ScenarioConfig {
    /// The damping the garment is sewn in the air with, 1/s (`sew_damping`, else
    /// dress-mannequin's [`SEW_DAMPING`] and 0 for the others: drape-pattern's lifted
    /// pieces closed every pair of the shipped dress undamped and, damped, stretched a
    /// shoulder to 2.27x in one run of two, docs/garments.md).
    pub fn sew_damping(&self) -> f32 {
        self.sew_damping.unwrap_or(match self.scenario {
            ScenarioName::DressMannequin => SEW_DAMPING,
            _ => 0.0,
        })
    }

    /// Checks every setting before any work: ranges that agree with each other (the grid
    /// with the vertex limit, the substeps with the simulation's), no NaN.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_range("grid", self.grid, 1, MAX_GRID, " cells a side")?;
        check_range("frames", self.frames, 1, MAX_FRAMES, "")?;
        check_range("cloth size", self.cloth_size, 0.01, 10.0, " m")?;
        check_range(
            "piece edge",
            self.piece_edge,
            EDGE_RANGE.0,
            EDGE_RANGE.1,
            " m",
        )?;
        if self.piece.is_some() && self.cloth.is_some() {
            return Err(ConfigError::OutOfRange {
                name: "cloth",
                rule: "one of --cloth FILE.obj and --piece SHAPE",
                value: "both".into(),
            });
        }
        check_range("frame duration", self.frame_dt, 1.0e-4, 1.0, " s")?;
        check_range("threads", self.threads, 1, MAX_THREADS, "")?;
        if let Some(n) = self.substeps {
            check_range("substeps", n, 1, MAX_FRAME_SUBSTEPS, " per frame")?;
        }
        if let Some(n) = self.check_every {
            check_range("check every", n, 1, MAX_FRAMES, " frames")?;
        }
        if (self.scenario == ScenarioName::DrapePattern) != self.pattern.is_some() {
            return Err(ConfigError::OutOfRange {
                name: "pattern",
                rule: "a pattern file (--pattern FILE) for drape-pattern, and for no other scenario",
                value: self
                    .pattern
                    .as_ref()
                    .map_or("none".into(), |p| p.display().to_string()),
            });
        }
        if self.body.is_none() && self.scenario.needs_body() {
            return Err(ConfigError::OutOfRange {
                name: "body",
                rule: "cube, sphere, mannequin, mannequin-apose, human or an .obj for this scenario (it acts on a body)",
                value: "floor".into(),
            });
        }
        if let Some(rate) = self.sew_damping.filter(|&r| r != 0.0) {
            check_range("sew damping", rate, 0.0, 1000.0, " 1/s")?;
        }
        check_range(
            "tear threshold",
            self.tear_threshold,
            1.0001,
            100.0,
            " x rest length",
        )?;
        self.material.validate()
    }

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
            pattern: None,
            piece: None,
            piece_edge: 1.0 / 64.0,
            frame_dt: 1.0 / 60.0,
            progress: false,
            threads: 1,
            tear_threshold: TearSettings::default().threshold,
            tear_mode: TearMode::Delete,
            check_every: None,
            fabric: None,
            piece_fabrics: Vec::new(),
            sew_damping: None,
            guard: true,
            sleep: false,
        }
    }
}

/// Builds the scene of a scenario as a new design: the body, and the cloth centred 5 cm
/// above it; with no body, the cloth lying flat on the floor (its thickness above it).
pub fn build_design(cfg: &ScenarioConfig) -> Result<Design, ScenarioError> {
    Ok(build_scene(cfg)?.0)
}

/// [`build_design`], and for the garment scenarios the pattern whose pieces the design
/// holds (to be sewn), with what its file's reader noticed.
pub fn build_scene(cfg: &ScenarioConfig) -> Result<(Design, Option<PatternSpec>), ScenarioError> {
    cfg.validate()?;
    let body = cfg.body.as_ref().map(BodyKind::build).transpose()?;
    let repairs = body.as_ref().map(|b| b.repairs.clone()).unwrap_or_default();
    let (cx, rest_y, cz) = match &body {
        Some(body) => {
            let (mn, mx) = body.bounds();
            ((mn.x + mx.x) * 0.5, mx.y + 0.05, (mn.z + mx.z) * 0.5)
        }
        None => (0.0, cfg.material.thickness, 0.0),
    };
    let garment = matches!(
        cfg.scenario,
        ScenarioName::DressMannequin | ScenarioName::DrapePattern
    );
    if garment && (cfg.cloth.is_some() || cfg.piece.is_some()) {
        return Err(ConfigError::OutOfRange {
            name: "cloth",
            rule: "the pattern's own pieces for dress-mannequin and drape-pattern (no --cloth or --piece)",
            value: "given".into(),
        }
        .into());
    }
    let mut notices = repairs;
    let (cloth, spec, records) = if garment {
        let (spec, made) = super::placing::placed_garment(
            &super::placing::Source {
                file: cfg.pattern.as_deref(),
                edge: cfg.piece_edge,
            },
            body.as_ref(),
            &mut notices,
        )?;
        let mut cloth = Cloth::new(made.mesh, &cfg.material)?;
        // The pieces start round the body; their rest shape stays the flat pattern.
        cloth.x = made.starts;
        (cloth, Some(spec), made.records)
    } else {
        let mut mesh = match &cfg.cloth {
            None if cfg.piece.is_some() => {
                let shape = cfg.piece.as_ref().ok_or(GeometryError::Empty)?;
                shape.mesh(cfg.piece_edge)?
            }
            None => ClothMesh::grid(cfg.cloth_size, cfg.cloth_size, cfg.grid, cfg.grid, 0.0)?,
            Some(path) => {
                let mesh = obj::load_obj(path).map_err(ScenarioError::ClothFile)?;
                let (x, tris) = crossings::weld(&mesh.positions, &mesh.triangles);
                let pairs = crossings::count_self(&x, &tris);
                if pairs > 0 {
                    return Err(ScenarioError::ClothFile(LoadError::CrossesItself {
                        path: path.clone(),
                        pairs,
                    }));
                }
                mesh
            }
        };
        // Centre the cloth over the body, its lowest point 5 cm above the body's top.
        let (cmin, cmax) = crate::mesh::bounds(&mesh.positions);
        let shift = Vec3::new(
            cx - (cmin.x + cmax.x) * 0.5,
            rest_y - cmin.y,
            cz - (cmin.z + cmax.z) * 0.5,
        );
        for p in &mut mesh.positions {
            *p += shift;
        }
        let cloth = Cloth::new(mesh, &cfg.material)?;
        // Nothing starts crossed: a cloth through itself or the body stays so (a
        // garment's start was counted where it was placed).
        let crossed = crossings::count(&cloth.x, &cloth.live.triangles(), body.as_ref());
        if crossed.self_pairs > 0 || crossed.body_pairs > 0 {
            return Err(ScenarioError::StartsCrossed {
                self_pairs: crossed.self_pairs,
                body_pairs: crossed.body_pairs,
                which: String::new(),
            });
        }
        (cloth, None, Vec::new())
    };
    let env = Environment {
        frame_dt: cfg.frame_dt,
        ..Environment::default()
    };
    // Each piece its own fabric (a cloth of one fabric has no zones).
    let (cloth, records) = piece_fabrics(cfg, cloth, records, &mut notices)?;
    let mut sim = Simulation::new(
        cloth,
        body,
        cfg.model,
        cfg.material,
        env,
        cfg.substeps.or(cfg.scenario.default_substeps(cfg.model)),
    )?;
    sim.set_threads(cfg.threads);
    if cfg.model == ModelKind::Xpbd {
        sim.set_guard(cfg.guard);
    }
    sim.sleep = cfg.sleep.then(SleepRule::default);
    sim.notices.extend(notices);
    let mut design = Design::new(sim);
    design.pieces = records;
    // The pattern draped (`drape-pattern`): its design file names it.
    if let Some(p) = &cfg.pattern {
        design.source = p.display().to_string();
    }
    Ok((design, spec))
}

/// The pattern's pieces named as `cfg`'s fabric and `--piece-fabric`s, and the cloth's
/// material zones from them.
fn piece_fabrics(
    cfg: &ScenarioConfig,
    mut cloth: Cloth,
    mut records: Vec<crate::design::PieceRecord>,
    notices: &mut Vec<String>,
) -> Result<(Cloth, Vec<crate::design::PieceRecord>), ScenarioError> {
    if let Some(f) = &cfg.fabric {
        for r in &mut records {
            r.fabric.clone_from(f);
        }
    }
    for (piece, fabric) in &cfg.piece_fabrics {
        let Some(r) = records.iter_mut().find(|r| &r.name == piece) else {
            let names: Vec<&str> = records.iter().map(|r| r.name.as_str()).collect();
            return Err(ConfigError::OutOfRange {
                name: "--piece-fabric",
                rule: if names.is_empty() {
                    "given only for a pattern's pieces (dress-mannequin, drape-pattern)"
                } else {
                    "a piece of the pattern"
                },
                value: format!("{piece:?} (the pattern's pieces: {})", names.join(", ")),
            }
            .into());
        };
        r.fabric.clone_from(fabric);
    }
    let (zones, said) = crate::design::fabric_zones(&records, &cfg.material)?;
    notices.extend(said);
    cloth.set_zones(zones, cfg.material.density);
    Ok((cloth, records))
}
