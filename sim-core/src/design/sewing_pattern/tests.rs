//! The pattern out's tests.

use super::*;
use crate::mesh::ClothMesh;
use crate::solver::{Cloth, Environment, Material, ModelKind, Simulation};
use glam::Vec2;

/// A flat `size` m square cloth of `n` x `n` cells on the floor.
pub(crate) fn square(size: f32, n: usize) -> Design {
    let m = Material::default();
    let cloth = Cloth::new(ClothMesh::grid(size, size, n, n, 0.0).unwrap(), &m).unwrap();
    let sim = Simulation::new(
        cloth,
        None,
        ModelKind::Xpbd,
        m,
        Environment::default(),
        None,
    )
    .unwrap();
    Design::new(sim)
}

#[test]
fn a_square_cloth_is_one_piece_with_its_perimeter() {
    let d = square(1.0, 8);
    let p = pieces(&d);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].loops.len(), 1);
    assert!(
        (p[0].perimeters()[0] - 4000.0).abs() < 0.01,
        "{:?}",
        p[0].perimeters()
    );
    assert!(area2(&p[0].loops[0]) > 0.0, "outer loop counter-clockwise");
    // A 10 mm allowance: the cut line is the square grown by 10 mm each side.
    let f = finish(p, 10.0);
    assert!((perimeter(&f[0].cut[0]) - 4080.0).abs() < 0.01);
    let (lo, _) = bounds(&f[0].cut[0]);
    assert!(
        lo.x.abs() < 1e-9 && lo.y.abs() < 1e-9,
        "laid out at the origin"
    );
}

#[test]
fn a_band_cut_out_makes_two_pieces_and_a_hole_makes_two_loops() {
    let mut d = square(1.0, 8);
    // The two middle rows of cells (triangle centres in the band), across the cloth.
    d.remove_region(Vec2::new(-0.1, 0.37), Vec2::new(1.1, 0.63))
        .unwrap();
    let p = pieces(&d);
    assert_eq!(p.len(), 2);
    for q in &p {
        // Each half: 1000 x 375 mm.
        assert!(
            (q.perimeters()[0] - 2750.0).abs() < 0.01,
            "{:?}",
            q.perimeters()
        );
    }
    let laid = finish(p, 0.0);
    let (lo0, hi0) = bounds(&laid[0].cut[0]);
    let (lo1, hi1) = bounds(&laid[1].cut[0]);
    // Two 1000 mm pieces: one row each, the second above, 20 mm apart.
    assert!(
        lo1.y >= hi0.y + 19.999 && lo0.x.abs() < 1e-9 && lo1.x.abs() < 1e-9,
        "laid out in rows without overlap: {lo0} {hi0} {lo1} {hi1}"
    );
    // Narrow pieces share a row, within the layout's width.
    let narrow: Vec<Piece> = (0..7)
        .map(|i| {
            let mut q = laid[i % 2].clone();
            let sq = vec![
                DVec2::ZERO,
                DVec2::new(300.0, 0.0),
                DVec2::new(300.0, 200.0),
                DVec2::new(0.0, 200.0),
            ];
            (q.loops, q.cut, q.seams, q.notches) = (vec![sq.clone()], vec![sq], vec![], vec![]);
            q
        })
        .collect();
    let laid = finish(narrow, 0.0);
    let boxes: Vec<(DVec2, DVec2)> = laid.iter().map(|q| bounds(&q.cut[0])).collect();
    // Four of 300 mm and three gaps in a row (1260 mm), then the other three.
    assert!(boxes.iter().all(|(_, hi)| hi.x <= LAYOUT_WIDTH_MM));
    assert_eq!(boxes.iter().filter(|(lo, _)| lo.y == 0.0).count(), 4);
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            let apart = a.1.x + 19.999 <= b.0.x
                || b.1.x + 19.999 <= a.0.x
                || a.1.y + 19.999 <= b.0.y
                || b.1.y + 19.999 <= a.0.y;
            assert!(apart, "{a:?} {b:?}");
        }
    }

    let mut d = square(1.0, 8);
    d.remove_region(Vec2::new(0.24, 0.24), Vec2::new(0.76, 0.76))
        .unwrap();
    let p = pieces(&d);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].loops.len(), 2, "an outline and a hole");
    assert!(
        (p[0].perimeters()[1] - 2000.0).abs() < 0.01,
        "{:?}",
        p[0].perimeters()
    );
    assert!(area2(&p[0].loops[1]) < 0.0, "the hole clockwise");
    // The hole's allowance goes into the hole: its cut line is shorter.
    let f = finish(p, 10.0);
    assert!(perimeter(&f[0].cut[1]) < perimeter(&f[0].loops[1]));
    assert!(perimeter(&f[0].cut[0]) > perimeter(&f[0].loops[0]));
}

