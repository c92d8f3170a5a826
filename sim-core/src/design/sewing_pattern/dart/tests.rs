//! Darts in the pattern out.

use glam::{DVec2, Vec2};

use super::super::{Piece, finish, notches::in_material, pieces};
use super::*;

/// A 500 x 300 mm piece (counter-clockwise, mm) with a dart 50 mm wide at its hem and
/// 200 mm long in its middle, its legs sewn as seam F.
fn dart_at_hem() -> Piece {
    let v = DVec2::new;
    let l = vec![
        v(0.0, 0.0),
        v(225.0, 0.0),
        v(250.0, 200.0),
        v(275.0, 0.0),
        v(500.0, 0.0),
        v(500.0, 300.0),
        v(0.0, 300.0),
    ];
    Piece {
        name: "front".into(),
        cut: vec![l.clone()],
        seams: vec![("F".into(), l[1], l[2]), ("F".into(), l[2], l[3])],
        loops: vec![l],
        seam_names: vec![],
        grain: (v(250.0, 250.0), v(350.0, 250.0)),
        fabric: "cloth".into(),
        notches: vec![],
        drills: vec![],
        press_second: vec![],
        presses: vec![],
        start: None,
        seam_starts: vec![],
    }
}

/// [`dart_at_hem`] with each leg in ten segments, the seam running on round the point
/// (as welded legs are labelled): one dart, its tip the V's point, not a vertex up a leg
/// (each of which starts a run of the seam too).
#[test]
fn a_seam_running_round_the_darts_point_finds_its_point() {
    let mut p = dart_at_hem();
    let l = &p.loops[0];
    let mut v = vec![l[0]];
    for (from, to) in [(l[1], l[2]), (l[2], l[3])] {
        v.extend((0..10).map(|k| from.lerp(to, k as f64 / 10.0)));
    }
    v.extend_from_slice(&l[3..]);
    p.seams = (1..21).map(|i| ("F".to_string(), v[i], v[i + 1])).collect();
    p.loops = vec![v.clone()];
    p.cut = p.loops.clone();
    let found = darts(&p);
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!((found[0].a, found[0].b), (1, 21));
    assert_eq!(found[0].tip, DVec2::new(250.0, 200.0));
    // Its drill hole is 10 mm down its middle from the point.
    let d = found[0].drill(&p.loops);
    assert!(d.distance(DVec2::new(250.0, 190.0)) < 1e-9, "{d}");
}

/// The dart is found; its cut line is the hem's 10 mm allowance bridged by a cap, not a
/// line up into the dart and back: folded shut (the half next to leg A mirrored in it,
/// the half next to leg B turned onto leg A), every point of the cap lies on the hem's
/// allowance line, and the cap's point stands on the dart's middle below that line. Its
/// legs are notched where their lines meet the cut line, and the sewing line keeps the V.
#[test]
fn a_darts_cut_line_is_capped_and_folds_shut_onto_the_hems_allowance() {
    let p = dart_at_hem();
    let found = darts(&p);
    assert_eq!(
        found,
        vec![Dart {
            label: "F".into(),
            loop_index: 0,
            a: 1,
            b: 3,
            tip: DVec2::new(250.0, 200.0),
            second: false,
        }]
    );
    let f = finish(vec![p.clone()], 10.0).remove(0);
    // Laid out: moved so its lowest point is at y = 0; put it back.
    let shift = f.loops[0][0] - p.loops[0][0];
    let cut: Vec<DVec2> = f.cut[0].iter().map(|&q| q - shift).collect();
    assert_eq!(f.loops[0].len(), 7, "the sewing line keeps the V");
    let (t, a, b) = (p.loops[0][2], p.loops[0][1], p.loops[0][3]);
    let ua = (a - t).normalize();
    let theta = ua.perp_dot(b - t).atan2(ua.dot(b - t));
    // Nothing of the cut line runs up into the dart.
    let under = |q: &&DVec2| q.x > 200.0 && q.x < 300.0;
    assert!(
        cut.iter().filter(under).all(|q| q.y <= -10.0 + 1e-9),
        "{cut:?}"
    );
    // The cap: the points under the dart's mouth, beyond its legs' lines.
    let cap: Vec<DVec2> = (cut.iter())
        .filter(|q| q.x > 215.0 && q.x < 285.0)
        .copied()
        .collect();
    assert!(cap.len() >= 3, "{cut:?}");
    let point = cap
        .iter()
        .copied()
        .fold(DVec2::ZERO, |m, q| if q.y < m.y { q } else { m });
    assert!(
        (point.x - 250.0).abs() < 1e-6,
        "the point on the middle: {point}"
    );
    assert!(point.y < -15.0, "the point below the allowance: {point}");
    for &q in &cap {
        let folded = if q.x <= 250.0 {
            t + ua * (2.0 * (q - t).dot(ua)) - (q - t)
        } else {
            t + DVec2::from_angle(-theta).rotate(q - t)
        };
        assert!((folded.y + 10.0).abs() < 1e-6, "{q} folds to {folded}");
    }
    // The intake is cloth: inside the cut line; the sewing line all inside it too.
    let mouth = (a + b) * 0.5 + DVec2::new(0.0, 20.0);
    assert!(in_material(std::slice::from_ref(&cut), mouth));
    assert!((p.loops[0].iter()).all(|&q| in_material(std::slice::from_ref(&cut), q)));
    // Two notches, one on each leg's line from the cut line toward the tip, and none at
    // the tip (the middle of the seam's chain).
    assert_eq!(f.notches.len(), 2, "{:?}", f.notches);
    for (from, to) in &f.notches {
        let (from, to) = (*from - shift, *to - shift);
        assert!(
            (from.y + 10.0).abs() < 1e-6,
            "the notch starts on the cut line: {from}"
        );
        let leg = if from.x < 250.0 { a } else { b };
        let along = (leg - t).normalize().perp_dot(from - t).abs();
        assert!(along < 1e-6, "on the leg's line: {from}");
        assert!(
            to.y > from.y && to.y < 0.0,
            "toward the tip: {from} -> {to}"
        );
    }
}

