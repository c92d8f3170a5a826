//! The pen path a caller gives a frame (`Simulation::step_with`): asked before every
//! substep while the pen pinches, and told where the pinched vertex is then. cloth-sim
//! sends the haptic loop its local model from that, so a frame slower than the loop's
//! 20 ms staleness limit still feeds the pen.

#![allow(clippy::unwrap_used)]

use glam::Vec3;
use sim_core::mesh::ClothMesh;
use sim_core::solver::{Cloth, Environment, Held, Material, ModelKind, Pinch, Simulation};

fn hanging(model: ModelKind) -> Simulation {
    let material = Material::default();
    let mesh = ClothMesh::grid(0.3, 0.3, 12, 12, 0.5).unwrap();
    let cloth = Cloth::new(mesh, &material).unwrap();
    let env = Environment::default();
    Simulation::new(cloth, None, model, material, env, None).unwrap()
}

#[test]
fn the_pen_is_told_where_the_pinched_vertex_is_before_every_substep() {
    for model in [ModelKind::Xpbd, ModelKind::Vbd] {
        let mut sim = hanging(model);
        // Not pinching: the pen is never asked.
        let mut asked = 0;
        sim.step_with(&mut |_, _, _| {
            asked += 1;
            None
        })
        .unwrap();
        assert_eq!(asked, 0, "{model:?}");
        // Pinch the middle vertex and pull it 10 cm up.
        let v = 6 * 13 + 6;
        let target = sim.cloth.x[v] + Vec3::new(0.0, 0.1, 0.0);
        sim.set_pinch(Some(Pinch {
            vertex: v as u32,
            held: vec![(v as u32, Vec3::ZERO)],
            target,
            stiffness: 100.0,
            force_limit: None,
        }));
        let (x0, v0) = (sim.cloth.x[v], sim.cloth.v[v]);
        let mut told: Vec<(usize, usize, Option<Held>)> = Vec::new();
        sim.step_with(&mut |k, n, held| {
            told.push((k, n, held));
            None
        })
        .unwrap();
        let n = sim.substeps;
        assert_eq!(told.len(), n, "{model:?}: asked {} times", told.len());
        let held: Vec<Held> = told
            .iter()
            .enumerate()
            .map(|(i, &(k, m, h))| {
                assert_eq!((k, m), (i, n), "{model:?}");
                h.unwrap()
            })
            .collect();
        // Before the first substep: where the frame began.
        assert_eq!((held[0].position, held[0].velocity), (x0, v0), "{model:?}");
        // Before each later one: where the substeps so far took it, rising to the pen.
        for w in held.windows(2) {
            assert!(
                w[1].position.y > w[0].position.y && w[1].velocity.y > 0.0,
                "{model:?}: {w:?}"
            );
        }
        assert!(sim.cloth.x[v].y > held[n - 1].position.y, "{model:?}");
    }
}
