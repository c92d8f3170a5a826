//! The published models and lists.

use super::*;
use sim_core::scenario::garment::SEAM_PULL;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_scene};

/// The edge the dress is meshed at where a test needs only its seams, m.
const DRESS_EDGE: f32 = 0.06;

/// The dress scenario's design at `edge` m edges, its seams sewn.
pub(crate) fn sewn_dress(edge: f32) -> sim_core::design::Design {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = edge;
    let (mut d, spec) = build_scene(&cfg).unwrap();
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), SEAM_PULL).unwrap();
    d
}

/// The dress's list names its seams and draws each of its four seams along both its
/// sides: the segments
/// of a seam are as long as its two sides together, but for an edge at each end
/// (the pattern's seam marks, as in pattern.svg, stop short of a corner where the
/// stitched vertices skip one). One side alone would be half.
#[test]
fn the_piece_list_draws_every_seam_along_both_sides() {
    let mut d = sewn_dress(DRESS_EDGE);
    d.name_seam(2, "left side, the longest name a seam could ever have")
        .unwrap();
    let mut l = piece_list(&d, &mut 0);
    let seams = shared::sim_to_ui::check_seams(&l).unwrap();
    let segments = shared::sim_to_ui::check_seam_segments(&l).unwrap();
    assert_eq!(seams.len(), 4);
    // A name is carried, cut at its array's 32 bytes.
    assert_eq!(seams[2].name(), "left side, the longest name a se");
    assert_eq!(seams[0].name(), "");
    for (i, s) in seams.iter().enumerate() {
        let drawn: f32 = segments
            .iter()
            .filter(|g| g.seam as usize == i)
            .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
            .sum();
        let sides = s.lengths[0] + s.lengths[1];
        assert!(
            drawn <= sides + 0.01 && drawn >= sides - 2.0 * DRESS_EDGE,
            "seam {}: drawn {drawn} m, sides {sides} m",
            s.label()
        );
    }
    // The pattern's lines: each listed piece's sewing line as long as the pattern
    // out's, its notches (one per shoulder side, three per side seam side) and one
    // grain line.
    let lines = shared::sim_to_ui::check_outline(&l).unwrap();
    assert_eq!(l.outline_total as usize, lines.len());
    let cut = sim_core::design::sewing_pattern::pieces(&d);
    let listed = shared::sim_to_ui::check_pieces(&l).unwrap();
    assert_eq!(listed.len(), 2);
    for (i, piece) in listed.iter().enumerate() {
        let of = |kind| {
            lines
                .iter()
                .filter(move |g| g.piece == i as u32 && g.kind == kind)
        };
        let sewing: f32 = of(outline::SEWING_LINE)
            .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
            .sum();
        let want = cut
            .iter()
            .find(|p| p.name == piece.name)
            .unwrap()
            .perimeters()[0];
        assert!(
            (sewing as f64 * 1000.0 - want).abs() < 0.5,
            "{}: {sewing} m drawn, {want} mm cut",
            piece.name
        );
        assert_eq!(of(outline::NOTCH).count(), 8, "{}", piece.name);
        assert_eq!(of(outline::GRAIN).count(), 1, "{}", piece.name);
    }
    // Lines naming no listed piece, of no known kind, or not finite are refused.
    for spoil in [
        |g: &mut OutlineSegment| g.piece = 2,
        |g: &mut OutlineSegment| g.kind = 7,
        |g: &mut OutlineSegment| g.b[1] = f32::NAN,
    ] {
        let kept = l.outline[5];
        spoil(&mut l.outline[5]);
        assert!(shared::sim_to_ui::check_outline(&l).is_err());
        l.outline[5] = kept;
    }
    l.outline_count = l.outline_total + 1;
    assert!(shared::sim_to_ui::check_outline(&l).is_err());
}

/// The front cut across at the waist: each side seam is drawn by its two stretches,
/// numbered as the pattern out labels them (B1 front to back, B2 lower front to back),
/// and drawn as long as before the cut but for the cut's own edges (the view dropped
/// a split seam's every segment: "B1" named no seam).
#[test]
fn a_seam_cut_across_is_drawn_by_its_stretches() {
    let mut d = sewn_dress(DRESS_EDGE);
    let drawn = |l: &PieceList, seam: u32, stretch: u32| -> f32 {
        let segments = shared::sim_to_ui::check_seam_segments(l).unwrap();
        (segments.iter())
            .filter(|g| g.seam == seam && g.stretch == stretch)
            .map(|g| glam::Vec2::from(g.a).distance(glam::Vec2::from(g.b)))
            .sum()
    };
    let before = piece_list(&d, &mut 0);
    let whole = [1, 3].map(|s| drawn(&before, s, 0));
    let (lo, hi) = sim_core::mesh::bounds2(&d.pieces[0].outline.loops[0]);
    let y = 0.5 * (lo.y + hi.y);
    let off = d.pieces[0].offset;
    let (a, b) = (
        glam::Vec2::new(lo.x - 0.02, y) + off,
        glam::Vec2::new(hi.x + 0.02, y) + off,
    );
    d.cut_line(a, b).unwrap();
    let l = piece_list(&d, &mut 0);
    for (k, seam) in [1, 3].into_iter().enumerate() {
        let parts = [0, 1, 2].map(|s| drawn(&l, seam, s));
        assert_eq!(parts[0], 0.0, "seam {seam} drawn whole: {parts:?}");
        assert!(parts[1] > 0.1 && parts[2] > 0.1, "seam {seam}: {parts:?}");
        let sum = parts[1] + parts[2];
        assert!(
            sum <= whole[k] + 1e-3 && sum >= whole[k] - 4.0 * DRESS_EDGE,
            "seam {seam}: {sum} m drawn, {} before the cut",
            whole[k]
        );
    }
    let a = (shared::sim_to_ui::check_seam_segments(&l)
        .unwrap()
        .into_iter())
    .find(|g| g.seam == 1 && g.stretch == 2)
    .unwrap();
    assert_eq!(a.label("B"), "B2");
}