/// The dart's point is marked by a drill hole 10 mm inside it on its middle, written to
/// the SVG (a circle and a cross, class `drill`) and the DXF (a POINT on AAMA layer 13);
/// both read back as the one piece with its one loop, the hole's circle no hole in it.
#[test]
fn a_darts_point_is_drilled_and_the_pattern_reads_back_whole() {
    let p = dart_at_hem();
    let f = finish(vec![p.clone()], 10.0);
    let shift = f[0].loops[0][0] - p.loops[0][0];
    assert_eq!(f[0].drills.len(), 1);
    let drill = f[0].drills[0] - shift;
    assert!(drill.distance(DVec2::new(250.0, 190.0)) < 1e-9, "{drill}");
    let svg = super::super::svg_string(&f);
    assert_eq!(svg.matches("class=\"drill\"").count(), 2, "{svg}");
    let dxf = super::super::dxf_string(&f);
    assert!(dxf.contains("POINT\n  8\n13\n"), "a drill on layer 13");
    for read in [
        crate::mesh::svg::read_svg(&svg).unwrap(),
        crate::mesh::dxf::read_dxf(&dxf).unwrap(),
    ] {
        assert_eq!(read.len(), 1);
        assert_eq!(read[0].outline.loops.len(), 1, "{:?}", read[0].outline);
    }
    // No dart, no drill.
    let mut plain = p;
    plain.seams.clear();
    assert!(finish(vec![plain], 10.0)[0].drills.is_empty());
}

/// Not darts: a seam turning a wide concave corner on one piece (an L), and a seam whose
/// two sides on one piece do not meet (a sleeve's tube).
#[test]
fn a_seam_round_a_corner_or_down_both_sides_is_no_dart() {
    let v = DVec2::new;
    // An L: the seam runs up the inner corner's two sides.
    let l = vec![
        v(0.0, 0.0),
        v(200.0, 0.0),
        v(200.0, 100.0),
        v(100.0, 100.0),
        v(100.0, 200.0),
        v(0.0, 200.0),
    ];
    let mut p = dart_at_hem();
    p.seams = vec![("A".into(), l[2], l[3]), ("A".into(), l[3], l[4])];
    p.loops = vec![l.clone()];
    p.cut = vec![l];
    assert!(darts(&p).is_empty());
    let mut p = dart_at_hem();
    let r = p.loops[0].clone();
    p.seams = vec![("T".into(), r[4], r[5]), ("T".into(), r[6], r[0])];
    assert!(darts(&p).is_empty());
}

