//! The stretch map in the studio, driven by egui_kittest with no system behind it: M shows
//! it, the cloth takes its colours in the rendered view, and the panel says how far the
//! cloth is stretched. And the tape measure (Fit), which reads the same cloth and body.

#![allow(clippy::unwrap_used)]

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui::app::{App, Options};
use ui::store::Store;

/// The studio over the demo cloth (1 m square, cut as it lies) stretched by `stretch`
/// along x.
fn harness(stretch: f32) -> Harness<'static, App> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1200.0, 900.0))
        .wgpu()
        .build_eframe(move |_cc| {
            let mut app = App::new(Options::default());
            let (mesh, x) = Store::demo_cloth(16, 0.4);
            let x = x
                .into_iter()
                .map(|[a, b, c]| [a * (1.0 + stretch), b, c])
                .collect();
            app.store.mesh = Some(mesh);
            app.store.set_positions(x);
            app
        });
    h.run_steps(3);
    h
}

/// The mean colour of the middle of the 3D view.
fn view_colour(h: &mut Harness<'static, App>) -> [f32; 3] {
    let img = h.render().unwrap();
    let rect = h.state().view.rect.unwrap();
    let (cx, cy) = (rect.center().x as u32, rect.center().y as u32);
    let mut sum = [0.0f32; 3];
    let mut n = 0.0;
    for x in cx - 30..cx + 30 {
        for y in cy - 30..cy + 30 {
            let p = img.get_pixel(x, y).0;
            for k in 0..3 {
                sum[k] += p[k] as f32;
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn the_stretch_map_shows_where_and_how_far_the_cloth_is_stretched() {
    let mut h = harness(0.3);
    // Off at first: the cloth's own off-white texture, and no summary.
    let [r, g, b] = view_colour(&mut h);
    assert!(r > 120.0 && g > 120.0 && b > 110.0, "{r} {g} {b}");
    assert!(h.query_by_label_contains("of the cloth past").is_none());
    assert!(h.state().store.stretch.is_none());

    // M shows it: every triangle is stretched 30%, past the default red (20%).
    h.key_press(egui::Key::M);
    h.run_steps(3);
    assert!(h.state().stretch.on);
    let worst = h.state().store.stretch.as_ref().unwrap().worst;
    assert!((worst - 0.3).abs() < 1e-3, "{worst}");
    h.get_by_label("Worst 30% · 100.0% of the cloth past 20%");
    let [r, g, b] = view_colour(&mut h);
    assert!(
        r > 2.0 * g && r > 2.0 * b,
        "red where it is stretched: {r} {g} {b}"
    );
    // The cloth under the mouse says how far it is stretched there.
    let centre = h.state().view.rect.unwrap().center();
    h.hover_at(centre);
    h.run_steps(30);
    assert!(h.get_all_by_label_contains("stretched 30.0%").count() >= 1);

    // Red at 60%: 30% is half way, between green and yellow.
    h.state_mut().stretch.full = 0.6;
    h.run_steps(3);
    h.get_by_label("Worst 30% · 0.0% of the cloth past 60%");
    let [r, g, b] = view_colour(&mut h);
    assert!(
        g > r && g > 1.5 * b,
        "green-yellow at half the scale: {r} {g} {b}"
    );

    // M again hides it: the texture is back.
    h.key_press(egui::Key::M);
    h.run_steps(3);
    assert!(h.state().store.stretch.is_none());
    let [r, g, b] = view_colour(&mut h);
    assert!(r > 120.0 && g > 120.0 && b > 110.0, "{r} {g} {b}");
}

#[test]
fn cloth_as_cut_is_blue_on_the_map() {
    let mut h = harness(0.0);
    h.state_mut().stretch.on = true;
    h.run_steps(3);
    h.get_by_label("Worst 0% · 0.0% of the cloth past 20%");
    let [r, g, b] = view_colour(&mut h);
    assert!(b > 2.0 * r && b > g, "blue as cut: {r} {g} {b}");
}

#[test]
fn the_pattern_view_shows_the_map_on_the_pieces() {
    let mut h = harness(0.3);
    h.state_mut().pieces.pattern_open = true;
    h.run_steps(3);
    // The pattern view's drawing area, under its hint (as the seam test finds it).
    let hint = h
        .get_by_label("Drag along a border, then along another: a seam joins them")
        .rect();
    let area = egui::Rect::from_min_size(
        egui::pos2(hint.left(), hint.bottom() + 8.0),
        egui::vec2(hint.width().max(300.0), 300.0),
    );
    let red = |h: &mut Harness<'static, App>| {
        let img = h.render().unwrap();
        let c = area.center();
        let mut n = 0;
        for x in (c.x - 50.0) as u32..(c.x + 50.0) as u32 {
            for y in (c.y - 50.0) as u32..(c.y + 50.0) as u32 {
                let p = img.get_pixel(x, y).0;
                if p[0] > 150 && (p[1] as u32) * 2 < p[0] as u32 && (p[2] as u32) * 2 < p[0] as u32
                {
                    n += 1;
                }
            }
        }
        n
    };
    assert_eq!(red(&mut h), 0, "no map: the pieces are outlines on grey");
    h.state_mut().stretch.on = true;
    h.run_steps(3);
    let n = red(&mut h);
    assert!(
        n > 9000,
        "the stretched piece is red in the pattern: {n} of 10000 pixels"
    );
}

#[test]
fn cloth_squeezed_shorter_than_cut_says_so_under_the_mouse() {
    // 10% shorter both ways: both threads, so the longer of them too.
    let mut h = harness(-0.1);
    let x: Vec<[f32; 3]> = h
        .state()
        .store
        .x
        .iter()
        .map(|&[a, b, c]| [a, b, 0.9 * c])
        .collect();
    h.state_mut().store.set_positions(x);
    h.state_mut().stretch.on = true;
    h.run_steps(3);
    let centre = h.state().view.rect.unwrap().center();
    h.hover_at(centre);
    h.run_steps(30);
    assert!(
        h.get_all_by_label_contains("10.0% shorter than cut")
            .count()
            >= 1
    );
}

#[test]
fn the_ease_map_shows_how_far_the_cloth_is_from_the_body() {
    let mut h = harness(0.0);
    // A 0.4 m cube under the middle of the cloth, its top 1 cm below it.
    let cube = sim_core::collision::body::cube(glam::Vec3::new(0.0, 0.19, 0.0), 0.2, 2).unwrap();
    let verts = cube.vertices.iter().map(|v| v.to_array()).collect();
    h.state_mut().store.body = Some((verts, cube.triangles.clone()));
    h.state_mut().store.body_version += 1;
    h.state_mut().stretch.on = true;
    h.state_mut().stretch.kind = ui::stretch::MapKind::Ease;
    h.run_steps(3);
    let map = h.state().store.stretch.clone().unwrap();
    assert_eq!(map.kind, ui::stretch::MapKind::Ease);
    // The middle of the cloth is 1 cm off the cube's top; its edges are far from it.
    let centre = (SIDE * SIDE) / 2;
    assert!(
        (map.vertex[centre] - 0.01).abs() < 1e-4,
        "{}",
        map.vertex[centre]
    );
    assert_eq!(map.vertex[0], 0.03);
    h.get_by_label("0% of the cloth on the body · half of it within 3.0 cm+");
    let at = h.state().view.rect.unwrap().center();
    h.hover_at(at);
    h.run_steps(30);
    // The tooltip says how far the cloth under the mouse is from the body.
    assert!(h.query_all_by_label_contains("from the body").count() >= 1);
    // Lowered onto it, the middle is on the body, red.
    let x: Vec<[f32; 3]> = h
        .state()
        .store
        .x
        .iter()
        .map(|&[a, _, c]| [a, 0.3905, c])
        .collect();
    h.state_mut().store.set_positions(x);
    h.state_mut().store.frame += 1;
    h.run_steps(3);
    let map = h.state().store.stretch.clone().unwrap();
    assert!(map.vertex[centre] < 1e-3, "{}", map.vertex[centre]);
    let [r, g, b, _] = map.colour_of(centre as u32);
    assert!(r > 4.0 * g && r > 4.0 * b, "red: {r} {g} {b}");
    // The cube's top is a sixth of the cloth: so much of it lies on the body.
    assert!((0.1..0.3).contains(&map.over), "{}", map.over);
    assert!(
        h.query_by_label_contains("of the cloth on the body")
            .is_some()
    );
}

/// The demo cloth's vertices a side.
const SIDE: usize = 17;

#[test]
fn the_fit_section_measures_a_tube_round_the_mannequin() {
    let mut h = harness(0.0);
    let body = sim_core::collision::body::mannequin().unwrap();
    let verts = body.vertices.iter().map(|v| v.to_array()).collect();
    h.state_mut().store.body = Some((verts, body.triangles.clone()));
    h.state_mut().store.body_version += 1;
    // A tube of 64 sides, 0.25 m in radius, round the torso from 0.8 to 1.45 m.
    let (n, r) = (64u32, 0.25f32);
    let mut x = Vec::new();
    for k in 0..n {
        let a = std::f32::consts::TAU * k as f32 / n as f32;
        x.push([r * a.cos(), 0.8, r * a.sin()]);
        x.push([r * a.cos(), 1.45, r * a.sin()]);
    }
    let corners: Vec<shared::sim_to_ui::MeshCorner> = (0..n)
        .flat_map(|k| {
            let (a, b) = (2 * k, 2 * ((k + 1) % n));
            [a, b, a + 1, b, b + 1, a + 1]
        })
        .map(|vertex| shared::sim_to_ui::MeshCorner {
            vertex,
            ..Default::default()
        })
        .collect();
    h.state_mut().store.mesh = Some(ui::store::Mesh::new(7, x.len(), corners));
    h.state_mut().store.mesh_generation += 1;
    h.state_mut().store.set_positions(x);
    h.run_steps(3);
    // Off: nothing measured, no rows.
    assert!(h.state().store.fit.is_none());
    assert!(h.query_by_label("waist").is_none());
    h.get_by_label("Fit (tape measure)").scroll_to_me();
    // The scroll animates over a few frames.
    h.run_steps(20);
    h.get_by_label("Fit (tape measure)").click();
    h.run_steps(3);
    let fit = h.state().store.fit.clone().unwrap();
    assert_eq!(fit.len(), 3);
    // The tube is 1.57 m round: each level's ease is that less the body's girth there.
    let round = n as f32 * 2.0 * r * (std::f32::consts::PI / n as f32).sin();
    for g in &fit {
        h.get_by_label(g.level);
        h.get_by_label(&format!("{:.1} cm", 100.0 * g.body_m));
        h.get_by_label(&format!("{:+.1} cm", 100.0 * (round - g.body_m)));
    }
    assert_eq!(
        h.query_all_by_label(&format!("{:.1} cm", 100.0 * round))
            .count(),
        3
    );
    // A level of the designer's own: 1 m up at first.
    h.get_by_label("Also at").scroll_to_me();
    h.run_steps(20);
    h.get_by_label("Also at").click();
    h.run_steps(3);
    assert_eq!(h.state().stretch.fit_at, Some(1.0));
    h.get_by_label("at 1.00 m");
    let cm = format!("{:.1} cm", 100.0 * round);
    assert_eq!(h.query_all_by_label(&cm).count(), 4);
    h.get_by_label("Also at").click();
    h.run_steps(3);
    assert!(h.query_by_label("at 1.00 m").is_none());
    // Switched off again: gone.
    h.get_by_label("Fit (tape measure)").click();
    h.run_steps(3);
    assert!(h.state().store.fit.is_none());
    assert!(h.query_by_label("waist").is_none());
}
