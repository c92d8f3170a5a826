//! Property tests: every query equals a brute-force answer on random meshes and points.

use glam::{Mat3, Quat, Vec3};
use proptest::prelude::*;

use super::geometry::{Obb, closest_point_on_triangle, ray_triangle};
use super::tree::{BuildOptions, ObbTree};
use super::walk::SurfaceWalk;

fn vec3(r: f32) -> impl Strategy<Value = Vec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A random triangle soup: `n` triangles with corners near random centres, so the tree
/// sees clusters, slivers and overlaps.
fn soup() -> impl Strategy<Value = (Vec<Vec3>, Vec<[u32; 3]>)> {
    prop::collection::vec((vec3(1.0), vec3(0.2), vec3(0.2), vec3(0.2)), 1..120).prop_map(|tris| {
        let mut v = Vec::new();
        let mut idx = Vec::new();
        for (c, a, b, d) in tris {
            let base = v.len() as u32;
            v.extend([c + a, c + b, c + d]);
            idx.push([base, base + 1, base + 2]);
        }
        (v, idx)
    })
}

fn brute_nearest(v: &[Vec3], idx: &[[u32; 3]], p: Vec3) -> f32 {
    idx.iter()
        .map(|t| {
            let (q, _) =
                closest_point_on_triangle(p, v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
            (q - p).length()
        })
        .fold(f32::INFINITY, f32::min)
}

/// A closed surface with dents and bumps: a unit icosphere (162 vertices, 320
/// triangles) with each vertex moved in or out by up to 15%, so it has reflex edges,
/// concave pits and creases.
fn bumpy_sphere() -> impl Strategy<Value = (Vec<Vec3>, Vec<[u32; 3]>)> {
    bumpy_icosphere(2, 1.0)
}

/// The same at the body's scale: a 15 cm icosphere of 1,280 triangles (2.3 cm edges)
/// with bumps of up to 2.2 cm, so a face has more rising triangles within the walk's
/// gathering radius than it lists, and the bounds on the rest decide the proofs.
fn fine_bumpy_sphere() -> impl Strategy<Value = (Vec<Vec3>, Vec<[u32; 3]>)> {
    bumpy_icosphere(3, 0.15)
}

fn bumpy_icosphere(
    subdivisions: usize,
    radius: f32,
) -> impl Strategy<Value = (Vec<Vec3>, Vec<[u32; 3]>)> {
    let (v, t) = crate::collision::body::icosphere(subdivisions);
    prop::collection::vec(-0.15f32..0.15, v.len()).prop_map(move |bumps| {
        let v = v
            .iter()
            .zip(&bumps)
            .map(|(p, b)| *p * radius * (1.0 + b))
            .collect();
        (v, t.clone())
    })
}

/// Checks every answer the walk proves against brute force, and every bound it gives
/// when it does not; returns how many it proved. Also checks a walk that lists no
/// rising triangle, which leaves them all to the bounds.
fn check_walk(
    v: &[Vec3],
    idx: &[[u32; 3]],
    queries: &[(Vec3, u32)],
) -> Result<usize, TestCaseError> {
    let tree = ObbTree::build(v, idx, BuildOptions::default()).unwrap();
    check_walk_with(
        v,
        idx,
        queries,
        &SurfaceWalk::with_near_lists(&tree, 0),
        &tree,
    )?;
    check_walk_with(v, idx, queries, &SurfaceWalk::new(&tree), &tree)
}

fn check_walk_with(
    v: &[Vec3],
    idx: &[[u32; 3]],
    queries: &[(Vec3, u32)],
    walk: &SurfaceWalk,
    tree: &ObbTree,
) -> Result<usize, TestCaseError> {
    let mut proved = 0;
    for &(p, start) in queries {
        let want = brute_nearest(v, idx, p);
        let hit = match walk.nearest(tree, p, start % idx.len() as u32) {
            Ok(hit) => hit,
            // Unproved, its bound still holds: nothing nearer.
            Err(miss) => {
                prop_assert!(
                    want >= miss.clear - 1e-5 * (1.0 + want),
                    "surface at {} within the walk's clearance {}",
                    want,
                    miss.clear
                );
                continue;
            }
        };
        proved += 1;
        prop_assert!(
            (hit.distance - want).abs() <= 1e-5 * (1.0 + want),
            "walk {} brute {} at {}",
            hit.distance,
            want,
            p
        );
        let t = idx[hit.tri as usize];
        let (q, _) =
            closest_point_on_triangle(p, v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
        prop_assert!((q - hit.point).length() <= 1e-5);
    }
    Ok(proved)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn walk_answers_equal_brute_force_on_bumpy_spheres((v, idx) in bumpy_sphere(), queries in prop::collection::vec((vec3(1.4), 0u32..320), 1..40)) {
        check_walk(&v, &idx, &queries)?;
    }

    #[test]
    fn walk_answers_equal_brute_force_on_fine_bumpy_spheres(
        (v, idx) in fine_bumpy_sphere(),
        near in prop::collection::vec((0usize..1280, 0.0f32..1.0, 0.0f32..1.0, -0.01f32..0.04), 1..60),
        corners in prop::collection::vec((0usize..1280, 0.0f32..0.04, vec3(0.004)), 0..40),
    ) {
        // Points up to 4 cm off random surface points, as cloth particles are, the walk
        // starting from the triangle under them (or beside them).
        let queries: Vec<(Vec3, u32)> = near
            .iter()
            .map(|&(t, a, b, h)| {
                let [p0, p1, p2] = idx[t].map(|i| v[i as usize]);
                let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                let n = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                (p0 + (p1 - p0) * a + (p2 - p0) * b + n * h, t as u32)
            })
            // And points off its corners, out along the corner's radius and a few mm
            // aside: some in the corner's normal cone, some beside it.
            .chain(corners.iter().map(|&(t, h, aside)| {
                let corner = v[idx[t][0] as usize];
                (corner + corner.normalize_or_zero() * h + aside, t as u32)
            }))
            .collect();
        check_walk(&v, &idx, &queries)?;
    }

    #[test]
    fn walk_answers_equal_brute_force_on_soups((v, idx) in soup(), queries in prop::collection::vec((vec3(1.5), 0u32..120), 1..20)) {
        check_walk(&v, &idx, &queries)?;
    }

    #[test]
    fn tree_is_valid((v, idx) in soup(), leaf in 1usize..6) {
        let tree = ObbTree::build(&v, &idx, BuildOptions { max_leaf_triangles: leaf }).unwrap();
        prop_assert_eq!(tree.validate(), Ok(()));
        prop_assert_eq!(tree.triangle_count(), idx.len());
    }

    #[test]
    fn nearest_equals_brute_force((v, idx) in soup(), pts in prop::collection::vec(vec3(1.5), 1..20), max_d in 0.05f32..3.0) {
        let tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
        for p in pts {
            let want = brute_nearest(&v, &idx, p);
            match tree.nearest(p, max_d) {
                Some(hit) => {
                    prop_assert!((hit.distance - want).abs() <= 1e-5 * (1.0 + want), "tree {} brute {}", hit.distance, want);
                    prop_assert!(hit.distance <= max_d * (1.0 + 1e-6));
                    let t = idx[hit.tri as usize];
                    let (q, _) = closest_point_on_triangle(p, v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
                    prop_assert!((q - hit.point).length() <= 1e-5);
                }
                None => prop_assert!(want > max_d * (1.0 - 1e-6), "missed a triangle at {} within {}", want, max_d),
            }
            // A hint never changes the answer.
            let hinted = tree.nearest_with_hint(p, max_d, Some((idx.len() as u32) / 2));
            prop_assert_eq!(hinted.map(|h| (h.distance * 1e4).round()), tree.nearest(p, max_d).map(|h| (h.distance * 1e4).round()));
        }
    }

    #[test]
    fn ray_equals_brute_force((v, idx) in soup(), o in vec3(2.0), d in vec3(1.0)) {
        prop_assume!(d.length() > 1e-3);
        let tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
        let want = idx.iter().filter_map(|t| ray_triangle(o, d, v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]))
            .fold(f32::INFINITY, f32::min);
        match tree.ray_cast(o, d, 100.0) {
            Some(hit) => prop_assert!((hit.t - want).abs() <= 1e-4 * (1.0 + want), "tree {} brute {}", hit.t, want),
            None => prop_assert!(want > 100.0, "missed a hit at t = {}", want),
        }
    }

    #[test]
    fn box_overlap_equals_brute_force((v, idx) in soup(), c in vec3(1.0), h in vec3(0.6), axis in vec3(1.0), angle in 0.0f32..3.0) {
        prop_assume!(axis.length() > 1e-3);
        let tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
        let q = Obb { center: c, axes: Mat3::from_quat(Quat::from_axis_angle(axis.normalize(), angle)), half: h.abs() + Vec3::splat(0.01) };
        let mut got = Vec::new();
        tree.overlap_box(&q, &mut got);
        got.sort_unstable();
        let want: Vec<u32> = (0..idx.len() as u32)
            .filter(|&t| { let t = idx[t as usize]; q.overlaps_triangle(v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]) })
            .collect();
        prop_assert_eq!(got, want);
    }

    #[test]
    fn refit_matches_rebuild_answers((v, idx) in soup(), shift in vec3(0.3), p in vec3(1.5)) {
        let mut tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
        let moved: Vec<Vec3> = v.iter().enumerate().map(|(i, x)| *x + shift * ((i % 7) as f32 / 7.0)).collect();
        tree.refit(&moved).unwrap();
        prop_assert_eq!(tree.validate(), Ok(()));
        let want = brute_nearest(&moved, &idx, p);
        let got = tree.nearest(p, 10.0).map(|h| h.distance).unwrap_or(f32::INFINITY);
        prop_assert!((got - want).abs() <= 1e-5 * (1.0 + want));
    }
}

#[test]
fn box_query_uses_the_triangle_test_not_just_boxes() {
    // One triangle whose leaf box overlaps the query box but whose plane does not.
    let v = vec![
        Vec3::new(2.5, 0.0, 0.0),
        Vec3::new(0.0, 2.5, 0.0),
        Vec3::new(2.5, 0.0, 5.0),
    ];
    let tree = ObbTree::build(&v, &[[0, 1, 2]], BuildOptions::default()).unwrap();
    let mut out = Vec::new();
    tree.overlap_box(&Obb::aabb(Vec3::splat(-1.0), Vec3::splat(1.0)), &mut out);
    assert!(out.is_empty());
}

#[test]
fn bad_meshes_are_rejected() {
    assert!(ObbTree::build(&[Vec3::ZERO], &[], BuildOptions::default()).is_err());
    assert!(
        ObbTree::build(
            &[Vec3::ZERO, Vec3::X],
            &[[0, 1, 2]],
            BuildOptions::default()
        )
        .is_err()
    );
    assert!(
        ObbTree::build(
            &[Vec3::ZERO, Vec3::X, Vec3::NAN],
            &[[0, 1, 2]],
            BuildOptions::default()
        )
        .is_err()
    );
}

#[test]
fn query_work_grows_like_log_n() {
    // Icospheres from 1,280 to 327,680 triangles (the 1k-100k and a step past); points within a quarter edge of the
    // surface, radius two edges, so the answer's neighbourhood has the same number of
    // triangles at every size and only the depth grows.
    let mut mean_visits = Vec::new();
    for subdiv in [3usize, 4, 5, 6, 7] {
        // The unit icosphere's mesh, without a body's other precomputation.
        let (vertices, triangles) = crate::collision::body::icosphere(subdiv);
        let tree = &ObbTree::build(&vertices, &triangles, BuildOptions::default()).unwrap();
        let t0 = triangles[0];
        let edge = (vertices[t0[0] as usize] - vertices[t0[1] as usize]).length();
        let mut visits = 0usize;
        let mut s = 11u64;
        let n = 2000;
        for _ in 0..n {
            let mut r = || {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
            };
            let dir = Vec3::new(r(), r(), r()).normalize_or(Vec3::Y);
            let p = dir * (1.0 + 0.25 * edge * r());
            assert!(
                tree.nearest_counted(p, 2.0 * edge, None, &mut visits)
                    .is_some()
            );
        }
        mean_visits.push((triangles.len(), visits as f64 / n as f64));
    }
    eprintln!("triangles, mean nodes visited per nearest query: {mean_visits:?}");
    let (n0, v0) = mean_visits[0];
    let (n3, v3) = mean_visits[4];
    // 256x the triangles: log2 grows by a factor 1.8 (10.3 -> 18.3); linear would be 256x.
    let log_ratio = (n3 as f64).log2() / (n0 as f64).log2();
    assert!(
        v3 / v0 < 1.5 * log_ratio,
        "visits grew {v0} -> {v3}, more than logarithmically"
    );
}

#[test]
fn depth_is_logarithmic_on_a_big_grid() {
    let n = 100;
    let mut v = Vec::new();
    let mut idx = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            v.push(Vec3::new(i as f32, (i as f32 * 0.3).sin(), j as f32));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = (j * (n + 1) + i) as u32;
            idx.push([a, a + 1, a + n as u32 + 1]);
            idx.push([a + 1, a + n as u32 + 2, a + n as u32 + 1]);
        }
    }
    let tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
    tree.validate().unwrap();
    // 20k triangles in leaves of <= 4: a balanced tree is ~13 deep.
    assert!(tree.depth() <= 20, "depth {}", tree.depth());
}

