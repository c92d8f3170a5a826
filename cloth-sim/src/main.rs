//! `cloth-sim`: the cloth simulation process (`run`), the headless scenarios
//! (`scenario`) and the real-time grid search (`max-realtime-grid`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use cloth_sim::{ServiceConfig, resume_or};
use shared::cli::whole_in;
use sim_core::collision::BodyKind;
use sim_core::design::TearMode;
use sim_core::design::garment::own_body;
use sim_core::fabric::{Library, Standard};
use sim_core::mesh::obj::load_obj;
use sim_core::scenario::{
    MAX_FRAMES, MAX_GRID, MAX_THREADS, PieceShape, ScenarioConfig, ScenarioName, max_realtime_grid,
    run_scenario,
};
use sim_core::solver::{MAX_FRAME_SUBSTEPS, Material, ModelKind};

mod fabrics;
mod subcommands;

#[derive(Parser)]
#[command(
    name = "cloth-sim",
    version,
    about = "Saiho cloth simulation: headless scenarios and measurements"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario headless; writes DIR/report.json, the cloth as DIR/cloth.obj + .mtl +
    /// .png and DIR/cloth.glb (a garment's pieces also as DIR/garment.glb, a mesh each),
    /// DIR/body.obj and the design as DIR/design.saiho.
    Scenario(ScenarioArgs),
    /// Run the simulation as a process: follow the pen from haptic-loop (button 1 pinches),
    /// publish the local model it renders force from, autosave and resume the design.
    Run(RunArgs),
    /// Count the exact crossings of a cloth OBJ (an export of ours or anyone's): pairs of
    /// its triangles that intersect (sharing no vertex), and with --body the triangles that
    /// intersect the body's surface. Exact predicates: touching counts, nothing is missed.
    Crossings {
        /// The cloth, as an OBJ (vertices at the same position are one vertex).
        cloth: PathBuf,
        /// The body: cube, sphere, mannequin, mannequin-apose, human (ours, as the
        /// scenarios place them) or an .obj (a scenario's body.obj).
        #[arg(long, value_parser = parse_body)]
        body: Option<BodyKind>,
    },
    /// Write a design's sewing pattern: every piece's outline in its pattern plane as it
    /// is now (after cuts, tears and welds; seams marked and paired by label, grain line,
    /// name), as DIR/pattern.svg (1 unit = 1 mm) and DIR/pattern.dxf (AAMA, ASCII R12).
    ExportPattern {
        /// The design file (.saiho: a scenario's design.saiho, or cloth-sim run's autosave).
        design: PathBuf,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Seam allowance added around every piece as its cut line, mm (0: none).
        #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
        allowance: f64,
    },
    /// Measure how a design's garment fits its body: the cloth's length round the bust,
    /// the waist and the hips (found on the body's own shape) beside the body's tape
    /// there, and the ease between (docs/garments.md, "How a garment fits").
    Fit {
        /// The design file (.saiho: a scenario's design.saiho, or cloth-sim run's autosave).
        design: PathBuf,
        /// Also measure at this height above the floor, m (a hem, a high hip; repeat for
        /// more): the level is named "level".
        #[arg(long, allow_negative_numbers = true)]
        at: Vec<f32>,
        /// Print the girths as JSON (per level: level, height_m, body_m, garment_m,
        /// ease_m, and where it does not go round the body, null there and open_runs and
        /// open_cloth_m: the runs of cloth the level crosses).
        #[arg(long)]
        json: bool,
    },
    /// List the fabric library: every fabric's source and its parameters in SI units
    /// (density, stretch and shear in N/m, bending rigidity warp/weft/bias in µN·m), and
    /// the drape coefficient its source measured. Conversions: docs/fabrics.md.
    Fabrics {
        /// Every field as JSON (for tools), with the model's material for each.
        #[arg(long)]
        json: bool,
    },
    /// Run the Cusick drape test (three specimens) on every fabric whose source measured
    /// its drape, and print ours beside theirs (a Markdown table) with the mean absolute error.
    ValidateFabrics {
        /// Also write the table as JSON (per fabric: name, dc_measured, dc_sim (the mean),
        /// dc_sim_spread, nodes_measured, nodes_sim; and mae_dc, in points).
        #[arg(long)]
        json: Option<PathBuf>,
        /// Cloth model (default: the implicit reference; see docs/fabrics.md).
        #[arg(long, value_parser = parse_model, default_value = "implicit")]
        model: ModelKind,
        /// Mesh edge, m.
        #[arg(long, default_value_t = sim_core::fabric::cusick::DEFAULT_EDGE, allow_negative_numbers = true)]
        edge: f32,
        /// No progress lines on stderr.
        #[arg(long)]
        quiet: bool,
    },
    /// Find the largest cloth grid a model steps in real time (drape-cube, 60 Hz frames).
    MaxRealtimeGrid {
        /// Cloth model.
        #[arg(long, value_parser = parse_model, default_value = "xpbd")]
        model: ModelKind,
        /// Frames measured per grid size.
        #[arg(long, default_value_t = 60, allow_negative_numbers = true, value_parser = whole_in::<u64>(4, MAX_FRAMES as i64, ""))]
        frames: u64,
        /// Also write the results as JSON here.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Seed model: give each unit-mass spring the default cotton's stiffness-to-mass
        /// ratio at every grid size (the same material), instead of the fixed default k.
        #[arg(long)]
        matched: bool,
    },
}

