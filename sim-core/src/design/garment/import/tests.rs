use super::*;
use crate::mesh::mesher::Outline;

fn square(name: &str, marks: Vec<SeamMark>) -> NamedOutline {
    NamedOutline {
        name: name.into(),
        outline: Outline::rectangle(1.0, 1.0),
        marks,
        saved: Default::default(),
    }
}

fn mark(label: &str, a: (f32, f32), b: (f32, f32)) -> SeamMark {
    SeamMark {
        label: label.into(),
        a: Vec2::new(a.0, a.1),
        b: Vec2::new(b.0, b.1),
        start: false,
    }
}

#[test]
fn marks_on_two_stretches_make_a_seam_and_others_a_notice() {
    // A on the right side of one square (in two pieces of mark) and the left of the
    // other; B only once; C across the first square's corner (0, 0).
    let a = square(
        "front",
        vec![
            mark("A", (1.0, 0.0), (1.0, 0.5)),
            mark("A", (1.0, 0.5), (1.0, 1.0)),
            mark("B", (0.0, 1.0), (0.5, 1.0)),
            mark("C", (0.0, 0.2), (0.0, 0.0)),
            mark("C", (0.0, 0.0), (0.3, 0.0)),
        ],
    );
    let b = square(
        "back",
        vec![
            mark("A", (0.0, 1.0), (0.0, 0.0)),
            mark("C", (0.2, 1.0), (0.8, 1.0)),
        ],
    );
    let (spec, notices) = pattern_from_outlines(vec![a, b]);
    assert_eq!(spec.seams.len(), 2, "{spec:?}");
    let s = &spec.seams[0];
    assert_eq!(s.label, "A");
    // Counter-clockwise on the front: up its right side.
    assert_eq!(
        (s.a.from, s.a.to),
        (Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0))
    );
    // Down the back's left side.
    assert_eq!(
        (s.b.from, s.b.to),
        (Vec2::new(0.0, 1.0), Vec2::new(0.0, 0.0))
    );
    // C wraps past the loop's first point.
    let c = &spec.seams[1];
    assert_eq!(
        (c.a.from, c.a.to),
        (Vec2::new(0.0, 0.2), Vec2::new(0.3, 0.0))
    );
    assert_eq!(notices.len(), 1);
    assert!(notices[0].contains("seam B"), "{notices:?}");
}

/// A seam whose marks on one piece stop for a short way and go on (our export's
/// notch where a weld took ease in as a dart) is sewn as one stretch there, and said;
/// a gap wider than a quarter of the marked length is not bridged.
#[test]
fn a_short_gap_in_a_seams_marks_is_bridged_and_said() {
    let front = square("front", vec![mark("A", (1.0, 0.0), (1.0, 1.0))]);
    let back = |low: f32, high: f32| {
        square(
            "back",
            vec![
                mark("A", (0.0, 1.0), (0.0, high)),
                mark("A", (0.0, low), (0.0, 0.0)),
            ],
        )
    };
    let (spec, notices) = pattern_from_outlines(vec![front.clone(), back(0.4, 0.5)]);
    assert_eq!(spec.seams.len(), 1, "{notices:?}");
    let s = &spec.seams[0];
    assert_eq!(
        (s.b.piece, s.b.from, s.b.to),
        (1, Vec2::new(0.0, 1.0), Vec2::new(0.0, 0.0))
    );
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(
        notices[0].contains("seam A") && notices[0].contains("back stop for 100 mm"),
        "{notices:?}"
    );
    // 0.8 m between 0.1 m and 0.1 m of marks: three stretches, unsewn.
    let (spec, notices) = pattern_from_outlines(vec![front, back(0.1, 0.9)]);
    assert!(spec.seams.is_empty(), "{spec:?}");
    assert!(notices[0].contains("3 stretches"), "{notices:?}");
}

