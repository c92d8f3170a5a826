//! The GarmentCode reader's tests.

use super::*;
use crate::design::garment::cone::Profile;

/// A front and a back rectangle in GarmentCode's form (cm), the front's top edge a
/// quadratic curve, the back turned half round; stitched at both sides.
const TWO_PANELS: &str = r#"{
  "pattern": {
    "panels": {
      "front": {
        "translation": [-25, 90, 30], "rotation": [0, 0, 0],
        "vertices": [[0, 0], [50, 0], [50, 60], [0, 60]],
        "edges": [
          {"endpoints": [0, 1]}, {"endpoints": [1, 2]},
          {"endpoints": [2, 3], "curvature": {"type": "quadratic", "params": [[0.5, 0.2]]}},
          {"endpoints": [3, 0]}
        ]
      },
      "back": {
        "translation": [25, 90, -25], "rotation": [0, 180, 0],
        "vertices": [[0, 0], [50, 0], [50, 60], [0, 60]],
        "edges": [
          {"endpoints": [0, 1]}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]},
          {"endpoints": [3, 0]}
        ]
      }
    },
    "stitches": [
      [{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
      [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}]
    ]
  },
  "properties": {"units_in_meter": 100, "curvature_coords": "relative"}
}"#;

/// A body with no arms, GarmentCode's standing `garmentcode` from its origin.
fn armless(garmentcode: Vec3) -> Landmarks {
    Landmarks {
        axis: Vec2::ZERO,
        torso: Vec2::new(0.215, 0.175),
        shoulders: 1.53,
        lift: 0.03,
        arms: None,
        garmentcode,
        profile: Profile::uniform(0.0, 0.15),
        waist: None,
    }
}

#[test]
fn panels_stitches_and_placement_are_read() {
    let marks = armless(Vec3::Y * GC_RAISE);
    let spec = read_garmentcode(TWO_PANELS, &marks).unwrap();
    assert_eq!(spec.pieces.len(), 2);
    assert_eq!(spec.seams.len(), 2);
    // Panels come in the order of their names (JSON objects have none).
    let (fi, bi) = (1, 0);
    let front = &spec.pieces[fi];
    assert_eq!(front.name, "front");
    // cm to m; the top edge, run right to left, curves to its left (down) by half
    // its control point's 0.2 x 0.5 m.
    let l = &front.outline.loops[0];
    let top = l.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    let dip = l
        .iter()
        .filter(|p| (p.x - 0.25).abs() < 0.01 && p.y > 0.3)
        .map(|p| p.y)
        .fold(f32::MAX, f32::min);
    assert!((top - 0.6).abs() < 1e-5, "{top}");
    assert!((dip - 0.55).abs() < 2e-3, "{dip}");
    // The front goes in front, the back (turned round) at the back, both reading
    // the right way out; the tops 10 cm higher on our body, and the lift above.
    match (front.placement, spec.pieces[bi].placement) {
        (
            Some(Placement::Around {
                angle: a,
                top: t,
                mirrored: false,
                ..
            }),
            Some(Placement::Around {
                angle: b,
                mirrored: false,
                ..
            }),
        ) => {
            assert!(a.abs() < 0.05, "{a}");
            assert!(
                (b.rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI).abs() < 0.05,
                "{b}"
            );
            assert!((t - (0.9 + 0.6 + GC_RAISE + 0.03)).abs() < 2e-3, "{t}");
        }
        other => panic!("{other:?}"),
    }
    // The front's right side (edge 1, up) meets the back's edge 3.
    let s = &spec.seams[0];
    assert_eq!((s.a.piece, s.b.piece), (fi, bi));
    assert!(s.a.from.abs_diff_eq(Vec2::new(0.5, 0.0), 1e-6), "{s:?}");
    assert!(s.a.to.abs_diff_eq(Vec2::new(0.5, 0.6), 1e-6), "{s:?}");
    assert!(
        read_garmentcode("{}", &marks)
            .unwrap_err()
            .contains("pattern")
    );
    let broken = TWO_PANELS.replace("\"edge\": 3}", "\"edge\": 9}");
    assert!(
        read_garmentcode(&broken, &marks)
            .unwrap_err()
            .contains("edge 9")
    );
}