/// A dart's drill hole reaches the pattern view where the export drills it: a dart
/// up from the front's hem, one DRILL line (a point) on the front, none before.
#[test]
fn the_piece_list_carries_a_darts_drill_hole() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.03;
    let (mut d, _) = build_scene(&cfg).unwrap();
    let drills = |l: &PieceList| -> Vec<OutlineSegment> {
        (shared::sim_to_ui::check_outline(l).unwrap().into_iter())
            .filter(|g| g.kind == outline::DRILL)
            .collect()
    };
    assert!(drills(&piece_list(&d, &mut 0)).is_empty());
    let (lo, hi) = sim_core::mesh::bounds2(&d.pieces[0].outline.loops[0]);
    let off = d.pieces[0].offset;
    let x = 0.5 * (lo.x + hi.x);
    let point = glam::Vec2::new(x, lo.y + 0.3) + off;
    let toward = glam::Vec2::new(x, lo.y - 0.05) + off;
    d.dart_on_plane(point, toward, 0.04).unwrap();
    let l = piece_list(&d, &mut 0);
    let got = drills(&l);
    assert_eq!(got.len(), 1, "{got:?}");
    assert_eq!(got[0].a, got[0].b);
    // Where the export drills it: the same place from the piece's lowest, leftmost
    // corner (the export lays pieces out, in mm; the view keeps the plane's metres).
    use sim_core::design::sewing_pattern::{finish, pieces};
    let cut = finish(pieces(&d), 0.0);
    let piece = cut.iter().find(|p| !p.drills.is_empty()).unwrap();
    assert_eq!(piece.drills.len(), 1);
    let names = shared::sim_to_ui::check_pieces(&l).unwrap();
    assert_eq!(names[got[0].piece as usize].name, piece.name);
    let corner = |l: &[glam::DVec2]| l.iter().fold(glam::DVec2::INFINITY, |m, q| m.min(*q));
    let sewing: Vec<glam::DVec2> = (shared::sim_to_ui::check_outline(&l).unwrap().iter())
        .filter(|g| g.piece == got[0].piece && g.kind == outline::SEWING_LINE)
        .map(|g| glam::Vec2::from(g.a).as_dvec2() * 1000.0)
        .collect();
    let at = glam::Vec2::from(got[0].a).as_dvec2() * 1000.0 - corner(&sewing);
    let want = piece.drills[0] - corner(&piece.loops[0]);
    assert!(at.distance(want) < 0.05, "{at} mm against {want} mm");
    // The dart's seam is listed as one, pressed toward its first leg, with one press
    // mark; pressed toward its second, the mark turns round (the dress's own seams are
    // no darts).
    let press = |l: &PieceList| {
        let seams = shared::sim_to_ui::check_seams(l).unwrap();
        let marks: Vec<OutlineSegment> = (shared::sim_to_ui::check_outline(l).unwrap())
            .into_iter()
            .filter(|g| g.kind == outline::PRESS)
            .collect();
        (seams.iter().map(|s| s.dart).collect::<Vec<u32>>(), marks)
    };
    let (kinds, marks) = press(&l);
    let dart_seam = d.seams.len() - 1;
    assert_eq!(
        kinds[dart_seam],
        shared::sim_to_ui::dart::FIRST,
        "{kinds:?}"
    );
    assert!(
        kinds[..dart_seam]
            .iter()
            .all(|&k| k == shared::sim_to_ui::dart::NONE)
    );
    assert_eq!(marks.len(), 1);
    d.press_dart(dart_seam, true).unwrap();
    let (kinds, turned) = press(&piece_list(&d, &mut 0));
    assert_eq!(kinds[dart_seam], shared::sim_to_ui::dart::SECOND);
    let way = |g: &OutlineSegment| glam::Vec2::from(g.b) - glam::Vec2::from(g.a);
    assert!(
        way(&marks[0]).dot(way(&turned[0])) < 0.0,
        "{marks:?} {turned:?}"
    );
}