/// A side seam over a dart's mouth: the front's right side marked below and above a
/// dart whose legs run in to a point, the back's left side once. Sewn as two seams
/// meeting where the dart closes (the back split at the share of the front's two
/// lengths, its ends meeting the front's as they stand), and said; the same gap
/// with no dart in it is left unsewn (above).
#[test]
fn a_side_seam_over_a_darts_mouth_is_sewn_as_two() {
    let p = |x: f32, y: f32| Vec2::new(x, y);
    let notched = vec![
        p(0.0, 0.0),
        p(1.0, 0.0),
        p(1.0, 0.3),
        p(0.5, 0.4),
        p(1.0, 0.5),
        p(1.0, 1.0),
        p(0.0, 1.0),
    ];
    // The dart marked round its point, or (as our export marks a dart's welded legs)
    // as two legs stopping short of it, or not marked at all (told by its shape).
    let round = [((1.0, 0.3), (0.5, 0.4)), ((0.5, 0.4), (1.0, 0.5))];
    let legs = [((1.0, 0.3), (0.55, 0.39)), ((0.55, 0.41), (1.0, 0.5))];
    for dart in [Some(round), Some(legs), None] {
        let mut marks = vec![
            mark("A", (1.0, 0.0), (1.0, 0.3)),
            mark("A", (1.0, 0.5), (1.0, 1.0)),
        ];
        marks.extend(dart.into_iter().flatten().map(|(a, b)| mark("D", a, b)));
        let front = NamedOutline {
            name: "front".into(),
            outline: Outline {
                loops: vec![notched.clone()],
            },
            marks,
            saved: Default::default(),
        };
        let back = square("back", vec![mark("A", (0.0, 1.0), (0.0, 0.0))]);
        let (spec, notices) = pattern_from_outlines(vec![front, back]);
        let a: Vec<&SeamSpec> = spec.seams.iter().filter(|s| s.label == "A").collect();
        assert_eq!(a.len(), 2, "{spec:?} {notices:?}");
        // Up the front below the dart, with the back's lower 0.375 (0.3 of 0.8).
        assert_eq!((a[0].a.from, a[0].a.to), (p(1.0, 0.0), p(1.0, 0.3)));
        assert_eq!(a[0].b.to, p(0.0, 0.0));
        assert!(a[0].b.from.distance(p(0.0, 0.375)) < 1e-5, "{:?}", a[0].b);
        assert_eq!((a[1].a.from, a[1].a.to), (p(1.0, 0.5), p(1.0, 1.0)));
        assert_eq!(a[1].b.from, p(0.0, 1.0));
        assert!(a[1].b.to.distance(p(0.0, 0.375)) < 1e-5, "{:?}", a[1].b);
        assert!(a.iter().all(|s| s.reversed == Some(true)));
        assert_eq!(
            spec.seams.iter().any(|s| s.label == "D"),
            dart.is_some(),
            "the dart"
        );
        assert!(
            notices
                .iter()
                .any(|n| n.contains("seam A") && n.contains("two seams")),
            "{notices:?}"
        );
    }
}

/// Found by the svg fuzz target: thousands of seam marks were chained and grouped
/// pair by pair (a 33 kB file took 54 s). Twelve thousand marks: a run of 4,000
/// short marks chained into one stretch on each of two pieces (one seam), and 4,000
/// with labels of their own (one notice each).
#[test]
fn thousands_of_marks_chain_and_group_in_one_pass() {
    let n = 4000;
    let run = |x: f32| -> Vec<SeamMark> {
        (0..n)
            .map(|i| {
                let (y0, y1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
                mark("A", (x, y0), (x, y1))
            })
            .collect()
    };
    let mut front = run(1.0);
    front.extend((0..n).map(|i| {
        let y = (i as f32 + 0.5) / n as f32;
        mark(&format!("L{i}"), (0.0, y), (0.0, y))
    }));
    let (spec, notices) =
        pattern_from_outlines(vec![square("front", front), square("back", run(0.0))]);
    assert_eq!(spec.seams.len(), 1);
    let s = &spec.seams[0];
    assert_eq!(
        (s.a.from, s.a.to),
        (Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0))
    );
    assert_eq!(notices.len(), n);
}