/// A dart cut into a square cloth in the pattern, as in the studio (two cuts from below
/// the hem to one point, the wedge between deleted, its legs seamed in the pattern
/// plane): the pattern out finds it, and with a 10 mm allowance the dart's intake is
/// inside the cut line.
#[test]
fn a_dart_cut_in_the_cloth_is_capped_in_the_pattern_out() {
    let mut d = super::super::tests::square(1.0, 16);
    let apex = Vec2::new(0.0, -0.3);
    let hem = |dx: f32| Vec2::new(dx, -0.5);
    let below = |dx: f32| apex + (hem(dx) - apex) * 1.05;
    d.cut_line(below(-0.03), apex).unwrap();
    d.cut_line(below(0.03), apex).unwrap();
    let list = d.piece_list();
    let wedge = (0..list.len()).min_by_key(|&i| list[i].vertices).unwrap();
    d.delete_piece(wedge).unwrap();
    d.seam_on_plane([hem(-0.03), apex], [hem(0.03), apex], 0.01)
        .unwrap();
    let p = pieces(&d);
    assert_eq!(p.len(), 1);
    let found = darts(&p[0]);
    assert_eq!(found.len(), 1, "{:?}", p[0].seams);
    let l = &p[0].loops[0];
    let (a, b) = (l[found[0].a], l[found[0].b]);
    let f = finish(p.clone(), 10.0).remove(0);
    let shift = f.loops[0][0] - l[0];
    let cut: Vec<DVec2> = f.cut[0].iter().map(|&q| q - shift).collect();
    let tip = found[0].tip;
    let intake = (a + b) * 0.5 + (tip - (a + b) * 0.5) * 0.1;
    assert!(
        in_material(std::slice::from_ref(&cut), intake),
        "{intake} outside {cut:?}"
    );
    assert!(
        !in_material(&p[0].loops, intake),
        "the intake is cut away in 3D"
    );
}

/// A symmetric dart square to a straight edge has its cap's mitre on the legs' lines,
/// where rounding put the hit just off the end of a segment: GarmentCode's pencil skirt
/// had one of its four back darts cut as a V. Every one of a sweep of such darts, placed
/// anywhere along the edge, is capped.
#[test]
fn every_symmetric_dart_is_capped() {
    let v = DVec2::new;
    for k in 0..200 {
        let (wide, long, at) = (
            8.0 + 0.37 * k as f64,
            90.0 + 0.83 * k as f64,
            120.0 + 1.7 * k as f64,
        );
        let h = 0.5 * wide;
        let l = vec![
            v(0.0, 0.0),
            v(at - h, 0.0),
            v(at, long),
            v(at + h, 0.0),
            v(700.0, 0.0),
            v(700.0, 400.0),
            v(0.0, 400.0),
        ];
        let p = Piece {
            seams: vec![("F".into(), l[1], l[2]), ("F".into(), l[2], l[3])],
            loops: vec![l.clone()],
            cut: vec![l.clone()],
            ..dart_at_hem()
        };
        let found = darts(&p);
        assert_eq!(found.len(), 1, "{wide} {long} {at}");
        assert!(
            cap(&l, 10.0, &found[0]).is_some(),
            "{wide} x {long} at {at}"
        );
    }
}

/// The shipped dress at `edge` m edges, sewn, with a dart 40 mm wide up its front from
/// the hem, `x` m from the front's side and `long` m long.
fn dart_on_sewn_dress(edge: f32, x: f32, long: f32) -> crate::design::Design {
    use crate::scenario::{ScenarioConfig, ScenarioName, build_scene};
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = edge;
    let (mut d, spec) = build_scene(&cfg).unwrap();
    crate::design::garment::sew(&mut d, &spec.unwrap(), 0.5).unwrap();
    let (lo, _) = crate::mesh::bounds2(&d.pieces[0].outline.loops[0]);
    let at = |y: f32| Vec2::new(lo.x + x, lo.y + y) + d.pieces[0].offset;
    d.dart_on_plane(at(long), at(-0.06), 0.04).unwrap();
    d
}

/// 150 frames of `d`; then every pair of its last seam (the dart) is welded and its
/// front is one loop with one dart in the pattern out (no allowance), which it returns.
fn sewn_with_one_loop(d: &mut crate::design::Design) -> Vec<Piece> {
    for _ in 0..150 {
        d.step().unwrap();
    }
    let s = d.seams.last().unwrap();
    assert!(s.pairs.iter().all(|(a, b)| a == b), "{:?}", s.pairs);
    let laid = finish(pieces(d), 0.0);
    let front = laid.iter().find(|f| f.name == "front").unwrap();
    assert_eq!(front.loops.len(), 1, "{:?}", &front.loops[1..]);
    assert_eq!(darts(front).len(), 1);
    laid
}

