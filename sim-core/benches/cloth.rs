//! Frame time of the cloth models (all substeps plus collision), single-threaded, on the
//! issue's workloads: a 128 x 128 cloth draped on the mannequin (target p50 <= 8 ms) and
//! 256 x 256 (target p50 <= 33 ms), plus the paper's drape-cube and the seed model.
//! Each benchmark first drapes for 120 frames so it measures a cloth in contact.

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use criterion::{Criterion, criterion_group, criterion_main};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};
use sim_core::solver::ModelKind;

fn frame(
    c: &mut Criterion,
    name: &str,
    scenario: ScenarioName,
    grid: usize,
    model: ModelKind,
    threads: usize,
    stretch_limits: bool,
) {
    let mut cfg = ScenarioConfig::new(scenario);
    cfg.grid = grid;
    cfg.model = model;
    cfg.threads = threads;
    cfg.material.stretch_limits = stretch_limits;
    let mut sim = build_design(&cfg).unwrap();
    for _ in 0..120 {
        sim.step().unwrap();
    }
    let mut g = c.benchmark_group("frame");
    g.sample_size(30);
    g.bench_function(name, |b| b.iter(|| sim.step().unwrap()));
    g.finish();
}

fn frames(c: &mut Criterion) {
    frame(
        c,
        "xpbd_mannequin_128_1thread",
        ScenarioName::DrapeMannequin,
        128,
        ModelKind::Xpbd,
        1,
        true,
    );
    // What the stretch limits cost (and what a less stretched drape saves in contacts).
    frame(
        c,
        "xpbd_mannequin_128_1thread_no_stretch_limits",
        ScenarioName::DrapeMannequin,
        128,
        ModelKind::Xpbd,
        1,
        false,
    );
    frame(
        c,
        "xpbd_mannequin_128_2threads",
        ScenarioName::DrapeMannequin,
        128,
        ModelKind::Xpbd,
        2,
        true,
    );
    frame(
        c,
        "xpbd_mannequin_256_1thread",
        ScenarioName::DrapeMannequin,
        256,
        ModelKind::Xpbd,
        1,
        true,
    );
    frame(
        c,
        "xpbd_mannequin_256_2threads",
        ScenarioName::DrapeMannequin,
        256,
        ModelKind::Xpbd,
        2,
        true,
    );
    frame(
        c,
        "xpbd_cube_64_1thread",
        ScenarioName::DrapeCube,
        64,
        ModelKind::Xpbd,
        1,
        true,
    );
    frame(
        c,
        "seed_cube_64",
        ScenarioName::DrapeCube,
        64,
        ModelKind::Seed,
        1,
        true,
    );
}

criterion_group!(benches, frames);
criterion_main!(benches);
