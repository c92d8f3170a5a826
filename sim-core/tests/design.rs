//! The design file: a saved design loads back identical; damaged, truncated or newer
//! files fail with a clear error; random and mutated bytes never panic the loader.

// Test helpers: a failed unwrap is a failed test, with its location.
#![allow(clippy::unwrap_used)]

use glam::Vec3;
use proptest::prelude::*;
use sim_core::design::Design;
use sim_core::design::TearMode;
use sim_core::design::file::{DesignError, FORMAT};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};
use sim_core::solver::{Simulation, StepError};

/// A small edited design on the cube: cut, torn, sewn, pinned, painted, with a seam.
fn edited() -> Design {
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
    cfg.grid = 12;
    let mut s = build_design(&cfg).unwrap();
    for _ in 0..10 {
        s.step().unwrap();
    }
    let c = (6 * 13 + 6) as u32;
    let copy = s.cut_vertex(c, Vec3::X).unwrap();
    s.cut_vertex(c + 13, Vec3::X).unwrap();
    s.sew(c, copy).unwrap();
    s.tear_edge(20, 21, TearMode::Delete).unwrap();
    s.set_pin(0, true).unwrap();
    let p = s.sim.cloth.x[c as usize];
    s.paint(p, 0.05, [10, 20, 200, 255]).unwrap();
    s.add_seam(&[1, 2, 3], &[9, 10, 11], 0.05).unwrap();
    s.tear.enabled = true;
    s
}

#[test]
fn a_design_round_trips() {
    let s = edited();
    let bytes = s.save_design().unwrap();
    let t = Design::load_design(&bytes).unwrap();
    assert_eq!(t.sim.cloth.live.triangles(), s.sim.cloth.live.triangles());
    let tris = |s: &Design| s.sim.cloth.live.iter().map(|(_, t)| *t).collect::<Vec<_>>();
    assert_eq!(tris(&t), tris(&s), "rest corners and UVs survive");
    assert_eq!(t.sim.cloth.x, s.sim.cloth.x);
    assert_eq!(t.sim.cloth.v, s.sim.cloth.v);
    assert_eq!(t.sim.cloth.pinned, s.sim.cloth.pinned);
    assert_eq!(t.sim.cloth.mass, s.sim.cloth.mass);
    assert_eq!(t.seams, s.seams);
    assert_eq!(t.texture.rgba, s.texture.rgba);
    assert_eq!(t.sim.material, s.sim.material);
    assert_eq!(t.tear, s.tear);
    assert_eq!(t.sim.frame, s.sim.frame);
    assert_eq!(t.sim.body.as_ref().unwrap().name, "cube");
    // And it simulates as a solver built afresh from the saved state does. (The
    // saved simulation itself differs slightly: its edited constraints are solved after
    // the packed ones, a different Gauss-Seidel order.)
    let mut fresh = Design::new(
        Simulation::new(
            s.sim.cloth.clone(),
            s.sim.body.clone(),
            s.sim.model,
            s.sim.material,
            s.sim.env,
            Some(s.sim.substeps),
        )
        .unwrap(),
    );
    fresh.seams = s.seams.clone();
    fresh.tear = s.tear;
    // The file keeps the guard's switch (on: the scenario's xpbd default). The steps are
    // compared without it: its pairs depend on distances in the pattern, which the loaded
    // pattern has to rounding only, and a pair listed or not moves a vertex by up to the
    // search's margin, far above the rounding this compares to.
    assert!(s.guarded() && t.guarded());
    let mut loaded = t;
    loaded.sim.set_guard(false);
    for _ in 0..5 {
        fresh.step().unwrap();
        loaded.step().unwrap();
    }
    let worst = fresh
        .sim
        .cloth
        .x
        .iter()
        .zip(&loaded.sim.cloth.x)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0f32, f32::max);
    // Rounding only (the loaded pattern mesh is rebuilt from the triangles' corners).
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn bad_files_fail_clearly() {
    let bytes = edited().save_design().unwrap();
    assert!(matches!(
        Design::load_design(b"hello world, not a design"),
        Err(DesignError::NotADesign)
    ));
    let mut newer = bytes.clone();
    newer[8..12].copy_from_slice(&(FORMAT + 1).to_le_bytes());
    let e = Design::load_design(&newer).unwrap_err();
    assert!(matches!(e, DesignError::Newer { found } if found == FORMAT + 1));
    assert!(e.to_string().contains("newer"), "{e}");
    let truncated = &bytes[..bytes.len() / 2];
    let e = Design::load_design(truncated).unwrap_err();
    assert!(
        e.to_string().contains("checksum") || e.to_string().contains("truncated"),
        "{e}"
    );
    let mut flipped = bytes.clone();
    let k = bytes.len() - 100;
    flipped[k] ^= 0x40;
    let e = Design::load_design(&flipped).unwrap_err();
    assert!(e.to_string().contains("checksum"), "{e}");
}