#[test]
fn both_sides_of_a_seam_carry_its_label_and_a_welded_seam_stays_an_edge() {
    let mut d = square(1.0, 8);
    // Cut a notch: remove two columns of cells from the bottom edge to the middle,
    // then sew the notch's two sides (a dart).
    d.remove_region(Vec2::new(0.37, -0.1), Vec2::new(0.63, 0.5))
        .unwrap();
    let side = |x: f32| -> Vec<u32> {
        let mut v: Vec<(f32, u32)> = (0..d.sim.cloth.len() as u32)
            .filter(|&i| d.sim.cloth.live.vertex_alive(i))
            .filter_map(|i| {
                let uv = d.vertex_uv(i)?;
                ((uv.x - x).abs() < 1e-4 && uv.y < 0.5 - 1e-4).then_some((uv.y, i))
            })
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        v.into_iter().map(|(_, i)| i).collect()
    };
    let (a, b) = (side(0.375), side(0.625));
    assert_eq!(a.len(), 4);
    d.add_seam(&a, &b, 0.05).unwrap();
    let p = pieces(&d);
    assert_eq!(p.len(), 1);
    let labelled = |p: &Piece| p.seams.iter().filter(|s| s.0 == "A").count();
    assert_eq!(
        labelled(&p[0]),
        6,
        "three segments each side: {:?}",
        p[0].seams
    );
    // Welding the pairs in 3D keeps the dart open in the pattern.
    for &(x, y) in &d.seams[0].pairs.clone() {
        d.sew(x, y).unwrap();
    }
    let p = pieces(&d);
    assert_eq!(p.len(), 1);
    assert!(
        (p[0].perimeters()[0] - 5000.0).abs() < 0.01,
        "{:?}",
        p[0].perimeters()
    );
}

#[test]
fn a_paths_pattern_length_is_its_rest_length_however_it_hangs() {
    let mut d = square(1.0, 8);
    let row: Vec<u32> = (0..=8).collect();
    assert!((d.pattern_length(&row) - 1.0).abs() < 1e-5);
    // Stretched in 3D, the pattern length stays.
    for v in &row {
        d.sim.cloth.x[*v as usize].x *= 2.0;
    }
    assert!((d.pattern_length(&row) - 1.0).abs() < 1e-5);
    assert!((d.pattern_length(&row[..3]) - 0.25).abs() < 1e-5);
    // A vertex skipped (as a seam's shorter side is paired): the pattern's distance
    // between the two, not the 3D one (0.5 m, stretched).
    assert!((d.pattern_length(&[0, 2, 3]) - 0.375).abs() < 1e-5);
}

#[test]
fn a_seam_skipping_vertices_on_a_straight_side_is_still_one_seam() {
    // A loop whose bottom side runs 0..4; the seam holds 0, 1, 3, 4 (2 skipped, on
    // the same straight side) and 6, round a corner from 4.
    let pts = [
        (0.0, 0.0),
        (1.0, 0.0),
        (2.0, 0.0),
        (3.0, 0.0),
        (4.0, 0.0),
        (4.0, 2.0),
        (2.0, 2.0),
        (0.0, 2.0),
    ];
    let l: Vec<Key> = (0..pts.len() as u32)
        .map(|v| (v, [v as i64, 0, 0]))
        .collect();
    let places: HashMap<Key, DVec2> = l
        .iter()
        .zip(pts)
        .map(|(k, (x, y))| (*k, DVec2::new(x, y)))
        .collect();
    // The outline edges marked as seam A when `held` are the seam's vertices.
    let edges = |held: &[u32]| -> Vec<(u32, u32)> {
        let seam_of: HashMap<u32, Vec<String>> =
            held.iter().map(|&v| (v, vec!["A".to_string()])).collect();
        let s = seam_segments(&l, &places, &seam_of);
        s.iter().map(|(_, a, b)| (a.0, b.0)).collect()
    };
    // 1-2 and 2-3 filled; 4-5-6 turns a corner: not.
    assert_eq!(
        edges(&[0, 1, 3, 4, 6]),
        vec![(0, 1), (1, 2), (2, 3), (3, 4)]
    );
    // The seam's last vertex follows a skipped one, and the outline turns at it (the
    // dress's back at the armhole corner, 29 mm of seam D lost before): 3-4 is the
    // seam's all the same.
    assert_eq!(edges(&[0, 1, 2, 4]), vec![(0, 1), (1, 2), (2, 3), (3, 4)]);
}