#[test]
fn labelled_waistbands_are_held_where_garmentcode_holds_them() {
    let marks = armless(Vec3::new(0.01, GC_RAISE, 0.0));
    assert!(
        read_garmentcode(TWO_PANELS, &marks)
            .unwrap()
            .holds
            .is_empty()
    );
    // The front's bottom (edge 0) a waistband, the back's bottom an unknown label,
    // the back's right side (edge 1) a neckline's left side: held only the first.
    let labelled = TWO_PANELS
        .replacen(
            r#"{"endpoints": [0, 1]}"#,
            r#"{"endpoints": [0, 1], "label": "lower_interface"}"#,
            1,
        )
        .replacen(
            r#"{"endpoints": [0, 1]}"#,
            r#"{"endpoints": [0, 1], "label": "bogus"}"#,
            1,
        )
        .replacen(
            r#"{"endpoints": [1, 2]}, {"endpoints": [2, 3]}"#,
            r#"{"endpoints": [1, 2], "label": "left_collar"}, {"endpoints": [2, 3]}"#,
            1,
        );
    let spec = read_garmentcode(&labelled, &marks).unwrap();
    assert_eq!(spec.holds.len(), 1, "{:?}", spec.holds);
    let waist = spec.holds.iter().find(|h| h.label == "lower_interface");
    let waist = waist.unwrap();
    // The back is piece 0, the front piece 1 (by name).
    assert_eq!(waist.edge.piece, 1);
    assert!(waist.edge.from.abs_diff_eq(Vec2::ZERO, 1e-6));
    assert!(waist.edge.to.abs_diff_eq(Vec2::new(0.5, 0.0), 1e-6));
    assert_eq!(waist.normal, Vec3::Y);
    assert!((waist.level - (1.0877 + GC_RAISE)).abs() < 1e-6);
}

/// GarmentCode's own body's landmarks, as `Landmarks::of` gives them for `human`.
fn human_marks() -> Landmarks {
    let arm = |x: f32| {
        (
            Vec3::new(x * 0.21, 1.33, -0.03),
            Vec3::new(x * 0.52, 1.035, 0.02),
            0.085,
        )
    };
    Landmarks {
        axis: Vec2::new(0.0, -0.005),
        torso: Vec2::new(0.21, 0.20),
        shoulders: 1.52,
        lift: 0.08,
        arms: Some([arm(1.0), arm(-1.0)]),
        garmentcode: Vec3::ZERO,
        profile: Profile::uniform(0.0, 0.15),
        waist: None,
    }
}

/// A panel: its name, corners (cm), translation and rotation.
type Panel<'a> = (&'a str, &'a [[f32; 2]], [f32; 3], [f32; 3]);

/// A GarmentCode pattern of straight-edged panels, no stitches.
fn panels(list: &[Panel]) -> String {
    let panels: serde_json::Map<String, Value> = list
        .iter()
        .map(|&(name, corners, t, r)| {
            let n = corners.len();
            let edges: Vec<Value> = (0..n)
                .map(|k| serde_json::json!({"endpoints": [k, (k + 1) % n]}))
                .collect();
            let panel = serde_json::json!({
                "translation": t, "rotation": r, "vertices": corners, "edges": edges
            });
            (name.to_string(), panel)
        })
        .collect();
    serde_json::json!({"pattern": {"panels": panels, "stitches": []}}).to_string()
}