fn parse_tear_mode(s: &str) -> Result<TearMode, String> {
    match s {
        "delete" => Ok(TearMode::Delete),
        "split" => Ok(TearMode::Split),
        other => Err(format!(
            "unknown tear mode '{other}' (expected delete or split)"
        )),
    }
}

#[derive(Args)]
struct RunArgs {
    /// Domain (iceoryx2 prefix) to run in; default $SAIHO_DOMAIN, else "default".
    #[arg(long)]
    domain: Option<String>,
    /// Body of a new design: cube, sphere, mannequin, mannequin-apose, human or a path to
    /// an .obj. Default: the cube, or the body the --pattern is cut for (the human body
    /// for a GarmentCode pattern; the one an SVG names on its root, `data-body`).
    #[arg(long, value_parser = parse_body)]
    body: Option<BodyKind>,
    /// Cells per side of the square cloth.
    #[arg(long, default_value_t = 64, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_GRID as i64, " cells a side"))]
    grid: usize,
    /// Cloth model of a new design: xpbd (the default: real time, with its guard the
    /// cloth never crosses itself or the body), vbd (never crosses, strain under 1%;
    /// several times slower, see docs/models.md), seed (the paper's mass-spring) or
    /// implicit (the reference; slow). A resumed design keeps the model it was made with
    /// (--fresh for a new one).
    #[arg(long, value_parser = parse_model)]
    model: Option<ModelKind>,
    /// XPBD with its guard (the default for a new design): the cloth never crosses itself
    /// or the body. Given, it applies to a resumed xpbd design too, whatever its file says.
    #[arg(long, conflicts_with = "no_guard")]
    guard: bool,
    /// Plain XPBD: no guard, so the cloth can cross itself and the body's edges, at a
    /// fraction of the frame time (docs/collision.md). Applies to a resumed xpbd design
    /// too. The studio's "Never cross (guard)" switch turns it back on.
    #[arg(long)]
    no_guard: bool,
    /// Keep simulating a cloth that has come to rest. By default it falls asleep once it
    /// has moved under 0.25 mm (root mean square) in a second, with no more than one
    /// vertex in a hundred past 2 mm, and costs nothing until the pen, an edit or a
    /// setting wakes it (docs/models.md, "A cloth at rest sleeps").
    #[arg(long)]
    no_sleep: bool,
    /// Substeps per frame (default: the model's).
    #[arg(long, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_FRAME_SUBSTEPS as i64, " per frame"))]
    substeps: Option<usize>,
    /// Frames per second (1-1000).
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    rate: f64,
    /// The design's autosave (resumed at start when valid). Default:
    /// ~/.local/state/saiho/DOMAIN.autosave.saiho ($XDG_STATE_HOME/saiho/ when set), in a
    /// directory of the user's alone.
    #[arg(long)]
    autosave: Option<PathBuf>,
    /// Start a new design even if an autosave exists.
    #[arg(long)]
    fresh: bool,
    /// A new design is this pattern's pieces (SVG, DXF or GarmentCode JSON) placed round
    /// the body and sewn, as `scenario drape-pattern` builds them, instead of a square
    /// cloth. A resumed design stays as it is (--fresh for the pattern's).
    #[arg(long, value_name = "FILE")]
    pattern: Option<PathBuf>,
    /// Pinch spring stiffness, N/m (the haptic loop renders the same spring).
    #[arg(long, default_value_t = 100.0, allow_negative_numbers = true)]
    pinch_stiffness: f32,
    /// Pull the cloth with the pinch spring alone, not limited to the force the haptic
    /// loop rendered (its reaction).
    #[arg(long)]
    no_force_coupling: bool,
    /// Stop after this many seconds (default: until SIGINT/SIGTERM).
    #[arg(long, allow_negative_numbers = true)]
    seconds: Option<f64>,
    /// Threads for the XPBD passes (1 or 2).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_THREADS as i64, ""))]
    threads: usize,
    /// Run only on these CPUs (such as 0 or 0-2); cloth-lab keeps cloth-sim off the
    /// haptic loop's CPU this way.
    #[arg(long)]
    cpus: Option<String>,
    #[command(flatten)]
    material: MaterialArgs,
}

