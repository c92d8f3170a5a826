//! A piece added to a design gets its own part of the texture: paint already there
//! follows its cloth, paint on the new piece shows nowhere else, and undo puts the
//! texture coordinates and the texture back as they were.

// Test helpers: a failed unwrap is a failed test, with its location.
#![allow(clippy::unwrap_used)]

use glam::Vec2;
use sim_core::design::Design;
use sim_core::design::garment::{PieceSpec, Place};
use sim_core::mesh::mesher::Outline;
use sim_core::mesh::warp_of;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

/// Every live triangle's slot, texture coordinates and warp direction.
fn uv_state(d: &Design) -> Vec<(u32, [Vec2; 3], glam::Vec3)> {
    d.sim
        .cloth
        .live
        .iter()
        .map(|(s, t)| (s, t.uv, warp_of(t.rest, t.uv)))
        .collect()
}

/// The texture's colour under the cloth point nearest to `p`.
fn colour_at(d: &Design, p: glam::Vec3) -> [u8; 4] {
    let (uv, _) = d.surface_uv(p, 0.05).unwrap();
    let (x, y) = d.texture.texel_of(uv);
    d.texture.texel(x, y)
}

#[test]
fn an_added_piece_gets_its_own_part_of_the_texture() {
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = 0.06;
    let mut d = build_design(&cfg).unwrap();
    // A red dab on the front, away from its border.
    let front = d.piece_slots(0).unwrap();
    let t = *d.sim.cloth.live.tri(front[front.len() / 2]).unwrap();
    let p = d.sim.cloth.x[t.v[0] as usize];
    d.paint(p, 0.04, [220, 20, 20, 255]).unwrap();
    assert_eq!(colour_at(&d, p), [220, 20, 20, 255]);
    let before = (uv_state(&d), d.texture.rgba.clone());

    let pocket = PieceSpec {
        name: "pocket".into(),
        outline: Outline::rectangle(0.3, 0.2),
        fabric: "cotton".into(),
        grain: 0.0,
        placement: None,
        start: None,
        fallback: None,
    };
    d.add_piece(&pocket, Place::Front, 0.05).unwrap();
    d.validate().unwrap();
    // The design's coordinates moved; no warp direction turned.
    for ((s0, uv0, w0), (s1, uv1, w1)) in before.0.iter().zip(uv_state(&d)) {
        assert_eq!(*s0, s1);
        assert!(w0.dot(w1) > 0.9999, "slot {s1}: {uv0:?} -> {uv1:?}");
    }
    // The pocket's part is right of everything else's.
    let added = d.piece_slots(2).unwrap();
    let u_of = |d: &Design, slots: &[u32]| -> (f32, f32) {
        slots
            .iter()
            .flat_map(|&s| d.sim.cloth.live.tri(s).unwrap().uv)
            .fold((f32::MAX, f32::MIN), |(a, b), uv| {
                (a.min(uv.x), b.max(uv.x))
            })
    };
    let others: Vec<u32> = d
        .sim
        .cloth
        .live
        .iter()
        .map(|(s, _)| s)
        .filter(|s| !added.contains(s))
        .collect();
    let (own, rest) = (u_of(&d, &added), u_of(&d, &others));
    assert!(rest.1 < own.0, "pocket u {own:?}, the others' {rest:?}");
    // The red dab followed the front (averaged down with what is beside it).
    let c = colour_at(&d, p);
    assert!(c[0] > 180 && c[1] < 90 && c[2] < 90, "{c:?}");

    // Blue on the pocket changes no texel of the others' part.
    let mid = d.sim.cloth.live.tri(added[added.len() / 2]).unwrap().v[0];
    let q = d.sim.cloth.x[mid as usize];
    let keep = (rest.1 * d.texture.width as f32) as usize;
    let region = |d: &Design| -> Vec<u8> {
        (0..d.texture.height)
            .flat_map(|y| (0..keep).map(move |x| (x, y)))
            .flat_map(|(x, y)| d.texture.texel(x, y))
            .collect()
    };
    let others_before = region(&d);
    d.paint(q, 0.03, [20, 20, 220, 255]).unwrap();
    assert_eq!(colour_at(&d, q), [20, 20, 220, 255]);
    assert!(
        region(&d) == others_before,
        "the pocket's paint showed on another piece"
    );

    // Undo the paint and the piece: coordinates and texture as before, to the byte.
    d.undo().unwrap();
    d.undo().unwrap();
    assert_eq!(uv_state(&d), before.0);
    assert!(d.texture.rgba == before.1);
    // Redo: the room again.
    d.redo().unwrap();
    let again = d.piece_slots(2).unwrap();
    assert!(u_of(&d, &again).0 > rest.1);
}
