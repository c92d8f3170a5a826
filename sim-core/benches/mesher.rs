//! Meshing a pattern piece: a 1 m square and a 0.6 x 0.4 m ellipse at edge lengths that
//! give about 10,000 triangles (the garment issue's target: <= 50 ms); and adding such a
//! piece to the dress on the mannequin (meshing, placing a layer out until it crosses
//! nothing, the undoable edit; the undo after each is not timed); the pattern out, and
//! the pattern view's lines cloth-sim sends the studio.

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use criterion::{Criterion, criterion_group, criterion_main};
use sim_core::design::garment::{PieceSpec, Place};
use sim_core::mesh::mesher::{Outline, mesh_outline};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

fn mesher(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesher");
    g.sample_size(20);
    let square = Outline::rectangle(1.0, 1.0);
    let n = mesh_outline(&square, 0.015).unwrap().triangles.len();
    g.bench_function(format!("square 1 m, edge 15 mm ({n} triangles)"), |b| {
        b.iter(|| mesh_outline(&square, 0.015).unwrap())
    });
    let ellipse = Outline::ellipse(0.6, 0.4, 0.011);
    let n = mesh_outline(&ellipse, 0.011).unwrap().triangles.len();
    g.bench_function(
        format!("ellipse 0.6 x 0.4 m, edge 11 mm ({n} triangles)"),
        |b| b.iter(|| mesh_outline(&ellipse, 0.011).unwrap()),
    );
    g.finish();
    let mut g = c.benchmark_group("add piece");
    g.sample_size(10);
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.03;
    let mut d = build_design(&cfg).unwrap();
    let piece = PieceSpec {
        name: "panel".into(),
        outline: Outline::rectangle(0.45, 0.7),
        fabric: "cotton".into(),
        grain: 0.0,
        placement: None,
        start: None,
        fallback: None,
    };
    let n = d.add_piece(&piece, Place::Back, 0.0105).unwrap();
    let tris = d.piece_list().last().unwrap().triangles;
    d.undo().unwrap();
    g.bench_function(
        format!("0.45 x 0.7 m, edge 10.5 mm ({tris} triangles, {n} vertices) to the dress"),
        |b| {
            // The add alone is timed; each undo after it is not.
            b.iter_custom(|iters| {
                let mut spent = std::time::Duration::ZERO;
                for _ in 0..iters {
                    let t = std::time::Instant::now();
                    d.add_piece(&piece, Place::Back, 0.0105).unwrap();
                    spent += t.elapsed();
                    d.undo().unwrap();
                }
                spent
            })
        },
    );
    g.finish();
    // The dress's pattern out (pieces, seams, allowance; SVG and DXF written).
    let mut g = c.benchmark_group("export pattern");
    g.sample_size(10);
    let dir = std::env::temp_dir().join(format!("saiho-bench-pattern-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    g.bench_function("the dress, 10 mm allowance, SVG and DXF", |b| {
        b.iter(|| sim_core::design::sewing_pattern::export_pattern(&d, &dir, 10.0).unwrap())
    });
    // What cloth-sim computes for the studio's pattern view whenever the pieces or the
    // seams change (outlines, seams, notches and grain lines, nothing written).
    g.bench_function("the dress, pattern view lines", |b| {
        b.iter(|| sim_core::design::sewing_pattern::view_pieces(&d))
    });
    let mut square = ScenarioConfig::new(ScenarioName::DrapeMannequin);
    square.grid = 128;
    let square = build_design(&square).unwrap();
    g.bench_function("128 x 128 square, piece list", |b| {
        b.iter(|| square.piece_list())
    });
    g.bench_function("128 x 128 square, pattern view lines", |b| {
        b.iter(|| sim_core::design::sewing_pattern::view_pieces(&square))
    });
    g.bench_function("128 x 128 square, piece list and view (as sent)", |b| {
        b.iter(|| square.piece_list_and_view())
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, mesher);
criterion_main!(benches);
