use sim_core::cloth::*;
use sim_core::mesh::ClothMesh;
fn main() {
    let n = 16;
    for curtain in [false, true] {
        for (stretch, shear, tethers) in [(2000.0, 40.0, true), (2000.0, 40.0, false)] {
            let material = Material {
                stretch,
                shear,
                tethers,
                ..Material::default()
            };
            let mut out = vec![];
            for sub in [5, 10, 20] {
                let mesh = ClothMesh::grid(0.5, 0.5, n, n, 1.0).unwrap();
                let mut cloth = Cloth::new(mesh, &material).unwrap();
                let pins: Vec<usize> = if curtain {
                    (0..=n).collect()
                } else {
                    vec![0, n]
                };
                for &p in &pins {
                    cloth.pin(p);
                }
                let env = Environment {
                    floor: None,
                    ..Environment::default()
                };
                let mut sim =
                    Simulation::new(cloth, None, ModelKind::Xpbd, material, env, Some(sub))
                        .unwrap();
                for _ in 0..900 {
                    sim.step().unwrap();
                }
                let low = sim
                    .cloth
                    .x
                    .iter()
                    .map(|p| p.y)
                    .fold(f32::INFINITY, f32::min);
                out.push(format!(
                    "{sub}: mid {:.4} low {:.5}",
                    1.0 - sim.cloth.x[n / 2].y,
                    1.0 - low
                ));
            }
            println!(
                "curtain {curtain} stretch {stretch} tethers {tethers}: {}",
                out.join(" | ")
            );
        }
    }
}
