use sim_core::scenario::*;
fn main() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeMannequin);
    cfg.grid = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    let mut sim = build_simulation(&cfg).unwrap();
    for f in 0..240 {
        sim.step().unwrap();
        if f % 40 == 39 {
            let body = sim.body.as_ref().unwrap();
            let mut worst: Vec<(f32, usize)> = sim
                .cloth
                .x
                .iter()
                .enumerate()
                .map(|(i, &p)| (body.penetration(p), i))
                .collect();
            worst.sort_by(|a, b| b.0.total_cmp(&a.0));
            let n = worst.iter().filter(|w| w.0 > 0.001).count();
            println!(
                "frame {f}: {n} verts deeper than 1mm; worst {:?}",
                &worst[..3]
                    .iter()
                    .map(|&(d, i)| (d, sim.cloth.x[i], body.signed_distance(sim.cloth.x[i], 1.0)))
                    .collect::<Vec<_>>()
            );
        }
    }
}