#[test]
fn saving_to_a_file_and_back() {
    let dir = std::env::temp_dir().join(format!("saiho-design-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("d.saiho");
    let s = edited();
    s.save_design_file(&path).unwrap();
    let t = Design::load_design_file(&path).unwrap();
    assert_eq!(t.sim.cloth.live.tri_count(), s.sim.cloth.live.tri_count());
    let e = Design::load_design_file(&dir.join("missing.saiho")).unwrap_err();
    assert!(e.to_string().contains("missing.saiho"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Re-seals a mutated file with a valid checksum so the loader's deeper checks run.
fn reseal(mut b: Vec<u8>) -> Vec<u8> {
    if b.len() < 8 {
        return b;
    }
    let n = b.len() - 8;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &x in &b[..n] {
        h ^= x as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    b[n..].copy_from_slice(&h.to_le_bytes());
    b
}

/// Found by the design fuzz target: a design whose cloth moves at 1e30 m/s loaded, and
/// its first frame sent the contact's grids over billions of cells. Refusing such speeds
/// was not the answer (the same target then found a loaded design blowing up, saving,
/// and not loading back): it loads slowed to 1000 m/s and says so, and steps. A vertex
/// beyond 10 km is refused, as a frame that leaves the scene is a divergence, so what a
/// frame leaves always loads.
#[test]
fn racing_vertices_load_slowed_far_flung_ones_are_refused() {
    let mut d = edited();
    d.sim.cloth.x[5].x = 1e5;
    let e = Design::load_design(&d.save_design().unwrap()).unwrap_err();
    assert!(e.to_string().contains("vertex 5 lies at"), "{e}");
    // The whole cloth 1 m inside the bound, flying out at 1000 m/s.
    let shift = Vec3::new(1e4 - 1.0 - d.sim.cloth.x[5].x, 0.0, 0.0);
    for (x, v) in d.sim.cloth.x.iter_mut().zip(&mut d.sim.cloth.v) {
        *x += shift;
        *v = Vec3::new(1e3, 0.0, 0.0);
    }
    assert!(matches!(d.step(), Err(StepError::Diverged { .. })));
    let mut d = edited();
    d.sim.cloth.v[3] = Vec3::new(0.0, -1e30, 0.0);
    let mut back = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert!(back.sim.cloth.v.iter().all(|v| v.length() <= 1000.0 + 1e-3));
    assert!(
        back.sim
            .notices
            .iter()
            .any(|n| n.contains("1 vertices were saved moving faster")),
        "{:?}",
        back.sim.notices
    );
    back.step().unwrap();
    Design::load_design(&back.save_design().unwrap()).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Random bytes (with the right magic or not) never panic the loader.
    #[test]
    fn random_bytes_never_panic(mut b in prop::collection::vec(any::<u8>(), 0..4096), magic in any::<bool>()) {
        if magic && b.len() >= 16 {
            b[..8].copy_from_slice(b"SAIHODSN");
            b[8..12].copy_from_slice(&1u32.to_le_bytes());
        }
        let _ = Design::load_design(&reseal(b));
    }

    /// A valid file with bytes overwritten, cut short or lengthened, then re-sealed: the
    /// loader returns an error or a valid design, never panics.
    #[test]
    fn mutated_designs_fail_cleanly(edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
                                    cut in any::<Option<prop::sample::Index>>()) {
        static BASE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
        let mut b = BASE.get_or_init(|| edited().save_design().unwrap()).clone();
        for (i, v) in &edits {
            let k = i.index(b.len());
            b[k] = *v;
        }
        if let Some(c) = cut {
            b.truncate(c.index(b.len()).max(16));
        }
        if let Ok(s) = Design::load_design(&reseal(b)) {
            prop_assert!(s.validate().is_ok());
        }
    }
}

/// A design saved crossing the body (moved 10 cm into the cube, as nobody's solver would
/// leave it) loads, and says how it crosses rather than hide it.
#[test]
fn a_crossed_design_loads_and_says_so() {
    let cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
    let mut s = build_design(&ScenarioConfig { grid: 12, ..cfg }).unwrap();
    let clean = Design::load_design(&s.save_design().unwrap()).unwrap();
    assert!(
        !clean.sim.notices.iter().any(|n| n.contains("crosses")),
        "{:?}",
        clean.sim.notices
    );
    for p in &mut s.sim.cloth.x {
        p.y -= 0.1;
    }
    let crossed = s.sim.crossings();
    assert!(crossed.body_pairs > 0);
    let t = Design::load_design(&s.save_design().unwrap()).unwrap();
    let note = t
        .sim
        .notices
        .iter()
        .find(|n| n.contains("crosses"))
        .unwrap_or_else(|| panic!("no crossing notice in {:?}", t.sim.notices));
    assert!(
        note.contains(&format!("the body in {}", crossed.body_pairs)),
        "{note}"
    );
    assert_eq!(t.sim.cloth.x, s.sim.cloth.x, "loaded as it was saved");
}

#[test]
fn pieces_round_trip_and_format_1_files_still_load() {
    // A dress: two named pieces, placed round the mannequin.
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let mut d = build_design(&cfg).unwrap();
    let names: Vec<String> = d.piece_list().into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["front", "back"]);
    d.source = "patterns/dress.svg".into();
    let t = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(t.pieces, d.pieces);
    assert_eq!(t.source, "patterns/dress.svg");
    // A pattern named with control characters is no path: left out, said, the design
    // whole.
    d.source = "dress\u{0}.svg".into();
    let t = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!((t.source.as_str(), t.pieces.len()), ("", 2));
    assert!(
        t.sim.notices.iter().any(|n| n.contains("not a path")),
        "{:?}",
        t.sim.notices
    );
    d.source.clear();
    assert!(t.pieces.iter().all(|p| p.placement.is_some()));
    // A file written in format 1 (before pieces), kept as it was written.
    let bytes = include_bytes!("fixtures/format1-drape-cube-grid8.saiho");
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 1);
    const { assert!(FORMAT >= 2) };
    let old = Design::load_design(bytes).unwrap();
    assert!(old.pieces.is_empty());
    assert!(old.source.is_empty());
    assert!(!old.guarded(), "a file without the field has no guard");
    assert_eq!(old.sim.cloth.len(), 81);
    let list = old.piece_list();
    assert_eq!(list.len(), 1);
    assert_eq!(list[0].name, "piece 1");
    // A piece record that is not one is refused, and nothing is built.
    let mut bad = d;
    bad.pieces[0].name = String::new();
    let err = Design::load_design(&bad.save_design().unwrap()).unwrap_err();
    assert!(err.to_string().contains("a piece's name"), "{err}");
}

/// The dress at 6 cm edges, its front cut in two: every triangle across a band at mid
/// height removed.
fn dress_with_front_cut() -> Design {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let mut d = build_design(&cfg).unwrap();
    let band = d.record_slots(0, |own| (own.y + 0.4).abs() < 0.05);
    assert!(!band.is_empty());
    d.remove_triangles(&band).unwrap();
    d
}

#[test]
fn cutting_a_piece_in_two_lists_two_pieces() {
    let d = dress_with_front_cut();
    let names: Vec<String> = d.piece_list().into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["front", "front 2", "back"], "{names:?}");
}

/// A part a cut left of a piece is named alone: the other part keeps its name, in the
/// list and in the pattern out, through a save and load, and after a further cut of the
/// named part (the larger side keeps the name). Undo gives the old names back; a name
/// another part has is refused and changes nothing; a piece in one part is renamed.
#[test]
fn a_part_of_a_cut_piece_is_named_alone() {
    let mut d = dress_with_front_cut();
    let names =
        |d: &Design| -> Vec<String> { d.piece_list().into_iter().map(|p| p.name).collect() };
    let at = |d: &Design, n: &str| names(d).iter().position(|m| m == n).unwrap();
    assert_eq!(names(&d), ["front", "front 2", "back"]);
    let steps = d.history.undo_steps();
    assert_eq!(d.name_piece(at(&d, "front 2"), "skirt").unwrap(), "front 2");
    assert_eq!(names(&d), ["front", "skirt", "back"]);
    assert_eq!(d.name_piece(at(&d, "front"), "bodice").unwrap(), "front");
    assert_eq!(names(&d), ["bodice", "skirt", "back"]);
    assert_eq!(d.history.undo_steps(), steps + 2);
    // Refused: a name another part or piece has, as the piece itself would be.
    for taken in ["skirt", "back"] {
        let e = d
            .name_piece(at(&d, "bodice"), taken)
            .unwrap_err()
            .to_string();
        assert!(e.contains("already"), "{e}");
    }
    assert_eq!(d.history.undo_steps(), steps + 2);
    let out = sim_core::design::sewing_pattern::pieces(&d);
    let mut out_names: Vec<&str> = out.iter().map(|p| p.name.as_str()).collect();
    out_names.sort();
    assert_eq!(out_names, ["back", "bodice", "skirt"]);
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(names(&loaded), ["bodice", "skirt", "back"]);
    let mut bad = loaded;
    bad.pieces[0].parts[0].points.clear();
    let e = Design::load_design(&bad.save_design().unwrap()).unwrap_err();
    assert!(e.to_string().contains("finite points"), "{e}");
    // The bodice (the front's top, own y above -0.35) cut again across its middle:
    // the part holding the most of the name's points keeps it, the other is called
    // after the front as made.
    let top = d.record_slots(0, |own| (own.y + 0.2).abs() < 0.03 && own.y > -0.35);
    assert!(!top.is_empty());
    d.remove_triangles(&top).unwrap();
    let now = names(&d);
    assert_eq!(now.len(), 4, "{now:?}");
    for n in ["bodice", "skirt", "back"] {
        assert_eq!(now.iter().filter(|m| *m == n).count(), 1, "{now:?}");
    }
    assert!(now.contains(&"front".to_string()), "{now:?}");
    d.undo().unwrap();
    d.undo().unwrap();
    assert_eq!(names(&d), ["front", "skirt", "back"]);
    d.undo().unwrap();
    assert_eq!(names(&d), ["front", "front 2", "back"]);
    // The back, in one part, is renamed as a piece.
    d.name_piece(at(&d, "back"), "back bodice").unwrap();
    assert_eq!(d.pieces[1].name, "back bodice");
    assert!(d.pieces[1].parts.is_empty());
}

/// Scissors in the pattern view: a straight line from beside the sewn, draped front to
/// beside it cuts the front in two (listed as two pieces), as one undoable operation;
/// the garment crosses nothing in the frames after. A line of no length is refused and
/// changes nothing.
#[test]
fn a_line_across_a_piece_in_the_pattern_cuts_it_in_two() {
    let mut d = sewn_dress();
    let steps = d.history.undo_steps();
    let front = &d.pieces[0];
    let (lo, hi) = outline_box(front);
    let y = 0.5 * (lo.y + hi.y);
    let (a, b) = (
        glam::Vec2::new(lo.x - 0.02, y) + front.offset,
        glam::Vec2::new(hi.x + 0.02, y) + front.offset,
    );
    assert!(d.cut_line(a, a).is_err());
    // 30 cm above the front's top: no cloth along it.
    let above = glam::Vec2::new(0.0, hi.y - lo.y);
    let e = d.cut_line(a + above, b + above).unwrap_err().to_string();
    assert!(e.contains("no cloth along the line"), "{e}");
    assert_eq!(
        d.history.undo_steps(),
        steps,
        "a refused cut changes nothing"
    );
    let split = d.cut_line(a, b).unwrap();
    assert!(split >= 5, "{split} vertices split");
    let names: Vec<String> = d.piece_list().into_iter().map(|p| p.name).collect();
    assert_eq!(names, ["front", "front 2", "back"], "{names:?}");
    assert_eq!(d.history.undo_steps(), steps + 1);
    // The pattern out: each side seam the cut crossed is marked by its two stretches
    // (front to back above the cut, lower front to back below), each label on two
    // pieces, as a pattern pairs its seams (the back's whole side said "B" to both).
    let pattern = sim_core::design::sewing_pattern::pieces(&d);
    let mut on: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for p in &pattern {
        for (label, ..) in &p.seams {
            let e = on.entry(label.clone()).or_default();
            if !e.contains(&p.name) {
                e.push(p.name.clone());
            }
        }
    }
    let labels: Vec<&String> = on.keys().collect();
    assert_eq!(labels, ["A", "B1", "B2", "C", "D1", "D2"], "{on:?}");
    assert!(on.values().all(|pieces| pieces.len() == 2), "{on:?}");
    assert!(on["B2"].contains(&"front 2".to_string()), "{on:?}");
    // The lower front (the part without the shoulders) deleted: the back's side below
    // the cut is sewn to nothing and is marked as no seam; above it, the seams are whole
    // again (the back's lower side said B2 on one piece alone).
    let lower = (pattern.iter())
        .find(|p| p.name.starts_with("front") && p.seams.iter().all(|(l, ..)| l != "A"))
        .map(|p| p.name.clone())
        .unwrap();
    let k = (d.piece_list().iter())
        .position(|p| p.name == lower)
        .unwrap();
    d.delete_piece(k).unwrap();
    let labels = |d: &Design| {
        let mut on: std::collections::BTreeMap<String, usize> = Default::default();
        for p in sim_core::design::sewing_pattern::pieces(d) {
            let mine: std::collections::BTreeSet<String> =
                p.seams.iter().map(|(l, ..)| l.clone()).collect();
            for l in mine {
                *on.entry(l).or_default() += 1;
            }
        }
        on
    };
    let after = labels(&d);
    assert_eq!(
        after.into_iter().collect::<Vec<_>>(),
        [("A", 2), ("B", 2), ("C", 2), ("D", 2)].map(|(l, n)| (l.to_string(), n)),
    );
    d.undo().unwrap();
    // The upper front (the shoulders) deleted instead: the back's shoulders are sewn to
    // nothing and have no label (they said A and C on the back alone); the sides below
    // the cut are whole seams between the lower front and the back.
    let upper = (pattern.iter())
        .find(|p| p.name.starts_with("front") && p.name != lower)
        .map(|p| p.name.clone())
        .unwrap();
    let k = (d.piece_list().iter())
        .position(|p| p.name == upper)
        .unwrap();
    d.delete_piece(k).unwrap();
    assert_eq!(
        labels(&d).into_iter().collect::<Vec<_>>(),
        [("B", 2), ("D", 2)].map(|(l, n)| (l.to_string(), n)),
    );
    d.undo().unwrap();
    // The cut undone as well, and the dress sewn whole again simulates without a
    // crossing. (Undone after 120 frames instead, it may be refused: the lower front,
    // cut free, hangs 7 cm below the upper one by then, and putting the two sides back
    // together would pass the cloth through the body; the undo says so and waits.)
    assert_eq!(d.undo().unwrap(), "cut line");
    for _ in 0..120 {
        d.step().unwrap();
    }
    assert_eq!(crossings(&d), (0, 0));
    assert_eq!(d.piece_list().len(), 2);
}

/// The dress at 6 cm triangles and a `w` x `h` m rectangle named `name` to add to it.
fn dress_and_rectangle(
    name: &str,
    w: f32,
    h: f32,
) -> (Design, sim_core::design::garment::PieceSpec) {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let spec = sim_core::design::garment::PieceSpec {
        name: name.into(),
        outline: sim_core::mesh::mesher::Outline::rectangle(w, h),
        fabric: "cotton".into(),
        grain: 0.0,
        placement: None,
        start: None,
        fallback: None,
    };
    (build_design(&cfg).unwrap(), spec)
}

/// A piece's top (or bottom) edge from corner to corner, where the pattern view draws
/// it (its outline's box, moved by the piece's offset).
fn top_or_bottom(r: &sim_core::design::PieceRecord, top: bool) -> [glam::Vec2; 2] {
    let (lo, hi) = outline_box(r);
    let y = if top { hi.y } else { lo.y };
    [
        glam::Vec2::new(lo.x, y) + r.offset,
        glam::Vec2::new(hi.x, y) + r.offset,
    ]
}

/// The box round a piece's outer outline, in its own pattern plane.
fn outline_box(r: &sim_core::design::PieceRecord) -> (glam::Vec2, glam::Vec2) {
    (r.outline.loops[0].iter()).fold((glam::Vec2::MAX, glam::Vec2::MIN), |(a, b), p| {
        (a.min(*p), b.max(*p))
    })
}

/// Two rectangles' sides seamed by drags as a designer makes them in the pattern view:
/// from a little inside one corner to a little inside the other, with the view's 8-pixel
/// tolerance wider than an edge. The seam follows each side from corner to corner (the
/// corners too); sorted along the drag, the first vertex round the far corner came before
/// the corner and the seam was refused ("not an edge on the cloth's border").
#[test]
fn a_drag_near_the_corners_seams_the_whole_side() {
    use sim_core::design::garment::Place;
    let (mut d, front) = dress_and_rectangle("front piece", 0.4, 0.5);
    let back = sim_core::design::garment::PieceSpec {
        name: "back piece".into(),
        ..front.clone()
    };
    d.add_piece(&front, Place::Front, 0.03).unwrap();
    d.add_piece(&back, Place::Back, 0.03).unwrap();
    let side = |r: &sim_core::design::PieceRecord, right: bool| {
        let (lo, hi) = outline_box(r);
        let x = if right { hi.x } else { lo.x };
        // 2 cm in from each corner, top to bottom.
        [
            glam::Vec2::new(x, hi.y - 0.02) + r.offset,
            glam::Vec2::new(x, lo.y + 0.02) + r.offset,
        ]
    };
    let n = d.pieces.len();
    let (a, b) = (side(&d.pieces[n - 2], false), side(&d.pieces[n - 1], true));
    let tol = 0.044;
    let pa = d.plane_path(a[0], a[1], tol);
    assert!(pa.len() >= 17, "{} vertices along a 50 cm side", pa.len());
    let pairs = d.seam_on_plane(a, b, tol).unwrap();
    assert_eq!(pairs, pa.len());
    // Both corners are in it: its ends lie 50 cm apart in the pattern.
    let ends = d.pattern_length(&pa);
    assert!((ends - 0.5).abs() < 0.005, "{ends}");
}

/// A cut sewn up again from the pattern view, as a waist seam along a style line is:
/// the cut's two sides lie on one line there, and two drags along it take one side and
/// then the other, vertex to vertex (before, both took the same side and the seam was
/// refused as sharing its vertices). The seam joins the two parts, which weld into one
/// piece again with a whole outline, and cross nothing.
#[test]
fn a_cut_is_sewn_up_again_by_dragging_along_it_twice() {
    let mut d = sewn_dress();
    let (lo, hi) = outline_box(&d.pieces[0]);
    let offset = d.pieces[0].offset;
    let y = 0.5 * (lo.y + hi.y);
    let at = |x: f32| glam::Vec2::new(x, y) + offset;
    let (a, b) = (at(lo.x - 0.02), at(hi.x + 0.02));
    let along = [at(lo.x + 0.02), at(hi.x - 0.02)];
    d.cut_line(a, b).unwrap();
    let names =
        |d: &Design| -> Vec<String> { d.piece_list().into_iter().map(|p| p.name).collect() };
    assert_eq!(names(&d), ["front", "front 2", "back"]);
    let tol = 0.02;
    // The second drag a little shorter, as a hand draws it: still the whole other side.
    let again = [at(lo.x + 0.06), at(hi.x - 0.05)];
    // Either drag first: whichever side each finds by itself, the second is the
    // first's twin.
    let (pa, pb) = d.seam_sides(again, along, tol, true);
    twins(&d, &pa, &pb);
    // Drags that each pass one end of the other: the longer side and its twins.
    let (left, right) = ([at(lo.x), at(hi.x - 0.08)], [at(lo.x + 0.08), at(hi.x)]);
    let (pl, pr) = d.seam_sides(left, right, tol, true);
    twins(&d, &pl, &pr);
    let longer = [left, right].map(|[a, b]| d.plane_path(a, b, tol).len());
    assert_eq!(pl.len(), longer[0].max(longer[1]));
    let (pa, pb) = d.seam_sides(along, again, tol, true);
    assert!(pa.len() >= 5 && pb.len() >= 5, "{pa:?} {pb:?}");
    assert!(pa.iter().all(|v| !pb.contains(v)), "{pa:?} {pb:?}");
    // One side on each part.
    let slots = d.piece_slots(0).unwrap();
    let in_first = |v: u32| {
        (slots.iter())
            .filter_map(|&s| d.sim.cloth.live.tri(s))
            .any(|t| t.v.contains(&v))
    };
    assert_ne!(in_first(pa[1]), in_first(pb[1]));
    // Each vertex paired with its twin across the cut, at the same place.
    twins(&d, &pa, &pb);
    let pairs = d.seam_on_plane(along, again, tol).unwrap();
    assert_eq!(pairs, pa.len());
    let paired: Vec<(u32, u32)> = pa.iter().copied().zip(pb.iter().copied()).collect();
    assert_eq!(d.seams.last().unwrap().pairs, paired, "each to its twin");
    // So also where the two sides lie unlike in 3D (one part hanging stretched): paired
    // by their lengths there, the pairs slipped a vertex and the welds left slits.
    let mut bunched = sewn_dress();
    bunched.cut_line(a, b).unwrap();
    let (qa, qb) = bunched.seam_sides(along, again, tol, true);
    let x = &mut bunched.sim.cloth.x;
    let was: Vec<glam::Vec3> = qb.iter().map(|&v| x[v as usize]).collect();
    let n = qb.len() - 1;
    for i in 1..n {
        // Vertex i at the square of its share of the way along.
        let t = (i as f32 / n as f32).powi(2) * n as f32;
        let k = t.floor() as usize;
        x[qb[i] as usize] = was[k].lerp(was[(k + 1).min(n)], t - k as f32);
    }
    bunched.seam_on_plane(along, again, tol).unwrap();
    let paired: Vec<(u32, u32)> = qa.iter().copied().zip(qb.iter().copied()).collect();
    assert_eq!(bunched.seams.last().unwrap().pairs, paired);
    for _ in 0..240 {
        d.step().unwrap();
    }
    assert_eq!(names(&d), ["front", "back"]);
    assert_eq!(crossings(&d), (0, 0));
    // The seam list's two lengths, both the cut's (the B side once read 909 mm for
    // 460, measured from its end's place on the back, across the side seam).
    let cut = d.pattern_length(&pa);
    let (la, lb) = d.seam_lengths(d.seams.last().unwrap());
    assert!(
        (la - cut).abs() < 1e-3 && (lb - cut).abs() < 1e-3,
        "{la} {lb} against {cut}"
    );
    // Welded where it was cut, the front's pattern is whole again: one outline, no slit.
    let out = sim_core::design::sewing_pattern::pieces(&d);
    let front = out.iter().find(|p| p.name == "front").unwrap();
    assert_eq!(front.loops.len(), 1, "{} loops", front.loops.len());
    // A slit (a cut from beside the front to its middle) sewn shut the same way.
    let mut slit = sewn_dress();
    let middle = at(0.5 * (lo.x + hi.x));
    slit.cut_line(a, middle).unwrap();
    let along = [at(lo.x + 0.01), middle];
    let (sa, sb) = slit.seam_sides(along, along, tol, true);
    assert!(sa.len() >= 4, "{sa:?}");
    twins(&slit, &sa, &sb);
    // Cut to a point, the slit is closed there: its point is both sides' one vertex,
    // one pair fewer to sew.
    assert_eq!(
        (sa.last(), sa.len()),
        (sb.last(), sb.len()),
        "{sa:?} {sb:?}"
    );
    assert_eq!(slit.seam_on_plane(along, along, tol).unwrap(), sa.len() - 1);
    // Along a border with nothing across it, the second drag is still the same border,
    // and refused in words a designer reads.
    let hem = along.map(|p| p + glam::Vec2::new(0.0, lo.y - y));
    let e = d.seam_on_plane(hem, hem, tol).unwrap_err().to_string();
    assert!(e.contains("one border"), "{e}");
}

/// Asserts that each vertex of `pa` shares a place in the pattern with its partner in
/// `pb`: the two sides of a cut, vertex to twin.
fn twins(d: &Design, pa: &[u32], pb: &[u32]) {
    let live = &d.sim.cloth.live;
    let places = |v: u32| -> Vec<glam::Vec2> {
        (live.tris_of(v).iter())
            .filter_map(|&s| live.tri(s))
            .map(|t| t.rest[t.corner(v).unwrap()])
            .map(|p| glam::Vec2::new(p.x, -p.z))
            .collect()
    };
    for (&a, &b) in pa.iter().zip(pb) {
        let (at_a, at_b) = (places(a), places(b));
        assert!(
            at_a.iter().any(|p| at_b.contains(p)),
            "{a} at {at_a:?}, {b} at {at_b:?}"
        );
    }
    assert_eq!(pa.len(), pb.len());
}

/// A piece asked to start lower (a skirt at the waist) starts that much lower, added,
/// moved or copied; a drop past the knees, negative or not a number is refused and
/// changes nothing.
#[test]
fn a_piece_starts_as_much_lower_as_asked() {
    use sim_core::design::garment::{Place, Start};
    let (mut d, skirt) = dress_and_rectangle("skirt", 0.6, 0.3);
    let n0 = d.sim.cloth.len();
    // The new piece's highest vertex.
    let top = |d: &Design| {
        d.sim.cloth.x[n0..]
            .iter()
            .map(|p| p.y)
            .fold(f32::MIN, f32::max)
    };
    d.add_piece(&skirt, Place::Back, 0.05).unwrap();
    let high = top(&d);
    d.undo().unwrap();
    let waist = Start {
        place: Place::Back,
        drop: 0.42,
    };
    d.add_piece(&skirt, waist, 0.05).unwrap();
    let low = top(&d);
    assert!((high - low - 0.42).abs() < 0.01, "{high} then {low} m");
    // Moved to the front, 0.2 m down from the shoulders.
    let at = d.piece_list().len() - 1;
    let front = Start {
        place: Place::Front,
        drop: 0.2,
    };
    d.place_piece(at, front).unwrap();
    assert!(
        (high - top(&d) - 0.2).abs() < 0.01,
        "{high} then {}",
        top(&d)
    );
    // Refused, nothing changed.
    let steps = d.history.undo_steps();
    let x = d.sim.cloth.x.clone();
    for drop in [1.5, -0.1, f32::NAN] {
        let bad = Start {
            place: Place::Front,
            drop,
        };
        let e = d.add_piece(&skirt, bad, 0.05).unwrap_err().to_string();
        assert!(e.contains("below the place's start"), "{e}");
        assert!(d.place_piece(at, bad).is_err());
        assert!(d.duplicate_piece(at, bad, false, 0.05).is_err());
    }
    assert_eq!((d.history.undo_steps(), &d.sim.cloth.x), (steps, &x));
}

/// A piece cut, then placed: its cut's two sides, at one pattern place, start parted as
/// a fresh cut's are (40 µm, each into its own triangles), not lying on each other with
/// no direction between them but the normal; nothing crosses. Until 2026-12-07 the
/// placement left them together (4 touching pairs on the fuzzer's small cloth).
#[test]
fn a_cut_piece_placed_starts_with_its_cut_parted() {
    use sim_core::design::garment::Place;
    let (mut d, pocket) = dress_and_rectangle("pocket", 0.3, 0.2);
    let n0 = d.sim.cloth.len() as u32;
    d.add_piece(&pocket, Place::Back, 0.05).unwrap();
    let live = &d.sim.cloth.live;
    let inner = (n0..d.sim.cloth.len() as u32)
        .find(|&v| live.vertex_alive(v) && !live.is_boundary(v))
        .expect("an inner vertex");
    let before = d.sim.cloth.len();
    d.cut_vertex(inner, Vec3::X).unwrap();
    assert!(d.sim.cloth.len() > before, "the cut made a copy");
    let at = d.piece_list().len() - 1;
    d.place_piece(at, Place::Front).unwrap();
    let c = d.sim.crossings();
    assert_eq!((c.self_pairs, c.body_pairs), (0, 0));
    let x = &d.sim.cloth.x;
    let apart = (before..d.sim.cloth.len())
        .map(|copy| x[copy].distance(x[inner as usize]))
        .fold(f32::MAX, f32::min);
    assert!((3e-5..1e-3).contains(&apart), "{apart} m apart");
    d.validate().unwrap();
}

/// A seam to a piece that is deleted before it closed goes with the piece (it could
/// never close, and the studio went on listing it); the dress's own seams stay; undo
/// brings piece and seam back.
#[test]
fn a_deleted_pieces_open_seams_go_with_it() {
    use sim_core::design::garment::Place;
    let (mut d, pocket) = dress_and_rectangle("pocket", 0.3, 0.2);
    d.add_piece(&pocket, Place::Front, 0.05).unwrap();
    let edge = top_or_bottom;
    // The front's hem to the back's (stays), the pocket's sides to each other (goes).
    let (front, back) = (edge(&d.pieces[0], false), edge(&d.pieces[1], false));
    d.seam_on_plane(front, back, 0.01).unwrap();
    let r = d.pieces[2].clone();
    let ([tl, tr], [bl, br]) = (edge(&r, true), edge(&r, false));
    d.seam_on_plane([tl, bl], [tr, br], 0.01).unwrap();
    let seams = d.seams.clone();
    assert_eq!(seams.len(), 2);
    d.delete_piece(2).unwrap();
    assert_eq!(d.seams[..], seams[..seams.len() - 1]);
    d.undo().unwrap();
    assert_eq!(d.seams, seams);
    d.validate().unwrap();
}

/// A sleeve added at the dress's shoulder starts clear of the shoulder (a layer out, or a
/// step down the arm), and one added where another is further out or lower, crossing
/// nothing (until 2026-12-05 a piece on an arm was refused wherever it would start on
/// cloth: "34 crossing triangle pairs" here, 56 on the draped dress in the studio).
#[test]
fn a_sleeve_starts_clear_of_the_shoulder_and_of_another_sleeve() {
    use sim_core::design::garment::{LAYER, Place, Placement};
    let (mut d, sleeve) = dress_and_rectangle("sleeve", 0.36, 0.3);
    let mut starts = Vec::new();
    for k in 0..2 {
        d.add_piece(&sleeve, Place::LeftArm, 0.04)
            .unwrap_or_else(|e| panic!("sleeve {k}: {e}"));
        let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
        let crossed =
            sim_core::collision::crossings::count(&d.sim.cloth.x, &tris, d.sim.body.as_ref());
        assert_eq!(
            (crossed.self_pairs, crossed.body_pairs),
            (0, 0),
            "sleeve {k}"
        );
        match d.pieces[2 + k].placement {
            Some(Placement::Arm { down, room, .. }) => starts.push((down, room)),
            other => panic!("{other:?}"),
        }
    }
    // The dress's shoulder covers the top of the arm: the first does not start where
    // asked; the second, on the first, a layer further out or lower still.
    assert_ne!(starts[0], (0.0, 0.0), "{starts:?}");
    assert!(
        starts[1].1 >= starts[0].1 + LAYER - 1e-6 || starts[1].0 > starts[0].0,
        "{starts:?}"
    );
}

/// A pocket added to the dress starts a layer out from the front, crossing nothing;
/// placed at the back it goes there; deleted, it leaves the list; undo takes each back.
#[test]
fn pieces_are_added_placed_and_deleted_undoably() {
    use sim_core::design::garment::{PieceSpec, Place, Placement};
    use sim_core::mesh::mesher::Outline;
    let (mut d, pocket) = dress_and_rectangle("pocket", 0.3, 0.2);
    let before = (d.sim.cloth.len(), d.piece_list());
    let n = d.add_piece(&pocket, Place::Front, 0.05).unwrap();
    assert!(n > 10);
    assert_eq!(d.sim.cloth.len(), before.0 + n);
    let list = d.piece_list();
    assert_eq!(
        list.iter().map(|p| p.name.as_str()).collect::<Vec<_>>(),
        ["front", "back", "pocket"]
    );
    assert_eq!(list[2].vertices, n);
    let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    let crossed = sim_core::collision::crossings::count(&d.sim.cloth.x, &tris, d.sim.body.as_ref());
    assert_eq!((crossed.self_pairs, crossed.body_pairs), (0, 0));
    // The front panel is there already: the pocket starts a layer (or more) out.
    match d.pieces[2].placement {
        Some(Placement::Around { out, .. }) => assert!(out > 0.0, "{out}"),
        other => panic!("{other:?}"),
    }
    // It is cloth like any other piece: it survives a frame, and the file keeps it.
    d.step().unwrap();
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(loaded.piece_list().len(), 3);
    // Placed at the back: its vertices go behind the body (z < 0).
    let front_z = d.sim.cloth.x[before.0].z;
    d.place_piece(2, Place::Back).unwrap();
    assert!(front_z > 0.0 && d.sim.cloth.x[before.0].z < 0.0);
    assert!(matches!(
        d.place_piece(7, Place::Back),
        Err(sim_core::design::EditError::NoPiece { index: 7, count: 3 })
    ));
    // A seam drawn in the pattern plane: the pocket's top edge to the front's hem (both
    // borders), as the studio's pattern view sends it.
    let edge_of = top_or_bottom;
    let (hem, top) = (edge_of(&d.pieces[0], false), edge_of(&d.pieces[2], true));
    let seams = d.seams.len();
    let pairs = d.seam_on_plane(top, hem, 0.01).unwrap();
    assert!(pairs >= 5, "{pairs} pairs");
    assert_eq!(d.seams.len(), seams + 1);
    // Two more: the pocket's sides to each other (a tube), its bottom to the back's hem.
    let r = d.pieces[2].clone();
    let [tl, tr] = edge_of(&r, true);
    let [bl, br] = edge_of(&r, false);
    d.seam_on_plane([tl, bl], [tr, br], 0.01).unwrap();
    d.seam_on_plane([bl, br], edge_of(&d.pieces[1].clone(), false), 0.01)
        .unwrap();
    // Removing a seam in the middle: the later ones move up; undo puts it back in place.
    let all = d.seams.clone();
    assert_eq!(all.len(), seams + 3);
    let n = d.remove_seam(seams + 1).unwrap();
    assert_eq!(n.pairs, all[seams + 1].pairs.len());
    assert_eq!(d.seams.len(), all.len() - 1);
    assert_eq!(d.seams[seams + 1], all[seams + 2]);
    assert!(matches!(
        d.remove_seam(99),
        Err(sim_core::design::EditError::NoSeam { index: 99, .. })
    ));
    assert_eq!(d.undo().unwrap(), "remove seam");
    assert_eq!(d.seams, all);
    // The tube's two sides are equal: the pocket's whole 0.2 m height, corner to corner
    // (until 2026-12-03 a path left out its start, and the seam was 0.15 m).
    let (la, lb) = d.seam_lengths(&d.seams[seams + 1]);
    assert!(
        (la - lb).abs() < 1e-4 && (la - 0.2).abs() < 1e-3,
        "{la} {lb}"
    );
    for _ in 0..3 {
        assert_eq!(d.undo().unwrap(), "seam");
    }
    // Deleted: two pieces listed again.
    d.delete_piece(2).unwrap();
    assert_eq!(d.piece_list().len(), 2);
    // Undo: delete, place, (the frame is not an edit), add.
    assert_eq!(d.undo().unwrap(), "delete piece");
    assert_eq!(d.undo().unwrap(), "place piece");
    assert!(d.sim.cloth.x[before.0].z > 0.0);
    assert_eq!(d.undo().unwrap(), "add piece");
    assert_eq!((d.sim.cloth.len(), d.piece_list()), before);
    d.validate().unwrap();
    // A piece that cannot be meshed is refused with its name, nothing changed.
    let bad = PieceSpec {
        outline: Outline {
            loops: vec![vec![glam::Vec2::ZERO, glam::Vec2::X]],
        },
        ..pocket
    };
    let err = d.add_piece(&bad, Place::Front, 0.05).unwrap_err();
    assert!(err.to_string().starts_with("pocket:"), "{err}");
    assert_eq!((d.sim.cloth.len(), d.piece_list()), before);
}

/// A piece too large to mesh at its edge (a 1 m square at 2 mm: some 290,000
/// vertices) or wider than the body is refused before meshing, saying what to change.
#[test]
fn pieces_too_large_or_too_wide_are_refused() {
    use sim_core::design::garment::{PieceSpec, Place};
    use sim_core::mesh::mesher::Outline;
    let (mut d, sheet) = dress_and_rectangle("sheet", 1.0, 1.0);
    let before = (d.sim.cloth.len(), d.piece_list());
    let err = d.add_piece(&sheet, Place::Front, 0.002).unwrap_err();
    assert!(err.to_string().contains("choose a longer edge"), "{err}");
    let wide = PieceSpec {
        outline: Outline::rectangle(2.0, 2.0),
        ..sheet
    };
    let err = d.add_piece(&wide, Place::Front, 0.0125).unwrap_err();
    assert!(err.to_string().contains("2.00 m wide"), "{err}");
    assert_eq!((d.sim.cloth.len(), d.piece_list()), before);
}

/// The vertex estimate made before meshing is close to what the mesher makes, so the
/// size limit refuses what it should and not much less.
#[test]
fn the_size_estimate_is_near_the_mesh() {
    use sim_core::mesh::mesher::{Outline, estimate_vertices, mesh_outline};
    for (w, h, edge, hole) in [
        (0.3, 0.2, 0.01, false),
        (1.0, 0.5, 0.02, false),
        (0.05, 0.8, 0.005, false),
        (0.6, 0.6, 0.003, false),
        (0.6, 0.6, 0.01, true),
    ] {
        let mut o = Outline::rectangle(w, h);
        if hole {
            // A square hole of half the side in the middle: a quarter of the area.
            let (a, b) = (0.25 * w, 0.75 * w);
            o.loops.push(
                [(a, a), (a, b), (b, b), (b, a)]
                    .map(|(x, y)| glam::Vec2::new(x, y))
                    .to_vec(),
            );
        }
        let (est, real) = (
            estimate_vertices(&o, edge),
            mesh_outline(&o, edge).unwrap().positions.len(),
        );
        let r = est as f32 / real as f32;
        assert!(
            (0.85..1.15).contains(&r),
            "{w} x {h} at {edge} (hole {hole}): {est} estimated, {real} made"
        );
    }
}

/// A seam named by the designer: undoable, kept by the design file, written in the
/// pattern; a name too long or with control characters is refused and changes nothing.
#[test]
fn seams_are_named_undoably_and_the_file_keeps_their_names() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.08;
    let (mut d, spec) = sim_core::scenario::build_scene(&cfg).unwrap();
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), 0.5).unwrap();
    assert_eq!(d.seams.len(), 4);
    d.name_seam(1, "  left side ").unwrap();
    assert_eq!(d.seams[1].name, "left side");
    d.undo().unwrap();
    assert_eq!(d.seams[1].name, "");
    d.redo().unwrap();
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(loaded.seams[1].name, "left side");
    assert_eq!(loaded.seams[0].name, "");
    // The pattern out names it beside its letter on both pieces; the marks our readers
    // pair seams by stay as they were.
    use sim_core::design::sewing_pattern::{dxf_string, pieces, svg_string};
    let out = pieces(&d);
    let svg = svg_string(&out);
    assert_eq!(svg.matches(">B left side</text>").count(), 2, "{svg}");
    // One path per side of the seam.
    assert_eq!(svg.matches("data-seam=\"B\"").count(), 2, "{svg}");
    let dxf = dxf_string(&out);
    assert_eq!(dxf.matches("Seam B name: left side").count(), 2);
    assert_eq!(dxf.matches("Seam: B").count(), 2);
    let long = "x".repeat(121);
    for bad in [long.as_str(), "left\nside"] {
        assert!(d.name_seam(1, bad).is_err(), "{bad:?}");
        assert_eq!(d.seams[1].name, "left side");
    }
    assert!(d.name_seam(9, "nowhere").is_err());
}

