//! `cloth-sim max-realtime-grid`: the largest cloth a model steps in real time.

use super::config::{ScenarioConfig, ScenarioError, ScenarioName, build_design};
use super::report::Percentiles;
use crate::solver::ModelKind;

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
        let mut sim = build_design(&cfg)?;
        let mut ms = Vec::new();
        for _ in 0..frames {
            ms.push(sim.step()?.wall_ms);
        }
        // Skip the first frames (cold caches, first contacts).
        let p50 = Percentiles::of(&ms[ms.len() / 4..]).p50;
        log(grid, p50, sim.sim.substeps);
        tried.push((grid, p50));
        if p50 > cfg.frame_dt as f64 * 1e3 {
            break;
        }
    }
    Ok(tried)
}
