use glam::Vec2;
use proptest::prelude::*;

use super::*;

/// The mesh's boundary edges (in one triangle only), as pattern points.
fn boundary(m: &ClothMesh) -> Vec<(Vec2, Vec2)> {
    let mut count = std::collections::HashMap::new();
    for t in &m.triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let p = |i: u32| {
        let q = m.positions[i as usize];
        Vec2::new(q.x, -q.z)
    };
    count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|((a, b), _)| (p(a), p(b)))
        .collect()
}

/// Distance from `p` to the outline's nearest side.
fn off_outline(o: &Outline, p: Vec2) -> f32 {
    let mut d = f32::INFINITY;
    for l in &o.loops {
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            d = d.min((a + (b - a) * t - p).length());
        }
    }
    d
}

/// Checks what the issue asks of any simple outline: a valid mesh whose boundary lies on
/// the outline and covers its length, no angle under 20 degrees, sides near `edge`.
fn check_mesh(o: &Outline, edge: f32) -> ClothMesh {
    let m = mesh_outline(o, edge).unwrap();
    m.validate().unwrap();
    let b = boundary(&m);
    for (p, q) in &b {
        assert!(
            off_outline(o, *p) < 1e-5 && off_outline(o, *q) < 1e-5,
            "{p} {q}"
        );
        assert!(
            (*q - *p).length() <= edge * 1.0001,
            "{} > {edge}",
            (*q - *p).length()
        );
    }
    let per: f32 = o
        .loops
        .iter()
        .map(|l| {
            (0..l.len())
                .map(|i| (l[(i + 1) % l.len()] - l[i]).length())
                .sum::<f32>()
        })
        .sum();
    let blen: f32 = b.iter().map(|(p, q)| (*q - *p).length()).sum();
    assert!(
        (blen - per).abs() < 1e-4 * per,
        "boundary {blen} against outline {per}"
    );
    assert!(m.min_angle_deg() >= 20.0, "min angle {}", m.min_angle_deg());
    // Winding: every triangle's normal points +Y.
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        assert!((b - a).cross(c - a).y > 0.0);
    }
    m
}

/// Found by the outline fuzz target: triangles whose corners lie on one line to within
/// f32 rounding passed the outline check, and spade panicked on their resampled sides
/// ("Conflicting edge"). They are refused, or meshed if spade can.
#[test]
fn slivers_are_refused_not_a_panic() {
    let p = |x: u8, y: u8| Vec2::new(x as f32 / 254.0, y as f32 / 254.0);
    for (corners, edge) in [
        ([p(0, 200), p(200, 0), p(120, 80)], 0.0976),
        ([p(80, 80), p(120, 0), p(60, 120)], 0.025),
        ([p(26, 0), p(31, 120), p(34, 192)], 0.0976),
    ] {
        let o = Outline {
            loops: vec![corners.to_vec()],
        };
        match mesh_outline(&o, edge) {
            Ok(m) => assert!(m.validate().is_ok()),
            Err(e) => assert!(
                matches!(
                    e,
                    MeshError::SidesMeet(_)
                        | MeshError::NoArea { .. }
                        | MeshError::SelfIntersecting { .. }
                ),
                "{e}"
            ),
        }
    }
}

/// Found by fuzzing (pattern-mesh, 2026-12-01): a DXF piece 60 km tall and 0.4 m wide
/// (a mistyped vertex) estimated under the vertex limit at a 0.5 m edge, and its
/// triangulation took 20 s. Beyond the span a piece may have, it is refused before any
/// work, whatever the edge; at the span it meshes.
#[test]
fn a_piece_beyond_the_span_is_refused_before_meshing() {
    let sliver = |h: f32| Outline {
        loops: vec![vec![
            Vec2::ZERO,
            Vec2::new(0.4, 0.0),
            Vec2::new(0.4, h),
            Vec2::new(0.0, 0.6),
        ]],
    };
    let e = check(&sliver(60_000.0)).unwrap_err();
    assert_eq!(e, MeshError::Span(60_000.0));
    assert!(e.to_string().contains("more than the 10 m"), "{e}");
    assert_eq!(mesh_outline(&sliver(60_000.0), 0.5), Err(e));
    let m = mesh_outline(&sliver(MAX_SPAN), 0.5).unwrap();
    assert!(m.validate().is_ok());
}