/// The file keeps xpbd's guard (format 2 unchanged: a file without the field has it off,
/// as the format 1 fixture above shows), and a file claiming one for a model that has
/// none is refused.
#[test]
fn the_guard_is_kept_and_a_false_claim_refused() {
    let mut d = edited();
    d.set_guard(true).unwrap();
    let back = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert!(back.guarded() && back.sim.never_crosses());
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
    cfg.grid = 6;
    cfg.model = sim_core::solver::ModelKind::Seed;
    let seed = build_design(&cfg).unwrap().save_design().unwrap();
    // Found in the bytes (a lossy text of them moves offsets past any invalid byte, such
    // as the header's length).
    let at = (seed.windows(13))
        .position(|w| w == b"\"guard\":false")
        .expect("the field is written");
    let mut claimed = seed.clone();
    // Same length, so the header's size and the sections' offsets stay right.
    claimed[at..at + 13].copy_from_slice(b"\"guard\":true ");
    let e = Design::load_design(&reseal(claimed)).unwrap_err();
    assert!(
        e.to_string().contains("the seed model, which has none"),
        "{e}"
    );
}

/// The `drape-pattern` scene of SVG pattern `svg` (written to a temporary file named
/// after `tag`), its seams sewn; `edge` the pieces' triangle edge, or the default.
fn sewn_pattern(svg: &str, tag: &str, edge: Option<f32>) -> Design {
    let name = format!("saiho-{tag}-{}.svg", std::process::id());
    let path = std::env::temp_dir().join(name);
    std::fs::write(&path, svg).unwrap();
    let mut cfg = ScenarioConfig::new(ScenarioName::DrapePattern);
    cfg.pattern = Some(path.clone());
    if let Some(edge) = edge {
        cfg.piece_edge = edge;
    }
    let built = sim_core::scenario::build_scene(&cfg);
    std::fs::remove_file(&path).unwrap();
    let (mut d, spec) = built.unwrap();
    let pull = sim_core::scenario::garment::SEAM_PULL;
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), pull).unwrap();
    d
}

