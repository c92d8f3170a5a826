//! The pen path a caller gives a frame (`Simulation::step_with`): told before every
//! substep where the cloth is, and while the pen pinches where the pinched vertex is.
//! cloth-sim sends the haptic loop its local model from that, so a frame slower than the
//! loop's 20 ms staleness limit still feeds the pen.

#![allow(clippy::unwrap_used)]

use glam::Vec3;
use sim_core::mesh::ClothMesh;
use sim_core::solver::{
    Cloth, Environment, Held, Material, ModelKind, PenInput, Pinch, Simulation,
};

fn hanging(model: ModelKind) -> Simulation {
    let material = Material::default();
    let mesh = ClothMesh::grid(0.3, 0.3, 12, 12, 0.5).unwrap();
    let cloth = Cloth::new(mesh, &material).unwrap();
    let env = Environment::default();
    Simulation::new(cloth, None, model, material, env, None).unwrap()
}

#[test]
fn the_pen_is_told_where_the_cloth_and_the_pinched_vertex_are_before_every_substep() {
    for model in [ModelKind::Xpbd, ModelKind::Vbd] {
        let mut sim = hanging(model);
        // Not pinching: told before every substep where the cloth falls, nothing held,
        // and a pointer given then changes nothing.
        let mut lowest: Vec<(usize, usize, f32)> = Vec::new();
        let before = sim.cloth.x.clone();
        sim.step_with(&mut |b| {
            assert!(b.held.is_none(), "{model:?}");
            let y = b.cloth.x.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
            lowest.push((b.substep, b.substeps, y));
            Some(PenInput {
                target: Vec3::new(0.0, 5.0, 0.0),
                force_limit: None,
            })
        })
        .unwrap();
        let n = sim.substeps;
        let told: Vec<(usize, usize)> = lowest.iter().map(|&(k, m, _)| (k, m)).collect();
        assert_eq!(
            told,
            (0..n).map(|k| (k, n)).collect::<Vec<_>>(),
            "{model:?}"
        );
        let y0 = before.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
        assert_eq!(lowest[0].2, y0, "{model:?}: the first is the frame's start");
        assert!(
            lowest[n - 1].2 < y0,
            "{model:?}: the last is after some falling"
        );
        assert!(sim.pinch().is_none(), "{model:?}");
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
        sim.step_with(&mut |b| {
            told.push((b.substep, b.substeps, b.held));
            None
        })
        .unwrap();
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

/// While a long contact search runs on a thread of its own, the pen path hears the
/// frame's heartbeat: the cloth as it stands (nothing moves during a search), nothing
/// held, the answer not taken; and the cloth comes out the same to the bit as without.
#[test]
fn a_long_search_beats_for_the_pen_and_changes_nothing() {
    use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};
    let landing = |beat: Option<std::time::Duration>| {
        // 64 x 64 landing: searches of 6-15 ms here, 2 ms (the threshold) on a machine
        // several times faster.
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 64;
        let mut d = build_design(&scene).unwrap();
        d.sim.heartbeat = beat;
        let (mut beats, mut last) = (0, None::<Vec<Vec3>>);
        for _ in 0..40 {
            d.step_with(&mut |b| {
                if b.heartbeat {
                    beats += 1;
                    assert!(b.held.is_none());
                    if let Some(x) = &last {
                        assert!(*x == b.cloth.x, "the cloth moved during a search");
                    }
                } else {
                    last = None;
                }
                if b.heartbeat && last.is_none() {
                    last = Some(b.cloth.x.clone());
                }
                // Taken only while pinching, and never from a heartbeat.
                Some(PenInput {
                    target: Vec3::new(0.0, 5.0, 0.0),
                    force_limit: None,
                })
            })
            .unwrap();
        }
        (beats, d.sim.cloth.x.clone())
    };
    let (none, plain) = landing(None);
    assert_eq!(none, 0);
    let (beats, beaten) = landing(Some(std::time::Duration::from_micros(100)));
    assert!(beats > 0, "no heartbeat in 40 landing frames");
    assert!(plain == beaten, "the heartbeat changed the cloth");
}
