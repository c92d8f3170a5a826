use super::*;

/// One of every variant, with values that are valid on the wire.
fn every_variant() -> Vec<Command> {
    let material = MaterialChange {
        density: Some(0.2),
        shear: Some(30.0),
        bending: Some(2e-5),
        damping: Some(0.5),
        shear_damping: Some(0.02),
        bend_damping: Some(0.003),
        ..MaterialChange::default() // stretch and friction kept
    };
    vec![
        Command::CutVertex {
            vertex: 7,
            direction: [1.0, 0.0, -0.5],
        },
        Command::Sew { a: 3, b: 9 },
        Command::Tear {
            a: 1,
            b: 2,
            split: false,
        },
        Command::Tear {
            a: 1,
            b: 2,
            split: true,
        },
        Command::Pin {
            vertex: 4,
            pinned: true,
        },
        Command::Pin {
            vertex: 4,
            pinned: false,
        },
        Command::Paint {
            point: [0.1, 0.45, -0.2],
            radius_m: 0.02,
            rgba: [200, 30, 40, 255],
        },
        Command::Undo,
        Command::Redo,
        Command::FreePins,
        Command::SetTearing(Tearing::Off),
        Command::SetTearing(Tearing::On {
            threshold: 1.6,
            split: false,
        }),
        Command::SetTearing(Tearing::On {
            threshold: 2.0,
            split: true,
        }),
        Command::Save {
            path: "/tmp/ß design.saiho".into(),
        },
        Command::SetTool {
            tool: crate::sim_to_ui::tool::PAINT,
            rgba: [1, 2, 3, 4],
            brush_m: 0.01,
        },
        Command::RemoveRegion {
            min: [0.75, 0.75],
            max: [1.5, 1.5],
        },
        Command::Seam {
            a: [[0.75, 0.75], [0.75, 1.0]],
            b: [[0.75, 0.75], [1.0, 0.75]],
            tolerance: 0.03,
        },
        Command::Export {
            dir: "out/export".into(),
            allowance_mm: 15.0,
        },
        Command::Reset {
            body: BodyChoice::Mannequin,
            grid: Some(96),
            material,
            substeps: Some(9),
            model: Some(crate::telemetry::scene_model::VBD),
            pattern: None,
        },
        Command::Reset {
            body: BodyChoice::Sphere,
            grid: None,
            material: MaterialChange::default(),
            substeps: None,
            model: None,
            pattern: None,
        },
        Command::Reset {
            body: BodyChoice::MannequinAPose,
            grid: Some(64),
            material: MaterialChange::default(),
            substeps: None,
            model: None,
            pattern: None,
        },
        Command::Reset {
            body: BodyChoice::Mannequin,
            grid: None,
            material: MaterialChange::default(),
            substeps: None,
            model: Some(crate::telemetry::scene_model::XPBD),
            pattern: Some("patterns/dress.svg".into()),
        },
        Command::Load {
            path: "design.saiho".into(),
        },
        Command::SetMaterial {
            material,
            substeps: None,
        },
        Command::SetMaterial {
            material: MaterialChange::default(),
            substeps: Some(20),
        },
    ]
    .into_iter()
    .chain(piece_variants())
    .collect()
}

/// The variants that make and sew pieces, and the fabric.
fn piece_variants() -> Vec<Command> {
    vec![
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.3, h: 0.5 },
            place: crate::ui_to_sim::place::BACK,
            drop_m: 0.42,
            edge_m: 0.02,
        },
        Command::AddPiece {
            shape: PieceShape::Ellipse { w: 0.2, h: 0.1 },
            place: crate::ui_to_sim::place::LEFT_ARM,
            drop_m: 0.0,
            edge_m: 0.01,
        },
        Command::AddPiece {
            shape: PieceShape::File {
                path: "patterns/skirt.dxf".into(),
            },
            place: crate::ui_to_sim::place::FRONT,
            drop_m: 0.3,
            edge_m: 0.03,
        },
        Command::SeamPlane {
            a: [[0.1, -0.2], [0.1, -0.6]],
            b: [[0.7, -0.2], [0.7, -0.6]],
            tolerance_m: 0.01,
        },
        Command::PlacePiece {
            piece: 2,
            place: 3,
            drop_m: 0.25,
        },
        Command::DeletePiece { piece: 1 },
        Command::RemoveSeam { seam: 3 },
        Command::SetFabric {
            name: "denim-11oz".into(),
        },
        Command::SetPieceFabric {
            piece: 1,
            name: "jersey-interlock".into(),
        },
        Command::NameSeam {
            seam: 2,
            name: "left side, 1 cm".into(),
        },
        Command::NamePiece {
            piece: 1,
            name: "back bodice".into(),
        },
        Command::PressDart {
            seam: 4,
            second: true,
        },
        Command::PressDart {
            seam: 0,
            second: false,
        },
        Command::DuplicatePiece {
            piece: 2,
            place: 1,
            drop_m: 0.0,
            mirrored: true,
            edge_m: 0.012,
        },
        Command::DuplicatePiece {
            piece: 0,
            place: 5,
            drop_m: 0.1,
            mirrored: false,
            edge_m: 0.03,
        },
        Command::SetGuard { on: true },
        Command::SetGuard { on: false },
        Command::SetSimulating { on: true },
        Command::SetSimulating { on: false },
        Command::SetStrainLimit { limit: 0.2 },
        Command::SetStrainLimit { limit: 0.0 },
        Command::CutPlane {
            from: [-0.05, -0.3],
            to: [0.45, -0.32],
        },
        Command::DartPlane {
            point: [0.2, -0.3],
            toward: [0.2, -0.52],
            width_m: 0.04,
        },
    ]
}