/// Two vertices skipped with one held between them (a dart's leg paired to a shorter
/// one in the studio: its pattern lost the second run, and with it the dart): both runs
/// are the seam's.
#[test]
fn a_seam_skipping_every_other_vertex_is_still_one_seam() {
    // The bottom side runs 0..6; the seam holds 0, 1, 3, 5, 6.
    let mut pts: Vec<(f64, f64)> = (0..7).map(|x| (x as f64, 0.0)).collect();
    pts.extend([(6.0, 2.0), (0.0, 2.0)]);
    let l: Vec<Key> = (0..pts.len() as u32)
        .map(|v| (v, [v as i64, 0, 0]))
        .collect();
    let places: HashMap<Key, DVec2> = l
        .iter()
        .zip(&pts)
        .map(|(k, &(x, y))| (*k, DVec2::new(x, y)))
        .collect();
    let seam_of: HashMap<u32, Vec<String>> = [0, 1, 3, 5, 6]
        .into_iter()
        .map(|v| (v, vec!["A".to_string()]))
        .collect();
    let s = seam_segments(&l, &places, &seam_of);
    let edges: Vec<(u32, u32)> = s.iter().map(|(_, a, b)| (a.0, b.0)).collect();
    assert_eq!(edges, (0..6).map(|v| (v, v + 1)).collect::<Vec<_>>());
}

#[test]
fn offset_mitres_right_angles_and_bevels_sharp_corners() {
    let sq = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(10.0, 10.0),
        DVec2::new(0.0, 10.0),
    ];
    let o = offset(&sq, 1.0);
    assert_eq!(o.len(), 4);
    assert!((o[0] - DVec2::new(-1.0, -1.0)).length() < 1e-9, "{o:?}");
    // A needle-sharp spike: its tip is bevelled (two points), not mitred far out.
    let spike = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(100.0, 0.5),
        DVec2::new(0.0, 1.0),
    ];
    let o = offset(&spike, 1.0);
    assert!(o.len() > 3);
    assert!(o.iter().all(|p| p.x < 106.0), "{o:?}");
}

/// The outline of `c` as chained loops of places.
fn outline(c: &Corners) -> Vec<Vec<DVec2>> {
    let boundary: Vec<(Key, Key)> = boundary_of(&c.tris)
        .into_iter()
        .map(|(a, b)| (c.keys[a as usize], c.keys[b as usize]))
        .collect();
    chain(&boundary)
        .iter()
        .map(|l| l.iter().map(|k| c.places[c.ids[k] as usize]).collect())
        .collect()
}

#[test]
fn triangles_a_weld_folded_away_go_back_into_the_outline() {
    let p = |x: f32, z: f32| Vec3::new(x, 0.0, z);
    let to2 = |q: Vec3| DVec2::new(q.x as f64, q.z as f64);
    let (c0, c1, c2, c3, m) = (
        p(0.0, 0.0),
        p(2.0, 0.0),
        p(2.0, 2.0),
        p(0.0, 2.0),
        p(1.0, 1.0),
    );
    // Corners numbered from (vertex, rest place) triangles.
    let part = |tris: &[[(u32, Vec3); 3]]| {
        let mut c = Corners::default();
        for t in tris {
            let tri = t.map(|(v, q)| c.id(key(v, q), || to2(q)));
            c.tris.push(tri);
        }
        c
    };
    // A notch: four triangles round a centre, the first folded away, its two corners
    // on the outline since merged into one vertex (7) as a seam's weld leaves them.
    let mut c = part(&[
        [(7, c1), (2, c2), (4, m)],
        [(2, c2), (3, c3), (4, m)],
        [(3, c3), (7, c0), (4, m)],
    ]);
    assert_eq!(outline(&c)[0].len(), 5, "the notch");
    add_eased(&mut c, &[[c0, c1, m]], to2);
    let l = &outline(&c)[0];
    assert_eq!(l.len(), 4, "{l:?}");
    assert!((perimeter(l) - 8.0).abs() < 1e-9);
    // A corner cut off: the square in two triangles, the one with corner c1 folded
    // away and c1 merged into another vertex (no key left at its place).
    let mut c = part(&[[(0, c0), (2, c2), (3, c3)]]);
    add_eased(&mut c, &[[c0, c1, c2]], to2);
    let l = &outline(&c)[0];
    assert_eq!(l.len(), 4, "{l:?}");
    assert!((perimeter(l) - 8.0).abs() < 1e-9);
    // A triangle of another part (no outline edge of this one) stays out.
    let mut c = part(&[[(0, c0), (2, c2), (3, c3)]]);
    add_eased(&mut c, &[[p(5.0, 0.0), p(6.0, 0.0), p(6.0, 1.0)]], to2);
    assert_eq!(c.tris.len(), 1);
}

