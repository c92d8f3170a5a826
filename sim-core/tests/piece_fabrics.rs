//! Pieces of different fabrics in one cloth: each hangs as its own fabric under every
//! model, and a design keeps each piece's fabric through edits, undo and its file.

// Test helpers: a failed unwrap is a failed test, with its location.
#![allow(clippy::unwrap_used)]

use glam::Vec3;
use sim_core::design::Design;
use sim_core::fabric::Library;
use sim_core::mesh::ClothMesh;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};
use sim_core::solver::{Cloth, Environment, Material, MaterialZones, ModelKind, Simulation, Zone};

const N: usize = 12;
const SIZE: f32 = 0.5;

/// A curtain, `SIZE` square and `N` x `N` cells, hanging from its whole top edge in the
/// plane z = 0, its left half (x < 0) of `left` and the rest of `base`; settled under
/// `model`. Returns how far its bottom-left and bottom-right corners hang below the top.
fn curtain(model: ModelKind, base: Material, left: Option<Material>) -> (f32, f32) {
    let mut mesh = ClothMesh::grid(SIZE, SIZE, N, N, 1.0).unwrap();
    for p in &mut mesh.positions {
        *p = Vec3::new(p.x, 1.0 - (p.z + SIZE / 2.0), 0.0);
    }
    let mut cloth = Cloth::new(mesh, &base).unwrap();
    if let Some(m) = left {
        let zone = Zone {
            lo: -SIZE,
            hi: 0.0,
            material: m,
        };
        let zones = MaterialZones::new(vec![zone], &base).unwrap();
        assert!(!zones.is_empty());
        cloth.set_zones(zones, base.density);
    }
    for i in 0..=N {
        cloth.pin(i);
    }
    let env = Environment {
        floor: None,
        ..Environment::default()
    };
    let mut sim = Simulation::new(cloth, None, model, base, env, None).unwrap();
    for i in 0..=N {
        sim.pin(i);
    }
    for _ in 0..240 {
        sim.step().unwrap();
    }
    let bottom = N * (N + 1);
    let drop = |i: usize| 1.0 - sim.cloth.x[i].y;
    (drop(bottom), drop(bottom + N))
}

/// A soft base (100 N/m, so stretch shows) whose left half is 10x softer or 4x heavier.
/// (The halves pull on each other through shear and the bottom edge, so the right half
/// does not hang exactly as it would alone: under vbd its bottom corner rises 1-3 mm.)
#[test]
fn a_piece_of_a_softer_or_heavier_fabric_stretches_more_under_every_model() {
    let base = Material {
        stretch: 100.0,
        ..Material::default()
    };
    let softer = Material {
        stretch: 10.0,
        ..base
    };
    let heavier = Material {
        density: 4.0 * base.density,
        ..base
    };
    let mut seen = Vec::new();
    for model in [ModelKind::Xpbd, ModelKind::Vbd, ModelKind::Implicit] {
        let (l0, r0) = curtain(model, base, None);
        let (ls, rs) = curtain(model, base, Some(softer));
        let (lh, rh) = curtain(model, base, Some(heavier));
        eprintln!(
            "{model:?}: one fabric {l0:.4} / {r0:.4}; left softer {ls:.4} / {rs:.4}; left \
             heavier {lh:.4} / {rh:.4} m"
        );
        // One fabric hangs evenly; a softer or heavier left half hangs lower there. The
        // weight over the stretch modulus gives about 18 mm at 10 N/m and 7 mm at 4x
        // the weight, against under 2 mm at 100 N/m.
        assert!((l0 - r0).abs() < 5e-4, "{model:?}: {l0} {r0}");
        assert!(ls - rs > 0.008, "{model:?}: softer {ls} {rs}");
        assert!(lh - rh > 0.003, "{model:?}: heavier {lh} {rh}");
        seen.push([ls, rs, lh, rh]);
    }
    // vbd comes to the implicit reference's equilibrium with the zones too.
    for (v, i) in seen[1].iter().zip(&seen[2]) {
        assert!(
            (v - i).abs() < 1e-3,
            "vbd {:?} implicit {:?}",
            seen[1],
            seen[2]
        );
    }
}

