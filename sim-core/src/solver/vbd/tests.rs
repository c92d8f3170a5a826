//! The VBD model against the implicit reference.

use glam::Vec3;

use super::step::Vbd;
use crate::collision::ContactCache;
use crate::mesh::ClothMesh;
use crate::solver::implicit::Implicit;
use crate::solver::material::Material;
use crate::solver::model::{Drive, Environment};
use crate::solver::model::{FrameInput, Solver};
use crate::solver::pinch::Grip;
use crate::solver::state::Cloth;

/// With enough iterations, one VBD step minimises the backward-Euler step's potential at
/// least as well as the implicit model's Newton solve.
#[test]
fn converged_step_is_the_implicit_step() {
    let m = Material {
        tethers: false,
        stretch_limits: false,
        shear_damping: 0.0,
        damping: 0.0,
        drag: 0.0,
        ..Material::default()
    };
    let n = 6;
    let mesh = ClothMesh::grid(0.3, 0.3, n, n, 1.0).expect("grid");
    let mut cloth = Cloth::new(mesh, &m).expect("cloth");
    cloth.pin(0);
    cloth.pin(n);
    // A swinging, stretched state.
    for (i, v) in cloth.v.iter_mut().enumerate() {
        if cloth.inv_mass[i] > 0.0 {
            *v = Vec3::new(0.1, -0.5 * (i as f32 / 49.0), 0.05);
        }
    }
    for p in cloth.x.iter_mut().skip(1) {
        p.y -= 0.01 * p.z;
    }
    cloth.x[n] = Vec3::new(0.3, 1.0, 0.0);
    let env = Environment {
        floor: None,
        ..Environment::default()
    };
    let contacts = ContactCache::new(cloth.len());
    let mut a = cloth.clone();
    let mut b = cloth.clone();
    let mut vbd = Vbd::new(&a, &m);
    vbd.iterations = 3000;
    vbd.contact = false;
    let mut grip = Grip::default();
    let mut pen = |_: &crate::solver::Between<'_>| None;
    let mut drive = Drive {
        grip: &mut grip,
        stitches: &[],
        holds: &[],
        pen: &mut pen,
        stretch_floor: crate::solver::StretchFloor::NONE,
        heartbeat: None,
    };
    vbd.frame(&mut a, None, &env, 1, &mut drive);
    let mut im = Implicit::new(&b, &m);
    im.step(
        FrameInput {
            cloth: &mut b,
            body: None,
            contacts: &contacts,
            env: &env,
            substeps: 1,
        },
        &mut drive,
    )
    .expect("implicit step");
    let worst =
        a.x.iter()
            .zip(&b.x)
            .map(|(p, q)| (*p - *q).length())
            .fold(0.0f32, f32::max);
    let phi = |x: &[Vec3]| {
        let mut e = vbd.elastic.energy(x, &m);
        for i in 0..x.len() {
            if cloth.inv_mass[i] > 0.0 {
                let y = cloth.x[i]
                    + cloth.v[i] * env.frame_dt
                    + env.gravity * env.frame_dt * env.frame_dt;
                e += 0.5
                    * (cloth.mass[i] / (env.frame_dt * env.frame_dt) * (x[i] - y).length_squared())
                        as f64;
            }
        }
        e
    };
    // The energy is not convex (the cloth can buckle either way), so the two may find
    // different minima; VBD's must be at least as low.
    let (pa, pb) = (phi(&a.x), phi(&b.x));
    assert!(
        pa <= pb + 1e-6 * pb.abs(),
        "VBD's step potential {pa} above the implicit's {pb} ({worst} m apart)"
    );
}

/// A cloth about to move more than half an edge in a frame is searched once a substep
/// (shorter motion boxes, fewer pairs); one at rest, once a frame.
#[test]
fn a_fast_cloth_is_searched_every_substep() {
    let m = Material::default();
    let mesh = ClothMesh::grid(0.5, 0.5, 16, 16, 1.0).expect("grid");
    let mut cloth = Cloth::new(mesh, &m).expect("cloth");
    let vbd = Vbd::new(&cloth, &m);
    let env = Environment::default();
    assert_eq!(vbd.search_groups(&cloth, &env, 2), 1, "at rest");
    // 1 m/s: 1.7 cm in a frame, more than half of a 3.1 cm edge.
    cloth.v[40] = Vec3::new(0.0, -1.0, 0.0);
    assert_eq!(vbd.search_groups(&cloth, &env, 2), 2, "one vertex falling");
    assert_eq!(vbd.search_groups(&cloth, &env, 5), 5);
    // A pinned vertex does not move, whatever its velocity says.
    cloth.v[40] = Vec3::ZERO;
    cloth.pin(3);
    let vbd = Vbd::new(&cloth, &m);
    cloth.v[3] = Vec3::new(0.0, -1.0, 0.0);
    assert_eq!(vbd.search_groups(&cloth, &env, 2), 1, "pinned");
}