/// A dart 40 x 330 mm up the sewn dress's front at 3 cm edges: its two cuts meet near
/// the point on one vertex and the first's end opens on to a vertex beside it, which
/// left a slit past the V's point (a 4-vertex hole in the pattern, open in the cloth).
/// Sewn shut with the legs: the front is one loop, every pair welds, nothing crosses.
#[test]
fn what_a_darts_cuts_leave_at_its_point_is_sewn_shut() {
    let mut d = dart_on_sewn_dress(0.03, 0.12, 0.33);
    sewn_with_one_loop(&mut d);
    let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    let c = crate::collision::crossings::count(&d.sim.cloth.x, &tris, d.sim.body.as_ref());
    assert_eq!((c.self_pairs, c.body_pairs), (0, 0));
}

/// A dart 40 x 250 mm up the sewn dress's front 20 cm from its side, at 3 cm edges: its
/// cuts leave a slit 12 mm past the V's point, which the legs' welds close. The pattern
/// out cut it as a hole touching the outline at the point, and our own reader refused the
/// file ("the outline crosses itself"). A slit the cloth has sewn shut is no cut in the
/// fabric: the front is one loop, and the pattern reads back and meshes.
#[test]
fn a_slit_sewn_shut_past_a_darts_point_is_no_cut() {
    let mut d = dart_on_sewn_dress(0.03, 0.2, 0.25);
    let laid = sewn_with_one_loop(&mut d);
    let read = crate::mesh::svg::read_svg(&super::super::svg_string(&laid)).unwrap();
    for p in &read {
        crate::mesh::mesher::check(&p.outline).unwrap();
        crate::mesh::mesher::mesh_outline(&p.outline, 0.03).unwrap();
    }
}

/// A dart 40 x 250 mm up the sewn dress's front 12 cm from its side, at 2 cm edges: one
/// cut passes a vertex near the hem and parts a triangle of the wedge from the rest. It
/// was left as a piece of its own ("front 2", one triangle), which fell with the cloth
/// and came out in the pattern as a third piece 2 mm across. Every piece wholly inside
/// the wedge now goes with it.
#[test]
fn a_triangle_the_cuts_part_from_the_wedge_goes_with_it() {
    let mut d = dart_on_sewn_dress(0.02, 0.12, 0.25);
    let list = d.piece_list();
    let names: Vec<(&str, usize)> = list.iter().map(|p| (&p.name[..], p.vertices)).collect();
    assert_eq!(list.len(), 2, "{names:?}");
    assert!(list.iter().all(|p| p.vertices > 100), "{names:?}");
    // One undo puts the wedge and its fragment back.
    assert_eq!(d.undo().unwrap(), "dart");
    assert_eq!(d.piece_list().len(), 2);
}

/// A dart 40 x 250 mm up the sewn dress's front 8 cm from its side, at 1.5 cm edges: its
/// two cuts pass through the same two vertices below the point, so one leg's border
/// zigzags between the cuts' copies and is longer than the other leg, which then set
/// the pairs; one of the other leg's vertices was in none. Welded, it left a hole of
/// three vertices past the point, and our own reader refused the pattern ("the outline
/// crosses itself"). Every vertex of both legs is stitched now, each leg's to the
/// other's in order: the front is one loop, and the pattern reads back and meshes. Its
/// dart ends where the cuts met first, 242 mm from the hem: past there the cut cloth
/// fills the V, its two sides sewn to each other, as in the cloth.
#[test]
fn a_darts_zigzag_leg_leaves_no_vertex_unstitched() {
    let mut d = dart_on_sewn_dress(0.015, 0.08, 0.25);
    let laid = sewn_with_one_loop(&mut d);
    let front = laid.iter().find(|f| f.name == "front").unwrap();
    let dart = darts(front).remove(0);
    let l = &front.loops[dart.loop_index];
    let long = dart.tip.distance((l[dart.a] + l[dart.b]) * 0.5);
    assert!(
        (235.0..=251.0).contains(&long),
        "{long} mm from the mouth to the tip"
    );
    let read = crate::mesh::svg::read_svg(&super::super::svg_string(&laid)).unwrap();
    for p in &read {
        crate::mesh::mesher::check(&p.outline).unwrap();
        crate::mesh::mesher::mesh_outline(&p.outline, 0.03).unwrap();
    }
}