#[derive(Args)]
struct ScenarioArgs {
    /// Scenario: drape-cube (the paper's drape), drape-mannequin, fit-cube (the paper's
    /// experiment end to end: drape, cut the corners away, sew the flaps), tear (pull a
    /// gripped corner until the cloth tears), paint (paint a pattern, export the texture) or
    /// fold (a cloth on the floor folded corner to corner, then across: four layers, which
    /// cross each other only with --no-guard), dress-mannequin (a front and a back
    /// panel arranged round the mannequin, sewn, draped, the neckline cut) or
    /// drape-pattern FILE (any pattern placed, sewn and draped the same way).
    /// cusick: the textile drape test (BS 5058: a 30 cm specimen clamped on an 18 cm
    /// disc) on --fabric NAME, three specimens averaged; writes report.json
    /// (drape_coefficient, nodes, converged), shadow.png and cloth.obj.
    #[arg(value_parser = parse_scenario_choice)]
    name: ScenarioChoice,
    /// drape-pattern: the pattern, an .svg or .dxf (pieces arranged by name: front,
    /// back, left/right side, left/right sleeve; seams from Saiho's marks) or a
    /// GarmentCode .json specification (its panels' placement and stitches).
    pattern: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long)]
    out: PathBuf,
    /// tear: an edge tears when stretched past this ratio of its rest length.
    #[arg(long, default_value_t = 1.6)]
    tear_threshold: f32,
    /// tear: delete (the paper's: the two triangles go) or split (the material separates,
    /// the triangles stay).
    #[arg(long, value_parser = parse_tear_mode, default_value = "delete")]
    tear_mode: TearMode,
    /// cusick: the standard's sizes, bs5058 (30 cm on 18 cm) or astm-d4848 (36 cm on
    /// 12.7 cm).
    #[arg(long, value_parser = parse_standard, default_value = "bs5058")]
    standard: Standard,
    /// cusick: skip the second run on a finer mesh (half the triangle area) that checks
    /// the drape coefficient has converged.
    #[arg(long)]
    no_refine: bool,
    /// Cells per side of the square cloth: N x N cells, (N+1)^2 vertices.
    #[arg(long, default_value_t = 64, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_GRID as i64, " cells a side"))]
    grid: usize,
    /// Cloth model: xpbd (default), vbd (never crosses; slow, see docs/models.md), seed (the
    /// paper's mass-spring) or implicit (reference; cusick's default).
    #[arg(long, value_parser = parse_model)]
    model: Option<ModelKind>,
    /// XPBD with its guard, the default: the vbd model's proximity search and guard around
    /// each substep, so the cloth never crosses itself or the body (2-12x plain xpbd's
    /// frame time, more for large sewn pieces: two 8k-vertex dress panels 44x; see
    /// docs/collision.md). Only with --model xpbd.
    #[arg(long, conflicts_with = "no_guard")]
    guard: bool,
    /// Plain XPBD, without its guard: the cloth can cross itself and the body's edges (the
    /// behaviour before 2026-11-28), at a fraction of the frame time.
    #[arg(long)]
    no_guard: bool,
    /// Let the cloth fall asleep once it has come to rest, as `cloth-sim run` does (under
    /// 0.25 mm root mean square in a second, at most 1% of its vertices past 2 mm): the
    /// report adds `frames_asleep` and `step_ms_awake`. Off by default, so that the frame
    /// times measure the solver.
    #[arg(long)]
    sleep: bool,
    /// Frames of 1/60 s to simulate (the operation scenarios act at frame 240).
    #[arg(long, default_value_t = 600, allow_negative_numbers = true, value_parser = whole_in::<u64>(1, MAX_FRAMES as i64, ""))]
    frames: u64,
    /// Body: cube, sphere, mannequin, mannequin-apose (its arms held out 50 degrees below
    /// the horizontal), human (an average adult figure, 1.72 m, arms held out 45 degrees:
    /// GarmentCode's own body, which its patterns are cut for), a path to an .obj (metres,
    /// Y up, closed, outward winding) or floor (none: the cloth lies on the floor).
    /// Default: the scenario's own (the cube; the mannequin for drape-mannequin and the
    /// garments, the human body for a GarmentCode pattern, the body an SVG names on its
    /// root (`data-body`); the floor for fold).
    #[arg(long, value_parser = parse_scenario_body)]
    body: Option<ScenarioBody>,
    /// Substeps per frame (default: 5 for xpbd, 1 for implicit, the stable count for seed).
    #[arg(long, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_FRAME_SUBSTEPS as i64, " per frame"))]
    substeps: Option<usize>,
    /// Use this OBJ (metres, Y up, with UVs for the warp/weft directions) as the cloth
    /// instead of the square grid; it is centred 5 cm above the body.
    #[arg(long)]
    cloth: Option<PathBuf>,
    /// Use pattern pieces instead of the square grid: rect:WxH or ellipse:WxH (metres), or
    /// FILE.svg (every closed shape a piece, holes inside; mm unless the file's size says
    /// otherwise, as our pattern.svg), meshed with well-shaped triangles (no angle under
    /// 20 degrees) of --piece-edge. An SVG's pieces lie as the file lays them out.
    #[arg(long, value_parser = parse_piece)]
    piece: Option<PieceShape>,
    /// The piece's triangle side, m (default 1/64 m, the 64 x 64 grid's cell).
    #[arg(long, allow_negative_numbers = true)]
    piece_edge: Option<f32>,
    /// Side of the square cloth, m.
    #[arg(long, default_value_t = 1.0)]
    cloth_size: f32,
    #[command(flatten)]
    material: MaterialArgs,
    /// Threads for the XPBD constraint passes (1 or 2; the result does not depend on it).
    #[arg(long, default_value_t = 2, allow_negative_numbers = true, value_parser = whole_in::<usize>(1, MAX_THREADS as i64, ""))]
    threads: usize,
    /// No progress lines on stderr.
    #[arg(long)]
    quiet: bool,
    /// Count the exact crossings every N frames too; the report keeps the most seen
    /// (`crossings_self_max`, `crossings_body_max`). They are always counted at the end.
    #[arg(long, allow_negative_numbers = true, value_parser = whole_in::<u64>(1, MAX_FRAMES as i64, " frames"))]
    check_every: Option<u64>,
    /// dress-mannequin, drape-pattern: the pattern piece PIECE made of the library's
    /// FABRIC (its mass, stretch, shear and bending; e.g. --piece-fabric front=denim);
    /// repeat for more pieces. The others are the design's material (--fabric or the
    /// material flags).
    #[arg(long, value_name = "PIECE=FABRIC", value_parser = parse_piece_fabric)]
    piece_fabric: Vec<(String, String)>,
    /// dress-mannequin, drape-pattern: sew in the air with the garment's motion dying
    /// away at RATE per second until its seams close [default: 30 for dress-mannequin,
    /// 0 for drape-pattern]. 0: dress-mannequin sews as it falls, drape-pattern in the
    /// air undamped (docs/garments.md).
    #[arg(long, value_name = "RATE", allow_negative_numbers = true)]
    sew_damping: Option<f32>,
}

