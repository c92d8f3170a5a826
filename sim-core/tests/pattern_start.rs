//! A pattern exported and draped again starts its pieces where the design started them,
//! in their fabrics and grains: the SVG carries each piece's start on the body
//! (`data-start`, `data-origin`), fabric and grain. Before 2026-12-06 the pieces were
//! arranged by their names, and a GarmentCode garment's ("skirt_front", "left_ftorso")
//! started at the shoulders or through the body.

use glam::Vec3;
use sim_core::collision::BodyKind;
use sim_core::design::Design;
use sim_core::design::garment::{Landmarks, assemble, load_pattern};
use sim_core::design::sewing_pattern::export_pattern;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_scene};

const SKIRT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/fixtures/gc-circle-skirt_specification.json"
);

/// Each piece's start box (lowest and highest corner) in `d`, by name: the triangles
/// whose pattern place lies in the piece's band of the pattern plane.
fn boxes_of(d: &Design) -> Vec<(String, Vec3, Vec3)> {
    let x = &d.sim.cloth.x;
    (d.pieces.iter())
        .map(|r| {
            let (lo, hi) = sim_core::mesh::bounds2(&r.outline.loops[0]);
            let band = (lo.x + r.offset.x - 1e-4, hi.x + r.offset.x + 1e-4);
            let (mut a, mut b) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
            for (_, t) in d.sim.cloth.live.iter() {
                if t.rest.iter().all(|p| (band.0..=band.1).contains(&p.x)) {
                    for &v in &t.v {
                        a = a.min(x[v as usize]);
                        b = b.max(x[v as usize]);
                    }
                }
            }
            (r.name.clone(), a, b)
        })
        .collect()
}

/// GarmentCode's circle skirt (its panels on cones, its waistband held) as the scenario
/// starts it on `human`, one piece given denim and its grain turned; its pattern out read
/// back for the same body starts every piece within 1 cm of where the design started
/// it, in its fabric and grain, and for another body carries the starts over and says
/// so. Arranged by their names, the skirt's panels started at the shoulders, 0.4 m up.
#[test]
fn a_pattern_read_back_starts_its_pieces_where_they_started() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
    cfg.pattern = Some(SKIRT.into());
    cfg.body = Some(BodyKind::Human);
    let (mut d, spec) = build_scene(&cfg).unwrap();
    assert!(spec.is_some());
    let first = d.piece_list()[0].name.clone();
    d.set_piece_fabric(0, "denim").unwrap();
    let k = (d.pieces.iter()).position(|r| r.name == first).unwrap();
    d.pieces[k].grain = 0.3;
    let dir = std::env::temp_dir().join(format!("saiho-start-{}", std::process::id()));
    export_pattern(&d, &dir, 10.0).unwrap();
    let svg = dir.join("pattern.svg");
    let human = Landmarks::of(d.sim.body.as_ref());
    let (spec, notices) = load_pattern(&svg, &human).unwrap();
    let mannequin = BodyKind::Mannequin.build().unwrap();
    let (_, elsewhere) = load_pattern(&svg, &Landmarks::of(Some(&mannequin))).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        notices.iter().all(|n| !n.contains("another body")),
        "{notices:?}"
    );
    assert!(
        elsewhere
            .iter()
            .any(|n| n.contains("placed for another body")),
        "{elsewhere:?}"
    );
    let made = assemble(&spec, &human, cfg.piece_edge).unwrap();
    let was = boxes_of(&d);
    assert_eq!(spec.pieces.len(), was.len());
    for ((p, range), (name, a, b)) in spec.pieces.iter().zip(&made.ranges).zip(&was) {
        assert_eq!(&p.name, name);
        let (mut c, mut e) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for q in &made.starts[range.clone()] {
            c = c.min(*q);
            e = e.max(*q);
        }
        let off = (c - *a).abs().max((e - *b).abs()).max_element();
        assert!(off < 0.01, "{name}: starts {off} m from where it started");
        let (fabric, grain) = if *name == first {
            ("denim", 0.3)
        } else {
            ("cotton", 0.0)
        };
        assert_eq!(p.fabric, fabric, "{name}");
        assert!((p.grain - grain).abs() < 1e-4, "{name}: grain {}", p.grain);
    }
}
