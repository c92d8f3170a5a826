//! What `cloth-sim run` is told, and what it counts.

use std::path::PathBuf;

use shared::domain::Domain;
use sim_core::error::{ConfigError, check_range};
use sim_core::scenario::{ScenarioConfig, ScenarioName};

#[derive(Clone, Debug)]
pub struct ServiceConfig {
    pub domain: Domain,
    /// Frames per second.
    pub rate_hz: f64,
    /// Where the design is autosaved, and resumed from at start.
    pub autosave: PathBuf,
    pub autosave_every_s: f64,
    /// Stop after this many seconds (None: until SIGINT/SIGTERM).
    pub seconds: Option<f64>,
    /// Pinch: grab radius (m) and spring stiffness (N/m).
    pub pinch_radius: f32,
    pub pinch_stiffness: f32,
    /// Limit the pinch's pull on the cloth to the force the haptic loop rendered (the
    /// reaction), when it sends one.
    pub couple_applied_force: bool,
    /// The scene a RESET command rebuilds (with its body, grid and material changes).
    pub scene: ScenarioConfig,
    /// `--guard` or `--no-guard` as given at start (`None`: neither): a loaded design
    /// takes it; otherwise it keeps the switch its file has.
    pub guard_forced: Option<bool>,
    /// Let a cloth at rest fall asleep (`--no-sleep`: never), whatever design is loaded.
    pub sleep: bool,
    /// The pattern file the first design was made from (`--pattern` on a new design; not
    /// a resumed one): the studio's Scene panel shows it (`PieceList::source`).
    pub source: Option<PathBuf>,
}

impl ServiceConfig {
    pub fn new(domain: Domain) -> Self {
        // The user's private state directory (checked when the autosave is first used).
        let autosave = shared::paths::state_dir_path()
            .0
            .join(format!("{}.autosave.saiho", domain.name()));
        Self {
            domain,
            rate_hz: 60.0,
            autosave,
            autosave_every_s: 2.0,
            seconds: None,
            pinch_radius: 0.05,
            pinch_stiffness: 100.0,
            couple_applied_force: true,
            scene: ScenarioConfig::new(ScenarioName::DrapeCube),
            guard_forced: None,
            sleep: true,
            source: None,
        }
    }
}

impl ServiceConfig {
    /// Checks every setting before any work (the scene's too): ranges, no NaN, an
    /// autosave path that is not a directory.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_range("rate", self.rate_hz, 1.0, 1000.0, " frames per second")?;
        if let Some(s) = self.seconds {
            check_range("seconds", s, 0.001, 1.0e7, " s")?;
        }
        check_range(
            "autosave interval",
            self.autosave_every_s,
            0.05,
            3600.0,
            " s",
        )?;
        check_range("pinch radius", self.pinch_radius, 0.001, 1.0, " m")?;
        check_range("pinch stiffness", self.pinch_stiffness, 1.0, 1.0e6, " N/m")?;
        if self.autosave.is_dir() {
            return Err(ConfigError::OutOfRange {
                name: "the autosave path",
                rule: "a file, not a directory",
                value: self.autosave.display().to_string(),
            });
        }
        self.scene.validate()
    }
}

#[derive(Debug, Default, Clone)]
pub struct ServiceStats {
    pub frames: u64,
    pub samples: u64,
    pub rejected: u64,
    pub pinches: u64,
    /// Autosaves written.
    pub autosaves: u64,
    /// Autosaves that could not be written (the design file on disk was left as it was).
    pub autosave_failures: u64,
    /// Commands from the UI answered.
    pub commands: u64,
    /// Substeps that took the pen from a sample of their own (pen read per substep).
    pub pen_substeps: u64,
    /// Substeps whose pinch had the haptic loop's applied force as its limit.
    pub coupled_substeps: u64,
    /// Of those, substeps in which the limit bound (the cloth was pulled at it).
    pub force_limited_substeps: u64,
    /// Applied-force messages received from the haptic loop.
    pub applied_forces: u64,
    /// Seam pairs welded.
    pub welds: u64,
    /// Largest pull of the pinch on the cloth in any substep, N.
    pub pinch_force_max_n: f32,
    /// Longest time an autosave held up a frame, ms.
    pub autosave_ms_max: f64,
    /// Local models that could not be sent to the haptic loop.
    pub model_send_failures: u64,
    /// Local models sent within a slow frame (`MID_FRAME_MODEL`): the touch planes between
    /// substeps, and the touch planes or the pinched vertex beside a long contact search.
    pub mid_frame_models: u64,
    pub resumed: bool,
}
