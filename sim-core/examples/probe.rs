use glam::Vec3;
use sim_core::body::BodyKind;
use sim_core::scenario::*;
fn main() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
    cfg.grid = 24;
    cfg.body = BodyKind::Mannequin;
    cfg.cloth_size = 0.6;
    let mut sim = build_simulation(&cfg).unwrap();
    for (p, v) in sim.cloth.x.iter_mut().zip(sim.cloth.v.iter_mut()) {
        p.y += 0.05;
        *v = Vec3::new(0.0, -2.0, 0.0);
    }
    let b = sim.body.clone().unwrap();
    for f in 0..30 {
        let before = sim.cloth.x.clone();
        let vb = sim.cloth.v.clone();
        sim.step().unwrap();
        for (i, &p) in sim.cloth.x.iter().enumerate() {
            let d = b.penetration(p);
            if d > 0.004 {
                println!(
                    "frame {f} vertex {i} pen {d:.4} at {p} from {} v {} mesh sd {:?}",
                    before[i],
                    vb[i],
                    b.signed_distance(p, 1.0)
                );
            }
        }
    }
}
