//! Headless scenarios, the top of the library: the paper's drape-over-a-cube experiment
//! and friends, each a scripted design with a JSON report and exports.
//!
//! Inside: `config` (names, settings, the scene) <- `scripts` (what fit-cube, tear and
//! paint do, through the design's public operations) and `held` (a garment held while it
//! settles, and whether it slid once let go) <- `run` (frames, measures, exports);
//! `report` (the JSON); `realtime` (the largest real-time grid).

mod config;
mod error;
pub mod garment;
mod held;
mod placing;
mod realtime;
mod report;
mod run;
pub mod scripts;

pub use config::{
    MAX_FRAMES, MAX_GRID, MAX_THREADS, PieceShape, SEW_DAMPING, ScenarioConfig, ScenarioError,
    ScenarioName, build_design, build_scene,
};
pub use held::{FIRM_SUBSTEPS, hold_pattern};
pub use realtime::max_realtime_grid;
pub use report::{OpsReport, Percentiles, Report};
pub use run::{SCENARIO_ALLOWANCE_MM, run_scenario};
