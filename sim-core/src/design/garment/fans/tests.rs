//! Fans found in outlines drawn as polylines, and where they start.

use super::*;
use crate::design::garment::cone::Profile;

/// A fan round `centre` from radius `r` to `big`, `deg` degrees opening down, its arcs
/// as `n` segments each (as a file's arcs are flattened), counter-clockwise.
fn fan(centre: Vec2, r: f32, big: f32, deg: f32, n: usize) -> Vec<Vec2> {
    let half = 0.5 * deg.to_radians();
    let at = |rad: f32, a: f32| centre + Vec2::new(a.sin(), -a.cos()) * rad;
    let mut pts: Vec<Vec2> = (0..=n)
        .map(|k| at(big, -half + 2.0 * half * k as f32 / n as f32))
        .collect();
    pts.extend((0..=n).map(|k| at(r, half - 2.0 * half * k as f32 / n as f32)));
    pts
}

/// A standing body 1.7 m tall whose widest reach is 15 cm everywhere, its waist 1.05 m up.
fn body() -> Landmarks {
    Landmarks {
        axis: Vec2::new(0.1, -0.05),
        torso: Vec2::new(0.2, 0.15),
        shoulders: 1.5,
        lift: 0.0,
        arms: None,
        garmentcode: Vec3::ZERO,
        profile: Profile::uniform(0.0, 0.15),
        waist: Some(1.05),
    }
}

#[test]
fn a_fan_drawn_as_polylines_is_found_with_its_centre_and_top_radius() {
    for (deg, n) in [(90.0, 48), (180.0, 96), (280.0, 64), (60.0, 12)] {
        let centre = Vec2::new(0.4, 0.1);
        let outline = fan(centre, 0.24, 0.84, deg, n);
        let (f, top) = fan_in(&outline).unwrap_or_else(|| panic!("{deg} degrees"));
        // The top arc's ends, in the outline's order.
        let half = 0.5 * f32::to_radians(deg);
        let end = |a: f32| centre + Vec2::new(a.sin(), -a.cos()) * 0.24;
        assert!((top.0 - end(half)).length() < 1e-5 && (top.1 - end(-half)).length() < 1e-5);
        assert!((f.centre - centre).length() < 1e-3, "{deg}: {:?}", f.centre);
        assert!((f.inner - 0.24).abs() < 1e-3, "{deg}: {}", f.inner);
    }
    // Wherever the loop starts.
    let mut outline = fan(Vec2::ZERO, 0.3, 0.9, 120.0, 40);
    outline.rotate_left(17);
    assert!((fan_in(&outline).unwrap().0.inner - 0.3).abs() < 1e-3);
}

#[test]
fn outlines_that_are_no_fan_have_none() {
    let rect = vec![
        Vec2::ZERO,
        Vec2::new(0.5, 0.0),
        Vec2::new(0.5, 0.8),
        Vec2::new(0.0, 0.8),
    ];
    assert_eq!(fan_in(&rect), None);
    // A rectangle with its corners rounded: arcs of one radius round four centres.
    let mut rounded = Vec::new();
    for (k, c) in [
        (0, Vec2::new(0.45, 0.05)),
        (1, Vec2::new(0.45, 0.75)),
        (2, Vec2::new(0.05, 0.75)),
        (3, Vec2::new(0.05, 0.05)),
    ] {
        for s in 0..=8 {
            let a = (k as f32 - 1.0 + s as f32 / 8.0) * FRAC_PI_2;
            rounded.push(c + Vec2::new(a.cos(), a.sin()) * 0.05);
        }
    }
    assert_eq!(fan_in(&rounded), None);
    // Two arcs round one centre 3 cm apart in radius: a curved band, not a fan.
    assert_eq!(fan_in(&fan(Vec2::ZERO, 0.30, 0.33, 90.0, 20)), None);
    // Points on no circle (a zigzag) and too few points.
    let zig: Vec<Vec2> = (0..40)
        .map(|k| Vec2::new(k as f32 * 0.01, if k % 2 == 0 { 0.0 } else { 0.01 }))
        .chain([Vec2::new(0.4, -0.5), Vec2::new(0.0, -0.5)])
        .collect();
    assert_eq!(fan_in(&zig), None);
    assert!(arcs_of(&rect[..3]).is_empty());
}