#[derive(Args)]
struct MaterialArgs {
    /// A fabric from the library (`cloth-sim fabrics` lists them): its density, stretch,
    /// shear, bending (warp, weft, bias), friction and thickness; damping, drag and the
    /// solver switches stay as given.
    #[arg(long, value_parser = parse_fabric, conflicts_with_all = ["density", "stretch", "shear", "bending", "friction", "thickness"])]
    fabric: Option<String>,
    /// Areal density, kg/m^2.
    #[arg(long, default_value_t = Material::default().density, allow_negative_numbers = true)]
    density: f32,
    /// Stretch modulus (warp and weft), N/m.
    #[arg(long, default_value_t = Material::default().stretch, allow_negative_numbers = true)]
    stretch: f32,
    /// Shear modulus, N/m.
    #[arg(long, default_value_t = Material::default().shear, allow_negative_numbers = true)]
    shear: f32,
    /// Shear damping time, s (the weave's internal friction in shear; 0 turns it off).
    #[arg(long, default_value_t = Material::default().shear_damping, allow_negative_numbers = true)]
    shear_damping: f32,
    /// Bending rigidity, N m.
    #[arg(long, default_value_t = Material::default().bending, allow_negative_numbers = true)]
    bending: f32,
    /// XPBD: bending damping time, s (internal friction in bending, across each fold, like
    /// the shear's; it stops a fine cloth's loose flaps swinging at rest; 0 turns it off).
    /// Off while a seam is being sewn or the pen holds the cloth.
    #[arg(long, default_value_t = Material::default().bend_damping, allow_negative_numbers = true)]
    bend_damping: f32,
    /// Velocity damping, 1/s.
    #[arg(long, default_value_t = Material::default().damping, allow_negative_numbers = true)]
    damping: f32,
    /// Air drag on normal velocity, kg/(m^2 s).
    #[arg(long, default_value_t = Material::default().drag, allow_negative_numbers = true)]
    drag: f32,
    /// Friction coefficient against bodies and the floor.
    #[arg(long, default_value_t = Material::default().friction, allow_negative_numbers = true)]
    friction: f32,
    /// Contact thickness, m.
    #[arg(long, default_value_t = Material::default().thickness, allow_negative_numbers = true)]
    thickness: f32,
    /// Seed model spring constant k, N/m (unit masses).
    #[arg(long, default_value_t = Material::default().seed_stiffness, allow_negative_numbers = true)]
    seed_stiffness: f32,
    /// XPBD: no long-range tethers to pinned vertices.
    #[arg(long)]
    no_tethers: bool,
    /// XPBD: no long-range stretch limits (the coarse lattice that stops fine cloth
    /// stretching under Gauss-Seidel lag); for comparison.
    #[arg(long)]
    no_stretch_limits: bool,
    /// XPBD: the most a triangle may stretch in any direction over its rest length,
    /// held hard each substep (0.2, the default: 1.2x, a woven fabric's stiff end; with
    /// `--fabric`, the fabric's: 0, none, for knits; 0 turns it off). Keeps drapes from
    /// stretching where the solver lags; costs 30-50% more frame.
    /// `run`: a resumed design takes it too, whatever its file says.
    #[arg(long, allow_negative_numbers = true)]
    strain_limit: Option<f32>,
}

