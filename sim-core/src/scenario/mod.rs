//! Headless scenarios: the paper's drape-over-a-cube experiment and friends, with a JSON
//! report and OBJ exports.

mod report;
mod run;
pub mod scripts;

pub use report::{Percentiles, Report};
pub use run::{
    ScenarioConfig, ScenarioError, ScenarioName, build_simulation, max_realtime_grid, run_scenario,
};