#[test]
fn the_walk_proves_almost_every_query_near_a_convex_body() {
    // A convex body: no face rises above another's plane, so nothing but the walk's own
    // triangle needs testing, and only corner regions and steps run out are left to the
    // tree.
    let (v, idx) = crate::collision::body::icosphere(3);
    let v: Vec<Vec3> = v.iter().map(|p| *p * 0.2).collect();
    let tree = ObbTree::build(&v, &idx, BuildOptions::default()).unwrap();
    let walk = SurfaceWalk::new(&tree);
    assert_eq!(walk.concave_count(), 0);
    let mut s = 5u64;
    let mut r = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut queries = Vec::new();
    for _ in 0..2000 {
        let dir = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5).normalize_or(Vec3::Y);
        let p = dir * (0.2 + 0.001 + 0.02 * r());
        // Last frame's triangle: the nearest from 1 cm away.
        let side = dir.any_orthonormal_vector() * 0.01;
        let start = tree.nearest(p + side, 1.0).unwrap().tri;
        queries.push((p, start));
    }
    let proved = check_walk(&v, &idx, &queries).unwrap();
    assert!(proved >= 1800, "proved only {proved} of 2000");
}

#[test]
fn the_walk_refuses_a_point_under_a_dent() {
    // A 20 cm square of two triangles with a narrow spike rising 5 cm from behind its
    // centre: a point above the square's middle is nearest the spike, which is far from
    // the walk's triangle across the plane. Either the spike is listed with the square's
    // triangles or the clearance refuses the proof; never the square's own point.
    let v = vec![
        Vec3::new(-0.1, 0.0, -0.1),
        Vec3::new(0.1, 0.0, -0.1),
        Vec3::new(0.1, 0.0, 0.1),
        Vec3::new(-0.1, 0.0, 0.1),
        Vec3::new(0.0, 0.05, 0.0),
        Vec3::new(0.002, -0.01, 0.0),
        Vec3::new(-0.002, -0.01, 0.001),
    ];
    let idx = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6]];
    let p = Vec3::new(0.02, 0.03, 0.01);
    let queries: Vec<(Vec3, u32)> = (0..3).map(|t| (p, t)).collect();
    check_walk(&v, &idx, &queries).unwrap();
}