/// The fan's pattern points' start positions under `placement`.
fn started(outline: &[Vec2], placement: &Placement, marks: &Landmarks) -> Vec<Vec3> {
    let bounds = crate::mesh::bounds2(outline);
    super::super::place("skirt", outline, bounds, placement, marks).unwrap()
}

#[test]
fn a_quarter_ring_starts_on_a_cone_at_the_waist() {
    let marks = body();
    let outline = fan(Vec2::new(0.3, 0.0), 0.24, 0.84, 90.0, 48);
    let fan = fan_start(&outline, Place::Back, &marks, &[]).unwrap();
    assert!((fan.angle.to_degrees() - 90.0).abs() < 0.5, "{}", fan.angle);
    let FanStart::Cone(on) = fan.start else {
        panic!("{:?}", fan.start)
    };
    let x = started(&outline, &on, &marks);
    // The top arc level at the waist, every point clear of the body, behind it.
    let top: Vec<&Vec3> = (x.iter().zip(&outline))
        .filter(|(_, p)| ((**p - Vec2::new(0.3, 0.0)).length() - 0.24).abs() < 1e-4)
        .map(|(x, _)| x)
        .collect();
    assert!(top.len() > 40);
    assert!(top.iter().all(|x| (x.y - 1.05).abs() < 1e-4), "{top:?}");
    let from_axis = |x: &Vec3| Vec2::new(x.x - marks.axis.x, x.z - marks.axis.y);
    assert!(x.iter().all(|x| from_axis(x).length() > 0.15 + 0.01));
    let mid = x.iter().map(from_axis).sum::<Vec2>() / x.len() as f32;
    assert!(mid.y < -0.1 && mid.x.abs() < 0.02, "{mid}");
}

#[test]
fn a_half_ring_starts_flat_at_the_waist_or_else_round_the_body() {
    let marks = body();
    let outline = fan(Vec2::new(0.7, 0.0), 0.12, 0.67, 180.0, 96);
    for (place, side) in [(Place::Front, 1.0), (Place::Back, -1.0)] {
        let fan = fan_start(&outline, place, &marks, &[]).unwrap();
        let FanStart::Flat(flat, round) = fan.start else {
            panic!("{:?}", fan.start)
        };
        assert_eq!(round, place.at(1.05));
        let x = started(&outline, &flat, &marks);
        // Square to the way it faces, past the body's reach, its top at the waist.
        let z: Vec<f32> = x.iter().map(|x| (x.z - marks.axis.y) * side).collect();
        assert!(
            z.iter().all(|z| (z - (0.15 + FLAT_CLEARANCE)).abs() < 1e-4),
            "{z:?}"
        );
        let top = x.iter().map(|x| x.y).fold(f32::MIN, f32::max);
        assert!((top - 1.05).abs() < 1e-4, "{top}");
        // The pattern's +x round the body the way the viewer facing it reads it: to the
        // viewer's right, the body's left in front (+x) and its right behind (-x).
        let right = outline.iter().position(|p| p.x > 1.36).unwrap();
        assert!((x[right].x - marks.axis.x) * side > 0.6, "{:?}", x[right]);
    }
    // No waist known (a body known only by its bounds, or none), no fan's start.
    let no_waist = Landmarks {
        waist: None,
        ..marks
    };
    assert_eq!(fan_start(&outline, Place::Front, &no_waist, &[]), None);
    // Nor at an arm, nor for a fan that opens upward.
    assert_eq!(fan_start(&outline, Place::LeftArm, &marks, &[]), None);
    let up: Vec<Vec2> = outline.iter().map(|p| Vec2::new(p.x, -p.y)).rev().collect();
    assert_eq!(fan_start(&up, Place::Front, &marks, &[]), None);
}