/// A seam eased 20 mm keeps its two sides' lengths in the seam list once its pairs
/// weld: each side is read on its own piece's triangles, not on whichever triangle held
/// the welded edge first (which showed the two sides equal).
#[test]
fn an_eased_seam_keeps_its_sides_lengths_as_it_welds() {
    // The shipped dress with its back 20 mm longer: side seams B and D are 530 mm on the
    // front and 550 mm on the back.
    let svg = include_str!("../assets/dress.svg")
        .replace(
            "height=\"790mm\" viewBox=\"0 0 1000 790\"",
            "height=\"810mm\" viewBox=\"0 0 1000 810\"",
        )
        .replace("M520.0,770.0 L980.0,770.0", "M520.0,790.0 L980.0,790.0")
        .replace(
            "x1=\"520.0\" y1=\"240.0\" x2=\"520.0\" y2=\"770.0\"",
            "x1=\"520.0\" y1=\"240.0\" x2=\"520.0\" y2=\"790.0\"",
        )
        .replace(
            "x1=\"980.0\" y1=\"240.0\" x2=\"980.0\" y2=\"770.0\"",
            "x1=\"980.0\" y1=\"240.0\" x2=\"980.0\" y2=\"790.0\"",
        );
    assert_eq!(svg.matches("790.0").count(), 4, "the back made longer");
    let mut d = sewn_pattern(&svg, "eased", Some(0.06));
    let names: Vec<char> = (0..d.seams.len())
        .map(|i| (b'A' + i as u8) as char)
        .collect();
    assert_eq!(names.len(), 4);
    let before: Vec<(f32, f32)> = d.seams.iter().map(|s| d.seam_lengths(s)).collect();
    for side in [1, 3] {
        let (a, b) = before[side];
        assert!(
            (b - a - 0.02).abs() < 0.004,
            "seam {}: {a} {b}",
            names[side]
        );
    }
    let welded = |d: &Design, i: usize| d.seams[i].pairs.iter().filter(|(p, q)| p == q).count();
    for _ in 0..400 {
        d.step().unwrap();
        if welded(&d, 1) == d.seams[1].pairs.len() && welded(&d, 3) == d.seams[3].pairs.len() {
            break;
        }
    }
    for (i, s) in d.seams.iter().enumerate() {
        let (a, b) = d.seam_lengths(s);
        assert!(welded(&d, i) > 0, "seam {} welded none", names[i]);
        assert!(
            (a - before[i].0).abs() < 1e-4 && (b - before[i].1).abs() < 1e-4,
            "seam {} ({} of {} welded): {a} {b}, before {:?}",
            names[i],
            welded(&d, i),
            s.pairs.len(),
            before[i]
        );
    }
}

