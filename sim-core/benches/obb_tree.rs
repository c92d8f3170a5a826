//! OBB tree against parry3d's BVH (`TriMesh`, which queries through its `Bvh`) on the same
//! meshes and queries: build, nearest point within a distance, ray cast; scaling over
//! 1k-100k triangles; and the cloth-sized workload (16k particles near the mannequin).

#![allow(clippy::unwrap_used)] // benchmark setup: a failure should stop the run

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use parry3d::query::{PointQuery, Ray, RayCast};
use parry3d::shape::TriMesh;
use sim_core::collision::body::{Body, BodyKind};
use sim_core::collision::obb::{BuildOptions, ObbTree};

fn lcg(seed: &mut u64) -> f32 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 40) as f32 / (1u64 << 24) as f32
}

/// Points within `band` of the body's surface, on either side (or only outside, as cloth
/// particles in contact are).
fn points_near(body: &Body, n: usize, band: f32, outside_only: bool) -> Vec<Vec3> {
    let mut s = 7u64;
    (0..n)
        .map(|_| {
            let t = body.triangles
                [(lcg(&mut s) * body.triangles.len() as f32) as usize % body.triangles.len()];
            let [a, b, c] = t.map(|i| body.vertices[i as usize]);
            let (mut u, mut v) = (lcg(&mut s), lcg(&mut s));
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let p = a + (b - a) * u + (c - a) * v;
            let n = (b - a).cross(c - a).normalize();
            let r = lcg(&mut s);
            p + n * if outside_only {
                r * band
            } else {
                (r * 2.0 - 1.0) * band
            }
        })
        .collect()
}

fn mean_edge(b: &Body) -> f32 {
    let sum: f32 = b
        .triangles
        .iter()
        .map(|t| (b.vertices[t[0] as usize] - b.vertices[t[1] as usize]).length())
        .sum();
    sum / b.triangles.len() as f32
}

fn sphere(subdiv: usize) -> Body {
    sim_core::collision::body::sphere(Vec3::new(0.0, 0.3, 0.0), 0.3, subdiv).unwrap()
}

fn parry_mesh(b: &Body) -> TriMesh {
    TriMesh::new(b.vertices.clone(), b.triangles.clone()).unwrap()
}

fn scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("scaling");
    g.sample_size(10);
    // 1,280 to 327,680 triangles: the 1k-100k range and one step past it.
    for subdiv in [3usize, 4, 5, 6, 7] {
        let body = sphere(subdiv);
        let n = body.triangles.len();
        g.bench_with_input(BenchmarkId::new("build/obb", n), &body, |b, body| {
            b.iter(|| {
                ObbTree::build(
                    black_box(&body.vertices),
                    &body.triangles,
                    BuildOptions::default(),
                )
                .unwrap()
            })
        });
        g.bench_with_input(
            BenchmarkId::new("build/parry_trimesh", n),
            &body,
            |b, body| b.iter(|| parry_mesh(black_box(body))),
        );
        // Band and radius scale with the triangles, so the number of triangles a correct
        // answer must look at stays the same and only the tree's depth grows.
        let edge = mean_edge(&body);
        let pts = points_near(&body, 1000, 0.25 * edge, false);
        let radius = 2.0 * edge;
        let tree = body.tree();
        let pm = parry_mesh(&body);
        g.throughput(Throughput::Elements(pts.len() as u64));
        g.bench_with_input(BenchmarkId::new("nearest_1k/obb", n), &pts, |b, pts| {
            b.iter(|| pts.iter().filter_map(|&p| tree.nearest(p, radius)).count())
        });
        g.bench_with_input(BenchmarkId::new("nearest_1k/parry", n), &pts, |b, pts| {
            b.iter(|| {
                pts.iter()
                    .filter_map(|&p| pm.project_local_point_with_max_dist(p, false, radius))
                    .count()
            })
        });
        let mut s = 3u64;
        let rays: Vec<(Vec3, Vec3)> = (0..1000)
            .map(|_| {
                let o = Vec3::new(lcg(&mut s) - 0.5, lcg(&mut s) + 0.8, lcg(&mut s) - 0.5);
                let target = Vec3::new(
                    lcg(&mut s) * 0.4 - 0.2,
                    lcg(&mut s) * 0.6,
                    lcg(&mut s) * 0.4 - 0.2,
                );
                (o, (target - o).normalize())
            })
            .collect();
        g.bench_with_input(BenchmarkId::new("ray_1k/obb", n), &rays, |b, rays| {
            b.iter(|| {
                rays.iter()
                    .filter_map(|&(o, d)| tree.ray_cast(o, d, 10.0))
                    .count()
            })
        });
        g.bench_with_input(BenchmarkId::new("ray_1k/parry", n), &rays, |b, rays| {
            b.iter(|| {
                rays.iter()
                    .filter_map(|&(o, d)| pm.cast_local_ray(&Ray::new(o, d), 10.0, false))
                    .count()
            })
        });
        g.throughput(Throughput::Elements(1));
    }
    g.finish();
}