#[test]
fn front_and_back_cuffs_go_in_front_of_and_behind_the_arm() {
    // A random design's left cuff: two 38 x 5.4 cm panels turned 44.5 degrees, their
    // pattern's -y down the arm, both facing +z, 17.5 cm in front and 12.5 behind.
    let cuff: &[[f32; 2]] = &[[0.0, 0.0], [38.0, 0.0], [38.0, 5.4], [0.0, 5.4]];
    let spec = read_garmentcode(
        &panels(&[
            ("cuff_f", cuff, [55.1, 124.2, 17.5], [0.0, 0.0, 44.5]),
            ("cuff_b", cuff, [55.1, 124.2, -12.5], [0.0, 0.0, 44.5]),
        ]),
        &human_marks(),
    )
    .unwrap();
    let angle = |name: &str| match spec.pieces.iter().find(|p| p.name == name) {
        Some(PieceSpec {
            placement:
                Some(Placement::Arm {
                    left: true,
                    angle,
                    turn: 0,
                    ..
                }),
            ..
        }) => *angle,
        other => panic!("{name}: {other:?}"),
    };
    assert_eq!(angle("cuff_f"), 0.0);
    assert!((angle("cuff_b") - std::f32::consts::PI).abs() < 1e-6);
}

#[test]
fn a_short_sleeve_goes_round_the_arm_and_its_cuff_at_its_end() {
    // A random design's left short sleeve (its middle 2.7 cm past the torso's side, its
    // halves 28.6 cm round) and cuff.
    let sleeve: &[[f32; 2]] = &[[0.0, 0.0], [-27.1, 0.0], [-15.7, -28.6], [0.0, -11.6]];
    let cuff: &[[f32; 2]] = &[[0.0, 0.0], [-8.3, 0.0], [-8.3, 5.4], [0.0, 5.4]];
    let spec = read_garmentcode(
        &panels(&[
            ("sleeve_f", sleeve, [42.7, 120.0, 17.5], [0.0, 0.0, -45.5]),
            ("cuff_f", cuff, [47.9, 114.7, 17.5], [0.0, 0.0, 44.5]),
        ]),
        &human_marks(),
    )
    .unwrap();
    let arm = |name: &str| match spec.pieces.iter().find(|p| p.name == name) {
        Some(PieceSpec {
            placement:
                Some(Placement::Arm {
                    left: true,
                    down,
                    room,
                    ..
                }),
            ..
        }) => (*down, *room),
        other => panic!("{name}: {other:?}"),
    };
    let (sleeve_down, room) = arm("sleeve_f");
    assert_eq!(sleeve_down, TURNED_SLEEVE_DOWN);
    // Half way round an arm 28.6 cm round at most, with 5% to spare.
    let r = 0.085 + room;
    assert!(
        (std::f32::consts::PI * r * 0.95 - 0.286).abs() < 1e-3,
        "{r}"
    );
    // The cuff as far below the sleeve's start as on their arm (28.6 cm: the sleeve
    // starts at the shoulder there).
    let (down, room) = arm("cuff_f");
    assert!(down > CUFF_START, "{down}");
    assert!((down - sleeve_down - 0.286).abs() < 0.005, "{down}");
    assert_eq!(room, 0.0);
}

#[test]
fn arcs_pass_through_their_ends_and_bulge_the_asked_way() {
    let (p, q) = (Vec2::ZERO, Vec2::new(2.0, 0.0));
    for (large, right) in [(false, false), (false, true), (true, false), (true, true)] {
        let pts = arc(p, q, 1.5, large, right, 32);
        let c = pts[15];
        // Right of p -> q (going +x) is -y.
        assert_eq!(c.y < 0.0, right, "{large} {right}");
        let depth = pts.iter().map(|v| v.y.abs()).fold(0.0, f32::max);
        let small = 1.5 - (1.5f32 * 1.5 - 1.0).sqrt();
        let want = if large { 3.0 - small } else { small };
        assert!(
            (depth - want).abs() < 0.02,
            "{large} {right}: {depth} {want}"
        );
    }
}