#[test]
fn the_walk_skips_a_wall_beside_the_face_only_where_the_face_is_nearer() {
    // A 10 cm square with a wall beside it, 2 cm past its edge: upright and 1 or 3 cm
    // high, or leaning over the square. Over the square's edge the face is the nearest
    // only up to where the wall comes nearer (2.5 cm for the low wall, 2 cm for the high
    // one): the heights up to which the walk skips the wall are tight there, and are
    // checked on a dense set of points against brute force.
    let square = [
        Vec3::new(-0.05, 0.0, -0.05),
        Vec3::new(0.05, 0.0, -0.05),
        Vec3::new(0.05, 0.0, 0.05),
        Vec3::new(-0.05, 0.0, 0.05),
    ];
    for top in [0.01, 0.03]
        .map(|y| Vec3::new(0.07, y, 0.0))
        .into_iter()
        .chain([Vec3::new(0.055, 0.03, 0.0)])
    {
        let mut v = square.to_vec();
        let (z0, z1) = (Vec3::new(0.0, 0.0, -0.08), Vec3::new(0.0, 0.0, 0.08));
        let foot = Vec3::new(0.07, -0.01, 0.0);
        v.extend([foot + z0, foot + z1, top + z1, top + z0]);
        let idx = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]];
        let mut queries = Vec::new();
        for x in [0.0, 0.03, 0.045, 0.049] {
            for k in 1..60 {
                let p = Vec3::new(x, 0.001 * k as f32, 0.003);
                // Start on the square's triangle under the point.
                let start = if p.x > p.z { 0 } else { 1 };
                queries.push((p, start));
            }
        }
        let proved = check_walk(&v, &idx, &queries).unwrap();
        assert!(proved > 0, "proved nothing");
    }
}