/// A seam's two sides get the same notches though one is just under the quarter-notch
/// length and the other just over (the count follows the seam's longer side).
#[test]
fn both_sides_of_a_seam_get_the_same_notches() {
    let piece = |w: f64| {
        let sq = vec![
            DVec2::ZERO,
            DVec2::new(w, 0.0),
            DVec2::new(w, 100.0),
            DVec2::new(0.0, 100.0),
        ];
        Piece {
            name: format!("{w}"),
            loops: vec![sq.clone()],
            cut: vec![sq],
            seams: vec![("A".into(), DVec2::ZERO, DVec2::new(w, 0.0))],
            seam_names: vec![],
            grain: (DVec2::new(10.0, 50.0), DVec2::new(20.0, 50.0)),
            fabric: "cloth".into(),
            notches: vec![],
            drills: vec![],
            press_second: vec![],
            presses: vec![],
            start: None,
            seam_starts: vec![],
        }
    };
    let short = QUARTER_NOTCHES_MM - 10.0;
    let laid = finish(vec![piece(short), piece(QUARTER_NOTCHES_MM + 10.0)], 10.0);
    assert_eq!(laid[0].notches.len(), 3);
    assert_eq!(laid[1].notches.len(), 3);
    // Alone, the short side has one (its middle).
    assert_eq!(finish(vec![piece(short)], 10.0)[0].notches.len(), 1);
}

/// A slit inside a piece (a cut that ends inside it, as a dart's two cuts could leave
/// beyond its point) is cut along as it is; offset by the allowance it was a hole 20 mm
/// wide. A real hole, 40 mm across, is still cut round, the allowance inside it.
#[test]
fn a_slit_is_cut_along_and_a_hole_round() {
    let v = DVec2::new;
    let outer = vec![v(0.0, 0.0), v(300.0, 0.0), v(300.0, 300.0), v(0.0, 300.0)];
    let slit = vec![
        v(100.0, 100.0),
        v(110.0, 105.0),
        v(120.0, 100.0),
        v(110.0, 105.0),
    ];
    let hole = vec![
        v(200.0, 200.0),
        v(200.0, 240.0),
        v(240.0, 240.0),
        v(240.0, 200.0),
    ];
    let piece = Piece {
        name: "p".into(),
        loops: vec![outer.clone(), slit.clone(), hole.clone()],
        cut: vec![outer, slit.clone(), hole.clone()],
        seams: vec![],
        seam_names: vec![],
        grain: (v(50.0, 150.0), v(250.0, 150.0)),
        fabric: "cloth".into(),
        notches: vec![],
        drills: vec![],
        press_second: vec![],
        presses: vec![],
        start: None,
        seam_starts: vec![],
    };
    let f = finish(vec![piece], 10.0).remove(0);
    let shift = f.loops[0][0];
    let back = |l: &[DVec2]| l.iter().map(|&q| q - shift).collect::<Vec<_>>();
    assert_eq!(back(&f.cut[1]), slit);
    assert!(
        area2(&f.cut[2]).abs() < 0.5 * area2(&hole).abs(),
        "{:?}",
        f.cut[2]
    );
}