impl MaterialArgs {
    /// `--strain-limit`, or `otherwise` (the fabric's or the default material's).
    fn strain_limit(&self, otherwise: f32) -> f32 {
        self.strain_limit.unwrap_or(otherwise)
    }

    fn material(&self) -> Material {
        let lib = Library::builtin();
        if let Some(f) = self.fabric.as_deref().and_then(|n| lib.get(n).ok()) {
            let fabric = f.material();
            return Material {
                shear_damping: self.shear_damping,
                bend_damping: self.bend_damping,
                damping: self.damping,
                drag: self.drag,
                seed_stiffness: self.seed_stiffness,
                tethers: !self.no_tethers,
                stretch_limits: !self.no_stretch_limits,
                strain_limit: self.strain_limit(fabric.strain_limit),
                ..fabric
            };
        }
        Material {
            density: self.density,
            stretch: self.stretch,
            shear: self.shear,
            shear_damping: self.shear_damping,
            bending: self.bending,
            bend_damping: self.bend_damping,
            bending_weft: 1.0,
            bending_bias: 1.0,
            damping: self.damping,
            drag: self.drag,
            friction: self.friction,
            thickness: self.thickness,
            seed_stiffness: self.seed_stiffness,
            tethers: !self.no_tethers,
            stretch_limits: !self.no_stretch_limits,
            strain_limit: self.strain_limit(Material::default().strain_limit),
        }
    }
}