/// The shipped dress, and the same with its back 20 mm longer (the side seams eased):
/// every stitch pairs a vertex of one side with the vertex of the other at the same share
/// of its length, one to one. Meshed on their own, the sides' border vertices fell where
/// each outline's refinement put them; the pairing matched some vertices twice and the
/// welds then held small triangles beside the neck at up to 1.9x their cut size, whatever
/// the solver.
#[test]
fn every_stitch_pairs_vertices_at_the_same_place_along_both_sides() {
    let shipped = include_str!("../assets/dress.svg").to_string();
    let eased = shipped
        .replace("M520.0,770.0 L980.0,770.0", "M520.0,790.0 L980.0,790.0")
        .replace("x2=\"520.0\" y2=\"770.0\"", "x2=\"520.0\" y2=\"790.0\"")
        .replace("x2=\"980.0\" y2=\"770.0\"", "x2=\"980.0\" y2=\"790.0\"");
    assert_ne!(eased, shipped, "the back made longer");
    for (k, svg) in [shipped, eased].into_iter().enumerate() {
        let d = sewn_pattern(&svg, &format!("pairs-{k}"), None);
        let places = d.sim.cloth.live.pattern_places(d.sim.cloth.len());
        // Each vertex's share of its side's length in the pattern.
        let shares = |side: &[u32]| -> Vec<f32> {
            let mut s = vec![0.0f32];
            for w in side.windows(2) {
                let step = (places[w[1] as usize] - places[w[0] as usize]).length();
                s.push(s.last().unwrap() + step);
            }
            let total = *s.last().unwrap();
            s.iter().map(|t| t / total).collect()
        };
        assert_eq!(d.seams.len(), 4);
        for (i, seam) in d.seams.iter().enumerate() {
            let a: Vec<u32> = seam.pairs.iter().map(|p| p.0).collect();
            let b: Vec<u32> = seam.pairs.iter().map(|p| p.1).collect();
            for side in [&a, &b] {
                let mut once = side.clone();
                once.sort_unstable();
                once.dedup();
                assert_eq!(
                    once.len(),
                    side.len(),
                    "dress {k} seam {i}: a vertex paired twice"
                );
            }
            for (j, (x, y)) in shares(&a).iter().zip(shares(&b)).enumerate() {
                assert!(
                    (x - y).abs() < 1e-3,
                    "dress {k} seam {i}, stitch {j}: at {x} of one side and {y} of the other"
                );
            }
        }
    }
}

/// The sewing-line perimeter of each piece of `d`'s pattern, mm, in the pieces' order.
fn pattern_perimeters(d: &Design) -> Vec<f64> {
    sim_core::design::sewing_pattern::pieces(d)
        .iter()
        .map(|p| p.perimeters()[0])
        .collect()
}

/// Unpicked (removed), the dress's hand-sewn side seams (the last two) give the cloth
/// eased into them (`eased` triangles) back to the mesh: every folded triangle is a
/// triangle again, and the outlines stay as `cut`.
fn unpicked_seams_give_the_eased_cloth_back(d: &mut Design, eased: usize, cut: &[f64]) {
    let tris = d.sim.cloth.live.tri_count();
    let mut back = 0;
    for k in [3, 2] {
        let eased = d.seams[k].eased.len();
        let r = d.remove_seam(k).unwrap();
        assert_eq!(r.eased_back, eased, "seam {k}: {r:?}");
        assert!(r.unpicked > 0 && r.kept == 0, "seam {k}: {r:?}");
        back += eased;
    }
    assert_eq!(back, eased);
    assert_eq!(d.sim.cloth.live.tri_count(), tris + eased);
    for (p, c) in pattern_perimeters(d).iter().zip(cut) {
        assert!((p - c).abs() < 0.5, "{p} against {c} as cut");
    }
}

