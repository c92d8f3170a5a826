//! The Cusick drape test (BS 5058 / ISO 9073-9; ASTM D4848's sizes as an option): a
//! circular specimen clamped between two smaller discs, left to hang until it settles;
//! the drape coefficient and the nodes from the mesh's shadow.

use std::time::Instant;

use glam::Vec3;

use super::shadow::{self, Node};
use crate::collision::crossings;
use crate::error::{ConfigError, check_range};
use crate::mesh::mesher::{self, MeshError, Outline};
use crate::solver::{
    Cloth, EarlyStop, Environment, Implicit, Material, ModelKind, Simulation, StepError,
};

/// Which standard's sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Standard {
    /// BS 5058 (and ISO 9073-9): a 30 cm specimen on an 18 cm disc.
    #[serde(rename = "bs5058")]
    Bs5058,
    /// ASTM D4848: a 36 cm specimen on a 12.7 cm disc.
    #[serde(rename = "astm-d4848")]
    AstmD4848,
}

impl Standard {
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "bs5058" => Ok(Self::Bs5058),
            "astm-d4848" => Ok(Self::AstmD4848),
            other => Err(ConfigError::Unknown {
                what: "standard",
                name: other.into(),
                expected: "bs5058, astm-d4848",
            }),
        }
    }

    /// (specimen radius, disc radius), m.
    pub fn radii(self) -> (f32, f32) {
        match self {
            Self::Bs5058 => (0.15, 0.09),
            Self::AstmD4848 => (0.18, 0.0635),
        }
    }
}

/// Mesh edge the drape test uses unless told: measured to change the drape coefficient
/// by under a point when halved in area (docs/fabrics.md).
pub const DEFAULT_EDGE: f32 = 0.006;

/// How one drape test runs.
#[derive(Clone, Debug)]
pub struct CusickConfig {
    pub material: Material,
    pub standard: Standard,
    /// Mesh edge length, m.
    pub edge: f32,
    pub model: ModelKind,
    pub substeps: Option<usize>,
    /// Simulated time the drape gets to settle at most, s.
    pub max_seconds: f32,
    pub frame_dt: f32,
    /// The implicit model's Newton iterations while the specimen falls (`None`: every
    /// step solved to the tolerance, slower for the same drape; docs/fabrics.md).
    pub early_stop: Option<EarlyStop>,
}

/// The model the drape test runs unless told: the implicit reference, which alone
/// reaches the material's equilibrium here (docs/fabrics.md: XPBD at its real-time
/// settings drapes far too limp, its bending not converged).
pub const DEFAULT_MODEL: ModelKind = ModelKind::Implicit;

/// Step of the drape test, s: long, since only the equilibrium is measured (backward
/// Euler at this step gives the same drape coefficient as at 1/60 s, within 0.1 point).
pub const DEFAULT_STEP: f32 = 0.1;

/// Newton iterations a step of the falling specimen gets under the implicit model, until
/// it moves slower than the settled speed (1 cm/s): the drape coefficients of a fall
/// solved to the tolerance at every step and of this one differ by what a different
/// mesh of the same size changes, in less time (docs/fabrics.md).
pub const EARLY_STOP: EarlyStop = EarlyStop {
    iterations: 4,
    calm_speed: SETTLED_SPEED,
};

impl CusickConfig {
    pub fn new(material: Material) -> Self {
        Self {
            material,
            standard: Standard::Bs5058,
            edge: DEFAULT_EDGE,
            model: DEFAULT_MODEL,
            substeps: None,
            max_seconds: 60.0,
            frame_dt: DEFAULT_STEP,
            early_stop: Some(EARLY_STOP),
        }
    }

    fn validate(&self) -> Result<(), ConfigError> {
        check_range("edge", self.edge, 0.002, 0.03, " m")?;
        check_range("settling time", self.max_seconds, 0.1, 600.0, " s")?;
        check_range("frame duration", self.frame_dt, 1e-4, 0.1, " s")?;
        self.material.validate()
    }
}

