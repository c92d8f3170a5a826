//! Time of one operation (and of undo / redo) on the 16k-vertex cloth: a 128 x 128
//! grid draped on the mannequin for 120 frames. Targets: an operation <= 2 ms, undo and
//! redo <= 5 ms. Each measured call is undone (or redone) outside the timing, so every
//! sample sees the same cloth.

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use sim_core::design::Design;
use sim_core::design::TearMode;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

fn draped() -> Design {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeMannequin);
    cfg.grid = 128;
    cfg.threads = 1;
    let mut sim = build_design(&cfg).unwrap();
    for _ in 0..120 {
        sim.step().unwrap();
    }
    sim
}

/// Times `op` alone; `reset` (untimed) puts the cloth back after each call.
fn timed(
    s: &mut Design,
    iters: u64,
    mut op: impl FnMut(&mut Design),
    mut reset: impl FnMut(&mut Design),
) -> Duration {
    let mut total = Duration::ZERO;
    for _ in 0..iters {
        let t = Instant::now();
        op(s);
        total += t.elapsed();
        reset(s);
    }
    total
}

/// Benchmarks `op` on `s`, undone after each run (the undo is not timed).
fn undoable(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    s: &mut Design,
    name: &str,
    op: impl Fn(&mut Design),
) {
    g.bench_function(name, |b| {
        b.iter_custom(|it| {
            timed(s, it, &op, |s| {
                s.undo().unwrap();
            })
        })
    });
}

fn ops(c: &mut Criterion) {
    let mut s = draped();
    let n = 128u32;
    let centre = n / 2 * (n + 1) + n / 2;
    let nb = s.sim.cloth.live.neighbours(centre)[0];
    let p = s.sim.cloth.x[centre as usize];
    // Along the cloth (as the pen draws it) through 20 cells of a row, not the chord
    // between its ends through the air.
    let stroke: Vec<Vec3> = (centre - 10..=centre + 10)
        .map(|v| s.sim.cloth.x[v as usize])
        .collect();
    let mut g = c.benchmark_group("edit-16k");
    g.sample_size(30);
    undoable(&mut g, &mut s, "cut_vertex", |s| {
        s.cut_vertex(centre, Vec3::X).unwrap();
    });
    undoable(&mut g, &mut s, "cut_stroke_20_vertices", |s| {
        s.cut_stroke(&stroke, 0.01).unwrap();
    });
    undoable(&mut g, &mut s, "sew", |s| s.sew(0, 2).unwrap());
    undoable(&mut g, &mut s, "tear_delete", |s| {
        s.tear_edge(centre, nb, TearMode::Delete).unwrap()
    });
    undoable(&mut g, &mut s, "tear_split", |s| {
        s.tear_edge(centre, nb, TearMode::Split).unwrap()
    });
    undoable(&mut g, &mut s, "paint_2cm", |s| {
        s.paint(p, 0.02, [200, 20, 20, 255]).unwrap()
    });
    undoable(&mut g, &mut s, "pin", |s| s.set_pin(centre, true).unwrap());
    undo_redo(&mut g, &mut s, &stroke);
    g.finish();
    frame_after_edits(c, centre);
}

/// Undo and redo of a cut stroke.
fn undo_redo(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    s: &mut Design,
    stroke: &[Vec3],
) {
    s.cut_stroke(stroke, 0.01).unwrap();
    g.bench_function("undo_cut_stroke", |b| {
        b.iter_custom(|it| {
            timed(
                s,
                it,
                |s| {
                    s.undo().unwrap();
                },
                |s| {
                    s.redo().unwrap();
                },
            )
        })
    });
    g.bench_function("redo_cut_stroke", |b| {
        b.iter_custom(|it| {
            s.undo().unwrap();
            let d = timed(
                s,
                it,
                |s| {
                    s.redo().unwrap();
                },
                |s| {
                    s.undo().unwrap();
                },
            );
            s.redo().unwrap();
            d
        })
    });
}

/// The frame after many edits: constraints added by edits are solved one by one.
fn frame_after_edits(c: &mut Criterion, centre: u32) {
    let mut g = c.benchmark_group("frame-after-edits");
    g.sample_size(20);
    let mut t = draped();
    for k in 0..20u32 {
        let v = centre - 40 + 4 * k;
        let _ = t.cut_vertex(v, Vec3::X);
    }
    g.bench_function("mannequin_128_after_20_cuts", |b| {
        b.iter(|| t.step().unwrap())
    });
    // The frame right after an edit, beside any frame: the guard's pairs follow the
    // edit (only the edited vertices' searched again) instead of a search of the whole
    // cloth.
    let mut s = draped();
    g.bench_function("mannequin_128_a_frame", |b| b.iter(|| s.step().unwrap()));
    g.bench_function("mannequin_128_a_cut_and_the_frame_after", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| {
                    s.cut_vertex(centre, Vec3::X).unwrap();
                    s.step().unwrap();
                },
                |s| {
                    s.undo().unwrap();
                    s.step().unwrap();
                },
            )
        })
    });
    g.finish();
}

criterion_group!(benches, ops);
criterion_main!(benches);
