//! A pattern exported and draped again starts its pieces where the design started them,
//! in their fabrics and grains: the SVG carries each piece's start on the body
//! (`data-start`, `data-origin`), fabric and grain. Before 2026-12-06 the pieces were
//! arranged by their names, and a GarmentCode garment's ("skirt_front", "left_ftorso")
//! started at the shoulders or through the body.

use glam::{Vec2, Vec3};
use sim_core::collision::BodyKind;
use sim_core::design::Design;
use sim_core::design::garment::{Landmarks, SeamSpec, assemble, load_pattern, own_body};
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
/// it, in its fabric and grain, its seams sewn the way round the JSON sews them, and
/// for another body carries the starts over and says so. Arranged by their names, the skirt's panels started at the shoulders, 0.4 m up.
#[test]
fn a_pattern_read_back_starts_its_pieces_where_they_started() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
    cfg.pattern = Some(SKIRT.into());
    cfg.body = Some(BodyKind::Human);
    let (mut d, spec) = build_scene(&cfg).unwrap();
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), 45.0).unwrap();
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
    // The body its starts name is the pattern's own (it drapes there by default, with
    // its fabric's strain limit, as a GarmentCode pattern does on `human`).
    assert_eq!(own_body(&svg), Some(BodyKind::Human));
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
    // Every seam sewn the same way round as the design sewed it: the file says which
    // ends meet (before, `None`: paired by where the pieces start).
    let (from_json, _) = load_pattern(std::path::Path::new(SKIRT), &human).unwrap();
    assert_eq!(spec.seams.len(), from_json.seams.len());
    let meets = |s: &SeamSpec| {
        let r = s.reversed.expect("the file says which ends meet");
        let (b0, b1) = if r {
            (s.b.to, s.b.from)
        } else {
            (s.b.from, s.b.to)
        };
        [
            (s.a.piece, s.a.from, s.b.piece, b0),
            (s.a.piece, s.a.to, s.b.piece, b1),
        ]
    };
    let near = |p: Vec2, q: Vec2| p.distance(q) < 0.01;
    for s in &spec.seams {
        let got = meets(s);
        let same = from_json.seams.iter().map(meets).any(|want| {
            let hit = |(pa, a, pb, b): (usize, Vec2, usize, Vec2)| {
                want.iter().any(|&(qa, c, qb, d)| {
                    (pa == qa && pb == qb && near(a, c) && near(b, d))
                        || (pa == qb && pb == qa && near(a, d) && near(b, c))
                })
            };
            got.iter().all(|&m| hit(m))
        });
        assert!(
            same,
            "seam {}: {got:?} is sewn otherwise in the JSON",
            s.label
        );
    }
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

/// A piece's start may say how far out from the torso's cylinder it starts (`out`, m;
/// the file's reader takes any number up to 100). Layering goes on from there, but no
/// further than its own 20 layers: a piece said to start 90 m out starts within 30 cm
/// of where it starts at 0.
#[test]
fn a_start_far_out_starts_no_further_than_layering_goes() {
    let mannequin = BodyKind::Mannequin.build().unwrap();
    let marks = Landmarks::of(Some(&mannequin));
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/dress.svg");
    let (mut spec, _) = load_pattern(std::path::Path::new(dress), &marks).unwrap();
    let reach = |spec: &sim_core::design::garment::PatternSpec| {
        let made = assemble(spec, &marks, 0.03).unwrap();
        let x = &made.starts[made.ranges[0].clone()];
        let r = |p: &Vec3| Vec2::new(p.x, p.z).distance(marks.axis);
        x.iter().map(r).fold(0.0f32, f32::max)
    };
    let near = reach(&spec);
    let Some(sim_core::design::garment::Placement::Around { out, .. }) =
        &mut spec.pieces[0].placement
    else {
        panic!("the front is placed round the torso");
    };
    *out = 90.0;
    let far = reach(&spec);
    assert!(
        far > near + 0.1 && far < near + 0.31,
        "{near} m, then {far} m"
    );
}