/// Where a seam's side has more vertices than its partner, its welds fold triangles of
/// that side away (the dress's side seams sewn by hand to the top two thirds of the
/// back's, within 40 frames). That
/// cloth is still the piece's: the pattern out keeps each piece's outline as it was cut
/// (the back had notches a triangle deep, spikes in its cut line), the design file keeps
/// the record, and the balance notches of a seam's two sides fall at the same fractions
/// of their lengths.
#[test]
fn cloth_eased_into_a_seam_stays_in_the_pattern_out() {
    let mut d = sewn(&ScenarioConfig::new(ScenarioName::DressMannequin));
    // A pattern's seams are meshed with both sides alike; a seam made by hand need not
    // be: each side seam sewn again to the top two thirds of the back's side.
    let sides: Vec<(Vec<u32>, Vec<u32>, f32)> = [1, 3]
        .map(|i| {
            let pairs = &d.seams[i].pairs;
            let a: Vec<u32> = pairs.iter().map(|p| p.0).collect();
            let b: Vec<u32> = pairs[..pairs.len() * 2 / 3].iter().map(|p| p.1).collect();
            (a, b, d.seams[i].max_force)
        })
        .into();
    d.remove_seam(3).unwrap();
    d.remove_seam(1).unwrap();
    for (a, b, force) in &sides {
        assert!(b.len() < a.len());
        d.add_seam(a, b, *force).unwrap();
    }
    let cut = pattern_perimeters(&d);
    for _ in 0..40 {
        d.step().unwrap();
    }
    let eased: usize = d.seams.iter().map(|s| s.eased.len()).sum();
    assert!(
        eased > 0,
        "no triangle eased into a seam: the case did not arise"
    );
    let welded: usize = (d.seams.iter())
        .map(|s| s.pairs.iter().filter(|(a, b)| a == b).count())
        .sum();
    assert!(welded > 0);
    let now = pattern_perimeters(&d);
    // The back is never cut: its outline is as made (the front's neckline is cut later).
    assert_eq!(now.len(), 2);
    for (p, c) in now.iter().zip(&cut) {
        assert!((p - c).abs() < 0.5, "{now:?} against {cut:?} as cut");
    }
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert_eq!(loaded.seams, d.seams, "the file keeps the eased triangles");
    let mut forgot = loaded;
    forgot.seams.iter_mut().for_each(|s| s.eased.clear());
    let notched = pattern_perimeters(&forgot);
    assert!(
        notched.iter().zip(&cut).any(|(p, c)| p - c > 5.0),
        "without the record the outline goes round the folded triangles: {notched:?}"
    );
    // Balance notches: each seam side's notches at the same fractions of its length as
    // its partner's, slits from the cut line half way to the sewing line.
    let pieces = sim_core::design::sewing_pattern::finish(
        sim_core::design::sewing_pattern::pieces(&d),
        10.0,
    );
    let count: usize = pieces.iter().map(|p| p.notches.len()).sum();
    // Four seams, two sides each: the shoulders (under 250 mm) one notch, the sides three.
    assert_eq!(count, 2 * (1 + 1 + 3 + 3), "{count}");
    // The distance from `q` to closed polyline `l`.
    let off = |l: &[glam::DVec2], q: glam::DVec2| {
        (0..l.len())
            .map(|i| {
                let (a, b) = (l[i], l[(i + 1) % l.len()]);
                let t = ((q - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
                q.distance(a + (b - a) * t)
            })
            .fold(f64::MAX, f64::min)
    };
    for p in &pieces {
        for &(a, b) in &p.notches {
            assert!(((b - a).length() - 5.0).abs() < 1e-6, "{a} {b}");
            // From the cut line to half way to the sewing line.
            assert!(off(&p.cut[0], a) < 0.01, "{a} {b}");
            assert!((off(&p.loops[0], b) - 5.0).abs() < 0.01, "{a} {b}");
        }
    }
    // Each seam's sides carry the same notches: per seam, as many on the front as on
    // the back, each on the sewing line of that seam (its point there: a + 2 (b - a)).
    let on_seam = |p: &sim_core::design::sewing_pattern::Piece, label: &str| {
        (p.notches.iter())
            .filter(|&&(a, b)| {
                let at = a + (b - a) * 2.0;
                (p.seams.iter().filter(|s| s.0 == label))
                    .any(|&(_, s0, s1)| off(&[s0, s1], at) < 0.01)
            })
            .count()
    };
    // The shoulders keep their places (A and B); the side seams, sewn again, follow (C, D).
    for (label, want) in [("A", 1), ("B", 1), ("C", 3), ("D", 3)] {
        for p in &pieces {
            assert_eq!(on_seam(p, label), want, "seam {label} on the {}", p.name);
        }
    }
    // The studio's pattern view has the same pieces, in metres: the eased cloth in each
    // outline, the same notches, 5 mm into the piece from its sewing line.
    let view = sim_core::design::sewing_pattern::view_pieces(&d);
    assert_eq!(view.len(), 2);
    for (v, c) in view.iter().zip(&cut) {
        assert!(
            (v.perimeters()[0] * 1000.0 - c).abs() < 0.5,
            "{} against {c}",
            v.perimeters()[0]
        );
        assert_eq!(v.notches.len(), 8, "{}", v.name);
        for &(a, b) in &v.notches {
            assert!(off(&v.loops[0], a) < 1e-6 && (off(&v.loops[0], b) - 0.005).abs() < 1e-5);
        }
    }
    unpicked_seams_give_the_eased_cloth_back(&mut d, eased, &cut);
}

/// A seam's eased triangles from a file are checked: not numbers, or more of them than
/// twice the cloth's vertices (more than its mesh ever had triangles), is a clear refusal (the design unchanged: nothing loads); far-off or stray ones (no outline edge to
/// join) load, and the pattern out leaves them out.
#[test]
fn a_files_eased_triangles_are_checked_and_strays_stay_out_of_the_pattern() {
    let mut d = sewn_at_6cm();
    let cut = pattern_perimeters(&d);
    let vertices = d.sim.cloth.len();
    let mut with = |eased: Vec<[Vec3; 3]>| {
        d.seams[0].eased = eased;
        Design::load_design(&d.save_design().unwrap())
    };
    // (JSON has no NaN: it is written as null, and the header does not read.)
    let nan = with(vec![[Vec3::NAN, Vec3::ZERO, Vec3::X]]).unwrap_err();
    assert!(nan.to_string().contains("corrupt"), "{nan}");
    let many = vec![[Vec3::ZERO, Vec3::X, Vec3::Z]; 2 * vertices + 1];
    assert!(with(many).unwrap_err().to_string().contains("eased"));
    let far = Vec3::splat(1e30);
    let stray = vec![
        [far, far + Vec3::X, far + Vec3::Z],
        [Vec3::ZERO, Vec3::X, Vec3::Z],
    ];
    let loaded = with(stray).unwrap();
    assert_eq!(pattern_perimeters(&loaded), cut);
}

/// `cfg`'s scene with its pattern's seams stitched (not yet stepped).
fn sewn(cfg: &ScenarioConfig) -> Design {
    let (mut d, spec) = sim_core::scenario::build_scene(cfg).unwrap();
    let pull = sim_core::scenario::garment::SEAM_PULL;
    sim_core::design::garment::sew(&mut d, &spec.unwrap(), pull).unwrap();
    d
}

/// The shipped dress at 6 cm edges, its seams stitched (not yet stepped).
fn sewn_at_6cm() -> Design {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    sewn(&cfg)
}

/// The shipped dress at 6 cm edges, its seams sewn for 240 frames on the mannequin.
fn sewn_dress() -> Design {
    let mut d = sewn_at_6cm();
    let mut welded = 0;
    for _ in 0..240 {
        welded += d.step().unwrap().welded;
    }
    let pairs = d.seams.iter().map(|s| s.pairs.len()).sum::<usize>();
    assert!(welded * 10 >= pairs * 9, "{welded} of {pairs}");
    d
}

fn crossings(d: &Design) -> (usize, usize) {
    let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    let c = sim_core::collision::crossings::count(&d.sim.cloth.x, &tris, d.sim.body.as_ref());
    (c.self_pairs, c.body_pairs)
}

/// The dress sewn and draped, then its last seam undone: the seam goes with every weld
/// it made, the welds opening where the cloth lies (put back as far apart as they were
/// found, from where the cloth had turned since, they went through the layers round the
/// seam and the undo was refused), and the garment crosses nothing in the frames after.
/// The other seams keep their welds; a weld made after the undo keeps its redo (it used to
/// clear it), and the redo brings the seam back welded.
#[test]
fn a_draped_seam_is_undone_and_redone_with_its_welds_crossing_nothing() {
    let mut d = sewn_dress();
    let (seams, steps) = (d.seams.len(), d.history.undo_steps());
    let welded_before: usize = (d.seams.iter().flat_map(|s| &s.pairs))
        .filter(|(a, b)| a == b)
        .count();
    let sewn = d.seams[seams - 1]
        .pairs
        .iter()
        .filter(|(a, b)| a == b)
        .count();
    assert!(sewn > 3, "the last seam welded {sewn} pairs");
    assert_eq!(d.undo().unwrap(), "seam");
    assert_eq!(
        (d.seams.len(), d.history.undo_steps()),
        (seams - 1, steps - 1)
    );
    d.validate().unwrap();
    assert_eq!(crossings(&d), (0, 0));
    let all = |d: &Design| -> usize {
        let s = d.seams.iter().flat_map(|s| &s.pairs);
        s.filter(|(a, b)| a == b).count()
    };
    // The other seams were welded in the same frames, but keep their welds (they used to
    // open with it: all four seams of the dress, sewn together).
    assert_eq!(all(&d), welded_before - sewn);
    let mut rewelded = 0;
    for _ in 0..60 {
        rewelded += d.step().unwrap().welded;
    }
    assert_eq!(crossings(&d), (0, 0));
    d.validate().unwrap();
    // A weld made since (a pair that had stalled closes) keeps the redo (it used to clear
    // it); the redo takes it back before it brings the seam back with its welds.
    assert_eq!((rewelded, d.history.autos_over_redo()), (1, 1));
    assert_eq!(d.history.redo_steps(), 1);
    assert_eq!(d.redo().unwrap(), "seam");
    assert_eq!((d.seams.len(), d.history.undo_steps()), (seams, steps));
    let closed = |d: &Design| {
        d.seams[seams - 1]
            .pairs
            .iter()
            .filter(|(a, b)| a == b)
            .count()
    };
    assert_eq!((closed(&d), all(&d)), (sewn, welded_before));
    d.validate().unwrap();
    assert_eq!(crossings(&d), (0, 0));
    for _ in 0..120 {
        d.step().unwrap();
    }
    assert_eq!(crossings(&d), (0, 0));
    d.validate().unwrap();
}

/// A seam undone, and its side pulled away from the body by the pen before the redo:
/// welding its pairs where they now lie would cross, so the redo brings the seam back
/// without its welds, says so, and the stitches pull the sides together and weld them
/// again; nothing crosses on the way.
#[test]
fn a_redo_after_the_cloth_moved_leaves_the_welds_to_the_stitches() {
    let mut d = sewn_dress();
    let seams = d.seams.len();
    assert_eq!(d.undo().unwrap(), "seam");
    let pairs = match d.history.redo_edits(1).next().unwrap().prims.as_slice() {
        [sim_core::design::Prim::Seam { new: Some(s), .. }, ..] => s.pairs.clone(),
        p => panic!("{p:?}"),
    };
    let (_, b) = pairs[pairs.len() / 2];
    let at = d.sim.cloth.x[b as usize];
    let out = Vec3::new(at.x, 0.0, at.z).normalize_or_zero();
    d.pinch_begin(at, 0.01, 0.08, 200.0).unwrap();
    for f in 1..=40 {
        d.pinch_move(at + out * (0.3 * f as f32 / 40.0));
        d.step().unwrap();
    }
    d.pinch_end();
    let (a, _) = pairs[pairs.len() / 2];
    let gap = (d.sim.cloth.x[a as usize] - d.sim.cloth.x[b as usize]).length();
    assert!(gap > 0.05, "the pen moved the side {gap} m");
    let told = d.sim.notices.len();
    assert_eq!(d.redo().unwrap(), "seam");
    let said = &d.sim.notices[told..];
    assert!(
        said.len() == 1 && said[0].starts_with("Redone: seam, but not its 10 welds"),
        "{said:?}"
    );
    assert_eq!((d.seams.len(), d.history.redo_steps()), (seams, 0));
    d.validate().unwrap();
    assert_eq!(crossings(&d), (0, 0));
    let mut welded = 0;
    for _ in 0..200 {
        welded += d.step().unwrap().welded;
    }
    let closed = d.seams[seams - 1]
        .pairs
        .iter()
        .filter(|(a, b)| a == b)
        .count();
    assert_eq!((welded, closed), (pairs.len(), pairs.len()));
    assert_eq!(crossings(&d), (0, 0));
    d.validate().unwrap();
}

/// A weld made after an undo is taken back, and not kept for a redo, by the next undo:
/// the redo further down must find the design as the first undo left it (redone over
/// that weld, the seam's own welds would find their vertices gone).
#[test]
fn an_undo_takes_back_the_welds_made_since_the_last_undo() {
    let mut d = sewn_dress();
    let (seams, steps) = (d.seams.len(), d.history.undo_steps());
    assert_eq!(d.undo().unwrap(), "seam");
    let mut rewelded = 0;
    for _ in 0..60 {
        rewelded += d.step().unwrap().welded;
    }
    assert_eq!((rewelded, d.history.autos_over_redo()), (1, 1));
    assert_eq!(d.undo().unwrap(), "seam");
    assert_eq!(d.history.autos_over_redo(), 0);
    assert_eq!((d.seams.len(), d.history.redo_steps()), (seams - 2, 2));
    d.validate().unwrap();
    assert_eq!(d.redo().unwrap(), "seam");
    assert_eq!(d.redo().unwrap(), "seam");
    assert_eq!((d.seams.len(), d.history.undo_steps()), (seams, steps));
    d.validate().unwrap();
    assert_eq!(crossings(&d), (0, 0));
}

/// Pulls the sewn dress's front hem down and out with the pen's tear (`near_pinch`) or
/// with tearing on everywhere (`None`) for 60 frames, tearing past 1.2x; returns the triangles torn and the
/// farthest of them from the pinched vertex when it tore (its nearest corner), m.
fn pull_the_hem(near_pinch: Option<f32>) -> (usize, f32) {
    let mut d = sewn_dress();
    assert_eq!(d.pieces[0].name, "front");
    let (v, p) = (d.record_slots(0, |_| true).into_iter())
        .flat_map(|s| d.sim.cloth.live.tri(s).unwrap().v)
        .map(|i| (i, d.sim.cloth.x[i as usize]))
        .min_by(|a, b| a.1.y.total_cmp(&b.1.y))
        .unwrap();
    // A weak fabric's threshold, under the 1.23x the sewn dress's shoulders stretch to
    // as it hangs (the studio's 5k-vertex dress stretched 1.8x at its welds).
    d.tear.enabled = true;
    d.tear.threshold = 1.2;
    d.tear.near_pinch = near_pinch;
    assert_eq!(d.pinch_begin(p, 0.05, 0.0, 100.0).unwrap(), v);
    let live = |d: &Design| -> std::collections::BTreeMap<u32, [u32; 3]> {
        d.sim.cloth.live.iter().map(|(s, t)| (s, t.v)).collect()
    };
    let (mut torn, mut farthest) = (0, 0.0f32);
    let mut before = live(&d);
    for f in 1..=60 {
        d.pinch_move(p + Vec3::new(0.0, -0.3, 0.3) * (f as f32 / 60.0));
        d.step().unwrap();
        let now = live(&d);
        let at = d.sim.cloth.x[v as usize];
        for (s, t) in &before {
            if !now.contains_key(s) {
                torn += 1;
                let near = (t.iter())
                    .map(|&i| d.sim.cloth.x[i as usize].distance(at))
                    .fold(f32::INFINITY, f32::min);
                farthest = farthest.max(near);
            }
        }
        before = now;
    }
    d.pinch_end();
    for _ in 0..30 {
        d.step().unwrap();
    }
    assert_eq!(
        crossings(&d),
        (0, 0),
        "torn and let go, the dress crosses nothing"
    );
    (torn, farthest)
}

/// The pen's tear tears where it pulls: pulled 30 cm down and out by its hem, the sewn
/// dress tears within the pen's reach of the held vertex and nowhere else. With tearing
/// on everywhere (as the pen's tear was), the strain limit loosened over the whole dress
/// and its shoulders, stretched most as it hangs, tore far from the pen.
#[test]
fn the_pens_tear_tears_where_it_pulls() {
    let reach = 0.08;
    let (torn, farthest) = pull_the_hem(Some(reach));
    eprintln!("near the pinch: {torn} torn, the farthest {farthest} m");
    assert!(torn > 0, "the pull tore nothing");
    assert!(farthest <= reach, "a tear {farthest} m from the pen");
    let (torn, farthest) = pull_the_hem(None);
    eprintln!("everywhere: {torn} torn, the farthest {farthest} m");
    assert!(farthest > 0.3, "everywhere, the shoulders tear too");
}

/// A piece named by the designer: undoable, kept by the design file, and what the list
/// and the pattern out call it; a name that is empty, too long, has control characters
/// or another piece's name, and a cloth not made as a pattern piece, are refused and
/// change nothing.
#[test]
fn pieces_are_named_undoably_and_the_pattern_out_calls_them_so() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.08;
    let (mut d, _) = sim_core::scenario::build_scene(&cfg).unwrap();
    let names =
        |d: &Design| -> Vec<String> { d.piece_list().into_iter().map(|p| p.name).collect() };
    let before = names(&d);
    let front = before.iter().position(|n| n == "front").unwrap();
    let undo = d.history.undo_steps();
    assert_eq!(d.name_piece(front, "  bodice front ").unwrap(), "front");
    assert_eq!(d.history.undo_steps(), undo + 1);
    assert!(
        names(&d).contains(&"bodice front".to_string()),
        "{:?}",
        names(&d)
    );
    assert!(!names(&d).contains(&"front".to_string()));
    use sim_core::design::sewing_pattern::{dxf_string, pieces, svg_string};
    let out = pieces(&d);
    assert!(out.iter().any(|p| p.name == "bodice front"));
    assert!(svg_string(&out).contains("bodice front"));
    assert!(dxf_string(&out).contains("bodice front"));
    d.undo().unwrap();
    assert_eq!(names(&d), before);
    d.redo().unwrap();
    let loaded = Design::load_design(&d.save_design().unwrap()).unwrap();
    assert!(names(&loaded).contains(&"bodice front".to_string()));
    // The same name again is no edit.
    d.name_piece(front, "bodice front").unwrap();
    assert_eq!(d.history.undo_steps(), undo + 1);
    let now = names(&d);
    let long = "x".repeat(121);
    for bad in ["", "   ", "back", long.as_str(), "bodice\nfront"] {
        assert!(d.name_piece(front, bad).is_err(), "{bad:?}");
        assert_eq!(names(&d), now, "{bad:?}");
    }
    assert!(d.name_piece(9, "nowhere").is_err());
    assert_eq!(d.history.undo_steps(), undo + 1);
    // The square cloth of a drape was not made as a piece: it has no name to change.
    let (mut square, _) =
        sim_core::scenario::build_scene(&ScenarioConfig::new(ScenarioName::DrapeCube)).unwrap();
    let e = square.name_piece(0, "front").unwrap_err().to_string();
    assert!(e.contains("not made as a pattern piece"), "{e}");
}

/// A piece's outline in the pattern view: its area (m²) and how far its centroid lies
/// right of its bounding box's middle (m).
fn outline_shape(d: &Design, name: &str) -> (f64, f64) {
    let p = sim_core::design::sewing_pattern::view_pieces(d)
        .into_iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("no piece {name}"));
    let l = &p.loops[0];
    let (mut area, mut cx) = (0.0, 0.0);
    for (i, a) in l.iter().enumerate() {
        let b = l[(i + 1) % l.len()];
        let cross = a.perp_dot(b);
        area += cross / 2.0;
        cx += (a.x + b.x) * cross / 6.0;
    }
    let (lo, hi) = l.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
        (lo.min(p.x), hi.max(p.x))
    });
    (area, cx / area - (lo + hi) / 2.0)
}