/// The per-frame collision workload of a 128 x 128 cloth on the mannequin: 16,641
/// particles within 1 cm of a ~10k-triangle body, radius 2 cm.
fn cloth_workload(c: &mut Criterion) {
    let body = BodyKind::Mannequin.build().unwrap();
    let pts = points_near(&body, 16_641, 0.01, false);
    let tree = body.tree();
    let pm = parry_mesh(&body);
    let hints: Vec<u32> = pts
        .iter()
        .map(|&p| tree.nearest(p, 1.0).map_or(u32::MAX, |h| h.tri))
        .collect();
    let mut g = c.benchmark_group(format!(
        "mannequin_{}tris_16k_particles",
        body.triangles.len()
    ));
    g.sample_size(20);
    g.bench_function("obb_cold", |b| {
        b.iter(|| pts.iter().filter_map(|&p| tree.nearest(p, 0.02)).count())
    });
    g.bench_function("obb_hinted", |b| {
        b.iter(|| {
            pts.iter()
                .zip(&hints)
                .filter_map(|(&p, &h)| tree.nearest_with_hint(p, 0.02, Some(h)))
                .count()
        })
    });
    // The simulation's search: the surface walk from the hint, the tree when it cannot
    // prove the answer (it never proves a point inside the body: half of these).
    g.bench_function("walk_from_hint", |b| {
        b.iter(|| {
            pts.iter()
                .zip(&hints)
                .filter_map(|(&p, &h)| body.contact_near(p, 0.02, h).0)
                .count()
        })
    });
    // Only outside, as cloth particles are: the tree and the walk on the same points.
    let outside = points_near(&body, 16_641, 0.01, true);
    let outside_hints: Vec<u32> = outside
        .iter()
        .map(|&p| tree.nearest(p, 1.0).map_or(u32::MAX, |h| h.tri))
        .collect();
    g.bench_function("outside_obb_hinted", |b| {
        b.iter(|| {
            outside
                .iter()
                .zip(&outside_hints)
                .filter_map(|(&p, &h)| tree.nearest_with_hint(p, 0.02, Some(h)))
                .count()
        })
    });
    g.bench_function("outside_walk_from_hint", |b| {
        b.iter(|| {
            outside
                .iter()
                .zip(&outside_hints)
                .filter_map(|(&p, &h)| body.contact_near(p, 0.02, h).0)
                .count()
        })
    });
    let dist = vec![0.02f32; pts.len()];
    let mut out = vec![None; pts.len()];
    g.bench_function("obb_hinted_2_threads", |b| {
        b.iter(|| tree.nearest_batch(&pts, &dist, &hints, &mut out, 2))
    });
    g.bench_function("parry", |b| {
        b.iter(|| {
            pts.iter()
                .filter_map(|&p| pm.project_local_point_with_max_dist(p, false, 0.02))
                .count()
        })
    });
    g.finish();
}

criterion_group!(benches, cloth_workload, scaling);
criterion_main!(benches);