fn parse_model(s: &str) -> Result<ModelKind, String> {
    ModelKind::parse(s).map_err(|e| e.to_string())
}
fn parse_body(s: &str) -> Result<BodyKind, String> {
    BodyKind::parse(s).map_err(|e| e.to_string())
}
/// The body of `run`'s new design: the one asked for, else the one the pattern is cut
/// for (the human body for a GarmentCode pattern, the body an SVG names), else the cube.
fn new_design_body(asked: Option<BodyKind>, pattern: Option<&Path>) -> BodyKind {
    asked
        .or_else(|| pattern.and_then(own_body))
        .unwrap_or(BodyKind::Cube)
}

/// A scenario's `--body`: a body, or `floor` for none.
#[derive(Clone, Debug)]
struct ScenarioBody(Option<BodyKind>);

fn parse_scenario_body(s: &str) -> Result<ScenarioBody, String> {
    if s == "floor" {
        return Ok(ScenarioBody(None));
    }
    parse_body(s).map(|b| ScenarioBody(Some(b)))
}
fn parse_piece(s: &str) -> Result<PieceShape, String> {
    PieceShape::parse(s).map_err(|e| e.to_string())
}
/// `scenario`'s name: the drape test, or a scene of the library's.
#[derive(Clone, Copy, Debug)]
enum ScenarioChoice {
    Cusick,
    Scene(ScenarioName),
}

fn parse_scenario_choice(s: &str) -> Result<ScenarioChoice, String> {
    if s == "cusick" {
        return Ok(ScenarioChoice::Cusick);
    }
    ScenarioName::parse(s)
        .map(ScenarioChoice::Scene)
        .map_err(|e| format!("{e}, cusick"))
}
fn parse_standard(s: &str) -> Result<Standard, String> {
    Standard::parse(s).map_err(|e| e.to_string())
}
fn parse_piece_fabric(s: &str) -> Result<(String, String), String> {
    let (piece, fabric) = s
        .split_once('=')
        .ok_or_else(|| format!("expected PIECE=FABRIC (e.g. front=denim), got {s:?}"))?;
    if piece.trim().is_empty() {
        return Err(format!(
            "expected PIECE=FABRIC with a piece's name, got {s:?}"
        ));
    }
    Ok((piece.trim().to_string(), parse_fabric(fabric.trim())?))
}
fn parse_fabric(s: &str) -> Result<String, String> {
    Library::builtin()
        .get(s)
        .map(|f| f.name.clone())
        .map_err(|e| e.to_string())
}

