//! Arrangement's tests: pieces bent round the body and the arms.

use super::*;

fn marks() -> Landmarks {
    Landmarks {
        axis: Vec2::new(0.1, -0.2),
        torso: Vec2::new(0.2, 0.15),
        shoulders: 1.5,
        lift: 0.0,
        arms: Some([
            (Vec3::new(0.25, 1.4, 0.0), Vec3::new(0.3, 0.9, 0.0), 0.07),
            (Vec3::new(-0.25, 1.4, 0.0), Vec3::new(-0.3, 0.9, 0.0), 0.07),
        ]),
        garmentcode: Vec3::ZERO,
        profile: Profile::uniform(0.0, 0.1),
        waist: None,
    }
}

/// A 0.3 x 0.2 grid of pattern points, 1 cm apart.
fn grid() -> Vec<Vec2> {
    (0..=30)
        .flat_map(|i| (0..=20).map(move |j| Vec2::new(i as f32 * 0.01, j as f32 * 0.01)))
        .collect()
}

#[test]
fn pieces_bend_round_the_body_by_arc_length_without_stretch() {
    let m = marks();
    let pts = grid();
    let bounds = (Vec2::ZERO, Vec2::new(0.3, 0.2));
    for place in [Place::Front, Place::Back, Place::LeftSide, Place::RightSide] {
        let x = super::place("p", &pts, bounds, &place.at(1.2), &m).unwrap();
        // Neighbours 1 cm apart in the pattern stay 1 cm apart (to the chord).
        for (i, p) in pts.iter().enumerate() {
            for (j, q) in pts.iter().enumerate() {
                if (*p - *q).length() < 0.0101 && i < j {
                    let d = (x[i] - x[j]).length();
                    assert!((d - 0.01).abs() < 2e-4, "{place:?}: {d}");
                }
            }
        }
        // On the cylinder, the top at 1.2 m.
        for p in &x {
            let d = Vec2::new(p.x - m.axis.x, p.z - m.axis.y) / m.torso;
            assert!((d.length() - 1.0).abs() < 1e-3);
            assert!(p.y <= 1.2 + 1e-6 && p.y >= 1.0 - 1e-6);
        }
    }
    // The front's middle is in front of the axis, the left side's to the +X.
    let mid = |place: Place| {
        let x = super::place("p", &[Vec2::new(0.15, 0.2)], bounds, &place.at(1.2), &m).unwrap()[0];
        Vec2::new(x.x - m.axis.x, x.z - m.axis.y)
    };
    assert!(mid(Place::Front).y > 0.14 && mid(Place::Front).x.abs() < 1e-3);
    assert!(mid(Place::LeftSide).x > 0.19);
    assert!(mid(Place::Back).y < -0.14);
    assert!(mid(Place::RightSide).x < -0.19);
}

#[test]
fn the_front_face_faces_out_and_mirroring_turns_it_in() {
    let m = marks();
    // A triangle wound counter-clockwise in the pattern: its normal is the front.
    let tri = [Vec2::ZERO, Vec2::new(0.1, 0.0), Vec2::new(0.0, 0.1)];
    let bounds = (Vec2::ZERO, Vec2::new(0.1, 0.1));
    for angle in [0.0, 1.0, PI, 4.0] {
        for mirrored in [false, true] {
            let p = Placement::Around {
                angle,
                top: 1.0,
                mirrored,
                out: 0.0,
            };
            let x = super::place("p", &tri, bounds, &p, &m).unwrap();
            let n = (x[1] - x[0]).cross(x[2] - x[0]);
            let out = Vec3::new(x[0].x - m.axis.x, 0.0, x[0].z - m.axis.y);
            assert_eq!(n.dot(out) > 0.0, !mirrored, "angle {angle}");
        }
    }
    // Round an arm too.
    let x = super::place("p", &tri, bounds, &Place::LeftArm.at(0.1), &m).unwrap();
    let (s, w, _) = m.arms.unwrap()[0];
    let axis = (w - s).normalize();
    let c = s + axis * axis.dot(x[0] - s);
    let n = (x[1] - x[0]).cross(x[2] - x[0]);
    assert!(n.dot(x[0] - c) > 0.0);
    assert!(((x[0] - c).length() - 0.07).abs() < 1e-4);
}