/// A dart made in the pattern and pressed toward its second leg: its seam says so, one
/// undo takes it back, a design file keeps it, and the pattern out's cap follows it. A
/// seam that is no dart, or no seam, is refused and changes nothing.
#[test]
fn a_dart_is_pressed_toward_either_leg_undoably_and_the_file_keeps_it() {
    let mut d = square(1.0, 16);
    d.dart_on_plane(Vec2::new(0.0, -0.2), Vec2::new(0.0, -0.6), 0.06)
        .unwrap();
    let cut = |d: &Design| finish(pieces(d), 10.0).remove(0).cut;
    let before = cut(&d);
    let undo = d.history.undo_len();
    d.press_dart(0, true).unwrap();
    assert!(d.seams[0].press_second);
    assert_eq!(d.history.undo_len(), undo + 1);
    let pressed = cut(&d);
    assert_ne!(before, pressed, "the cap turns over");
    let view = view_pieces(&d);
    assert_eq!(view[0].presses.len(), 1);
    // Saved and read back.
    let back = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert!(back.seams[0].press_second);
    assert_eq!(cut(&back), pressed);
    d.undo().unwrap();
    assert!(!d.seams[0].press_second);
    assert_eq!(cut(&d), before);
    // A straight seam along the square's far edge is no dart; seam 7 is not there.
    let mut s = square(1.0, 8);
    s.seam_on_plane(
        [Vec2::new(-0.5, 0.5), Vec2::new(0.0, 0.5)],
        [Vec2::new(0.5, 0.5), Vec2::new(0.0, 0.5)],
        0.01,
    )
    .unwrap();
    let e = s.press_dart(0, true).unwrap_err().to_string();
    assert!(e.contains("seam A is no dart"), "{e}");
    assert!(matches!(
        s.press_dart(7, true),
        Err(crate::design::EditError::NoSeam { index: 7, .. })
    ));
    assert!(!s.seams[0].press_second);
}

/// Two triangles eased into a seam side by side (a dart's leg at its mouth, welded in
/// turn to one vertex that then welded on: a side-seam dart on the dress at 3 cm edges,
/// frame 56) share the corner their welds merged away, which no live triangle has any
/// more. Each was put back with a corner of its own there, so the outline ran out to
/// their far corner and back (a spike into the piece, and an exported pattern our own
/// reader refused as crossing itself). Put back with one corner there, the outline runs
/// along the leg again, each place once.
#[test]
fn triangles_eased_side_by_side_share_the_corner_their_welds_merged_away() {
    let at = |x: f32, y: f32| Vec3::new(x, 0.0, y);
    let (p57, p58, p52, p48, p49) = (
        at(-1.0, 0.0),
        at(0.0, 0.0),
        at(1.0, 0.0),
        at(3.0, 0.0),
        at(4.0, 0.0),
    );
    let (p234, top) = (at(0.5, 1.0), at(1.5, 3.0));
    let to2 = |p: Vec3| DVec2::new(p.x as f64, p.z as f64);
    let mut c = Corners::default();
    let live = [
        [(1, p57), (2, p58), (3, p234)],
        [(3, p234), (4, p48), (5, p49)],
        [(1, p57), (3, p234), (6, top)],
        [(3, p234), (5, p49), (6, top)],
    ];
    for t in live {
        let tri = t.map(|(v, p)| c.id(key(v, p), || to2(p)));
        c.tris.push(tri);
    }
    let outline = |c: &Corners| -> Vec<DVec2> {
        let b = boundary_of(&c.tris);
        let next: HashMap<u32, u32> = b.iter().copied().collect();
        let mut at = b.iter().map(|e| e.0).min().unwrap();
        let mut out = vec![];
        for _ in 0..b.len() {
            out.push(c.places[at as usize]);
            at = next[&at];
        }
        out
    };
    // The notch the two welds left: 57, 58, 234, 48, 49, top.
    assert_eq!(outline(&c).len(), 6);
    add_eased(&mut c, &[[p234, p52, p48], [p234, p58, p52]], to2);
    let loop_ = outline(&c);
    let want: Vec<DVec2> = [p57, p58, p52, p48, p49, top].map(to2).to_vec();
    assert_eq!(boundary_of(&c.tris).len(), 6, "{loop_:?}");
    let start = loop_.iter().position(|q| *q == want[0]).unwrap();
    let turned: Vec<DVec2> = (0..6).map(|k| loop_[(start + k) % 6]).collect();
    assert_eq!(turned, want);
}