fn main() -> ExitCode {
    let cli: Cli = shared::cli::parse();
    let result = match cli.command {
        Command::Scenario(a) => subcommands::scenario(a),
        Command::Run(a) => run_service(a),
        Command::MaxRealtimeGrid {
            model,
            frames,
            json,
            matched,
        } => subcommands::realtime(model, frames, json, matched),
        Command::Crossings { cloth, body } => subcommands::crossings(&cloth, body.as_ref()),
        Command::Fit { design, at, json } => subcommands::fit(&design, &at, json),
        Command::Fabrics { json } => fabrics::list(json),
        Command::ValidateFabrics {
            json,
            model,
            edge,
            quiet,
        } => fabrics::validate(model, edge, json, quiet),
        Command::ExportPattern {
            design,
            out,
            allowance,
        } => subcommands::export_pattern(&design, &out, allowance),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run_service(a: RunArgs) -> Result<(), Box<dyn std::error::Error>> {
    let domain = shared::domain::Domain::from_arg_or_env(a.domain.as_deref())?;
    let mut cfg = ServiceConfig::new(domain);
    if let Some(p) = a.autosave {
        cfg.autosave = p;
    }
    cfg.rate_hz = a.rate;
    cfg.seconds = a.seconds;
    cfg.sleep = !a.no_sleep;
    cfg.pinch_stiffness = a.pinch_stiffness;
    cfg.couple_applied_force = !a.no_force_coupling;
    let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
    scene.body = Some(new_design_body(a.body, a.pattern.as_deref()));
    scene.grid = a.grid;
    scene.model = a.model.unwrap_or(ModelKind::Xpbd);
    let forced = guard_choice(a.guard, a.no_guard, scene.model)?;
    scene.guard = forced.unwrap_or(true);
    cfg.guard_forced = forced;
    scene.substeps = a.substeps;
    scene.material = a.material.material();
    scene.threads = a.threads;
    cfg.scene = scene.clone();
    cfg.validate()?;
    if let Some(cpus) = &a.cpus {
        shared::cpus::keep_on(&shared::cpus::parse_list(cpus)?)?;
    }
    let stop = shared::signals::termination_flag();
    let mut log = |m: &str| eprintln!("cloth-sim: {m}");
    cloth_sim::prepare_dir(&cfg.autosave)?;
    // The first design: the square, or the pattern's pieces (a new scene from the studio
    // is the square unless it names a pattern).
    let mut first = scene.clone();
    first.pattern = a.pattern.clone();
    let build = || {
        let (d, sewn) = cloth_sim::new_design(&first)?;
        if let (Some(p), Some(sewn)) = (&a.pattern, sewn) {
            eprintln!(
                "cloth-sim: the {} pieces of {} round the body, {sewn}",
                d.pieces.len(),
                p.display()
            );
        }
        Ok(d)
    };
    let (mut design, resumed) = if a.fresh {
        (cloth_sim::start_fresh(&cfg, build, &mut log)?, false)
    } else {
        resume_or(&cfg, build, &mut log)?
    };
    cfg.source = a.pattern.clone().filter(|_| !resumed);
    for n in &design.sim.notices {
        log(&format!("note: {n}"));
    }
    if let Some(on) = forced
        && !design.sim.set_guard(on)
    {
        log(&format!(
            "note: --{}guard is the xpbd model's; the resumed design runs the {} model",
            if on { "" } else { "no-" },
            design.sim.model.name()
        ));
    }
    if let Some(limit) = a.material.strain_limit.filter(|_| resumed) {
        match cloth_sim::set_strain_limit(&mut design, limit) {
            Ok(said) => log(&format!("--strain-limit on the resumed design: {said}")),
            Err(e) => log(&format!("note: --strain-limit: {e}")),
        }
    }
    if let Some(p) = a.pattern.as_ref().filter(|_| resumed) {
        log(&format!(
            "note: --pattern {}: the resumed design stays as it is (--fresh starts the \
             pattern's)",
            p.display()
        ));
    }
    if let Some(m) = a.model.filter(|&m| resumed && m != design.sim.model) {
        log(&format!(
            "note: the resumed design runs the {} model, not --model {}: a design keeps \
             the model it was made with (--fresh starts a new one)",
            design.sim.model.name(),
            m.name()
        ));
    }
    log(&format!(
        "{} vertices, {} model{}, domain '{}', {} Hz, autosave {}{}",
        design.sim.cloth.len(),
        design.sim.model.name(),
        if design.sim.model == ModelKind::Xpbd && design.sim.never_crosses() {
            " with its guard"
        } else {
            ""
        },
        cfg.domain.name(),
        cfg.rate_hz,
        cfg.autosave.display(),
        if resumed { " (resumed)" } else { "" }
    ));
    let stats = cloth_sim::run(design, &cfg, stop, &mut log)?;
    log(&stopped_line(&stats));
    if stats.model_send_failures > 0 {
        log(&format!(
            "{} of the pen's models could not be sent to haptic-loop",
            stats.model_send_failures
        ));
    }
    Ok(())
}

/// The service's last line: what it did.
fn stopped_line(stats: &cloth_sim::ServiceStats) -> String {
    format!(
        "stopped after {} frames: {} device samples ({} rejected), {} applied forces, {} pinches ({} substeps read the pen, {} coupled to the rendered force, {} pulled at its limit, largest pull {:.2} N), {} models sent within slow frames, {} autosaves, {} failed (longest hold-up {:.1} ms)",
        stats.frames,
        stats.samples,
        stats.rejected,
        stats.applied_forces,
        stats.pinches,
        stats.pen_substeps,
        stats.coupled_substeps,
        stats.force_limited_substeps,
        stats.pinch_force_max_n,
        stats.mid_frame_models,
        stats.autosaves,
        stats.autosave_failures,
        stats.autosave_ms_max
    )
}

/// `--guard` or `--no-guard` as asked (`None`: neither), refused with a model other than
/// xpbd, whose contact it is.
fn guard_choice(guard: bool, no_guard: bool, model: ModelKind) -> Result<Option<bool>, String> {
    let asked = (guard || no_guard).then_some(guard);
    if asked.is_some() && model != ModelKind::Xpbd {
        return Err(format!(
            "--{}guard is the xpbd model's, not --model {}'s (vbd's contact is always \
             guarded; seed and implicit have none)",
            if guard { "" } else { "no-" },
            model.name()
        ));
    }
    Ok(asked)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_garmentcode_pattern_starts_on_its_own_body_unless_told() {
        let shirt = Path::new("shirt_specification.JSON");
        assert_eq!(new_design_body(None, Some(shirt)), BodyKind::Human);
        assert_eq!(
            new_design_body(None, Some(Path::new("dress.svg"))),
            BodyKind::Cube
        );
        assert_eq!(new_design_body(None, None), BodyKind::Cube);
        // The sleeved dress we ship says it is cut for the mannequin.
        let dress = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../sim-core/assets/dress-sleeves.svg"
        );
        assert_eq!(
            new_design_body(None, Some(Path::new(dress))),
            BodyKind::Mannequin
        );
        assert_eq!(
            new_design_body(Some(BodyKind::Mannequin), Some(shirt)),
            BodyKind::Mannequin
        );
    }
}
