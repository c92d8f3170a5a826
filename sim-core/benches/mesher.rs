//! Meshing a pattern piece: a 1 m square and a 0.6 x 0.4 m ellipse at edge lengths that
//! give about 10,000 triangles (the garment issue's target: <= 50 ms).

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use criterion::{Criterion, criterion_group, criterion_main};
use sim_core::mesh::mesher::{Outline, mesh_outline};

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
}

criterion_group!(benches, mesher);
criterion_main!(benches);
