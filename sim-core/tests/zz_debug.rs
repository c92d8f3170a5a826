use sim_core::design::Design;
#[test]
#[ignore]
fn debug_slits() {
    let bytes = std::fs::read("/tmp/s95/out/export/design.saiho").unwrap();
    let d = Design::load_design(&bytes).unwrap();
    let live = &d.sim.cloth.live;
    let y = -0.44829696f32;
    // Boundary edges (by vertex) with a corner near the line.
    let mut count = std::collections::HashMap::new();
    for (s, t) in live.iter() {
        for k in 0..3 {
            let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            count.entry(key).or_insert(vec![]).push((s, k));
        }
    }
    for ((a, b), uses) in &count {
        let (s, k) = uses[0];
        let t = live.tri(s).unwrap();
        let (pa, pb) = (t.rest[k], t.rest[(k + 1) % 3]);
        let near = |p: glam::Vec3| (-p.z - y).abs() < 0.01 && p.x > -0.01 && p.x < 0.47;
        if near(pa) || near(pb) {
            if uses.len() == 1 {
                eprintln!(
                    "border edge {a}-{b}: {:?} {:?}",
                    (pa.x, -pa.z),
                    (pb.x, -pb.z)
                );
            } else {
                // interior edge whose two triangles disagree on rest places
                let t2 = live.tri(uses[1].0).unwrap();
                let ka = t2.corner(*a).unwrap();
                let kb = t2.corner(*b).unwrap();
                let ka1 = t.corner(*a).unwrap();
                let kb1 = t.corner(*b).unwrap();
                if t.rest[ka1] != t2.rest[ka] || t.rest[kb1] != t2.rest[kb] {
                    eprintln!(
                        "seam edge {a}-{b}: {:?}/{:?} vs {:?}/{:?}",
                        (t.rest[ka1].x, -t.rest[ka1].z),
                        (t.rest[kb1].x, -t.rest[kb1].z),
                        (t2.rest[ka].x, -t2.rest[ka].z),
                        (t2.rest[kb].x, -t2.rest[kb].z)
                    );
                }
            }
        }
    }
}