#[test]
fn rectangles_ellipses_and_l_shapes_mesh_well() {
    let m = check_mesh(&Outline::rectangle(1.0, 0.5), 0.05);
    // About area / equilateral triangle: 0.5 / (0.433 * 0.05^2) = 462 triangles.
    assert!(
        m.triangles.len() > 300 && m.triangles.len() < 1500,
        "{}",
        m.triangles.len()
    );
    check_mesh(&Outline::ellipse(0.3, 0.2, 0.02), 0.02);
    let l = Outline {
        loops: vec![vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(0.6, 0.0),
            Vec2::new(0.6, 0.2),
            Vec2::new(0.2, 0.2),
            Vec2::new(0.2, 0.5),
            Vec2::new(0.0, 0.5),
        ]],
    };
    check_mesh(&l, 0.03);
}

#[test]
fn a_hole_stays_a_hole() {
    let mut o = Outline::rectangle(1.0, 1.0);
    // A clockwise square hole in the middle.
    o.loops.push(vec![
        Vec2::new(0.3, 0.3),
        Vec2::new(0.3, 0.7),
        Vec2::new(0.7, 0.7),
        Vec2::new(0.7, 0.3),
    ]);
    let m = check_mesh(&o, 0.05);
    for t in &m.triangles {
        let c = t
            .iter()
            .map(|&i| m.positions[i as usize])
            .sum::<glam::Vec3>()
            / 3.0;
        let p = Vec2::new(c.x, -c.z);
        assert!(
            !(p.x > 0.3 && p.x < 0.7 && p.y > 0.3 && p.y < 0.7),
            "{p} in the hole"
        );
    }
}

#[test]
fn bad_outlines_are_refused_with_where() {
    let bow = Outline {
        loops: vec![vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
        ]],
    };
    let e = mesh_outline(&bow, 0.05).unwrap_err();
    assert_eq!(
        e,
        MeshError::SelfIntersecting {
            la: 0,
            a: 0,
            lb: 0,
            b: 2
        }
    );
    assert!(e.to_string().contains("crosses itself"));
    let two = Outline {
        loops: vec![vec![Vec2::ZERO, Vec2::X]],
    };
    assert!(matches!(
        mesh_outline(&two, 0.05),
        Err(MeshError::TooFewPoints { .. })
    ));
    let flat = Outline {
        loops: vec![vec![Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0)]],
    };
    // Flat: it runs back over itself, which is what is reported.
    assert!(matches!(
        mesh_outline(&flat, 0.05),
        Err(MeshError::NoArea { .. } | MeshError::SelfIntersecting { .. })
    ));
    let nan = Outline {
        loops: vec![vec![Vec2::ZERO, Vec2::X, Vec2::new(f32::NAN, 1.0)]],
    };
    assert!(matches!(
        mesh_outline(&nan, 0.05),
        Err(MeshError::NotFinite { .. })
    ));
    let sq = Outline::rectangle(1.0, 1.0);
    for edge in [0.0, -1.0, f32::NAN, 2.0] {
        assert!(matches!(
            mesh_outline(&sq, edge),
            Err(MeshError::EdgeLength(_))
        ));
    }
    assert!(matches!(
        mesh_outline(&Outline::rectangle(10.0, 10.0), 0.001),
        Err(MeshError::TooLarge { .. })
    ));
    // A hole crossing the outline.
    let mut o = Outline::rectangle(1.0, 1.0);
    o.loops.push(vec![
        Vec2::new(0.5, 0.5),
        Vec2::new(1.5, 0.5),
        Vec2::new(1.5, 0.6),
    ]);
    assert!(matches!(
        mesh_outline(&o, 0.05),
        Err(MeshError::SelfIntersecting { la: 0, lb: 1, .. })
    ));
}