/// The cap of dart `p` (its one dart) with a 10 mm allowance, where `p` lies.
fn cap_of(p: &Piece) -> Vec<DVec2> {
    let found = darts(p);
    assert_eq!(found.len(), 1);
    cap(&p.loops[0], 10.0, &found[0]).unwrap()
}

/// Every point of `cap` (of a dart with tip `t` and mouth `a`-`b`) between the dart's
/// legs folded shut toward leg B (`toward_b`) or A: the half of the cap beside that leg
/// mirrored in it, the other half turned onto it about the tip; with whether it was
/// between them (the cap's ends lie on the edge's allowance beyond the legs).
fn folded(cap: &[DVec2], t: DVec2, a: DVec2, b: DVec2, toward_b: bool) -> Vec<(DVec2, bool)> {
    let (ua, ub) = ((a - t).normalize(), (b - t).normalize());
    let theta = ua.perp_dot(ub).atan2(ua.dot(ub));
    let (leg, turn) = if toward_b { (ub, -theta) } else { (ua, theta) };
    cap.iter()
        .map(|&q| {
            let phi = ua.perp_dot(q - t).atan2(ua.dot(q - t));
            if !(1e-9..theta - 1e-9).contains(&phi) {
                return (q, false);
            }
            // Beside leg A: the first half of the angle from A to B.
            if (phi < 0.5 * theta) != toward_b {
                (t + leg * (2.0 * (q - t).dot(leg)) - (q - t), true)
            } else {
                (t + DVec2::from_angle(-turn).rotate(q - t), true)
            }
        })
        .collect()
}

/// A dart pressed toward its second leg: its cap folds shut over leg B onto the hem's
/// allowance, where pressed toward its first it folds over leg A. Each cap is
/// symmetric about the dart's middle (the half beside the far leg is the near half
/// turned, which is that half mirrored twice), so a symmetric dart square to a straight
/// hem has the same cap either way; a dart leaning to one side does not. The sewing
/// line, the notches on the legs and the drill stay where they were.
#[test]
fn a_dart_pressed_toward_its_second_leg_is_capped_over_that_leg() {
    let first = dart_at_hem();
    let mut second = dart_at_hem();
    second.press_second = vec!["F".into()];
    assert!(darts(&second)[0].second && !darts(&first)[0].second);
    let (a_cap, b_cap) = (cap_of(&first), cap_of(&second));
    let (t, a, b) = (first.loops[0][2], first.loops[0][1], first.loops[0][3]);
    assert_eq!(b_cap.len(), a_cap.len());
    for (q, p) in b_cap.iter().zip(&a_cap) {
        assert!(q.distance(*p) < 1e-9, "{b_cap:?} against {a_cap:?}");
    }
    for (q, _) in folded(&b_cap, t, a, b, true) {
        assert!((q.y + 10.0).abs() < 1e-6, "folded over B to {q}");
    }
    // At a kink in the hem (side B rising 60 mm over its 225), the two presses differ.
    let v = DVec2::new;
    let kinked = |press: Vec<String>| {
        let mut p = dart_at_hem();
        p.loops[0][4] = v(500.0, 60.0);
        p.press_second = press;
        p
    };
    let (la, lb) = (kinked(vec![]), kinked(vec!["F".into()]));
    let l = la.loops[0].clone();
    let (t, a, b) = (l[2], l[1], l[3]);
    // Folded, each point lies on the closed hem's allowance, 10 mm outside it: the near
    // side's hem line, or the far side's turned onto the near one.
    let ua = (a - t).normalize();
    let theta = ua.perp_dot(b - t).atan2(ua.dot(b - t));
    let outside = |q: DVec2, p0: DVec2, p1: DVec2| {
        ((p1 - p0).normalize().perp_dot(q - p0) + 10.0).abs() < 1e-6
    };
    let on_a = |q: DVec2| outside(q, l[0], l[1]);
    let on_b = |q: DVec2| outside(q, l[3], l[4]);
    for (p, toward_b) in [(&la, false), (&lb, true)] {
        let back = if toward_b { -theta } else { theta };
        let mut inside = 0;
        for (q, between) in folded(&cap_of(p), t, a, b, toward_b) {
            let far = t + DVec2::from_angle(back).rotate(q - t);
            let ok = match (between, toward_b) {
                (false, _) => on_a(q) || on_b(q),
                (true, true) => on_b(q) || on_a(far),
                (true, false) => on_a(q) || on_b(far),
            };
            assert!(ok, "{toward_b}: folded to {q}");
            inside += usize::from(between);
        }
        assert!(inside >= 1, "{toward_b}: a cap between the legs");
    }
    let (ca, cb) = (cap_of(&la), cap_of(&lb));
    let apart = ca
        .iter()
        .zip(&cb)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max);
    assert!(apart > 1.0, "the two presses differ: {ca:?} {cb:?}");
    let (fa, fb) = (finish(vec![first], 10.0), finish(vec![second], 10.0));
    assert_eq!(fa[0].loops, fb[0].loops);
    assert_eq!(fa[0].drills, fb[0].drills);
    assert_eq!(fa[0].notches.len(), fb[0].notches.len());
    // The press mark runs from the dart's middle toward the pressed leg.
    let mark = |f: &[Piece]| {
        let (label, from, to) = f[0].presses[0].clone();
        assert_eq!(label, "F");
        to.x - from.x
    };
    assert!(mark(&fa) < -1.0 && mark(&fb) > 1.0);
}