/// A dart marked as one stretch round its point, as our export marks welded legs
/// (before, "marked on 1 stretches ... left unsewn" and the dart was lost on the way
/// back in): its two legs, sewn mouth to mouth. On two pieces the same turn is no
/// dart: each piece's stretch stays whole.
#[test]
fn a_dart_marked_round_its_point_is_sewn_leg_to_leg() {
    let v = Vec2::new;
    let l = vec![
        v(0.0, 0.0),
        v(0.45, 0.0),
        v(0.5, 0.3),
        v(0.55, 0.0),
        v(1.0, 0.0),
        v(1.0, 1.0),
        v(0.0, 1.0),
    ];
    let piece = |name: &str, marks| NamedOutline {
        name: name.into(),
        outline: Outline {
            loops: vec![l.clone()],
        },
        marks,
        saved: Default::default(),
    };
    let e = || {
        vec![
            mark("E", (0.45, 0.0), (0.475, 0.15)),
            mark("E", (0.475, 0.15), (0.5, 0.3)),
            mark("E", (0.5, 0.3), (0.55, 0.0)),
        ]
    };
    let (spec, notices) = pattern_from_outlines(vec![piece("front", e())]);
    assert!(notices.is_empty(), "{notices:?}");
    assert_eq!(spec.seams.len(), 1);
    let s = &spec.seams[0];
    assert_eq!((s.a.from, s.a.to), (v(0.45, 0.0), v(0.5, 0.3)));
    assert_eq!((s.b.from, s.b.to), (v(0.5, 0.3), v(0.55, 0.0)));
    assert_eq!(s.reversed, Some(true), "mouth to mouth");
    let (spec, _) = pattern_from_outlines(vec![piece("front", e()), piece("back", e())]);
    assert_eq!(spec.seams.len(), 1);
    assert_eq!(
        (spec.seams[0].a.from, spec.seams[0].a.to),
        (v(0.45, 0.0), v(0.55, 0.0))
    );
}

/// A start that is not ours to read (not JSON, or a number out of range) is said and
/// dropped: the piece is arranged by its name, the pattern still reads.
#[test]
fn a_start_that_cannot_be_read_is_said_and_the_piece_arranged_by_name() {
    let with = |start: &str| {
        let mut p = square("front", Vec::new());
        p.saved.start = Some(start.into());
        p.saved.fabric = Some("denim".into());
        p
    };
    let good = r#"{"placement":{"kind":"around","angle":0.0,"top":1.5,"mirrored":false,"out":0.0},"bounds":[0,0,1,1],"body":[]}"#;
    let (spec, notices) = pattern_from_outlines(vec![with(good)]);
    assert!(notices.is_empty(), "{notices:?}");
    assert!(spec.pieces[0].start.is_some());
    assert_eq!(spec.pieces[0].fabric, "denim");
    for (bad, why) in [
        ("{not json", "could not be read ("),
        (&good.replace("1.5", "1e30"), "beyond 100"),
        (&good.replace("[0,0,1,1]", "[0,0,-1,1]"), "not a box"),
        (&good.replace("[0,0,1,1]", "[0,0,1,1e30]"), "not a box"),
        (
            &good.replace(r#""body":[]"#, r#""body":[1e30]"#),
            "not a body's",
        ),
    ] {
        let (spec, notices) = pattern_from_outlines(vec![with(bad)]);
        assert_eq!(spec.pieces[0].start, None, "{bad}");
        assert_eq!(spec.pieces[0].placement, None, "{bad}");
        assert!(
            notices.len() == 1
                && notices[0].starts_with("piece front: its start on the body")
                && notices[0].contains(why),
            "{bad}: {notices:?}"
        );
    }
}

/// A pattern may say on its root which body it is cut for (`data-body`), as the sleeved
/// dress we ship does: one of ours is that body; a body file, a name we do not know or none is
/// no body (a pattern from elsewhere, draped on whatever body is asked).
#[test]
fn a_pattern_says_on_its_root_which_body_it_is_cut_for() {
    let shipped = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/dress-sleeves.svg");
    assert_eq!(own_body(Path::new(shipped)), Some(BodyKind::Mannequin));
    let dir = std::env::temp_dir().join(format!("saiho-cut-for-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let said = |root: &str| {
        let path = dir.join("p.svg");
        let text = format!(
            "<?xml version=\"1.0\"?>\n<!-- a pattern -->\n<svg xmlns=\"http://www.w3.org/2000/svg\" {root} \
             viewBox=\"0 0 100 100\"><g id=\"front\"><rect width=\"50\" height=\"50\"/></g></svg>"
        );
        std::fs::write(&path, text).unwrap();
        own_body(&path)
    };
    let found = [
        said("data-body=\"human\""),
        said("data-body=\"mannequin-apose\""),
        said("data-body=\"/tmp/someone.obj\""),
        said("data-body=\"a dress form\""),
        said(""),
    ];
    std::fs::remove_dir_all(&dir).ok();
    let ours = [Some(BodyKind::Human), Some(BodyKind::MannequinAPose)];
    assert_eq!(found, [ours[0].clone(), ours[1].clone(), None, None, None]);
}