/// The dress's pieces, each its own fabric: masses follow each piece's density, a
/// piece's fabric changes undoably, and the design file keeps them.
#[test]
fn each_piece_keeps_its_fabric_through_edits_undo_and_the_file() {
    let lib = Library::builtin();
    let denim = lib.get("denim").unwrap().material();
    let jersey = lib.get("jersey-interlock").unwrap().material();
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    cfg.piece_fabrics = vec![("front".into(), "denim".into())];
    let mut d = build_design(&cfg).unwrap();
    assert_eq!(d.pieces[0].fabric, "denim");
    let base = d.sim.material.density;
    // The mass each piece should have: its rest area times its fabric's density.
    let expected = |d: &Design, front: f32, back: f32| -> f64 {
        d.sim
            .cloth
            .live
            .iter()
            .map(|(_, t)| {
                let c = (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0;
                let rho = match d.record_at(glam::Vec2::new(c.x, -c.z)) {
                    Some(0) => front,
                    Some(1) => back,
                    other => panic!("a triangle of no piece: {other:?}"),
                };
                (rho * t.rest_area()) as f64
            })
            .sum()
    };
    let total = |d: &Design| d.sim.cloth.mass.iter().map(|&m| m as f64).sum::<f64>();
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-4;
    let with_denim = total(&d);
    assert!(close(with_denim, expected(&d, denim.density, base)));
    assert!(
        denim.density > 2.0 * base,
        "denim is heavier than the default"
    );

    // The back made of jersey: masses follow; undo and redo take it back and forth.
    let back = d
        .piece_list()
        .iter()
        .position(|p| p.name == "back")
        .unwrap();
    assert_eq!(
        d.set_piece_fabric(back, "jersey-interlock").unwrap(),
        "back"
    );
    assert_eq!(d.pieces[1].fabric, "jersey-interlock");
    let with_jersey = total(&d);
    assert!(close(
        with_jersey,
        expected(&d, denim.density, jersey.density)
    ));
    d.step().unwrap();
    d.undo().unwrap();
    assert_eq!(d.pieces[1].fabric, "cotton");
    assert_eq!(total(&d), with_denim);
    d.redo().unwrap();
    assert_eq!(total(&d), with_jersey);

    // An unknown fabric or piece changes nothing.
    assert!(d.set_piece_fabric(back, "silk-charmeuse").is_err());
    assert!(d.set_piece_fabric(9, "denim").is_err());
    assert_eq!(total(&d), with_jersey);

    // The file keeps every piece's fabric, and the masses with it.
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(loaded.pieces[0].fabric, "denim");
    assert_eq!(loaded.pieces[1].fabric, "jersey-interlock");
    assert!(close(total(&loaded), with_jersey));
    assert!(!loaded.sim.cloth.zones.is_empty());
}

/// A piece named for a fabric the library does not have hangs as the design's material,
/// with a notice; --piece-fabric for a piece the pattern has not is refused.
#[test]
fn unknown_fabrics_and_pieces_are_said() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    cfg.piece_fabrics = vec![("sleeve".into(), "denim".into())];
    let err = build_design(&cfg).err().unwrap().to_string();
    assert!(
        err.contains("\"sleeve\"") && err.contains("front, back"),
        "{err}"
    );

    cfg.piece_fabrics = vec![("back".into(), "silk-charmeuse".into())];
    let d = build_design(&cfg).unwrap();
    assert!(
        d.sim.cloth.zones.is_empty(),
        "hangs as the design's material"
    );
    assert!(
        d.sim.notices.iter().any(|n| n.contains("silk-charmeuse")),
        "{:?}",
        d.sim.notices
    );
}