#[test]
fn every_variant_round_trips_through_the_wire_record() {
    let all = every_variant();
    let mut ops: Vec<u32> = all.iter().map(Command::op).collect();
    ops.sort_unstable();
    ops.dedup();
    assert_eq!(
        ops,
        (1..=op::LAST).collect::<Vec<_>>(),
        "a variant is missing"
    );
    let mut seq = 0;
    for c in all {
        let wire = c.to_wire(Header::next(&mut seq)).unwrap();
        assert_eq!(wire.op, c.op());
        assert_eq!(Command::from_wire(&wire), Ok(c.clone()), "{wire:?}");
    }
}

#[test]
fn a_bad_record_is_refused_and_a_long_path_is_not_sent() {
    let mut seq = 0;
    let mut wire = Command::Undo.to_wire(Header::next(&mut seq)).unwrap();
    wire.op = op::LAST + 1;
    assert!(Command::from_wire(&wire).is_err());
    let mut wire = Command::SetGuard { on: true }
        .to_wire(Header::next(&mut seq))
        .unwrap();
    wire.mode = 2;
    assert!(Command::from_wire(&wire).is_err(), "guard 2");
    let mut wire = Command::SetSimulating { on: false }
        .to_wire(Header::next(&mut seq))
        .unwrap();
    wire.mode = 3;
    let e = Command::from_wire(&wire).unwrap_err().to_string();
    assert!(e.contains("simulating 3"), "{e}");
    let mut wire = Command::Reset {
        body: BodyChoice::Cube,
        grid: None,
        material: MaterialChange::default(),
        substeps: None,
        model: None,
        pattern: None,
    }
    .to_wire(Header::next(&mut seq))
    .unwrap();
    wire.rgba[0] = 5;
    assert!(Command::from_wire(&wire).is_err(), "model 5");
    wire.rgba[0] = 0;
    wire.b = body::LAST + 1;
    assert!(Command::from_wire(&wire).is_err(), "body past the last");
    let mut wire = Command::DuplicatePiece {
        piece: 0,
        place: 0,
        drop_m: 0.0,
        mirrored: true,
        edge_m: 0.02,
    }
    .to_wire(Header::next(&mut seq))
    .unwrap();
    wire.mode = 2;
    let e = Command::from_wire(&wire).unwrap_err().to_string();
    assert!(e.contains("turned over 2"), "{e}");
    let mut wire = Command::PressDart {
        seam: 0,
        second: true,
    }
    .to_wire(Header::next(&mut seq))
    .unwrap();
    wire.mode = 2;
    let e = Command::from_wire(&wire).unwrap_err().to_string();
    assert!(e.contains("toward leg 2"), "{e}");
    let mut wire = Command::Undo.to_wire(Header::next(&mut seq)).unwrap();
    wire.header.protocol += 1;
    assert!(matches!(
        Command::from_wire(&wire),
        Err(MessageError::Protocol { .. })
    ));
    // A piece of no size, a place that is not one, an edge out of range, NaN.
    for bad in bad_pieces().into_iter().chain([
        // A strain limit below the material's range but not 0, past it, negative, NaN.
        Command::SetStrainLimit { limit: 0.005 },
        Command::SetStrainLimit { limit: 11.0 },
        Command::SetStrainLimit { limit: -0.2 },
        Command::SetStrainLimit { limit: f32::NAN },
        Command::SetFabric { name: "  ".into() },
        Command::SetPieceFabric {
            piece: 0,
            name: String::new(),
        },
    ]) {
        let wire = bad.to_wire(Header::next(&mut seq)).unwrap();
        assert!(Command::from_wire(&wire).is_err(), "{bad:?}");
    }
    let long = Command::Save {
        path: "x".repeat(TEXT_LEN + 1),
    };
    assert_eq!(
        long.to_wire(Header::default()),
        Err(CommandError::PathTooLong { len: TEXT_LEN + 1 })
    );
}

/// Pieces a sender must not ask for: of no size, at a place that is not one, with an
/// edge or a drop out of range or not a number.
fn bad_pieces() -> Vec<Command> {
    vec![
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.0, h: 0.4 },
            place: 0,
            drop_m: 0.0,
            edge_m: 0.02,
        },
        Command::AddPiece {
            shape: PieceShape::Ellipse {
                w: 0.2,
                h: f32::NAN,
            },
            place: 0,
            drop_m: 0.0,
            edge_m: 0.02,
        },
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.2, h: 0.2 },
            place: crate::ui_to_sim::place::LAST + 1,
            drop_m: 0.0,
            edge_m: 0.02,
        },
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.2, h: 0.2 },
            place: 0,
            drop_m: 0.0,
            edge_m: 0.0001,
        },
        Command::AddPiece {
            shape: PieceShape::File {
                path: String::new(),
            },
            place: 0,
            drop_m: 0.0,
            edge_m: 0.02,
        },
        Command::PlacePiece {
            piece: 0,
            place: 9,
            drop_m: 0.0,
        },
        // A top below the knees, above the place's start, not a number.
        Command::PlacePiece {
            piece: 0,
            place: 0,
            drop_m: 1.5,
        },
        Command::AddPiece {
            shape: PieceShape::Rectangle { w: 0.2, h: 0.2 },
            place: 0,
            drop_m: -0.1,
            edge_m: 0.02,
        },
        Command::DuplicatePiece {
            piece: 0,
            place: 0,
            drop_m: f32::NAN,
            mirrored: false,
            edge_m: 0.02,
        },
        Command::DuplicatePiece {
            piece: 0,
            place: 9,
            drop_m: 0.0,
            mirrored: false,
            edge_m: 0.02,
        },
        Command::DuplicatePiece {
            piece: 0,
            place: 0,
            drop_m: 0.0,
            mirrored: true,
            edge_m: f32::NAN,
        },
    ]
}