#[test]
fn the_human_bodys_landmarks_are_on_its_mesh() {
    let body = crate::collision::BodyKind::Human.build().unwrap();
    let m = Landmarks::of(Some(&body));
    assert_eq!(
        m.garmentcode,
        Vec3::ZERO,
        "GarmentCode's patterns are placed for it"
    );
    // The arms' axes run inside the arms, 45 degrees below the horizontal.
    for (s, w, r) in m.arms.unwrap() {
        for t in [0.0, 0.5, 1.0] {
            let p = s.lerp(w, t);
            assert!(body.penetration(p) > 0.015, "{p}: {}", body.penetration(p));
        }
        let d = (w - s).normalize();
        assert!((-d.y).asin().to_degrees() > 40.0 && (-d.y).asin().to_degrees() < 50.0);
        assert!(r > 0.05 && r < 0.1);
    }
    // The torso's cylinder clears the torso (inside the arms) from the hips to the
    // shoulders, and the shoulders are below where the tops start.
    for v in &body.vertices {
        if v.x.abs() < 0.18 && (0.8..1.45).contains(&v.y) {
            let d = Vec2::new(v.x - m.axis.x, v.z - m.axis.y) / m.torso;
            assert!(d.length() < 0.96, "{v}: {}", d.length());
        }
        if v.x.abs() > 0.1 && v.x.abs() < 0.15 {
            assert!(v.y < m.shoulders - m.lift + 0.01, "{v}");
        }
    }
}

#[test]
fn a_cone_placement_is_saved_and_read_back() {
    let cone = Placement::Cone {
        angle: 3.1,
        top: 1.12,
        mirrored: true,
        centre: Vec2::new(0.18, 0.16),
        inner: 0.245,
        sine: 0.7,
    };
    let text = serde_json::to_string(&cone).unwrap();
    assert!(text.contains(r#""kind":"cone""#), "{text}");
    assert_eq!(serde_json::from_str::<Placement>(&text).unwrap(), cone);
}

/// A sleeve as wide as the way round its arm's cylinder, or wider, goes round a
/// wider one: its long edges a tenth of the way round apart, its points at the
/// distances they have in the pattern (a 0.44 m sleeve was refused on a 0.44 m arm).
#[test]
fn a_sleeve_as_wide_as_the_arm_goes_round_it_loosely() {
    let m = marks();
    let (s, w, r) = m.arms.unwrap()[0];
    let axis = (w - s).normalize();
    for width in [0.3, TAU * r, 0.6] {
        let pts: Vec<Vec2> = (0..=60)
            .flat_map(|i| [0.0, 0.01].map(|y| Vec2::new(width * i as f32 / 60.0, y)))
            .collect();
        let bounds = (Vec2::ZERO, Vec2::new(width, 0.01));
        let x = super::place("sleeve", &pts, bounds, &Place::LeftArm.at(0.1), &m).unwrap();
        let radius = |p: Vec3| (p - s - axis * axis.dot(p - s)).length();
        let want = r.max(width / (TAU * ARM_WRAP));
        for (i, p) in x.iter().enumerate() {
            assert!((radius(*p) - want).abs() < 1e-4, "{width}: {}", radius(*p));
            if let Some(q) = x.get(i + 2) {
                let d = (*p - *q).length();
                assert!((d - width / 60.0).abs() < 2e-4, "{width}: {d}");
            }
        }
        // Its middle faces out from the body, its edges meet under the arm.
        let mid = x[60];
        assert!(mid.x - s.x > 0.9 * want, "{width}: {mid}");
        // The two long edges' ends stay apart: at least the gap's chord.
        let gap = (x[0] - x[120]).length();
        let least = 2.0 * want * (PI * (1.0 - ARM_WRAP)).sin() * 0.99;
        assert!(gap >= least.min(0.01 * width), "{width}: {gap} < {least}");
        if width >= TAU * r {
            assert!(gap >= least, "{width}: {gap} < {least}");
        }
    }
}

/// Round the right arm the middle faces out too: to -X.
#[test]
fn a_piece_on_the_right_arm_faces_out_to_the_right() {
    let m = marks();
    let (s, _, r) = m.arms.unwrap()[1];
    let pts = [Vec2::new(0.05, 0.1), Vec2::ZERO, Vec2::new(0.1, 0.0)];
    let bounds = (Vec2::ZERO, Vec2::new(0.1, 0.1));
    let x = super::place("p", &pts, bounds, &Place::RightArm.at(0.0), &m).unwrap();
    assert!(s.x - x[0].x > 0.99 * r, "{}", x[0]);
}

#[test]
fn too_wide_or_no_arms_is_refused() {
    let mut m = marks();
    let wide = (Vec2::ZERO, Vec2::new(1.5, 0.2));
    assert!(matches!(
        super::place("p", &[Vec2::ZERO], wide, &Place::Front.at(1.0), &m),
        Err(PlaceError::TooWide { .. })
    ));
    m.arms = None;
    let small = (Vec2::ZERO, Vec2::new(0.1, 0.1));
    assert_eq!(
        super::place("sleeve", &[Vec2::ZERO], small, &Place::RightArm.at(0.0), &m),
        Err(PlaceError::NoArms {
            piece: "sleeve".into()
        })
    );
    assert_eq!(Place::parse("Left side"), Some(Place::LeftSide));
    assert_eq!(Place::parse("left_arm"), Some(Place::LeftArm));
    assert_eq!(Place::parse("hat"), None);
}