/// A densely sampled curve (a GarmentCode curve is 64 points however short) loses the
/// points closer than the asked length, keeps its corners and the points asked to stay,
/// and still meshes with no side much shorter than the edge along it.
#[test]
fn simplify_drops_crowded_points_and_keeps_corners_and_seam_ends() {
    // A half disc of radius 0.1 m: its arc 400 points (0.8 mm apart), then the diameter.
    let mut l: Vec<Vec2> = (0..=400)
        .map(|k| {
            let t = k as f32 / 400.0 * std::f32::consts::PI;
            Vec2::new(t.cos(), t.sin()) * 0.1
        })
        .collect();
    l.push(Vec2::new(0.0, 0.0));
    let o = Outline { loops: vec![l] };
    let keep = o.loops[0][137];
    let edge = 0.03;
    let s = simplify(&o, 0.4 * edge, &[keep]);
    let out = &s.loops[0];
    assert!(out.len() < 40, "{} points left", out.len());
    let corners = [o.loops[0][0], o.loops[0][400], o.loops[0][401]];
    for c in corners.into_iter().chain([keep]) {
        assert!(out.contains(&c), "{c} kept");
    }
    for i in 0..out.len() {
        let (p, q) = (out[i], out[(i + 1) % out.len()]);
        let kept = |v: Vec2| v == keep || corners.contains(&v);
        assert!(
            (p - q).length() >= 0.4 * edge || kept(p) || kept(q),
            "{p} and {q} are {} apart",
            (p - q).length()
        );
    }
    // Every point dropped lies within the asked length of the new outline.
    for p in &o.loops[0] {
        assert!(off_outline(&s, *p) < 0.4 * edge);
    }
    let fine = mesh_outline(&o, edge).unwrap();
    let coarse = check_mesh(&s, edge);
    assert!(coarse.positions.len() * 3 < fine.positions.len());
    // Corners all but on top of each other merge (GarmentCode has 0.01 mm edges).
    let notch = Outline {
        loops: vec![vec![
            Vec2::ZERO,
            Vec2::new(0.4, 0.0),
            Vec2::new(0.4, 0.5),
            Vec2::new(0.39999, 0.5),
            Vec2::new(0.0, 0.5),
        ]],
    };
    assert_eq!(simplify(&notch, 0.4 * edge, &[]).loops[0].len(), 4);
    // An outline that simplifying would leave under three points stays as it was.
    let tiny = Outline::rectangle(0.005, 0.005);
    assert_eq!(simplify(&tiny, 0.012, &[]), tiny);
}

/// A star-shaped polygon: `n` points at angles evenly spaced, radii from `r`.
fn star(r: &[f32]) -> Outline {
    let n = r.len();
    Outline {
        loops: vec![
            (0..n)
                .map(|k| {
                    let t = k as f32 / n as f32 * std::f32::consts::TAU;
                    Vec2::new(t.cos(), t.sin()) * r[k]
                })
                .collect(),
        ],
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Any star-shaped outline whose corners are not sharper than the angle limit.
    #[test]
    fn star_outlines_mesh_well(r in prop::collection::vec(0.25f32..0.4, 5..24)) {
        let o = star(&r);
        // Skip outlines with a corner under 25 degrees (the refinement cannot widen an
        // angle the outline itself makes).
        let l = &o.loops[0];
        let n = l.len();
        let sharp = (0..n).any(|i| {
            let (p, c, q) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
            (p - c).angle_to(q - c).abs().to_degrees() < 25.0
        });
        prop_assume!(!sharp);
        check_mesh(&o, 0.04);
    }
}