#[test]
fn a_piece_is_copied_as_it_is_now_turned_over_when_asked_and_undoably() {
    use sim_core::design::garment::Place;
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.04;
    let (mut d, _) = sim_core::scenario::build_scene(&cfg).unwrap();
    // The front's upper left corner cut away: the piece is no longer symmetric.
    let front = sim_core::design::sewing_pattern::view_pieces(&d)
        .into_iter()
        .find(|p| p.name == "front")
        .unwrap();
    let (lo, hi) = front.loops[0]
        .iter()
        .fold((glam::DVec2::MAX, glam::DVec2::MIN), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let (a, b) = (
        glam::Vec2::new(lo.x as f32 - 0.05, hi.y as f32 - 0.2),
        glam::Vec2::new(lo.x as f32 + 0.2, hi.y as f32 + 0.05),
    );
    assert!(d.cut_line(a, b).unwrap() > 0);
    let (area, off) = outline_shape(&d, "front");
    assert!(
        off > 0.005,
        "the cut front's centroid {off} m right of its middle"
    );
    let list = d.piece_list();
    let at = list.iter().position(|p| p.name == "front").unwrap();
    let fabric = list[at].fabric.clone();
    let undo = d.history.undo_steps();

    let (name, vertices) = d.duplicate_piece(at, Place::Back, false, 0.04).unwrap();
    assert_eq!(name, "front (2)");
    let copy = d.piece_list().into_iter().find(|p| p.name == name).unwrap();
    assert_eq!(
        (copy.vertices, copy.fabric.as_str()),
        (vertices, fabric.as_str())
    );
    assert_eq!(d.piece_list().len(), list.len() + 1);
    assert_eq!(d.history.undo_steps(), undo + 1);
    // A copy of the copy is numbered on, not numbered twice.
    let second = d.piece_list().iter().position(|p| p.name == name).unwrap();
    let (again, _) = d.duplicate_piece(second, Place::Back, false, 0.04).unwrap();
    assert_eq!(again, "front (3)");
    d.undo().unwrap();
    let (copy_area, copy_off) = outline_shape(&d, &name);
    assert!(
        (copy_area / area - 1.0).abs() < 0.03,
        "{copy_area} against {area} m²"
    );
    assert!((copy_off - off).abs() < 0.01, "{copy_off} against {off} m");
    // It starts clear of everything, as any added piece does.
    let x = &d.sim.cloth.x;
    let tris: Vec<[u32; 3]> = d.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    assert_eq!(
        sim_core::collision::crossings::count_self(x, &tris),
        0,
        "the copy starts crossing the cloth"
    );

    d.undo().unwrap();
    assert_eq!(d.piece_list().len(), list.len());
    // Turned over: the cut corner is on the other side.
    let (name, _) = d.duplicate_piece(at, Place::Back, true, 0.04).unwrap();
    let (m_area, m_off) = outline_shape(&d, &name);
    assert!(
        (m_area / area - 1.0).abs() < 0.03,
        "{m_area} against {area} m²"
    );
    assert!(
        (m_off + off).abs() < 0.01,
        "mirrored: {m_off} against {off} m"
    );

    // Bad input changes nothing.
    let now = d.piece_list().len();
    let steps = d.history.undo_steps();
    assert!(matches!(
        d.duplicate_piece(99, Place::Front, false, 0.04),
        Err(sim_core::design::EditError::NoPiece { .. })
    ));
    assert!(d.duplicate_piece(at, Place::Front, false, 0.0).is_err());
    assert_eq!((d.piece_list().len(), d.history.undo_steps()), (now, steps));
}

/// A sleeve sewn into a tube (its two sides to each other, as in the studio) reads both
/// sides 0.45 m once every pair has welded: until 2026-12-05 the second side's walk
/// jumped to the first side's triangles where its own did not hold an edge, and read
/// 0.81 m (the sleeve's width counted in), shown orange as a mismatch. (Every pair
/// welds within 40 frames when the sides pair by their lengths in 3D, within 80 by their
/// lengths in the pattern, the pairing since 2026-12-05, late: 100 frames are given.)
#[test]
fn a_welded_tube_reads_its_two_sides_equal() {
    use sim_core::design::garment::Place;
    let (mut d, sleeve) = dress_and_rectangle("sleeve", 0.36, 0.45);
    d.add_piece(&sleeve, Place::LeftArm, 0.03).unwrap();
    let r = d.pieces[2].clone();
    let [tl, tr] = top_or_bottom(&r, true);
    let [bl, br] = top_or_bottom(&r, false);
    d.seam_on_plane([tl, bl], [tr, br], 0.01).unwrap();
    let s = d.seams.len() - 1;
    for _ in 0..100 {
        d.step().unwrap();
    }
    assert!(
        d.seams[s].pairs.iter().all(|(a, b)| a == b),
        "not all welded"
    );
    let (la, lb) = d.seam_lengths(&d.seams[s]);
    assert!(
        (la - 0.45).abs() < 1e-3 && (lb - 0.45).abs() < 1e-3,
        "{la} {lb}"
    );
}

/// A dart cut into the dress's front at the hem (40 mm wide, 150 mm long), its wedge
/// deleted and its legs seamed in the pattern: once welded, both legs read the same
/// length (within 10%). A weld collapses a stretch of a leg into one vertex, and the
/// walk along one leg jumped to the other's triangles there: 126 / 154 mm here, and 82 /
/// 69 mm, orange as a mismatch, for a studio dart whose legs are 80 mm.
#[test]
fn a_sewn_darts_legs_read_alike() {
    let mut d = sewn_dress();
    let (lo, _) = outline_box(&d.pieces[0]);
    let offset = d.pieces[0].offset;
    let apex = glam::Vec2::new(0.23, lo.y + 0.15) + offset;
    let hem = |dx: f32| glam::Vec2::new(0.23 + dx, lo.y) + offset;
    let below = |dx: f32| apex + (hem(dx) - apex) * (1.0 + 0.01 / 0.15);
    d.cut_line(below(-0.02), apex).unwrap();
    d.cut_line(below(0.02), apex).unwrap();
    let wedge = (d.piece_list().iter())
        .position(|p| p.name == "front 2")
        .unwrap();
    d.delete_piece(wedge).unwrap();
    d.seam_on_plane([hem(-0.02), apex], [hem(0.02), apex], 0.01)
        .unwrap();
    let s = d.seams.len() - 1;
    let alike = |d: &Design, when: &str| {
        let (la, lb) = d.seam_lengths(&d.seams[s]);
        assert!((la - lb).abs() < 0.1 * la.max(lb), "{when}: {la} / {lb}");
    };
    // (As found by the drags at these 6 cm triangles the sides are 111 and 124 mm.)
    for _ in 0..60 {
        d.step().unwrap();
    }
    assert!(
        d.seams[s].pairs.iter().all(|(a, b)| a == b),
        "not all welded"
    );
    alike(&d, "welded");
    assert_eq!(crossings(&d), (0, 0));
}

/// A dart made in one step in the pattern plane (`Design::dart_on_plane`, the studio's
/// Dart drag): 40 mm wide at the front's hem, 150 mm long. The wedge goes, the legs are
/// seamed, the operation is one step of the history ("dart") and one undo takes all of
/// it back. Sewn, it closes without crossing anything and the pattern out finds it (a
/// drill hole at its point). Bad drags change nothing.
#[test]
fn a_dart_is_made_in_one_step_and_undone_in_one() {
    let mut d = sewn_dress();
    let (lo, _) = outline_box(&d.pieces[0]);
    let offset = d.pieces[0].offset;
    let at = |x: f32, y: f32| glam::Vec2::new(x, lo.y + y) + offset;
    let (edits, seams, tris) = (
        d.history.undo_len(),
        d.seams.len(),
        d.sim.cloth.live.tri_count(),
    );
    let pieces = d.piece_list().len();
    // Refused, nothing changed: a point on no piece, a drag that stays on the piece, a
    // width out of range, a dart wider than half its length.
    for (p, q, w) in [
        (at(0.23, -0.2), at(0.23, -0.4), 0.04),
        (at(0.23, 0.15), at(0.23, 0.05), 0.04),
        (at(0.23, 0.15), at(0.23, -0.02), 0.6),
        (at(0.23, 0.05), at(0.23, -0.02), 0.04),
    ] {
        assert!(d.dart_on_plane(p, q, w).is_err(), "{p} {q} {w}");
        assert_eq!(d.history.undo_len(), edits);
        assert_eq!(d.sim.cloth.live.tri_count(), tris);
    }
    let pairs = d
        .dart_on_plane(at(0.23, 0.15), at(0.23, -0.02), 0.04)
        .unwrap();
    assert!(pairs >= 3, "{pairs} pairs");
    assert_eq!(d.history.undo_len(), edits + 1, "one step");
    assert_eq!(d.history.labels().last(), Some("dart"));
    assert_eq!(d.seams.len(), seams + 1);
    assert_eq!(d.piece_list().len(), pieces, "the wedge is gone");
    assert!(d.sim.cloth.live.tri_count() < tris + 40);
    // One undo takes it all back; redo brings it again.
    assert_eq!(d.undo().unwrap(), "dart");
    assert_eq!((d.seams.len(), d.sim.cloth.live.tri_count()), (seams, tris));
    d.redo().unwrap();
    assert_eq!(d.seams.len(), seams + 1);
    for _ in 0..60 {
        d.step().unwrap();
    }
    let s = d.seams.len() - 1;
    // Each leg from the hem to the point (150 mm; a leg that ran round the point, or
    // stopped short of it where the cut passed a vertex off its line, read 108 / 141).
    let (la, lb) = d.seam_lengths(&d.seams[s]);
    assert!(
        (la - lb).abs() < 0.1 * la.max(lb) && la.min(lb) > 0.135,
        "legs {la} / {lb} m"
    );
    assert!(
        d.seams[s].pairs.iter().all(|(a, b)| a == b),
        "not all welded"
    );
    assert_eq!(crossings(&d), (0, 0));
    let laid = sim_core::design::sewing_pattern::finish(
        sim_core::design::sewing_pattern::pieces(&d),
        10.0,
    );
    assert_eq!(laid.iter().map(|p| p.drills.len()).sum::<usize>(), 1);
    // The drill hole 10 mm down from the point, 150 mm up from the hem (laid out
    // without an allowance, the hem is at y = 0; the legs' seam may stop a cell short
    // of it); the front one loop, no slit left beyond the point.
    let laid =
        sim_core::design::sewing_pattern::finish(sim_core::design::sewing_pattern::pieces(&d), 0.0);
    let front = laid.iter().find(|p| !p.drills.is_empty()).unwrap();
    assert!(
        (115.0..=145.0).contains(&front.drills[0].y),
        "drilled {} mm up",
        front.drills[0].y
    );
    assert_eq!(front.loops.len(), 1, "{:?}", &front.loops[1..]);
}

/// A sleeve with a cap (its top curved 15 cm above its underarm corners), seamed to the
/// dress's armhole by a drag from the cap's top to a corner as in the pattern view: the
/// seam follows the cap's curve, which leaves the drag's straight line by 4 cm. Until
/// 2026-12-05 only the vertices within the tolerance of the drag's line were walked, and
/// the seam was refused as "not an edge on the cloth's border".
#[test]
fn a_curved_border_is_seamed_along_its_curve() {
    use sim_core::design::garment::Place;
    let (w, under, cap) = (0.30f32, 0.30f32, 0.15f32);
    let mut outline = vec![glam::Vec2::ZERO, glam::Vec2::new(w, 0.0)];
    outline.extend((0..=24).map(|k| {
        let x = w * (1.0 - k as f32 / 24.0);
        let y = under + cap * 0.5 * (1.0 - (std::f32::consts::TAU * x / w).cos());
        glam::Vec2::new(x, y)
    }));
    let (mut d, mut sleeve) = dress_and_rectangle("sleeve", w, under);
    sleeve.outline = sim_core::mesh::mesher::Outline {
        loops: vec![outline],
    };
    d.add_piece(&sleeve, Place::LeftArm, 0.03).unwrap();
    let s = d.pieces[2].clone();
    let (lo, hi) = outline_box(&s);
    let top = glam::Vec2::new(0.5 * (lo.x + hi.x), hi.y) + s.offset;
    let corner = glam::Vec2::new(lo.x, lo.y + under) + s.offset;
    let (_, fhi) = outline_box(&d.pieces[0]);
    let fo = d.pieces[0].offset;
    let armhole = [
        glam::Vec2::new(fhi.x, fhi.y) + fo,
        glam::Vec2::new(fhi.x, fhi.y - 0.22) + fo,
    ];
    let (_, cap_side) = d.seam_sides(armhole, [top, corner], 0.01, true);
    let half = d.pattern_length(&cap_side);
    assert!((half - 0.22).abs() < 0.01, "the cap's half reads {half} m");
    let pairs = d.seam_on_plane(armhole, [top, corner], 0.01).unwrap();
    assert!(pairs >= cap_side.len(), "{pairs} pairs");
}

/// An ellipse's two left quarters seamed by drags from its top and bottom to its left
/// end, as in the pattern view: at 3 cm edges no vertex lies within the tolerance of the
/// left end, so until 2026-12-05 each side was one vertex and the seam was refused ("no
/// border path of two or more vertices"); now each side runs from the vertex nearest
/// each end along the curve, a quarter of the way round (0.198 m).
#[test]
fn a_drag_ending_between_a_curves_vertices_takes_the_nearest() {
    use sim_core::design::garment::Place;
    let (mut d, mut spec) = dress_and_rectangle("ellipse", 0.3, 0.2);
    spec.outline = sim_core::mesh::mesher::Outline::ellipse(0.15, 0.10, 0.03);
    d.add_piece(&spec, Place::Front, 0.03).unwrap();
    let r = d.pieces[2].clone();
    let (lo, hi) = outline_box(&r);
    let c = (lo + hi) * 0.5 + r.offset;
    let at = |x: f32, y: f32| c + glam::Vec2::new(x, y);
    let (top, left, bottom) = (at(0.0, 0.1), at(-0.15, 0.0), at(0.0, -0.1));
    let (pa, pb) = d.seam_sides([top, left], [bottom, left], 0.008, true);
    for side in [&pa, &pb] {
        let l = d.pattern_length(side);
        assert!((l - 0.198).abs() < 0.03, "{} vertices, {l} m", side.len());
    }
    assert!(d.seam_on_plane([top, left], [bottom, left], 0.008).unwrap() >= 5);
}

/// A GarmentCode panel kept flat where its file puts it (a full circle skirt's half
/// ring, wider at its top than half the way round the body), added in the studio where
/// that start would cross the design's cloth, starts flat a layer or two further from
/// the body; where every such start crosses (the panel sunk into the body), it starts
/// round the torso, its fallback, as the scenario starts such a panel. Without the
/// fallback the flat start is refused.
#[test]
fn a_panel_kept_flat_that_would_cross_starts_further_out_or_round_the_body() {
    use sim_core::design::garment::{Landmarks, PieceSpec, Place, Placement, load_pattern};
    let (mut d, _) = dress_and_rectangle("unused", 0.1, 0.1);
    let marks = Landmarks::of(d.sim.body.as_ref());
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/gc-full-circle-skirt_specification.json");
    let (spec, _) = load_pattern(&file, &marks).unwrap();
    let front = (spec.pieces.iter())
        .find(|p| p.name == "skirt_front")
        .unwrap();
    let Some(Placement::Transform {
        rotation,
        translation,
    }) = front.placement
    else {
        panic!("{:?}", front.placement)
    };
    assert!(matches!(front.fallback, Some(Placement::Around { .. })));
    // Where the file puts it, it would start through the dress.
    let alone = PieceSpec {
        fallback: None,
        ..front.clone()
    };
    let pieces = d.pieces.len();
    let refused = d.add_piece(&alone, Place::Front, 0.04);
    assert!(
        matches!(
            refused,
            Err(sim_core::design::EditError::PieceWouldCross { .. })
        ),
        "{refused:?}"
    );
    assert_eq!(d.pieces.len(), pieces);
    // Sunk into the body, no flat start is clear: round the torso.
    let sunk = PieceSpec {
        placement: Some(Placement::Transform {
            rotation,
            translation: translation.with_z(0.0),
        }),
        ..front.clone()
    };
    d.add_piece(&sunk, Place::Front, 0.04).unwrap();
    let added = d.pieces.last().unwrap();
    assert!(
        matches!(added.placement, Some(Placement::Around { .. })),
        "{:?}",
        added.placement
    );
    assert_eq!(crossings(&d), (0, 0));
    // As the file has it, beside the dress: flat, further from the body.
    let (mut d, _) = dress_and_rectangle("unused", 0.1, 0.1);
    d.add_piece(front, Place::Front, 0.04).unwrap();
    let added = d.pieces.last().unwrap();
    match added.placement {
        Some(Placement::Transform {
            rotation: r,
            translation: t,
        }) => {
            assert_eq!(r, rotation);
            assert!(t.z > translation.z + 0.01, "{t} against {translation}");
            assert!(t.z <= translation.z + 0.061, "{t} against {translation}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(crossings(&d), (0, 0));
}
