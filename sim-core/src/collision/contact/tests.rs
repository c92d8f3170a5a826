use glam::Vec3;

use super::*;
use crate::collision::body::{Body, sphere};

const DT: f32 = 1.0 / 60.0;

fn params() -> ContactParams {
    ContactParams {
        thickness: 0.004,
        friction: 0.0,
        floor: None,
    }
}

/// Particles on a ring around a 0.2 m sphere, `height` from its surface, moving
/// tangentially at `speed`.
fn ring(n: usize, height: f32, speed: f32) -> (Vec<Vec3>, Vec<Vec3>) {
    (0..n)
        .map(|i| {
            let a = i as f32 / n as f32 * std::f32::consts::TAU;
            let dir = Vec3::new(a.cos(), 0.3, a.sin()).normalize();
            let tangent = Vec3::Y.cross(dir).normalize();
            (dir * (0.2 + height), tangent * speed)
        })
        .unzip()
}

/// A 0.2 m sphere, a ring of particles around it (see [`ring`]) and their cache after
/// one broad phase.
struct Ring {
    body: Body,
    p: ContactParams,
    x: Vec<Vec3>,
    v: Vec<Vec3>,
    inv_mass: Vec<f32>,
    cache: ContactCache,
}

fn ring_on_sphere(n: usize, height: f32, speed: f32) -> Ring {
    let body = sphere(Vec3::ZERO, 0.2, 3).unwrap();
    let p = params();
    let (x, v) = ring(n, height, speed);
    let mut cache = ContactCache::new(x.len());
    cache.update(&body, &x, &v, DT, 9.81, &p);
    Ring {
        inv_mass: vec![1.0; x.len()],
        body,
        p,
        x,
        v,
        cache,
    }
}

/// Every particle has a plane, at the gap a cache searching from scratch finds.
fn assert_planes_of_a_fresh_cache(
    cache: &ContactCache,
    body: &Body,
    x: &[Vec3],
    v: &[Vec3],
    p: &ContactParams,
) {
    let mut fresh = ContactCache::new(x.len());
    fresh.update(body, x, v, DT, 9.81, p);
    for (i, &xi) in x.iter().enumerate() {
        let (a, b) = (cache.gap(i, xi, 0.0), fresh.gap(i, xi, 0.0));
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!((a - b).abs() < 1e-6, "{a} {b}");
    }
}

#[test]
fn the_frame_end_search_is_kept_for_the_next_update() {
    let Ring {
        body,
        p,
        mut x,
        mut v,
        inv_mass,
        mut cache,
    } = ring_on_sphere(64, 0.005, 0.5);
    assert_eq!(cache.last_queries, x.len());
    assert_eq!(cache.active_count(), x.len());
    // The frame moves every particle 8 mm along the surface: more than its clearance.
    for (x, v) in x.iter_mut().zip(&v) {
        *x = (*x + *v * DT).normalize() * 0.205;
    }
    let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
    assert_eq!(moved, 0);
    // The next frame's update finds them where the check searched: no new search, and
    // the same planes it would have found.
    cache.update(&body, &x, &v, DT, 9.81, &p);
    assert_eq!(cache.last_queries, 0);
    assert_eq!(cache.active_count(), x.len());
    assert_planes_of_a_fresh_cache(&cache, &body, &x, &v, &p);
}

#[test]
fn a_particle_found_inside_at_frame_end_is_moved_out_and_searched_again_next_frame() {
    let Ring {
        body,
        p,
        mut x,
        mut v,
        inv_mass,
        mut cache,
    } = ring_on_sphere(8, 0.005, 0.0);
    // Dragged 3 cm into the sphere and moving inward.
    x[0] *= 0.835;
    v[0] = -x[0];
    let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
    assert_eq!(moved, 1);
    let r = x[0].length();
    assert!((r - 0.204).abs() < 2e-3, "moved out to {r}");
    // The inward 0.17 m/s is gone (up to the facet's tilt from the radius).
    let inward = -v[0].dot(x[0].normalize());
    assert!(inward < 0.02, "inward velocity left: {inward}");
    cache.update(&body, &x, &v, DT, 9.81, &p);
    assert_eq!(cache.last_queries, 1);
}

#[test]
fn a_particle_teleported_deep_inside_is_still_found_inside() {
    // Searched 5 mm outside, then (an edit, a grab) 12 cm inside a 0.2 m sphere at
    // rest: deeper than the search radius, so the bounded search finds nothing. It
    // moved farther than its clearance plus the radius, so the unbounded search runs
    // and the frame-end check moves it out.
    let Ring {
        body,
        p,
        mut x,
        mut v,
        inv_mass,
        mut cache,
    } = ring_on_sphere(4, 0.005, 0.0);
    x[0] = x[0].normalize() * 0.08;
    let moved = cache.resolve_penetrations(&body, &mut x, &mut v, &inv_mass, DT, 9.81, &p);
    assert_eq!(moved, 1);
    assert!(
        (x[0].length() - 0.204).abs() < 2e-3,
        "moved out to {}",
        x[0].length()
    );
}