/// The shipped test fixture, a half circle skirt drawn with SVG arcs (flattened by the
/// reader), read and normalised; its marks make seams and nothing else.
fn half_circle_skirt() -> super::super::PatternSpec {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/half-circle-skirt.svg"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let pieces = crate::mesh::svg::read_svg(&text).unwrap();
    let (mut spec, notices) = super::super::pattern_from_outlines(pieces);
    assert!(notices.is_empty(), "{notices:?}");
    spec.normalise().unwrap();
    spec
}

/// A piece named `name`, 0.3 m wide and `h` tall, not placed.
fn rect(name: &str, h: f32) -> super::super::PieceSpec {
    super::super::PieceSpec {
        name: name.into(),
        outline: crate::mesh::mesher::Outline::rectangle(0.3, h),
        fabric: "cloth".into(),
        grain: 0.0,
        placement: None,
        start: None,
        fallback: None,
    }
}

/// The shipped test fixture (SVG arcs, flattened by the reader) arranged on a body with a
/// waist: both fans on cones at the waist, each with its top arc held just below it; a
/// rectangle named as a skirt's starts at the waist too, its top held, and other pieces
/// as before.
#[test]
fn an_svg_circle_skirt_is_arranged_on_cones_with_its_waist_held() {
    let mut spec = half_circle_skirt();
    spec.pieces.push(rect("skirt left side", 0.4));
    spec.pieces.push(rect("right side yoke", 0.4));
    let marks = body();
    let said = spec.arrange(&marks);
    assert_eq!(said.len(), 2, "{said:?}");
    for i in 0..2 {
        let Some(Placement::Cone { top, angle, .. }) = spec.pieces[i].placement else {
            panic!("{:?}", spec.pieces[i].placement)
        };
        assert_eq!(top, 1.05);
        assert_eq!(angle, if i == 0 { 0.0 } else { PI });
    }
    assert_eq!(spec.holds.len(), 3);
    for h in &spec.holds[..2] {
        assert!(h.measured && h.normal == Vec3::Y && (h.level - 1.02).abs() < 1e-6);
        // Its ends on the fan's top arc (0.90 m / pi round its centre).
        let outline = &spec.pieces[h.edge.piece].outline.loops[0];
        let (fan, _) = fan_in(outline).unwrap();
        for end in [h.edge.from, h.edge.to] {
            assert!(
                ((end - fan.centre).length() - 0.9 / PI).abs() < 2e-3,
                "{end}"
            );
        }
    }
    // The skirt's rectangle held by its top side, the way round its outline runs.
    let h = &spec.holds[2];
    assert_eq!(h.edge.piece, 2);
    assert_eq!(
        (h.edge.from, h.edge.to),
        (Vec2::new(0.3, 0.4), Vec2::new(0.0, 0.4))
    );
    assert!(h.measured && (h.level - 1.02).abs() < 1e-6);
    // The skirt's rectangle at the waist, the yoke from the shoulders.
    let top = |s: &super::super::PatternSpec, i: usize| match s.pieces[i].placement {
        Some(Placement::Around { top, .. }) => top,
        ref p => panic!("{p:?}"),
    };
    assert_eq!((top(&spec, 2), top(&spec, 3)), (1.05, 1.5));
    // On a body whose waist is not known, as before: round the torso from the shoulders.
    spec.holds.clear();
    spec.pieces.iter_mut().for_each(|p| p.placement = None);
    assert!(
        spec.arrange(&Landmarks {
            waist: None,
            ..marks
        })
        .is_empty()
    );
    assert!(spec.holds.is_empty());
    assert_eq!(top(&spec, 0), 1.5);
}