#[derive(Debug, thiserror::Error)]
pub enum CusickError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("specimen: {0}")]
    Mesh(#[from] MeshError),
    #[error("specimen: {0}")]
    Geometry(#[from] crate::error::GeometryError),
    #[error(transparent)]
    Step(#[from] StepError),
}

/// What one drape test measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CusickResult {
    pub standard: Standard,
    pub edge_m: f32,
    pub vertices: usize,
    pub triangles: usize,
    /// Drape coefficient, 0-1.
    pub drape_coefficient: f64,
    pub shadow_area_m2: f64,
    pub nodes: usize,
    pub node_depths_m: Vec<f32>,
    pub node_depth_mean_m: f32,
    pub settled: bool,
    pub simulated_s: f32,
    pub frames: u64,
    pub wall_s: f64,
    pub frame_ms_p50: f64,
    pub kinetic_energy_final_j: f64,
    pub crossings_self: usize,
    /// The shadow's outline, m, in [`shadow::DIRECTIONS`] directions.
    #[serde(skip)]
    pub radii: Vec<f32>,
    #[serde(skip)]
    pub node_list: Vec<Node>,
    /// The settled cloth, for export.
    #[serde(skip)]
    pub positions: Vec<Vec3>,
    #[serde(skip)]
    pub uvs: Vec<glam::Vec2>,
    #[serde(skip)]
    pub tris: Vec<[u32; 3]>,
}

/// Height of the clamped specimen above the floor, m (it hangs at most its overhang).
const TABLE: f32 = 0.5;

/// A crest must stand this far out beyond its troughs to count as a node, m.
pub const MIN_NODE_DEPTH: f32 = 0.004;

/// The speed the cloth is settled under (mass-weighted RMS), m/s.
const SETTLED_SPEED: f64 = 0.01;

/// How long the cloth must stay below the settled energy, s.
const SETTLED_FOR: f32 = 0.5;

/// Runs the drape test: the specimen meshed flat, clamped inside the disc, released, and
/// stepped until its speed stays under 1 cm/s for half a second (or `max_seconds`);
/// `progress` hears the simulated time and kinetic energy once a simulated second.
pub fn run(
    cfg: &CusickConfig,
    progress: &mut dyn FnMut(f32, f64),
) -> Result<CusickResult, CusickError> {
    cfg.validate()?;
    let (big, disc) = cfg.standard.radii();
    let mut mesh = mesher::mesh_outline(&Outline::ellipse(big, big, cfg.edge), cfg.edge)?;
    for p in &mut mesh.positions {
        p.y = TABLE;
    }
    let mut cloth = Cloth::new(mesh, &cfg.material)?;
    let centre = Vec3::new(0.0, TABLE, 0.0);
    // Clamped between the discs: every vertex over the disc, its rim included.
    for i in 0..cloth.len() {
        if (cloth.x[i] - centre).length() <= disc + 1e-5 {
            cloth.pin(i);
        }
    }
    let env = Environment {
        frame_dt: cfg.frame_dt,
        ..Environment::default()
    };
    let mut sim = Simulation::new(cloth, None, cfg.model, cfg.material, env, cfg.substeps)?;
    if cfg.model == ModelKind::Implicit {
        // The same model, told it may stop Newton early while the specimen falls.
        let mut implicit = Implicit::new(&sim.cloth, &sim.cloth.zones.reference(&cfg.material));
        implicit.early_stop = cfg.early_stop;
        sim.solver = Box::new(implicit);
    }
    let mass: f64 = (0..sim.cloth.len())
        .filter(|&i| !sim.cloth.is_pinned(i))
        .map(|i| sim.cloth.mass[i] as f64)
        .sum();
    let calm = 0.5 * mass * SETTLED_SPEED.powi(2);
    let needed = (SETTLED_FOR / cfg.frame_dt).ceil() as u64;
    let limit = (cfg.max_seconds / cfg.frame_dt).ceil() as u64;
    let started = Instant::now();
    let (mut frames, mut quiet, mut ke) = (0u64, 0u64, f64::INFINITY);
    let mut times = Vec::with_capacity(limit as usize);
    let per_second = (1.0 / cfg.frame_dt).round().max(1.0) as u64;
    while frames < limit && quiet < needed {
        let stats = sim.step()?;
        times.push(stats.wall_ms);
        frames += 1;
        ke = sim.cloth.kinetic_energy();
        // The first second is the fall, however slow it starts.
        quiet = if ke <= calm && frames >= per_second {
            quiet + 1
        } else {
            0
        };
        if frames % per_second == 0 {
            progress(frames as f32 * cfg.frame_dt, ke);
        }
    }
    let wall_s = started.elapsed().as_secs_f64();
    let tris = sim.cloth.live.triangles();
    let radii = shadow::outline(&sim.cloth.x, &tris, centre);
    let shadow_area = shadow::area(&radii);
    let node_list = shadow::nodes(&radii, MIN_NODE_DEPTH);
    let depths: Vec<f32> = node_list.iter().map(|n| n.depth_m).collect();
    times.sort_by(f64::total_cmp);
    Ok(CusickResult {
        standard: cfg.standard,
        edge_m: cfg.edge,
        vertices: sim.cloth.len(),
        triangles: tris.len(),
        drape_coefficient: shadow::drape_coefficient(shadow_area, disc as f64, big as f64),
        shadow_area_m2: shadow_area,
        nodes: node_list.len(),
        node_depth_mean_m: depths.iter().sum::<f32>() / depths.len().max(1) as f32,
        node_depths_m: depths,
        settled: quiet >= needed,
        simulated_s: frames as f32 * cfg.frame_dt,
        frames,
        wall_s,
        frame_ms_p50: times.get(times.len() / 2).copied().unwrap_or(0.0),
        kinetic_energy_final_j: ke,
        crossings_self: crossings::count_self(&sim.cloth.x, &tris),
        radii,
        node_list,
        positions: sim.cloth.x.clone(),
        uvs: sim.cloth.rest.uvs.clone(),
        tris,
    })
}

/// Specimens a drape test averages. A specimen's drape depends on how it buckles as it
/// falls (its node count), and a mesh 0.2% finer buckles differently: the drape
/// coefficient moves by up to 2.6 points between such meshes (docs/fabrics.md), as it
/// does between specimens cut from one fabric, which is why the standards average
/// several specimens.
pub const SPECIMENS: usize = 3;

/// Each specimen's mesh has its triangles' side this much longer than the one before.
const SPECIMEN_EDGE_STEP: f32 = 0.002;

/// The drape tests of several specimens of one fabric.
#[derive(Clone, Debug)]
pub struct Specimens {
    pub runs: Vec<CusickResult>,
}

impl Specimens {
    /// The mean drape coefficient, 0-1.
    pub fn drape_coefficient(&self) -> f64 {
        self.runs.iter().map(|r| r.drape_coefficient).sum::<f64>() / self.runs.len().max(1) as f64
    }

    /// Highest minus lowest drape coefficient.
    pub fn spread(&self) -> f64 {
        let dc = self.runs.iter().map(|r| r.drape_coefficient);
        dc.clone().fold(f64::MIN, f64::max) - dc.fold(f64::MAX, f64::min)
    }

    /// The median node count.
    pub fn nodes(&self) -> usize {
        let mut n: Vec<usize> = self.runs.iter().map(|r| r.nodes).collect();
        n.sort_unstable();
        n.get(n.len() / 2).copied().unwrap_or(0)
    }

    pub fn settled(&self) -> bool {
        self.runs.iter().all(|r| r.settled)
    }

    /// Wall time of the slowest specimen, s.
    pub fn slowest_s(&self) -> f64 {
        self.runs.iter().map(|r| r.wall_s).fold(0.0, f64::max)
    }
}

/// Runs the drape test on `count` specimens (at least one), meshed `cfg.edge`, then
/// 0.2%, 0.4%, ... longer; `progress` hears the specimen's index with [`run`]'s.
pub fn run_specimens(
    cfg: &CusickConfig,
    count: usize,
    progress: &mut dyn FnMut(usize, f32, f64),
) -> Result<Specimens, CusickError> {
    let mut runs = Vec::with_capacity(count.max(1));
    for k in 0..count.max(1) {
        let mut one = cfg.clone();
        one.edge = cfg.edge * (1.0 + SPECIMEN_EDGE_STEP * k as f32);
        runs.push(run(&one, &mut |t, ke| progress(k, t, ke))?);
    }
    Ok(Specimens { runs })
}