/// GarmentCode's circle skirt of a random design (`bench/gc_sample.py`, seed 7, design 9)
/// on its own body: front and back fans of 99 degrees, 24.5 cm round their centre at the
/// top and 103.3 cm at the hem, 1.57 m wide; the back as the front (not turned), 30 cm
/// behind it. Its top, which their design put lower, is at their body's waist (108.8
/// cm), labelled as their waistbands are.
const CIRCLE_SKIRT: &str =
    include_str!("../../../../tests/fixtures/gc-circle-skirt_specification.json");

#[test]
fn a_circle_skirts_fans_start_on_cones_clear_of_the_body() {
    let body = crate::collision::BodyKind::Human.build().unwrap();
    let marks = Landmarks::of(Some(&body));
    let spec = read_garmentcode(CIRCLE_SKIRT, &marks).unwrap();
    for (name, facing) in [("skirt_front", 0.0), ("skirt_back", std::f32::consts::PI)] {
        let p = spec.pieces.iter().find(|p| p.name == name).unwrap();
        let pl = p.placement.unwrap();
        let Placement::Cone {
            angle,
            top,
            mirrored,
            inner,
            sine,
            ..
        } = pl
        else {
            panic!("{name}: {pl:?}");
        };
        // Facing out at the front and at the back, the back's pattern running the other
        // way round; the top arc's ends where their file puts them.
        // (Their fans stand 7 mm to the body's right of its middle.)
        let off = (angle - facing + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU)
            - std::f32::consts::PI;
        assert!(off.abs() < 0.05, "{name}: {angle}");
        assert_eq!(mirrored, facing != 0.0, "{name}");
        assert!((top - (1.0877 + marks.lift)).abs() < 1e-3, "{name}: {top}");
        assert!((inner - 0.24483).abs() < 1e-4, "{name}: {inner}");
        assert!(sine > 0.5 && sine < 1.0, "{name}: {sine}");
        let outline = &p.outline.loops[0];
        let x =
            super::super::place::place(name, outline, crate::mesh::bounds2(outline), &pl, &marks)
                .unwrap();
        for q in &x {
            // Level at the top, and clear of the body below it by the cone's clearance.
            assert!(q.y <= top + 1e-4 && q.y > 0.0, "{name}: {q}");
            let k = ((q.y - marks.profile.base) / cone::BAND) as usize;
            let r = Vec2::new(q.x - marks.axis.x, q.z - marks.axis.y).length();
            assert!(r > marks.profile.radii[k], "{name}: {q} at {r}");
            assert_eq!(body.penetration(*q), 0.0, "{name}: {q} is in the body");
        }
        // Round the body: each fan less than half way round, in front or behind.
        let widest = (x.iter())
            .map(|q| {
                let a = (q.x - marks.axis.x).atan2(q.z - marks.axis.y) - angle;
                (a + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI
            })
            .fold(0.0f32, |m, a| m.max(a.abs()));
        assert!(
            widest < 0.5 * std::f32::consts::PI,
            "{name} goes {} degrees from its middle",
            widest.to_degrees()
        );
    }
}

#[test]
fn a_panel_whose_curve_runs_across_another_side_is_refused_naming_both() {
    // A 50 x 60 cm panel whose top edge, a neckline, dips through its bottom edge.
    let text = serde_json::json!({"pattern": {"panels": {"back": {
        "translation": [0, 100, -20], "rotation": [0, 0, 0],
        "vertices": [[0, 0], [50, 0], [50, 60], [0, 60]],
        "edges": [
            {"endpoints": [0, 1]}, {"endpoints": [1, 2]},
            {"endpoints": [2, 3], "label": "left_collar",
             "curvature": {"type": "quadratic", "params": [[0.5, 3.0]]}},
            {"endpoints": [3, 0]}
        ]
    }}, "stitches": []}})
    .to_string();
    let e = read_garmentcode(&text, &human_marks()).unwrap_err();
    assert!(
        e.starts_with("panel back: its outline crosses itself")
            && e.contains("edge 0")
            && e.contains("edge 2 (left_collar)"),
        "{e}"
    );
    // Dipping to 10 cm above the bottom, it is read.
    let fine = text.replace("3.0", "2.0");
    assert!(read_garmentcode(&fine, &human_marks()).is_ok());
}

#[test]
fn a_stitch_pairs_the_ends_garmentcode_pairs() {
    let marks = armless(Vec3::Y * GC_RAISE);
    // GarmentCode sews the end of a stitch's first edge to the start of its second (in
    // the file's directions), unless the stitch says "right_wrong".
    let spec = read_garmentcode(TWO_PANELS, &marks).unwrap();
    assert!(spec.seams.iter().all(|s| s.reversed == Some(true)));
    let wrong = TWO_PANELS.replace(
        r#"{"panel": "back", "edge": 1}]"#,
        r#"{"panel": "back", "edge": 1}, "right_wrong"]"#,
    );
    let spec = read_garmentcode(&wrong, &marks).unwrap();
    assert_eq!(
        spec.seams.iter().map(|s| s.reversed).collect::<Vec<_>>(),
        [Some(true), Some(false)]
    );
    // A panel drawn clockwise runs the other way here (its ends swapped), and the
    // pairing with it too, so that the ends GarmentCode sews meet: front (50, 60) with
    // the back's (0, 0), the start of its edge 0, which runs up its left side.
    let mut two: Value = serde_json::from_str(TWO_PANELS).unwrap();
    let back = &mut two["pattern"]["panels"]["back"];
    back["edges"] = serde_json::json!([
        {"endpoints": [0, 3]}, {"endpoints": [3, 2]}, {"endpoints": [2, 1]}, {"endpoints": [1, 0]}
    ]);
    two["pattern"]["stitches"] = serde_json::json!([
        [{"panel": "front", "edge": 1}, {"panel": "back", "edge": 0}]
    ]);
    let spec = read_garmentcode(&two.to_string(), &marks).unwrap();
    let s = &spec.seams[0];
    assert_eq!(spec.pieces[s.a.piece].name, "front");
    assert!((s.a.to - Vec2::new(0.5, 0.6)).length() < 1e-6, "{:?}", s.a);
    let meets_a_to = if s.reversed.unwrap() {
        s.b.from
    } else {
        s.b.to
    };
    assert!(meets_a_to.length() < 1e-6, "{s:?}");
}

#[test]
fn a_panel_too_large_to_mesh_is_refused_before_any_work() {
    // Found by the pattern-mesh fuzz target: the back panel 5.6e17 m wide (a mistyped
    // number). Resampling its seams' sides asked for a 4.4e18-byte allocation and
    // aborted; now its span is checked first and the error names the piece.
    let marks = Landmarks::of(None);
    let back_sized = |x: &str, y: &str| {
        let (front, back) = TWO_PANELS.split_once(r#""back""#).unwrap();
        let sized = format!("[{x}, 0], [{x}, {y}], [0, {y}]");
        let back = back.replacen("[50, 0], [50, 60], [0, 60]", &sized, 1);
        let mut spec = read_garmentcode(&format!(r#"{front}"back"{back}"#), &marks).unwrap();
        spec.normalise().unwrap();
        spec.arrange(&marks);
        spec
    };
    let assemble = crate::design::garment::assemble;
    let e = assemble(&back_sized("55555555555555555550", "60"), &marks, 0.5)
        .err()
        .expect("refused")
        .to_string();
    assert!(e.starts_with("piece back: the outline spans"), "{e}");
    // Within the span (1 x 9 m) but too many vertices at the edge asked for: refused
    // by the estimate before the seams' sides are resampled.
    let e = assemble(&back_sized("100", "900"), &marks, 0.001)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        e.starts_with("piece back: the piece would have") && e.contains("more than 4000000"),
        "{e}"
    );
    // At its own size the same pattern meshes.
    assert!(assemble(&back_sized("50", "60"), &marks, 0.05).is_ok());
}

/// A panel taller than a waistband whose top is two runs with a waist between them, wider
/// from end to end than half the way round the torso, is kept flat where its file puts
/// it (a full circle skirt's half ring); an A-line skirt's panel, wide only at its hem,
/// a waistband and a gathered skirt's panel as wide along one run are not.
#[test]
fn only_a_tall_panel_wider_at_its_top_than_half_round_is_kept_flat() {
    let marks = human_marks();
    let half = 0.5 * marks.girth();
    let (rot, trans) = (Mat3::IDENTITY, Vec3::new(-0.13, 1.09, 0.15));
    // A half ring, 0.97 m along its top (the side seams and the waist between), its
    // hem 0.49 m below.
    let ring: Vec<Vec2> = (0..=32)
        .map(|k| {
            let a = std::f32::consts::PI * k as f32 / 32.0;
            Vec2::new(0.13 - 0.49 * a.cos(), -0.49 * a.sin())
        })
        .chain((0..=16).map(|k| {
            let a = std::f32::consts::PI * (16 - k) as f32 / 16.0;
            Vec2::new(0.13 - 0.134 * a.cos(), -0.134 * a.sin())
        }))
        .collect();
    assert!(0.97 > half);
    match kept_flat(&ring, rot, trans, &marks) {
        Some(Placement::Transform {
            rotation,
            translation,
        }) => assert_eq!((rotation, translation), (rot, trans)),
        other => panic!("{other:?}"),
    }
    // An A-line panel: 0.3 m at the waist, 0.9 m at the hem 0.6 m below.
    let a_line = [
        Vec2::new(0.0, 0.0),
        Vec2::new(-0.3, -0.6),
        Vec2::new(0.6, -0.6),
        Vec2::new(0.3, 0.0),
    ];
    assert_eq!(kept_flat(&a_line, rot, trans, &marks), None);
    // A waistband 0.8 m long and 8 cm tall.
    let band = [
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, -0.08),
        Vec2::new(0.8, -0.08),
        Vec2::new(0.8, 0.0),
    ];
    assert_eq!(kept_flat(&band, rot, trans, &marks), None);
    // A gathered skirt's panel, 1 m along its top too, but its top is its waist seam:
    // one run, no waist dipping between two.
    let gathered = [
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, -0.6),
        Vec2::new(1.0, -0.6),
        Vec2::new(1.0, 0.0),
    ];
    assert_eq!(kept_flat(&gathered, rot, trans, &marks), None);
    // The half ring turned upside down is wide at its hem, not its top.
    let flipped = Mat3::from_rotation_z(std::f32::consts::PI);
    assert_eq!(kept_flat(&ring, flipped, trans, &marks), None);
}

/// A panel kept flat, moved out, goes along its normal away from the body's axis: a
/// front forward, a back backward, whichever way its face turns; other placements stay.
#[test]
fn a_flat_panel_moves_out_away_from_the_body() {
    let marks = human_marks();
    let bounds = (Vec2::new(-0.5, -0.5), Vec2::new(0.5, 0.0));
    for (z, turn) in [
        (0.175f32, 0.0f32),
        (-0.125, 0.0),
        (-0.125, 180.0),
        (0.175, 180.0),
    ] {
        let rotation = Mat3::from_rotation_y(turn.to_radians());
        let pl = Placement::Transform {
            rotation,
            translation: Vec3::new(0.0, 1.0, z),
        };
        match moved_out(pl, bounds, &marks, 0.03) {
            Placement::Transform {
                rotation: r,
                translation,
            } => {
                assert_eq!(r, rotation);
                let want = Vec3::new(0.0, 1.0, z + 0.03 * z.signum());
                assert!(
                    (translation - want).length() < 1e-5,
                    "{translation} for {z} {turn}"
                );
            }
            other => panic!("{other:?}"),
        }
    }
    let around = Placement::Around {
        angle: 0.0,
        top: 1.0,
        mirrored: false,
        out: 0.0,
    };
    assert_eq!(moved_out(around, bounds, &marks, 0.03), around);
}
