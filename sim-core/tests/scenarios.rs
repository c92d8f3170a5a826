//! The operation scenarios end to end: fit-cube (the paper's experiment), tear, paint.

// Test helpers: a failed unwrap is a failed test, with its location.
#![allow(clippy::unwrap_used)]

use sim_core::collision::BodyKind;
use sim_core::design::Design;
use sim_core::design::garment::Placement;
use sim_core::scenario::{Report, ScenarioConfig, ScenarioName, run_scenario};

fn run(name: ScenarioName, grid: usize, frames: u64) -> (Report, std::path::PathBuf) {
    let mut cfg = ScenarioConfig::new(name);
    cfg.grid = grid;
    cfg.frames = frames;
    let out = std::env::temp_dir().join(format!("saiho-{}-{}", name.name(), std::process::id()));
    let r = run_scenario(&cfg, &out).unwrap();
    (r, out)
}

/// The paper's experiment: after cutting the corners away and sewing the flaps, the side
/// panels hug the cube. Bound: mean standoff beyond the contact thickness under 5 mm
/// and every point within 3 cm (a panel hanging against a vertical face is not pressed
/// onto it by gravity, so a few millimetres of standoff remain; the hem can flare); less
/// on average than the same cloth merely draped, and at most half its largest standoff
/// (the corners' folds flaring out, which the cut and the seams take away). With the 1 mm
/// contact and the guard (the defaults since 2026-11-28) the draped panels hang 3.5-4 mm
/// off on average against 11 mm at 4 mm, so the mean alone no longer tells a fit from a
/// drape: fit 2.3-2.7 / drape 3.5-4.1 mm on average, 10-12 / 30-42 mm at most.
#[test]
fn fit_cube_takes_the_cubes_shape() {
    // Grid 40: the cut lines fall exactly on the cube's faces (0.2 m = 8 cells of 2.5 cm).
    let (fit, out) = run(ScenarioName::FitCube, 40, 600);
    assert_eq!(fit.ops.cuts, Some(4));
    assert_eq!(fit.ops.seams, Some(4));
    assert_eq!(
        fit.ops.welds, fit.ops.seam_pairs,
        "every stitched pair welded"
    );
    assert!(fit.mesh_valid && fit.settled && fit.max_penetration_m <= fit.thickness_m);
    // The default xpbd has its guard: nothing crosses (586-608 pairs with the cube without).
    assert!(fit.guard);
    assert_eq!((fit.crossings_self, fit.crossings_body), (0, 0));
    let (mean, max) = (
        fit.ops.fit_gap_mean_m.unwrap(),
        fit.ops.fit_gap_max_m.unwrap(),
    );
    assert!(mean < 0.005 && max < 0.03, "fit gap mean {mean} max {max}");
    let (drape, drape_out) = run(ScenarioName::DrapeCube, 40, 600);
    let _ = std::fs::remove_dir_all(drape_out);
    let (drape_mean, drape_max) = (
        drape.ops.fit_gap_mean_m.unwrap(),
        drape.ops.fit_gap_max_m.unwrap(),
    );
    assert!(
        mean < drape_mean && max < 0.5 * drape_max,
        "fit {mean} / {max} vs drape {drape_mean} / {drape_max}"
    );
    // The export and the design file are there and the design loads.
    for f in [
        "cloth.obj",
        "cloth.mtl",
        "cloth.png",
        "body.obj",
        "report.json",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let obj = std::fs::read_to_string(out.join("cloth.obj")).unwrap();
    assert!(obj.contains("mtllib cloth.mtl") && obj.contains("vt ") && obj.contains("f "));
    // The binary glTF: container, JSON chunk and the index count match the cloth.
    let glb = std::fs::read(out.join("cloth.glb")).unwrap();
    let gltf = sim_core::design::export::glb_json(&glb).unwrap();
    assert_eq!(gltf["accessors"][3]["count"], 3 * fit.triangles);
    let d = Design::load_design_file(&out.join("design.saiho")).unwrap();
    assert_eq!(d.sim.cloth.live.tri_count(), fit.triangles);
    assert_eq!(d.seams.len(), 4);
    std::fs::remove_dir_all(out).unwrap();
}

/// A drape is at rest once it has been still for a second by the sleep rule, which a
/// cloth still landing is not. A 16 x 16 cloth on the cube is still from about frame 400:
/// with the hinges damped (`Material::bend_damping`) it still moved 0.39 mm (root mean
/// square, 2 mm at most) between frames 340 and 400 and 0.03 mm between 400 and 460
/// (without, it was still from about frame 270; of grids 12-32, 16 and 20 were still
/// moving at 400 with the damping, none without; both were at rest at 600).
#[test]
fn a_drape_is_at_rest_only_once_it_has_been_still_for_a_second() {
    let (landing, out) = run(ScenarioName::DrapeCube, 16, 60);
    assert!(!landing.at_rest && !landing.sleep && landing.frames_asleep == 0);
    let (rested, _) = run(ScenarioName::DrapeCube, 16, 600);
    assert!(rested.at_rest && rested.settled);
    assert_eq!(
        rested.frames_asleep, 0,
        "a scenario sleeps only with --sleep"
    );
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn pulling_a_gripped_corner_tears_the_cloth() {
    let (r, out) = run(ScenarioName::Tear, 24, 420);
    assert!(r.ops.tears.unwrap() > 0, "{:?}", r.ops);
    assert!(r.triangles < 2 * 24 * 24);
    assert!(
        r.ops.first_tear_frame.unwrap() > 240,
        "no tear before the pull"
    );
    assert!(r.ops.pinch_force_max_n.unwrap() > 0.1);
    assert!(r.mesh_valid);
    std::fs::remove_dir_all(out).unwrap();
}

#[test]
fn paint_scenario_paints_and_exports_the_texture() {
    let (r, out) = run(ScenarioName::Paint, 24, 260);
    assert_eq!(r.ops.paint_strokes, Some(25));
    assert!(r.ops.texels_painted.unwrap() > 10_000);
    let png = std::fs::read(out.join("cloth.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    std::fs::remove_dir_all(out).unwrap();
}

/// A GarmentCode pattern whose panels have an edge of a hundredth of a millimetre (their
/// data set has such), stitched to each other: the crowded points merge when meshed, the
/// seam along that edge is left unsewn with a notice, and the rest is sewn.
#[test]
fn a_garmentcode_seam_shorter_than_the_mesh_is_left_unsewn_with_a_notice() {
    let panel = |x: f32, turn: f32| {
        gc_panel(
            [x, 90.0, 0.0],
            [0.0, turn, 0.0],
            &[
                [0.0, 0.0],
                [40.0, 0.0],
                [40.0, 50.0],
                [39.999, 50.0],
                [0.0, 50.0],
            ],
        )
    };
    let (r, dir) = drape_gc(
        None,
        "tiny",
        &[("front", panel(-20.0, 0.0)), ("back", panel(20.0, 180.0))],
        &[
            (("front", 1), ("back", 4)),
            (("front", 2), ("back", 2)),
            (("front", 4), ("back", 1)),
        ],
        0.05,
        2,
    );
    let r = r.unwrap();
    assert_eq!(r.ops.pieces, Some(2));
    assert_eq!(r.ops.seams, Some(2), "{:?}", r.notices);
    assert!(
        r.notices.iter().any(|n| n.contains("left unsewn")),
        "{:?}",
        r.notices
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A GarmentCode panel: its points (cm) joined in order by straight edges, at their
/// translation (cm) and rotation (XYZ degrees).
fn gc_panel(t: [f32; 3], r: [f32; 3], points: &[[f32; 2]]) -> serde_json::Value {
    let n = points.len();
    let edges: Vec<_> = (0..n)
        .map(|k| serde_json::json!({"endpoints": [k, (k + 1) % n]}))
        .collect();
    serde_json::json!({"translation": t, "rotation": r, "vertices": points, "edges": edges})
}

/// One side of a GarmentCode stitch: a panel's name and one of its edges.
type Side<'a> = (&'a str, usize);

/// The highest point of the cloth a scenario in `dir` exported (`out/cloth.obj`), m.
fn cloth_top(dir: &std::path::Path) -> f32 {
    sim_core::mesh::obj::load_obj(&dir.join("out/cloth.obj"))
        .unwrap()
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f32::MIN, f32::max)
}

/// drape-pattern on a GarmentCode specification of `panels` and `stitches` (each a pair of
/// (panel, edge)), written to a file in a fresh directory, on `body` (`None`: the
/// scenario's own, the mannequin); the directory is returned for the outputs (under
/// `out/`) and to be removed.
fn drape_gc(
    body: Option<sim_core::collision::BodyKind>,
    tag: &str,
    panels: &[(&str, serde_json::Value)],
    stitches: &[(Side, Side)],
    edge: f32,
    frames: u64,
) -> (
    Result<Report, sim_core::scenario::ScenarioError>,
    std::path::PathBuf,
) {
    let panels: serde_json::Map<String, serde_json::Value> = panels
        .iter()
        .map(|(n, p)| ((*n).to_string(), p.clone()))
        .collect();
    let side = |(panel, edge): Side| serde_json::json!({"panel": panel, "edge": edge});
    let stitches: Vec<_> = stitches
        .iter()
        .map(|&(a, b)| serde_json::json!([side(a), side(b)]))
        .collect();
    let spec = serde_json::json!({
        "pattern": {"panels": panels, "stitches": stitches},
        "properties": {"units_in_meter": 100}
    });
    let dir = std::env::temp_dir().join(format!("saiho-gc-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{tag}_specification.json"));
    std::fs::write(&file, spec.to_string()).unwrap();
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
    cfg.pattern = Some(file);
    if body.is_some() {
        cfg.body = body;
    }
    cfg.piece_edge = edge;
    cfg.frames = frames;
    (run_scenario(&cfg, &dir.join("out")), dir)
}

/// A GarmentCode top on thin straps, as their pencil dress's bodice: its straps come level
/// with their body's shoulders, and the panels are raised to start above ours (as our own
/// tops do), so the strap seams close over the shoulders while the panels fall. Started
/// level with our shoulders instead, the straps slid off before they were sewn and the
/// top fell to the floor within half a second (coverage 0, its highest point at the hips).
#[test]
fn a_garmentcode_top_on_straps_stays_on_the_mannequins_shoulders() {
    // Front and back as one panel each (cm): the bodice, the armholes, two 4.4 cm straps
    // and a V neck, as GarmentCode's dress_pencil's torso halves put side by side.
    let bodice = |z: f32, turn: f32, neck: f32| {
        gc_panel(
            [0.0, 83.5, z],
            [0.0, turn, 0.0],
            &[
                [-28.7, 0.0],
                [28.7, 0.0],
                [28.7, 33.8],
                [17.2, 55.3],
                [12.8, 57.05],
                [0.0, neck],
                [-12.8, 57.05],
                [-17.2, 55.3],
                [-28.7, 33.8],
            ],
        )
    };
    // The back is turned round: its edge 1 (x = 28.7) lies on the body's right, beside
    // the front's edge 8, and its straps' tops (edges 3 and 6) above the front's 6 and 3.
    let (r, dir) = drape_gc(
        None,
        "straps",
        &[
            ("front", bodice(30.0, 0.0, 42.8)),
            ("back", bodice(-25.0, 180.0, 51.6)),
        ],
        &[
            (("front", 1), ("back", 8)),
            (("front", 8), ("back", 1)),
            (("front", 3), ("back", 6)),
            (("front", 6), ("back", 3)),
        ],
        0.03,
        90,
    );
    let r = r.unwrap();
    assert_eq!(r.ops.seams, Some(4), "{:?}", r.notices);
    let top = cloth_top(&dir);
    let coverage = r.ops.torso_coverage.unwrap();
    assert!(
        top > 1.40 && coverage > 0.8,
        "the top hangs from {top} m, coverage {coverage}"
    );
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    std::fs::remove_dir_all(&dir).ok();
}

/// A GarmentCode skirt wider than the hips, its waistband labelled as their skirts' are
/// (`lower_interface`): held at the waist while it settles, it stays there; the same
/// skirt unlabelled falls past the hips.
#[test]
fn a_garmentcode_waistband_is_held_at_the_waist_while_the_skirt_settles() {
    // Two 60 x 50 cm panels (120 cm round, against hips of 103.5), their tops at their
    // body's waist (108.8 cm), sewn at both sides.
    let panel = |z: f32, turn: f32, waistband: bool| {
        let mut p = gc_panel(
            [0.0, 58.8, z],
            [0.0, turn, 0.0],
            &[[-30.0, 0.0], [30.0, 0.0], [30.0, 50.0], [-30.0, 50.0]],
        );
        if waistband {
            p["edges"][2]["label"] = "lower_interface".into();
        }
        p
    };
    let top_after = |tag: &str, waistband: bool| {
        let (r, dir) = drape_gc(
            Some(sim_core::collision::BodyKind::Human),
            tag,
            &[
                ("front", panel(22.0, 0.0, waistband)),
                ("back", panel(-22.0, 180.0, waistband)),
            ],
            &[(("front", 1), ("back", 3)), (("front", 3), ("back", 1))],
            0.04,
            100,
        );
        let r = r.unwrap();
        assert_eq!(r.body, "human");
        assert_eq!(r.ops.seams, Some(2), "{:?}", r.notices);
        assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
        let top = cloth_top(&dir);
        std::fs::remove_dir_all(&dir).ok();
        (top, r.ops.held_vertices, r.notices)
    };
    let (held, n, said) = top_after("waistband", true);
    // 1.20 m round is more than the hips: it is held up now, and the run says it will
    // not stay up once let go.
    let wide = "its waist is 1.20 m round at rest, longer than the body's 1.0";
    assert!(
        said.iter()
            .any(|n| n.starts_with(wide) && n.contains("m round the hips")),
        "{said:?}"
    );
    // Both waistbands, 120 cm at 4 cm edges.
    assert!(n.unwrap() >= 2 * 60 / 4, "{n:?} held");
    assert!(
        (held - 1.088).abs() < 0.03,
        "the held skirt's top is at {held} m"
    );
    let (free, n, said) = top_after("no-waistband", false);
    assert_eq!(n, Some(0));
    assert!(!said.iter().any(|n| n.contains("waist")), "{said:?}");
    assert!(free < 0.95, "the free skirt's top is at {free} m");
    // Their waist is their body's: on the mannequin the skirt, which hangs from it, is held
    // at the mannequin's own waist (until 2026-12-07 nothing was held there, and
    // GarmentCode's circle skirts fell to its feet).
    let (r, dir) = drape_gc(
        None,
        "waistband-mannequin",
        &[
            ("front", panel(22.0, 0.0, true)),
            ("back", panel(-22.0, 180.0, true)),
        ],
        &[(("front", 1), ("back", 3)), (("front", 3), ("back", 1))],
        0.04,
        1,
    );
    let r = r.unwrap();
    assert_eq!(r.body, "mannequin");
    assert!(
        r.ops.held_vertices.unwrap() >= 2 * 60 / 4,
        "{:?}",
        r.ops.held_vertices
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A GarmentCode top whose sides reach up to where our arms leave the torso: lifted the
/// full 8 cm its armpits would start through the arms, so it starts lower, and says so.
#[test]
fn a_garmentcode_top_that_would_start_through_the_arms_starts_lower() {
    let top = |z: f32, turn: f32| {
        gc_panel(
            [0.0, 94.6, z],
            [0.0, turn, 0.0],
            &[
                [-28.7, 0.0],
                [28.7, 0.0],
                [28.7, 25.0],
                [17.0, 46.0],
                [-17.0, 46.0],
                [-28.7, 25.0],
            ],
        )
    };
    let (r, dir) = drape_gc(
        None,
        "armpits",
        &[("front", top(30.0, 0.0)), ("back", top(-25.0, 180.0))],
        &[(("front", 1), ("back", 5)), (("front", 5), ("back", 1))],
        0.03,
        1,
    );
    let r = r.unwrap();
    let said = r
        .notices
        .iter()
        .find(|n| n.contains("above the shoulders rather than 8"));
    assert!(said.is_some(), "{:?}", r.notices);
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    std::fs::remove_dir_all(&dir).ok();
}

/// A pattern whose piece would start through the body is refused before anything runs,
/// and the refusal names the piece.
#[test]
fn a_pattern_that_starts_through_the_body_is_refused_naming_the_piece() {
    // A front panel, and a "belt" lying flat through the torso at 1.2 m (kept in its
    // own transform: it lies flat).
    let square = |side: f32| [[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]];
    let (r, dir) = drape_gc(
        None,
        "belt",
        &[
            (
                "front",
                gc_panel([-20.0, 70.0, 30.0], [0.0; 3], &square(40.0)),
            ),
            (
                "belt",
                gc_panel([-25.0, 110.0, -25.0], [90.0, 0.0, 0.0], &square(50.0)),
            ),
        ],
        &[],
        0.05,
        1,
    );
    let e = r.unwrap_err().to_string();
    assert!(e.contains("(belt through the body in "), "{e}");
    assert!(!e.contains("front"), "{e}");
    assert!(!dir.join("out/report.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// GarmentCode's sleeves, cut and placed for arms held out, go round the A-posed
/// mannequin's arms (turned so the arm runs down their pattern), and keep their own
/// transform beside arms that hang, where bent round the arm they would start through
/// the torso's panels.
#[test]
fn garmentcode_sleeves_go_round_the_arms_of_the_a_posed_mannequin() {
    // GarmentCode's shirt's left sleeve: the arm along -x from the cuff at the origin,
    // turned 50.5 degrees down, in front of the arm and behind it.
    let sleeve = |z: f32| {
        gc_panel(
            [53.6, 111.1, z],
            [0.0, 0.0, -50.5],
            &[[0.0, 0.0], [-54.0, 0.0], [-54.0, -18.7], [0.0, -18.7]],
        )
    };
    let json = serde_json::json!({
        "pattern": {"panels": {"sleeve_f": sleeve(17.5), "sleeve_b": sleeve(-12.5)}, "stitches": []},
        "properties": {"units_in_meter": 100}
    });
    let dir = std::env::temp_dir().join(format!("saiho-gc-sleeves-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sleeves_specification.json");
    std::fs::write(&file, json.to_string()).unwrap();
    for (body, round) in [("mannequin-apose", true), ("mannequin", false)] {
        let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
        cfg.pattern = Some(file.clone());
        cfg.piece_edge = 0.04;
        cfg.body = Some(sim_core::collision::BodyKind::parse(body).unwrap());
        let (design, _) = sim_core::scenario::build_scene(&cfg).unwrap();
        for r in &design.pieces {
            let placed = r.placement.unwrap();
            match placed {
                Placement::Arm {
                    left: true,
                    angle,
                    turn: 3,
                    ..
                } if round => {
                    let behind = r.name == "sleeve_b";
                    assert_eq!(angle > 1.0, behind, "{body} {}: {placed:?}", r.name);
                }
                Placement::Transform { .. } if !round => {}
                other => panic!("{body} {}: {other:?}", r.name),
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `drape-pattern` of the fixture `fixture` (`tests/fixtures/`) on `body` at `edge` m
/// triangles for `frames` frames.
fn fixture_cfg(fixture: &str, body: BodyKind, edge: f32, frames: u64) -> ScenarioConfig {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
    cfg.pattern = Some(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures")
            .join(fixture),
    );
    cfg.body = Some(body);
    cfg.piece_edge = edge;
    cfg.frames = frames;
    cfg
}

/// A GarmentCode fixture draped on `human` at `edge` m triangles for `frames` frames, in
/// a scratch directory named by `tag` (the caller removes it): the report, the cloth's
/// top (m) and the directory.
fn drape_fixture(
    fixture: &str,
    tag: &str,
    edge: f32,
    frames: u64,
) -> (sim_core::scenario::Report, f32, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("saiho-{tag}-{}", std::process::id()));
    let cfg = fixture_cfg(fixture, BodyKind::Human, edge, frames);
    let r = run_scenario(&cfg, &dir.join("out")).unwrap();
    let cloth = sim_core::mesh::obj::load_obj(&dir.join("out/cloth.obj")).unwrap();
    let top = cloth.positions.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    (r, top, dir)
}

/// A full circle skirt (seed 13's random design 11): two half rings whose side seams run
/// along their tops, each wider there than half the way round the body. Bent round the
/// torso's cylinder, as they started until 2026-12-07, each wrapped past the body's sides
/// over the other, and half the pairs stayed open (10 of 20 on this mesh, and the skirt
/// never settled); kept flat where GarmentCode puts them, they are sewn in the air.
#[test]
fn a_full_circle_skirt_starts_flat_and_sews_every_pair() {
    let (r, top, dir) = drape_fixture(
        "gc-full-circle-skirt_specification.json",
        "gc-full-circle",
        0.04,
        300,
    );
    assert!(
        r.notices
            .iter()
            .any(|n| n.contains("start flat where they were placed")),
        "{:?}",
        r.notices
    );
    let (pairs, welded) = (r.ops.seam_pairs.unwrap(), r.ops.seam_pairs_welded.unwrap());
    assert!(pairs >= 16, "{pairs} pairs");
    assert_eq!(welded, pairs, "{welded} of {pairs} pairs welded");
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    assert!(r.settled);
    // Held at the waist (1.09 m) while it settles.
    assert!(top > 1.0 && top < 1.16, "the skirt's top is at {top} m");
    std::fs::remove_dir_all(&dir).ok();
}

/// A half circle skirt drawn in an SVG (two quarter rings as SVG arcs, named "skirt
/// front" and "skirt back", `tests/fixtures/`): its fans are found in the outlines and
/// start on cones at the body's waist, held there while it settles, and it is sewn at
/// both sides. Until 2026-12-07 an SVG's pieces started round the torso's cylinder from
/// the shoulders by their names, and this skirt started through the body (the same
/// skirt for the mannequin crossed it in 295 pairs and was refused).
#[test]
fn a_circle_skirt_drawn_in_an_svg_starts_on_cones_at_the_waist() {
    let (r, top, dir) = drape_fixture("half-circle-skirt.svg", "svg-circle", 0.04, 300);
    let on_cones = (r.notices.iter())
        .filter(|n| n.contains("starts on a cone round the body, its top at the waist"))
        .count();
    assert_eq!(on_cones, 2, "{:?}", r.notices);
    assert!(
        r.ops.held_vertices.unwrap() > 10,
        "{:?}",
        r.ops.held_vertices
    );
    // The release build welds all 30 pairs on this mesh (39 of 40 at 3 cm: one threaded
    // round a fold of the other panel); the test profile's arithmetic (opt-level 1)
    // leaves one of seam A threaded so, 21 mm open, and the run says so.
    let (pairs, welded) = (r.ops.seam_pairs.unwrap(), r.ops.seam_pairs_welded.unwrap());
    assert!(pairs >= 16, "{pairs} pairs");
    assert!(welded + 1 >= pairs, "{welded} of {pairs} pairs welded");
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    assert!(r.settled);
    // On the hips below `human`'s waist (1.11 m), not on the floor.
    assert!(top > 0.95 && top < 1.15, "the skirt's top is at {top} m");
    std::fs::remove_dir_all(&dir).ok();
}

/// GarmentCode's circle skirt on the mannequin: its waistband, which GarmentCode holds at
/// its own body's waist, is held at the mannequin's (1.17 m) while it settles, since the
/// skirt hangs from it. Unheld, as until 2026-12-07, it fell to the mannequin's feet.
#[test]
fn a_garmentcode_skirt_on_another_body_is_held_at_that_bodys_waist() {
    let dir = std::env::temp_dir().join(format!("saiho-gc-held-{}", std::process::id()));
    let cfg = fixture_cfg(
        "gc-circle-skirt_specification.json",
        BodyKind::Mannequin,
        0.05,
        120,
    );
    let r = run_scenario(&cfg, &dir.join("out")).unwrap();
    let cloth = sim_core::mesh::obj::load_obj(&dir.join("out/cloth.obj")).unwrap();
    let low = cloth.positions.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        r.ops.held_vertices.unwrap_or(0) > 20,
        "{:?}",
        r.ops.held_vertices
    );
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    // Hanging from the waist, not lying on the floor.
    assert!(low > 0.2, "the skirt's lowest point is at {low} m");
    // Beside the hanging arms, which its sides close round: told, with the way out.
    assert!(
        (r.notices.iter()).any(|n| n.contains("beside the mannequin's hanging arms")
            && n.contains("--body mannequin-apose")),
        "{:?}",
        r.notices
    );
}

/// A circle skirt draped from the pattern our scenario exported (its pieces start where
/// the pattern saved them, `data-start`) is held at the waist while its seams close, as
/// it was when first draped; until 2026-12-07 it went unheld and was on the floor by
/// frame 150 (its top at 0.28 m).
#[test]
fn a_circle_skirt_draped_again_from_its_pattern_out_is_held_at_the_waist() {
    let (_, _, dir) = drape_fixture("half-circle-skirt.svg", "svg-skirt-again", 0.05, 2);
    let mut cfg = fixture_cfg("half-circle-skirt.svg", BodyKind::Human, 0.05, 150);
    cfg.pattern = Some(dir.join("out/pattern.svg"));
    let r = run_scenario(&cfg, &dir.join("again")).unwrap();
    let cloth = sim_core::mesh::obj::load_obj(&dir.join("again/cloth.obj")).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    let ys = cloth.positions.iter().map(|p| p.y);
    let (low, top) = ys.fold((f32::MAX, f32::MIN), |(l, t), y| (l.min(y), t.max(y)));
    assert!(
        r.ops.held_vertices.unwrap_or(0) > 20,
        "{:?}",
        r.ops.held_vertices
    );
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    assert!(top > 0.9 && low > 0.2, "the skirt spans {low}-{top} m");
}

/// A half circle skirt cut in one piece (a fan of 180 degrees sewn to itself at the back,
/// `tests/fixtures/`) goes round `human` on one cone from the waist, more than half way,
/// and is sewn closed at the back; until 2026-12-07 it started flat in front and before
/// that it was refused as too wide. On the mannequin whose arms hang beside its hips the
/// cone starts through them: refused, the A-posed mannequin named as the way out.
#[test]
fn a_circle_skirt_cut_in_one_piece_goes_round_on_one_cone() {
    let (r, top, dir) = drape_fixture("one-piece-circle-skirt.svg", "svg-one-fan", 0.04, 300);
    assert!(
        (r.notices.iter()).any(|n| n.contains("skirt starts on a cone round the body")),
        "{:?}",
        r.notices
    );
    // `human` holds its arms out: nothing said of them.
    assert!(
        !(r.notices.iter()).any(|n| n.contains("hanging arms")),
        "{:?}",
        r.notices
    );
    let (pairs, welded) = (r.ops.seam_pairs.unwrap(), r.ops.seam_pairs_welded.unwrap());
    assert!(
        pairs >= 10 && welded == pairs,
        "{welded} of {pairs} pairs welded"
    );
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    assert!(top > 0.95 && top < 1.15, "the skirt's top is at {top} m");
    std::fs::remove_dir_all(&dir).ok();

    let cfg = fixture_cfg("one-piece-circle-skirt.svg", BodyKind::Mannequin, 0.04, 1);
    let out = dir.join("hanging");
    let e = run_scenario(&cfg, &out).unwrap_err().to_string();
    assert!(e.contains("(skirt through the body in "), "{e}");
    assert!(
        e.contains("`--body mannequin-apose` holds them clear"),
        "{e}"
    );
    assert!(!out.join("report.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// GarmentCode's circle skirt (two fans 1.57 m wide, `tests/fixtures/`): bent round the
/// torso's cylinder (1.29 m round) its fans could not start; rolled up on cones round the
/// body from the waist they do, are sewn at both sides, and hang from the waist, where
/// they stay once its holds let go (frame 400). Before (2026-11-30) the pattern was
/// refused as too wide; until 2026-12-01 it ran at 5 substeps and slid 0.53 m down the
/// hips once let go.
#[test]
fn a_garmentcode_circle_skirt_starts_on_cones_and_hangs_from_the_waist() {
    let (r, top, dir) = drape_fixture("gc-circle-skirt_specification.json", "gc-circle", 0.04, 560);
    assert_eq!(r.body, "human");
    assert!(
        !r.notices.iter().any(|n| n.contains("slid")),
        "{:?}",
        r.notices
    );
    assert_eq!(r.ops.seams, Some(2), "{:?}", r.notices);
    assert!(
        r.ops.held_vertices.unwrap() > 20,
        "{:?}",
        r.ops.held_vertices
    );
    // It hangs from its waist: xpbd runs it at 20 substeps (at 5 it slid off the hips
    // once let go, docs/garments.md).
    assert_eq!(r.substeps, sim_core::scenario::FIRM_SUBSTEPS);
    assert_eq!((r.crossings_self, r.crossings_body), (0, 0));
    let cloth = sim_core::mesh::obj::load_obj(&dir.join("out/cloth.obj")).unwrap();
    let hem = cloth.positions.iter().map(|p| p.y).fold(f32::MAX, f32::min);
    // It stays round the waist (1.09 m) once let go; fallen, its top would be below the
    // hips (0.8 m; at 5 substeps 0.6 m).
    assert!(top > 1.0 && top < 1.16, "the skirt's top is at {top} m");
    assert!(hem > 0.05 && hem < 0.8, "its hem is at {hem} m");
    std::fs::remove_dir_all(&dir).ok();
}