/// A seam whose pairs stopped closing is listed so: a cloth hung from two corners
/// 0.5 m apart, stitched together, which can never close. Before the watch's three
/// seconds the list says nothing stalled; after them, both pairs and their gaps.
/// Beside a long search the pinched vertex goes out at rest where the loop's
/// extrapolation has got it (at most 50 ms on); not pinching, the touch planes.
#[test]
fn the_mid_frame_model_holds_a_pinched_vertex_still_beside_a_search() {
    use sim_core::mesh::ClothMesh;
    use sim_core::solver::{Cloth, Material};
    let mesh = ClothMesh::grid(0.2, 0.2, 4, 4, 0.5).unwrap();
    let cloth = Cloth::new(mesh, &Material::default()).unwrap();
    let held = Held {
        position: Vec3::new(0.0, 0.5, 0.0),
        velocity: Vec3::new(1.0, 0.0, 0.0),
    };
    let b = Between {
        substep: 2,
        substeps: 5,
        held: Some(held),
        cloth: &cloth,
        body: None,
        heartbeat: true,
    };
    let at = |ms: u64| {
        let since = std::time::Duration::from_millis(ms);
        let m = mid_frame_model(
            &b,
            (7, Some(0.0)),
            ((Vec3::ZERO, 9), since),
            &mut 0,
            (100.0, [0.0; 4]),
        );
        assert_eq!((m.pinching, m.frame, m.pen_sent_ns), (1, 7, 9));
        assert_eq!(m.vertex_velocity, [0.0; 3]);
        m.vertex_position[0]
    };
    assert!((at(20) - 0.02).abs() < 1e-6 && (at(400) - 0.05).abs() < 1e-6);
    let b = Between { held: None, ..b };
    let tip = Vec3::new(0.0, 0.5, 0.0);
    let m = mid_frame_model(
        &b,
        (7, Some(0.0)),
        ((tip, 9), Default::default()),
        &mut 0,
        (100.0, [0.0; 4]),
    );
    // The cloth's plane through its vertex under the tip, and the floor.
    assert_eq!((m.pinching, m.plane_count, m.frame), (0, 2, 7));
}

#[test]
fn the_list_marks_the_pairs_that_stopped_closing() {
    use sim_core::design::{Design, STALL_TOLD_AFTER};
    use sim_core::mesh::ClothMesh;
    use sim_core::solver::{Cloth, Environment, Material, ModelKind, Simulation};
    let n = 8u32;
    let mesh = ClothMesh::grid(0.5, 0.5, n as usize, n as usize, 1.0).unwrap();
    let m = Material::default();
    let cloth = Cloth::new(mesh, &m).unwrap();
    let env = Environment {
        floor: None,
        ..Environment::default()
    };
    let sim = Simulation::new(cloth, None, ModelKind::Xpbd, m, env, None).unwrap();
    let mut d = Design::new(sim);
    d.sim.pin(0);
    d.sim.pin(n as usize);
    d.add_seam(&[0, 1], &[n, n - 1], 0.5).unwrap();
    let stalled = |d: &Design| {
        let l = piece_list(d, &mut 0);
        let s = shared::sim_to_ui::check_seams(&l).unwrap()[0];
        (s.open, s.stalled, s.stalled_gap)
    };
    d.step().unwrap();
    assert_eq!(stalled(&d), (2, 0, [0.0; 2]));
    for _ in 0..STALL_TOLD_AFTER + 60 {
        d.step().unwrap();
    }
    let (open, n, [lo, hi]) = stalled(&d);
    assert_eq!((open, n), (2, 2));
    assert!(0.0 < lo && lo <= hi && (hi - 0.5).abs() < 1e-3, "{lo} {hi}");
}

/// The local model carries the scene's workspace: on the mannequin it reaches the
/// body's top and its feet (the default reached only 0.3-0.9 m up), and a pinch's
/// model carries the same one; without a body, the default (all zero).
#[test]
fn the_model_carries_a_workspace_that_reaches_the_whole_body() {
    use shared::sim_to_haptic::TOUCH_HALF_EXTENT_M;
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let (d, _) = build_scene(&cfg).unwrap();
    let body = d.sim.body.as_ref().unwrap();
    let ws = scene_workspace(&d);
    let tip = Vec3::new(0.0, 1.0, 0.5);
    let m = local_model(&d, tip, 0, &mut 0, (100.0, ws));
    shared::Checked::check_body(&m).unwrap();
    assert_eq!(m.workspace, ws);
    for p in &body.vertices {
        for i in 0..3 {
            let reach = TOUCH_HALF_EXTENT_M[i] * ws[3];
            assert!((p[i] - ws[i]).abs() <= reach, "{p} out of {ws:?}");
        }
    }
    let top = body.vertices.iter().map(|p| p.y).fold(0.0, f32::max);
    assert!(top > 1.6, "the mannequin's top at {top} m");
    let held = Held {
        position: Vec3::new(0.0, 1.4, 0.1),
        velocity: Vec3::ZERO,
    };
    assert_eq!(pinch_model(3, held, 0, &mut 0, (100.0, ws)).workspace, ws);
    let mut bare = ScenarioConfig::new(ScenarioName::DrapeCube);
    bare.grid = 4;
    let (mut d, _) = build_scene(&bare).unwrap();
    d.sim.body = None;
    assert_eq!(scene_workspace(&d), [0.0; 4]);
}