/// A skirt whose file saved its start (our SVG's `data-start`: a pattern exported and
/// draped again) starts where it was saved and is held at the waist as it was when first
/// draped: a fan by its top arc, a piece named as a skirt's by its top; another piece is
/// not held, and on a body whose waist is not known nothing is.
#[test]
fn a_skirt_that_starts_where_its_file_saved_it_is_held_at_the_waist() {
    let mut spec = half_circle_skirt();
    spec.pieces.push(rect("skirt yoke", 0.1));
    spec.pieces.push(rect("collar", 0.1));
    let marks = body();
    spec.arrange(&marks);
    let first = spec.holds.clone();
    assert_eq!(first.len(), 3, "{first:?}");
    // Saved as the pattern out saves it, and read back: no placements, no holds.
    let mut saved = spec.clone();
    saved.holds.clear();
    for p in &mut saved.pieces {
        let (lo, hi) = crate::mesh::bounds2(&p.outline.loops[0]);
        p.start = Some(crate::design::garment::start::PieceStart {
            placement: p.placement.take().unwrap(),
            bounds: [lo.x, lo.y, hi.x, hi.y],
            body: crate::design::garment::start::signature(&marks),
            body_name: None,
        });
    }
    let mut again = saved.clone();
    assert_eq!(again.start_where_saved(&marks), None);
    assert!(again.arrange(&marks).is_empty(), "every piece started");
    assert_eq!(again.holds, first);
    for (a, b) in again.pieces.iter().zip(&spec.pieces) {
        assert_eq!(a.placement, b.placement, "{}", a.name);
    }
    // No waist, no holds.
    let mut blind = saved;
    let no_waist = Landmarks {
        waist: None,
        ..marks
    };
    blind.start_where_saved(&no_waist);
    assert!(blind.holds.is_empty());
}

/// A half circle skirt cut in one piece, a fan of 180 degrees sewn to itself at the back,
/// goes nearly all the way round on a cone; the same fan not sewn to itself (one of a
/// front and a back) cannot go more than half way, and starts flat. A dart's legs are no
/// such seam.
#[test]
fn a_fan_sewn_to_itself_goes_round_on_one_cone() {
    let marks = body();
    let centre = Vec2::new(0.9, 0.0);
    let (r, big) = (0.9 / PI, 0.9 / PI + 0.55);
    let outline = fan(centre, r, big, 180.0, 96);
    let side = |s: f32| {
        (
            centre + Vec2::new(s * r, 0.0),
            centre + Vec2::new(s * big, 0.0),
        )
    };
    let back = [side(-1.0), side(1.0)];
    assert!(closes_itself(&fan_in(&outline).unwrap().0, big, back));
    let dart = [
        (
            centre + Vec2::new(0.0, -0.4),
            centre + Vec2::new(0.02, -0.6),
        ),
        (
            centre + Vec2::new(0.04, -0.4),
            centre + Vec2::new(0.02, -0.6),
        ),
    ];
    assert!(!closes_itself(&fan_in(&outline).unwrap().0, big, dart));
    let one = fan_start(&outline, Place::Front, &marks, &[back]).unwrap();
    let FanStart::Cone(on) = one.start else {
        panic!("{:?}", one.start)
    };
    let x = started(&outline, &on, &marks);
    // Round the body from the front on the narrowest cone that clears it (here 312
    // degrees round, where one of two fans goes at most 171): its two sides near the
    // back.
    let round = |p: &Vec3| (p.x - marks.axis.x).atan2(p.z - marks.axis.y);
    // The hem's two ends (the outline's first point and its 97th).
    let (a, b) = (round(&x[0]), round(&x[96]));
    assert!(
        a.abs() > 0.85 * PI && b.abs() > 0.85 * PI && a * b < 0.0,
        "{a} {b}"
    );
    for (seams, what) in [(&[][..], "no seam"), (&[dart][..], "a dart")] {
        let other = fan_start(&outline, Place::Front, &marks, seams).unwrap();
        assert!(
            matches!(other.start, FanStart::Flat(..)),
            "{what}: {:?}",
            other.start
        );
    }
}
