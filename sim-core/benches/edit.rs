//! Time of one operation (and of undo / redo) on the 16k-vertex cloth: a 128 x 128
//! grid draped on the mannequin for 120 frames. Targets: an operation <= 2 ms, undo and
//! redo <= 5 ms. Each measured call is undone (or redone) outside the timing, so every
//! sample sees the same cloth.

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use sim_core::cloth::Simulation;
use sim_core::edit::TearMode;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_simulation};

fn draped() -> Simulation {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeMannequin);
    cfg.grid = 128;
    cfg.threads = 1;
    let mut sim = build_simulation(&cfg).unwrap();
    for _ in 0..120 {
        sim.step().unwrap();
    }
    sim
}

/// Times `op` alone; `reset` (untimed) puts the cloth back after each call.
fn timed(
    s: &mut Simulation,
    iters: u64,
    mut op: impl FnMut(&mut Simulation),
    mut reset: impl FnMut(&mut Simulation),
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

fn ops(c: &mut Criterion) {
    let mut s = draped();
    let n = 128u32;
    let centre = n / 2 * (n + 1) + n / 2;
    let nb = s.cloth.live.neighbours(centre)[0];
    let p = s.cloth.x[centre as usize];
    let mut g = c.benchmark_group("edit-16k");
    g.sample_size(30);
    let undo = |s: &mut Simulation| {
        s.undo().unwrap();
    };
    g.bench_function("cut_vertex", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| {
                    s.cut_vertex(centre, Vec3::X).unwrap();
                },
                undo,
            )
        })
    });
    let stroke = [
        s.cloth.x[(centre - 10) as usize],
        s.cloth.x[(centre + 10) as usize],
    ];
    g.bench_function("cut_stroke_20_vertices", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| {
                    s.cut_stroke(&stroke, 0.01).unwrap();
                },
                undo,
            )
        })
    });
    g.bench_function("sew", |b| {
        b.iter_custom(|it| timed(&mut s, it, |s| s.sew(0, 2).unwrap(), undo))
    });
    g.bench_function("tear_delete", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| s.tear_edge(centre, nb, TearMode::Delete).unwrap(),
                undo,
            )
        })
    });
    g.bench_function("tear_split", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| s.tear_edge(centre, nb, TearMode::Split).unwrap(),
                undo,
            )
        })
    });
    g.bench_function("paint_2cm", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
                it,
                |s| s.paint(p, 0.02, [200, 20, 20, 255]).unwrap(),
                undo,
            )
        })
    });
    g.bench_function("pin", |b| {
        b.iter_custom(|it| timed(&mut s, it, |s| s.set_pin(centre, true).unwrap(), undo))
    });
    s.cut_stroke(&stroke, 0.01).unwrap();
    g.bench_function("undo_cut_stroke", |b| {
        b.iter_custom(|it| {
            timed(
                &mut s,
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
                &mut s,
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
    g.finish();
    // The frame after many edits: constraints added by edits are solved one by one.
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
    g.finish();
}

criterion_group!(benches, ops);
criterion_main!(benches);