#[test]
fn sliding_particles_get_the_planes_a_fresh_tree_search_gives() {
    // Particles sliding 8 mm a frame along a sphere, 5 mm above it: after the first
    // frame every search starts from last frame's triangle (the walk answers them),
    // and the planes are the ones an unhinted tree search gives.
    let Ring {
        body,
        p,
        mut x,
        v,
        mut cache,
        ..
    } = ring_on_sphere(64, 0.005, 0.5);
    for _ in 0..5 {
        cache.update(&body, &x, &v, DT, 9.81, &p);
        for (i, &xi) in x.iter().enumerate() {
            let tree = body.contact(xi, 1.0, u32::MAX).unwrap();
            let gap = cache.gap(i, xi, 0.0).unwrap();
            assert!((gap - tree.signed_distance).abs() < 1e-5, "{gap} {tree:?}");
        }
        for (x, v) in x.iter_mut().zip(&v) {
            *x = (*x + *v * DT).normalize() * 0.205;
        }
    }
    let (_, start) = body.contact_near(x[0], 0.1, cache.hint[0]);
    assert_ne!(start, u32::MAX);
}

#[test]
fn particles_the_body_grid_proves_out_of_reach_are_not_searched_until_near() {
    // 8 cm off the sphere, falling toward it at 1 m/s: they could travel ~2.7 cm this
    // frame, and the body's clearance grid proves them farther than that.
    let Ring {
        body,
        p,
        mut x,
        mut v,
        cache: mut far,
        ..
    } = ring_on_sphere(64, 0.08, 0.0);
    for (x, v) in x.iter().zip(v.iter_mut()) {
        *v = -x.normalize();
    }
    far.update(&body, &x, &v, DT, 9.81, &p);
    assert_eq!(far.last_queries, 0);
    assert_eq!(far.active_count(), 0);
    // Within reach a frame later: searched, and given the planes a fresh cache gives.
    for x in x.iter_mut() {
        *x = x.normalize() * 0.21;
    }
    far.update(&body, &x, &v, DT, 9.81, &p);
    assert_eq!(far.last_queries, x.len());
    assert_eq!(far.active_count(), x.len());
    assert_planes_of_a_fresh_cache(&far, &body, &x, &v, &p);
}

#[test]
fn static_friction_left_by_the_push_holds_later_moves_until_used_up() {
    // Particles 1 mm above the floor's contact layer, the body far away.
    let body = sphere(Vec3::new(0.0, 5.0, 0.0), 0.2, 2).unwrap();
    let p = ContactParams {
        thickness: 0.004,
        friction: 0.4,
        floor: Some(0.0),
    };
    let mut x: Vec<Vec3> = (0..4)
        .map(|i| Vec3::new(0.1 * i as f32, 0.005, 0.0))
        .collect();
    let (v, inv_mass) = (vec![Vec3::ZERO; 4], vec![1.0; 4]);
    let mut cache = ContactCache::new(x.len());
    cache.update(&body, &x, &v, DT, 9.81, &p);
    let mut prev = x.clone();
    // Particle 0 pressed 2 mm into the layer while sliding 0.3 mm: held (the cone is
    // 0.8 mm), with 0.5 mm left. Particle 1 slides 1 mm: past the cone, none left.
    x[0] += Vec3::new(0.0003, -0.003, 0.0);
    x[1] += Vec3::new(0.001, -0.003, 0.0);
    let mut spare = StaticFriction::default();
    cache.project_keeping(&mut x, &mut prev, &inv_mass, &p, Some(&mut spare));
    assert!((x[0] - prev[0]).x.abs() < 1e-7, "held by the push");
    assert!(
        ((x[1] - prev[1]).x - 0.0002).abs() < 1e-6,
        "slides past the cone"
    );
    // Later moves of 0.3 mm along the floor: the first held whole, the second by the
    // 0.2 mm left, the third not at all; particle 1's and 2's (nothing pushed it) not.
    let mut slid = Vec::new();
    for _ in 0..3 {
        let from = x[0];
        x[0] += Vec3::new(0.0003, 0.0001, 0.0);
        spare.hold(0, from, &mut x[0]);
        slid.push(x[0] - from);
    }
    let near = |a: Vec3, b: [f32; 3]| (a - Vec3::from(b)).length() < 1e-7;
    assert!(near(slid[0], [0.0, 0.0001, 0.0]), "{slid:?}");
    assert!(near(slid[1], [0.0001, 0.0001, 0.0]), "{slid:?}");
    assert!(near(slid[2], [0.0003, 0.0001, 0.0]), "{slid:?}");
    for i in [1, 2] {
        let from = x[i];
        x[i] += Vec3::new(0.0003, 0.0, 0.0);
        spare.hold(i, from, &mut x[i]);
        assert!(near(x[i] - from, [0.0003, 0.0, 0.0]), "particle {i}");
    }
}