/// A dart leaning on a straight hem (its point 40 mm right of its mouth's middle) has
/// legs of different lengths, 210 and 201 mm: closed, the hem steps along the dart's
/// line. Its cap starts where side A's own allowance meets leg A and ends where side B's
/// meets leg B, the step taken along the far leg's line, so the cut line runs into the
/// cap and out of it without a jog (it jumped 4.4 mm at each end, off a mitre between two
/// nearly parallel lines). Pressed toward B, the same with the legs' parts swapped.
#[test]
fn a_leaning_darts_cap_meets_both_sides_allowance() {
    let v = DVec2::new;
    for press in [vec![], vec!["F".to_string()]] {
        let mut p = dart_at_hem();
        p.loops[0][2] = v(290.0, 200.0);
        let l = p.loops[0].clone();
        p.seams = vec![("F".into(), l[1], l[2]), ("F".into(), l[2], l[3])];
        p.press_second = press.clone();
        let cap = cap_of(&p);
        let on_leg = |q: DVec2, end: DVec2| {
            let u = (end - l[2]).normalize();
            u.perp_dot(q - l[2]).abs() < 1e-6
        };
        let (first, last) = (cap[0], *cap.last().unwrap());
        assert!(
            (first.y + 10.0).abs() < 1e-6 && on_leg(first, l[1]),
            "{press:?}: starts at {first}"
        );
        assert!(
            (last.y + 10.0).abs() < 1e-6 && on_leg(last, l[3]),
            "{press:?}: ends at {last}"
        );
        // The step: the two points before the end on the far leg's line (B's pressed
        // toward A), or the two after the start on the near one's.
        let (far_leg, step) = if press.is_empty() {
            (l[3], cap[cap.len() - 2])
        } else {
            (l[1], cap[1])
        };
        assert!(on_leg(step, far_leg), "{press:?}: the step from {step}");
        // In the cut line, both sides' allowances run straight into it: beside the
        // dart, outside its V (where the cap is), nothing stands inside the allowance
        // but the step on the far leg's line.
        let f = finish(vec![p.clone()], 10.0).remove(0);
        let shift = f.loops[0][0] - p.loops[0][0];
        let cut: Vec<DVec2> = f.cut[0].iter().map(|&q| q - shift).collect();
        let (ua, ub) = ((l[1] - l[2]).normalize(), (l[3] - l[2]).normalize());
        let in_v = |q: DVec2| ua.perp_dot(q - l[2]) > 1e-6 && (q - l[2]).perp_dot(ub) > 1e-6;
        let beside = |q: &&DVec2| {
            q.y > -10.0 - 1e-6 && q.y < 0.0 && (q.x - 250.0).abs() < 60.0 && !in_v(**q)
        };
        let inside: Vec<&DVec2> = cut.iter().filter(beside).collect();
        assert!(
            inside
                .iter()
                .all(|q| (q.y + 10.0).abs() < 1e-6 || on_leg(**q, far_leg)),
            "{press:?}: a jog inside the allowance {inside:?}"
        );
    }
}