/// A part a cut left of a piece, given a fabric of its own, becomes a piece of its own
/// (a fabric belongs to a whole pattern piece): the dress's front cut at the waist and
/// its lower part made of denim. Its triangles move to a band of their own in the
/// pattern, their rest shapes unchanged; the cloth's mass grows by denim's; the upper
/// part stays cotton and keeps its name; cloth eased into a seam from it moves with it;
/// the pattern out has three pieces. One undoable edit; the file keeps it; the cloth
/// crosses nothing in the frames after.
#[test]
fn a_part_given_its_own_fabric_becomes_a_piece_of_its_own() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let (mut d, spec) = sim_core::scenario::build_scene(&cfg).unwrap();
    let pull = sim_core::scenario::garment::SEAM_PULL;
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), pull).unwrap();
    // Cut across the front's middle in the pattern, as the studio's Cut tool does.
    let front = &d.pieces[0];
    let (lo, hi) = (front.outline.loops[0].iter())
        .fold((glam::Vec2::MAX, glam::Vec2::MIN), |(a, b), p| {
            (a.min(*p), b.max(*p))
        });
    let at = |x: f32| glam::Vec2::new(x, 0.5 * (lo.y + hi.y)) + front.offset;
    let (a, b) = (at(lo.x - 0.02), at(hi.x + 0.02));
    d.cut_line(a, b).unwrap();
    let list = |d: &Design| -> Vec<(String, String)> {
        (d.piece_list().into_iter())
            .map(|p| (p.name, p.fabric))
            .collect()
    };
    let piece = |n: &str, f: &str| (n.to_string(), f.to_string());
    let cut = [
        piece("front", "cotton"),
        piece("front 2", "cotton"),
        piece("back", "cotton"),
    ];
    assert_eq!(list(&d), cut);
    let total = |d: &Design| d.sim.cloth.mass.iter().map(|&m| m as f64).sum::<f64>();
    let shapes = |d: &Design| {
        let mut a: Vec<f32> = d
            .sim
            .cloth
            .live
            .iter()
            .map(|(_, t)| t.rest_area())
            .collect();
        a.sort_by(f32::total_cmp);
        a
    };
    // Cloth a weld eased into a seam, one triangle from each part (set by hand here:
    // the dress's sides are meshed alike and ease nothing): the lower part's goes with
    // it, the upper's stays, also one with two corners on the cut (where the lower part
    // has corners at the same places).
    let rests = |d: &Design, piece: usize| -> Vec<(u32, [Vec3; 3])> {
        (d.piece_slots(piece).unwrap().into_iter())
            .map(|s| (s, d.sim.cloth.live.tri(s).unwrap().rest))
            .collect()
    };
    let (low, eased_low) = rests(&d, 1)[0];
    let lower: Vec<Vec3> = rests(&d, 1).iter().flat_map(|(_, t)| *t).collect();
    let (_, eased_high) = (rests(&d, 0).into_iter())
        .find(|(_, t)| t.iter().filter(|p| lower.contains(p)).count() == 2)
        .expect("a triangle of the upper part on the cut");
    d.seams[0].eased = vec![eased_low, eased_high];
    let (mass, areas, steps) = (total(&d), shapes(&d), d.history.undo_steps());
    assert_eq!(d.set_piece_fabric(1, "denim").unwrap(), "front 2");
    let moved = d.sim.cloth.live.tri(low).unwrap().rest;
    assert!(moved[0].x > eased_low[0].x + 0.1, "{moved:?}");
    assert_eq!(d.seams[0].eased, [moved, eased_high]);
    let separate = [
        piece("front", "cotton"),
        piece("back", "cotton"),
        piece("front 2", "denim"),
    ];
    assert_eq!(list(&d), separate);
    assert_eq!(d.history.undo_steps(), steps + 1);
    // The rest shapes as they were (but for rounding: the corners moved along x).
    let now = shapes(&d);
    assert_eq!(now.len(), areas.len());
    let worst = (now.iter().zip(&areas))
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-4, "a rest area changed by {worst}");
    assert!(total(&d) > 1.1 * mass, "{} against {mass}", total(&d));
    let out = sim_core::design::sewing_pattern::pieces(&d);
    let mut names: Vec<&str> = out.iter().map(|p| p.name.as_str()).collect();
    names.sort();
    assert_eq!(names, ["back", "front", "front 2"]);
    // Its band lies right of the others in the pattern plane.
    let band = |r: &sim_core::design::PieceRecord| {
        let xs = r.outline.loops[0].iter().map(|p| p.x + r.offset.x);
        xs.fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)))
    };
    let [front, back, part] = [0, 1, 2].map(|k| band(&d.pieces[k]));
    assert!(part.0 > front.1.max(back.1));
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(list(&loaded), separate);
    for _ in 0..60 {
        d.step().unwrap();
    }
    let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    let c = sim_core::collision::crossings::count(&d.sim.cloth.x, &tris, d.sim.body.as_ref());
    assert_eq!((c.self_pairs, c.body_pairs), (0, 0));
    for _ in 0..60 {
        d.undo().unwrap();
        if d.history.undo_steps() == steps {
            break;
        }
    }
    assert_eq!(list(&d), cut);
    assert!((total(&d) / mass - 1.0).abs() < 1e-4);
}
