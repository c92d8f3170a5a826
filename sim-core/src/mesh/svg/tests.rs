//! The SVG reader's tests: shapes, units, holes, marks, the pieces' order and bad input.

use super::*;

fn perimeter(l: &[Vec2]) -> f32 {
    (0..l.len())
        .map(|i| (l[(i + 1) % l.len()] - l[i]).length())
        .sum()
}

#[test]
fn shapes_transforms_units_and_holes() {
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="100mm" viewBox="0 0 20 10">
        <g id="front"><title>Front</title>
          <rect x="0" y="0" width="8" height="5"/>
          <circle cx="4" cy="2.5" r="1"/>
        </g>
        <g transform="translate(10,0)"><path d="M0,0 L5,0 A2.5,2.5 0 0 1 0,0 Z"/></g>
        <path d="M0,8 L3,8" />
    </svg>"#;
    let p = read_svg(svg).unwrap();
    assert_eq!(p.len(), 2, "{p:?}");
    // 1 user unit = 10 mm: the rect is 80 x 50 mm, with the circle (r 10 mm) a hole.
    assert_eq!(p[0].name, "Front");
    assert_eq!(p[0].outline.loops.len(), 2);
    assert!((perimeter(&p[0].outline.loops[0]) - 0.26).abs() < 1e-5);
    let c = perimeter(&p[0].outline.loops[1]);
    assert!((c - 0.02 * std::f32::consts::PI).abs() < 2e-4, "{c}");
    // The half disc: 50 mm of line and a 25 mm-radius half circle, drawn with an arc.
    let d = perimeter(&p[1].outline.loops[0]);
    assert!(
        (d - (0.05 + 0.025 * std::f32::consts::PI)).abs() < 3e-4,
        "{d}"
    );
    assert_eq!(p[1].name, "piece 2");
    // Meshable, hole included.
    crate::mesh::mesher::mesh_outline(&p[0].outline, 0.005).unwrap();
    // The pieces come in the file's order, not by size.
    let two = r#"<svg xmlns="http://www.w3.org/2000/svg"><g id="small"><rect width="2" height="2"/>
        </g><g id="big"><rect x="5" width="8" height="5"/></g></svg>"#;
    let names: Vec<String> = read_svg(two).unwrap().into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["small", "big"]);
}

#[test]
fn a_seam_mark_of_no_length_is_left_out() {
    // A seam along the rect's bottom edge, closed, and then closed 10,000 times more:
    // its two segments are marks, the closings of no length are not.
    let svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="80mm" height="50mm" viewBox="0 0 80 50">
          <rect x="0" y="0" width="80" height="50"/>
          <path class="seam" data-seam="A" d="M0,50 L40,50 L40,50 Z{}"/>
        </svg>"#,
        "Z".repeat(10_000)
    );
    let p = read_svg(&svg).unwrap();
    assert_eq!(p.len(), 1);
    assert_eq!(
        p[0].marks.len(),
        2,
        "{:?}",
        &p[0].marks[..3.min(p[0].marks.len())]
    );
    assert!(p[0].marks.iter().all(|m| (m.b - m.a).length() > 0.0));
}

#[test]
fn no_shape_or_no_svg_is_a_clear_error() {
    assert!(matches!(
        read_svg(r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 L1,1"/></svg>"#),
        Err(SvgError::NoClosedShape)
    ));
    assert!(matches!(read_svg("hello"), Err(SvgError::Xml(_))));
    assert!(matches!(
        read_svg(r#"<svg><path d="Q oops"/></svg>"#),
        Err(SvgError::PathData(_))
    ));
}

/// Found by the svg fuzz target: a coordinate of 1e29 made the flattening ask for
/// 690 GB (an abort), one of 2e30 in a curve's control point took seconds.
#[test]
fn a_shape_beyond_the_scene_is_refused() {
    for d in [
        "M 10 10 L 190 100000000000000000000000000000 C 0 150 0 50 10 10 Z",
        "M 10 10 L 190 10 Q 2000000000000000000000000000000 100 190 190 Z",
    ] {
        let svg = format!(r#"<svg width="200mm" viewBox="0 0 200 200"><path d="{d}"/></svg>"#);
        let e = read_svg(&svg).unwrap_err();
        assert!(matches!(e, SvgError::TooFar(_)), "{e}");
        assert!(e.to_string().contains("another unit"), "{e}");
    }
    // Found by the svg fuzz target: an arc whose end lies 1e44 away (flags run into
    // the number) and a huge circle took minutes to cut into Béziers.
    for shape in [
        r#"<path d="M 10 10 L 191 01 h 9a11 100 040 1000011111111111111111111111111111111111111111131 1 41 11 10 Z"/>"#,
        r#"<circle cx="0" cy="0" r="1e40"/>"#,
        r#"<path d="M0,0L1e10-3z"/>"#,
    ] {
        let svg = format!(r#"<svg width="200mm" viewBox="0 0 200 200">{shape}</svg>"#);
        assert!(
            matches!(read_svg(&svg), Err(SvgError::TooFar(_))),
            "{shape}"
        );
    }
    assert_eq!(first_huge("M 1e9 -2.5e+3 .5-7"), None);
    assert_eq!(first_huge("L3-1.5e10"), Some(-1.5e10));
    // A transform that scales a small shape out of the scene, likewise.
    let svg = r#"<svg><g transform="scale(1e12)"><rect width="10" height="10"/></g></svg>"#;
    assert!(matches!(read_svg(svg), Err(SvgError::TooFar(_))));
}
