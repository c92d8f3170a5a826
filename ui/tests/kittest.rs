//! The studio driven by egui_kittest, with no system behind it: each tool is chosen by its
//! label and used on a demo cloth in the 3D view, and the commands and pen moves the UI
//! emits are checked, with the state it shows; a snapshot of the rendered 3D view.

#![allow(clippy::unwrap_used)]

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use shared::ports;
use shared::sim_to_ui::tool;
use shared::ui_to_sim::op;
use ui::action::Emitted;
use ui::app::{App, Options};
use ui::store::Store;

fn harness() -> Harness<'static, App> {
    let mut h = Harness::builder()
        .with_size(egui::vec2(1200.0, 760.0))
        .wgpu()
        .build_eframe(|_cc| {
            let mut app = App::new(Options::default());
            let (mesh, x) = Store::demo_cloth(16, 0.4);
            app.store.mesh = Some(mesh);
            app.store.set_positions(x);
            app
        });
    h.run_steps(3);
    h
}

/// A studio with nothing in it yet, listening on `domain` (a test publishes there).
fn connected_harness(domain: &shared::domain::ScratchDomain) -> Harness<'static, App> {
    let name = domain.0.clone();
    Harness::builder()
        .with_size(egui::vec2(1200.0, 760.0))
        .wgpu()
        .build_eframe(move |_cc| {
            App::new(Options {
                domain: Some(name),
                ..Options::default()
            })
        })
}

fn view_centre(h: &Harness<'_, App>) -> egui::Pos2 {
    h.state().view.rect.unwrap().center()
}

fn click(h: &mut Harness<'_, App>, p: egui::Pos2) {
    h.hover_at(p);
    h.run_steps(1);
    h.drag_at(p);
    h.run_steps(1);
    h.drop_at(p);
    h.run_steps(2);
}

/// Clicks the button `label`, scrolling the tools panel to it first.
fn press(h: &mut Harness<'_, App>, label: &str) {
    h.get_by_label(label).scroll_to_me();
    // The scroll animates over a few frames.
    h.run_steps(20);
    h.get_by_label(label).click();
    h.run_steps(2);
}

fn commands(h: &Harness<'_, App>) -> Vec<shared::ui_to_sim::ToolCommand> {
    h.state()
        .emitted
        .iter()
        .filter_map(|e| match e {
            Emitted::Command(c) => Some(c.to_wire(shared::Header::default()).unwrap()),
            _ => None,
        })
        .collect()
}

#[test]
fn each_tool_by_its_label_emits_its_commands() {
    let mut h = harness();
    let centre = view_centre(&h);
    cut_and_sew(&mut h, centre);
    seam_by_shift_clicks(&mut h);
    pin_paint_and_pinch(&mut h, centre);
    keys_load_and_reset(&mut h);
}

/// The demo cloth's vertices a side.
const SIDE: usize = 17;

fn cut_and_sew(h: &mut Harness<'static, App>, centre: egui::Pos2) {
    // Cut: choosing it tells cloth-sim; a click on the cloth splits the vertex there.
    h.get_by_label("Cut  (C)").click();
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!((c.op, c.a), (op::SET_TOOL, tool::CUT));
    assert_eq!(h.state().tool, tool::CUT);
    h.get_by_label_contains("Cut tool: ");
    click(h, centre);
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::CUT_VERTEX, "{c:?}");
    let (r, col) = (c.a as usize / SIDE, c.a as usize % SIDE);
    assert!(
        (4..=12).contains(&r) && (4..=12).contains(&col),
        "cut vertex {}",
        c.a
    );
    assert!(c.vec.iter().any(|v| *v != 0.0));

    // Sew: two clicks on two vertices.
    h.get_by_label("Sew  (S)").click();
    h.run_steps(2);
    click(h, centre);
    assert!(h.state().sew_first.is_some());
    click(h, centre + egui::vec2(60.0, 20.0));
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::SEW, "{c:?}");
    assert_ne!(c.a, c.b);
    assert!(h.state().sew_first.is_none());
}

/// A seam: shift-click the start and end of two boundary paths (rows 0 and 16, columns
/// 3 to 7 of the demo cloth, a hair inside it so the click lands on the cloth).
fn seam_by_shift_clicks(h: &mut Harness<'static, App>) {
    let rect = h.state().view.rect.unwrap();
    let screen = |h: &Harness<'_, App>, r: usize, c: usize| {
        let x = h.state().store.x[r * SIDE + c];
        let inward = if r == 0 { 0.01 } else { -0.01 };
        let p = glam::Vec3::new(x[0], x[1], x[2] + inward);
        let s = h
            .state()
            .camera
            .to_screen(p, glam::Vec2::new(rect.width(), rect.height()))
            .unwrap();
        rect.min + egui::vec2(s.x, s.y)
    };
    h.event(egui::Event::ModifiersChanged(egui::Modifiers::SHIFT));
    for (r, c) in [(0, 3), (0, 7), (16, 3), (16, 7)] {
        let p = screen(h, r, c);
        click(h, p);
    }
    h.event(egui::Event::ModifiersChanged(egui::Modifiers::NONE));
    h.run_steps(1);
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::SEAM, "{c:?}");
    // Path A runs along v = 0 from u = 3/16 to 7/16; path B along v = 1.
    assert!(
        (c.uv[3] - 0.0).abs() < 1e-4 && (c.uv[7] - 1.0).abs() < 1e-4,
        "{:?}",
        c.uv
    );
    assert!(
        (c.uv[2] - 7.0 / 16.0).abs() < 1e-4 && c.uv[0] < 3.0 / 16.0,
        "{:?}",
        c.uv
    );
    assert!(c.value > 0.0 && c.value < 1.0 / 16.0);
}

fn pin_paint_and_pinch(h: &mut Harness<'static, App>, centre: egui::Pos2) {
    // Pin: a click pins.
    h.get_by_label("Pin  (N)").click();
    h.run_steps(2);
    click(h, centre);
    let c = *commands(h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::PIN, 1));

    // Paint: the colour and brush go with the dab, at the point under the mouse.
    h.get_by_label("Paint  (B)").click();
    h.run_steps(2);
    click(h, centre);
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::PAINT);
    assert_eq!(c.rgba, [200, 30, 40, 255]);
    assert!((c.value - 0.02).abs() < 1e-6);
    assert!((c.vec[1] - 0.4).abs() < 1e-3, "painted at {:?}", c.vec);

    // Pinch: a drag moves the simulated pen with its button held, then lets go.
    h.get_by_label("Pinch  (P)").click();
    h.run_steps(2);
    let pen = drag_up(h, centre);
    assert!(pen.len() >= 3, "{pen:?}");
    assert_eq!(pen[0].1, 1);
    assert_eq!(pen.last().unwrap().1, 0);
    assert!(
        pen.last().unwrap().0[1] > pen[0].0[1] + 0.02,
        "dragging up lifts: {pen:?}"
    );

    // Cut: the same drag rides the cloth under the mouse (the stroke is cut where it
    // meets the cloth; at the press's depth it left it within a few centimetres).
    h.get_by_label("Cut  (C)").click();
    h.run_steps(2);
    let pen = drag_up(h, centre);
    assert!(pen.len() >= 3, "{pen:?}");
    assert!(
        pen.iter().all(|(p, _)| (p[1] - 0.4).abs() < 1e-3),
        "the stroke lies on the cloth (y = 0.4): {pen:?}"
    );
    let moved = glam::Vec3::from(pen.last().unwrap().0).distance(glam::Vec3::from(pen[0].0));
    assert!(moved > 0.02, "{pen:?}");
}

/// Drags 60 px up from `centre` with the current tool: the pen's points sent, with
/// their button.
fn drag_up(h: &mut Harness<'static, App>, centre: egui::Pos2) -> Vec<([f32; 3], u32)> {
    let before = h.state().emitted.len();
    h.hover_at(centre);
    h.run_steps(1);
    h.drag_at(centre);
    h.run_steps(1);
    for k in 1..=5 {
        h.hover_at(centre + egui::vec2(0.0, -12.0 * k as f32));
        h.run_steps(1);
    }
    h.drop_at(centre + egui::vec2(0.0, -60.0));
    h.run_steps(2);
    pen_since(h, before)
}

/// The pen's points (position, buttons) the studio sent since its `before`-th emission.
fn pen_since(h: &Harness<'static, App>, before: usize) -> Vec<([f32; 3], u32)> {
    (h.state().emitted[before..].iter())
        .filter_map(|e| match e {
            Emitted::Pointer(p, b) => Some((*p, *b)),
            _ => None,
        })
        .collect()
}

/// Undo and redo by button and by keyboard, a tool by its shortcut, load, export, a new
/// scene, and a click beside the cloth.
fn keys_load_and_reset(h: &mut Harness<'static, App>) {
    // Undo and redo by button and by keyboard.
    h.get_by_label("Undo").click();
    h.run_steps(2);
    assert_eq!(commands(h).last().unwrap().op, op::UNDO);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Y);
    h.run_steps(2);
    assert_eq!(commands(h).last().unwrap().op, op::REDO);
    // A tool by its shortcut.
    h.key_press(egui::Key::T);
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!((c.op, c.a), (op::SET_TOOL, tool::TEAR));
    // Load names the file; a new scene needs a second click and carries body and grid.
    h.get_by_label("Load").click();
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::LOAD);
    assert!(
        c.text().unwrap().ends_with("design.saiho"),
        "{:?}",
        c.text()
    );
    // Export names the folder and carries the seam allowance for the pattern.
    h.get_by_label("Export").click();
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!(c.op, op::EXPORT);
    assert!(c.text().unwrap().ends_with("out/export"), "{:?}", c.text());
    assert_eq!(c.value, shared::command::DEFAULT_ALLOWANCE_MM);
    let n = commands(h).len();
    press(h, "New scene");
    assert_eq!(commands(h).len(), n, "one click must not reset");
    press(h, "Click again to reset");
    let c = *commands(h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.b),
        (op::RESET, 64, shared::ui_to_sim::body::CUBE)
    );
    assert!((c.uv[0] - 0.15).abs() < 1e-6 && c.uv[1] > 0.0);
    // A click beside the cloth is explained, not sent. (The tools panel scrolled down
    // for the buttons above: scroll back to the tool.)
    press(h, "Pin  (N)");
    let n = commands(h).len();
    let rect = h.state().view.rect.unwrap();
    click(h, rect.left_top() + egui::vec2(5.0, 5.0));
    assert_eq!(commands(h).len(), n);
    h.get_by_label("Pin: nothing under the mouse");
}

#[test]
fn the_3d_view_draws_the_cloth() {
    let mut h = harness();
    h.run_steps(2);
    let img = h.render().unwrap();
    let rect = h.state().view.rect.unwrap();
    // The demo cloth's off-white texture, lit: bright pixels in the middle of the view.
    let (cx, cy) = (rect.center().x as u32, rect.center().y as u32);
    let bright = (cx - 40..cx + 40)
        .flat_map(|x| (cy - 40..cy + 40).map(move |y| (x, y)))
        .filter(|&(x, y)| img.get_pixel(x, y).0[..3].iter().all(|&c| c > 120))
        .count();
    assert!(bright > 3000, "{bright} bright pixels where the cloth is");
    // The view's corner is background.
    let bg = img
        .get_pixel(rect.min.x as u32 + 3, rect.min.y as u32 + 3)
        .0;
    assert!(bg[..3].iter().all(|&c| c < 110), "{bg:?}");
    // The status panel shows wall-clock rates (frames per second): not part of the picture.
    let right = egui::Rect::from_min_max(
        egui::pos2(rect.max.x + 1.0, 0.0),
        egui::pos2(10_000.0, 10_000.0),
    );
    h.mask(right);
    h.snapshot("view3d");
}

/// The material panel shows cloth-sim's material and substeps (from its telemetry), and
/// Apply sends the edited ones for the current design.
#[test]
fn the_material_follows_cloth_sim_and_applies_in_place() {
    use shared::telemetry::SimTelemetry;
    let mut h = harness();
    // Nothing heard from cloth-sim: nothing to apply to.
    let n = commands(&h).len();
    press(&mut h, "Apply");
    assert_eq!(commands(&h).len(), n);

    let heard = |substeps, material| {
        Some(Box::new(SimTelemetry {
            substeps,
            material,
            ..Default::default()
        }))
    };
    let m0 = [0.2, 1000.0, 40.0, 1e-5, 0.4, 0.6, 0.005, 0.002];
    h.state_mut().store.sim_tel = heard(5, m0);
    h.run_steps(2);
    assert_eq!(h.state().material.values, m0);
    assert_eq!(h.state().material.substeps, 5);

    h.state_mut().material.substeps = 9;
    h.state_mut().material.values[1] = 500.0;
    h.state_mut().material.values[6] = 0.02;
    h.state_mut().material.values[7] = 0.004;
    h.run_steps(2);
    press(&mut h, "Apply");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.a), (op::SET_MATERIAL, 9));
    assert_eq!(c.uv, [0.2, 500.0, 40.0, 1e-5, 0.4, 0.6, 0.02, 0.004]);

    // A new scene carries the material and substeps too.
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::RESET, 9));
    assert_eq!((c.uv[1], c.uv[6], c.uv[7]), (500.0, 0.02, 0.004));

    // cloth-sim changed (here: another design loaded): the panel follows it.
    let m1 = [0.1, 3000.0, 20.0, 1e-4, 0.5, 1.0, 0.02, 0.01];
    h.state_mut().store.sim_tel = heard(12, m1);
    h.run_steps(2);
    assert_eq!(h.state().material.values, m1);
    assert_eq!(h.state().material.substeps, 12);

    // Values beyond the sliders' ranges (set by cloth-sim's flags) are shown as they are,
    // not clamped into a change nobody asked for (the shear and bending damping off, 0,
    // too).
    let m2 = [1.0, 50_000.0, 20.0, 1e-4, 0.5, 1.0, 0.0, 0.0];
    h.state_mut().store.sim_tel = heard(60, m2);
    h.run_steps(2);
    assert_eq!(h.state().material.values, m2);
    assert_eq!(h.state().material.substeps, 60);
    let n = commands(&h).len();
    press(&mut h, "Apply");
    assert_eq!(commands(&h).len(), n, "nothing changed, nothing to apply");
}

/// The fabric chooser names the library's fabrics, sends the one picked for the whole
/// design, and shows which one the design has from cloth-sim's telemetry alone.
#[test]
fn a_fabric_is_chosen_by_name() {
    use shared::telemetry::SimTelemetry;
    let mut h = harness();
    let tel = |values: [f32; 5]| {
        let [d, s, g, b, f] = values;
        Some(Box::new(SimTelemetry {
            substeps: 5,
            material: [d, s, g, b, f, 0.6, 0.005, 0.002],
            ..Default::default()
        }))
    };
    h.state_mut().store.sim_tel = tel([0.15, 2000.0, 40.0, 1e-5, 0.4]);
    h.run_steps(2);
    assert_eq!(h.state().material.current_fabric(), None);
    // cloth-sim's default material, which is none of the library's, by its own name.
    assert_eq!(h.state().material.shown_fabric(), "cotton (default)");
    press(&mut h, "Fabric");
    press(&mut h, "denim");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.text()), (op::SET_FABRIC, Some("denim")));

    // cloth-sim reports denim's values: the chooser names it.
    let denim = sim_core::fabric::Library::builtin()
        .get("denim")
        .unwrap()
        .material();
    h.state_mut().store.sim_tel = tel([
        denim.density,
        denim.stretch,
        denim.shear,
        denim.bending,
        denim.friction,
    ]);
    h.run_steps(2);
    assert_eq!(h.state().material.current_fabric(), Some("denim"));
    assert_eq!(h.state().material.shown_fabric(), "denim");
    // Edited by hand, it is no longer denim.
    h.state_mut().store.sim_tel = tel([
        denim.density,
        denim.stretch,
        denim.shear,
        denim.bending * 2.0,
        denim.friction,
    ]);
    h.run_steps(2);
    assert_eq!(h.state().material.current_fabric(), None);
    assert_eq!(h.state().material.shown_fabric(), "custom");
}

/// A peer from another build: the UI rejects its messages, says why over the view, and
/// keeps running.
#[test]
fn a_peer_of_another_protocol_version_gets_a_banner() {
    use shared::domain::ScratchDomain;
    use shared::{Header, PROTOCOL_VERSION, services, sim_to_ui::ToolState};

    let domain = ScratchDomain::new(&format!("kt-mismatch-{}", std::process::id())).unwrap();
    let node = services::node(&domain, "test-peer").unwrap();
    let publisher = ports::publisher(&node, services::tool_state).unwrap();
    let mut h = connected_harness(&domain);
    let mut seq = 0;
    let mut shown = false;
    for _ in 0..200 {
        let mut header = Header::next(&mut seq);
        header.protocol = PROTOCOL_VERSION + 1;
        publisher
            .send_copy(ToolState {
                header,
                tool: tool::CUT,
                ..Default::default()
            })
            .unwrap();
        h.run_steps(1);
        if h.query_all_by_label_contains("Cannot read a peer's messages")
            .next()
            .is_some()
        {
            shown = true;
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert!(shown, "no mismatch banner");
    let why = format!(
        "the peer speaks version {}, this build speaks {PROTOCOL_VERSION}",
        PROTOCOL_VERSION + 1
    );
    assert!(h.get_all_by_label_contains(&why).next().is_some());
    // Nothing of the rejected message was taken: the tool is still the default.
    assert_eq!(h.state().tool, tool::PINCH);
    assert!(h.state().store.rejected > 0);
    assert!(h.state().store.tool.is_none());
    drop(h);
    drop(publisher);
    drop(node);
}

/// Every tool, chosen by its label, says in words what it does (never "tool 1").
#[test]
fn status_texts_are_sentences() {
    let mut h = harness();
    for (t, name, _, _) in ui::tools::TOOLS {
        h.get_by_label(&format!(
            "{name}  ({:?})",
            ui::tools::TOOLS.iter().find(|x| x.0 == t).unwrap().2
        ))
        .click();
        h.run_steps(2);
        let status = h.state().status.clone();
        let words: Vec<&str> = status.split_whitespace().collect();
        assert!(
            status.starts_with(&format!("{name} tool: ")) && words.len() >= 6,
            "{status}"
        );
        assert!(
            !(words.len() == 2 && words[1].parse::<u32>().is_ok()),
            "a bare code: {status}"
        );
    }
    // The hints of a seam being picked and of a click beside the cloth read as sentences.
    h.get_by_label("Pin  (N)").click();
    h.run_steps(2);
    let rect = h.state().view.rect.unwrap();
    click(&mut h, rect.left_top() + egui::vec2(5.0, 5.0));
    assert_eq!(h.state().status, "Pin: nothing under the mouse");
}

/// The camera frames a tall body: a mannequin-sized body that arrives is wholly inside
/// the view, with the cloth.
#[test]
fn the_view_frames_a_tall_body() {
    let mut h = harness();
    // A standing figure's box, 1.75 m tall, feet on the floor.
    let (lo, hi) = ([-0.25f32, 0.0, -0.15], [0.25f32, 1.75, 0.15]);
    let v: Vec<[f32; 3]> = (0..8)
        .map(|k| {
            [
                if k & 1 == 0 { lo[0] } else { hi[0] },
                if k & 2 == 0 { lo[1] } else { hi[1] },
                if k & 4 == 0 { lo[2] } else { hi[2] },
            ]
        })
        .collect();
    let t = vec![[0, 1, 2], [1, 3, 2], [4, 6, 5], [5, 6, 7]];
    {
        let app = h.state_mut();
        app.store.body = Some((v.clone(), t));
        app.store.body_version += 1;
    }
    h.run_steps(3);
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    let inside = |p: [f32; 3]| {
        h.state()
            .camera
            .to_screen(glam::Vec3::from(p), size)
            .is_some_and(|s| s.x >= 0.0 && s.y >= 0.0 && s.x <= size.x && s.y <= size.y)
    };
    assert!(v.iter().all(|&p| inside(p)), "the body leaves the view");
    assert!(
        h.state().store.x.iter().all(|&p| inside(p)),
        "the cloth leaves the view"
    );
    // And the head is not a dot: the body fills a good part of the view's height.
    let cam = h.state().camera;
    let top = cam
        .to_screen(glam::Vec3::new(0.0, 1.75, 0.0), size)
        .unwrap();
    let foot = cam.to_screen(glam::Vec3::ZERO, size).unwrap();
    assert!((foot.y - top.y) > 0.5 * size.y, "{top} {foot} in {size}");
}

/// The pieces panel lists what cloth-sim lists; selecting one tints it (the store's
/// highlight is its mesh piece); Add, Place at and Delete send their commands; the seams
/// are listed and one removed; the pattern view opens and two drags there make a seam.
#[test]
fn the_pieces_panel_lists_selects_adds_places_and_deletes() {
    use shared::sim_to_ui::ListedPiece;
    use shared::ui_to_sim::place;
    let mut h = harness();
    let corner = h.state().store.mesh.as_ref().unwrap().corners[0];
    h.state_mut().store.pieces = vec![ListedPiece {
        name: "front".into(),
        fabric: "cotton".into(),
        vertices: 289,
        triangles: 512,
        anchor: Some((corner.vertex, [corner.u, corner.v])),
    }];
    h.state_mut().store.pieces_total = 1;
    seam_rows(&mut h);
    assert_eq!(h.state().store.highlight, None);
    press(&mut h, "front · 289 vertices · cotton");
    let want = h
        .state()
        .store
        .mesh
        .as_ref()
        .unwrap()
        .piece_of
        .get(&ui::store::key(corner.vertex, [corner.u, corner.v]))
        .copied();
    assert!(want.is_some());
    assert_eq!(h.state().store.highlight, want);

    h.state_mut().pieces.place = place::BACK;
    // 0.42 m lower: the top at the mannequin's waist.
    h.state_mut().pieces.drop = 0.42;
    h.run_steps(1);
    press(&mut h, "Place at");
    let c = *commands(&h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.b, c.vec[2]),
        (op::PLACE_PIECE, 0, place::BACK, 0.42)
    );
    // The selected piece alone gets a fabric of its own.
    press(&mut h, "Piece fabric");
    press(&mut h, "jersey-interlock");
    let c = *commands(&h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.text()),
        (op::SET_PIECE_FABRIC, 0, Some("jersey-interlock"))
    );
    // Naming it: Name opens the field with its name so far; OK sends the new one.
    h.get_all_by_label("Name").next().unwrap().click();
    h.run_steps(2);
    assert_eq!(
        h.state().pieces.piece_naming,
        Some((0, "front".to_string()))
    );
    h.state_mut().pieces.piece_naming = Some((0, " bodice front ".into()));
    h.run_steps(1);
    press(&mut h, "OK");
    let c = *commands(&h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.text()),
        (op::NAME_PIECE, 0, Some("bodice front"))
    );
    assert_eq!(h.state().pieces.piece_naming, None);
    // A copy, turned over, at the place chosen (behind the body).
    press(&mut h, "Turned over");
    assert!(h.state().pieces.mirror);
    press(&mut h, "Copy to");
    let c = *commands(&h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.b, c.mode, c.vec[2]),
        (op::DUPLICATE_PIECE, 0, place::BACK, 1, 0.42)
    );
    assert_eq!(c.value, h.state().pieces.edge);
    press(&mut h, "Delete");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.a), (op::DELETE_PIECE, 0));
    assert_eq!(h.state().pieces.selected, None);

    press(&mut h, "Add piece");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode, c.a), (op::ADD_PIECE, 0, place::BACK));
    assert_eq!(c.vec, [0.6, 0.6, 0.42]);
    // From a file with no path: nothing goes out, the status says why.
    let n = commands(&h).len();
    press(&mut h, "From file");
    press(&mut h, "Add piece");
    assert_eq!(commands(&h).len(), n);
    assert!(
        h.state().status.contains("pattern file"),
        "{}",
        h.state().status
    );

    press(&mut h, "Pattern view");
    assert!(h.state().pieces.pattern_open);
    h.get_by_label("Pattern");
    seam_by_two_drags(&mut h);
    dart_by_a_drag(&mut h);
    cut_by_a_drag(&mut h);
    zoom_and_pan(&mut h);
}

/// With Dart ticked, one drag in the pattern view takes in a dart: from its point out
/// across the edge, at the width beside the tick (40 mm unless changed), sent in the
/// pattern plane; ticked off, drags make seams again.
fn dart_by_a_drag(h: &mut Harness<'static, App>) {
    h.get_by_label("Dart").click();
    h.run_steps(2);
    assert!(h.state().pieces.darting);
    let hint = h
        .get_by_label("Dart: drag from the dart's point out across the piece's edge")
        .rect();
    let n = commands(h).len();
    let c = egui::pos2(hint.center().x.max(200.0), hint.bottom() + 160.0);
    drag(h, c, c + egui::vec2(0.0, 120.0));
    let sent = commands(h);
    assert_eq!(sent.len(), n + 1, "one dart");
    let s = sent.last().unwrap();
    assert_eq!(s.op, op::DART_PLANE);
    // Down the view: the pattern's y falls from the point toward the edge.
    assert!(s.uv[1] > s.uv[3] + 0.05, "{:?}", s.uv);
    assert!((s.value - 0.04).abs() < 1e-6, "{}", s.value);
    assert!(h.state().pieces.seam_sides.is_empty());
    h.get_by_label("Dart").click();
    h.run_steps(2);
    assert!(!h.state().pieces.darting);
}

/// A primary drag from `a` to `b`, held and moved as a hand does.
fn drag(h: &mut Harness<'_, App>, a: egui::Pos2, b: egui::Pos2) {
    h.hover_at(a);
    h.run_steps(1);
    h.drag_at(a);
    h.run_steps(2);
    h.hover_at(b);
    h.run_steps(2);
    h.drop_at(b);
    h.run_steps(2);
}

/// With the Cut tool, one drag in the pattern view is a cut along its line (sent in the
/// pattern plane), not a seam's side.
fn cut_by_a_drag(h: &mut Harness<'static, App>) {
    // By its key: the pattern window lies over the tools.
    h.key_press(egui::Key::C);
    h.run_steps(2);
    let s = cut_drag(h);
    // Left to right across the view, level: pattern x grows, y stays.
    assert!(s.uv[0] + 0.1 < s.uv[2], "{:?}", s.uv);
    assert!((s.uv[1] - s.uv[3]).abs() < 1e-3, "{:?}", s.uv);
    assert!(h.state().pieces.seam_sides.is_empty());
}

/// The middle of the pattern view, under the Cut tool's hint.
fn pattern_middle(h: &Harness<'static, App>) -> egui::Pos2 {
    let hint = h
        .get_by_label("Cut tool: drag a line across a piece to cut it along the line")
        .rect();
    egui::pos2(hint.center().x, hint.bottom() + 158.0)
}

/// A cut dragged 240 pixels level across the pattern view's middle: the one command sent.
fn cut_drag(h: &mut Harness<'static, App>) -> shared::ui_to_sim::ToolCommand {
    let n = commands(h).len();
    let c = pattern_middle(h);
    drag(h, c + egui::vec2(-120.0, 0.0), c + egui::vec2(120.0, 0.0));
    let sent = commands(h);
    assert_eq!(sent.len(), n + 1, "one cut");
    let s = *sent.last().unwrap();
    assert_eq!(s.op, op::CUT_PLANE);
    s
}

/// The wheel zooms the pattern view about the mouse: the same drag on the screen is then
/// a line as many times shorter in the pattern, through the same place; a middle drag
/// pans it (the drag's line moves the other way); Fit goes back to every piece in view.
fn zoom_and_pan(h: &mut Harness<'static, App>) {
    let before = cut_drag(h);
    let c = pattern_middle(h);
    h.hover_at(c);
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 300.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Unknown,
        modifiers: egui::Modifiers::default(),
    });
    h.run_steps(40);
    let zoom = h.state().pieces.pattern_zoom;
    assert!(zoom > 2.0, "{zoom}");
    let after = cut_drag(h);
    let len = |c: &shared::ui_to_sim::ToolCommand| c.uv[2] - c.uv[0];
    let ratio = len(&before) / len(&after);
    assert!((ratio / zoom - 1.0).abs() < 0.02, "{ratio} against {zoom}");
    // About the mouse: the middle of the drag is the same place in the pattern.
    let mid = |c: &shared::ui_to_sim::ToolCommand| 0.5 * (c.uv[0] + c.uv[2]);
    assert!(
        (mid(&before) - mid(&after)).abs() < 2e-3,
        "{before:?} {after:?}"
    );
    // A middle drag 100 pixels to the right: the pattern moves with the mouse.
    h.event(egui::Event::PointerButton {
        pos: c,
        button: egui::PointerButton::Middle,
        pressed: true,
        modifiers: egui::Modifiers::default(),
    });
    h.run_steps(1);
    for k in 1..=5 {
        h.hover_at(c + egui::vec2(20.0 * k as f32, 0.0));
        h.run_steps(1);
    }
    h.event(egui::Event::PointerButton {
        pos: c + egui::vec2(100.0, 0.0),
        button: egui::PointerButton::Middle,
        pressed: false,
        modifiers: egui::Modifiers::default(),
    });
    h.run_steps(2);
    let n = commands(h).len();
    let panned = cut_drag(h);
    assert_eq!(commands(h).len(), n + 1, "the middle drag sent nothing");
    let moved = mid(&after) - mid(&panned);
    let metres = 100.0 * len(&after) / 240.0;
    assert!(
        (moved - metres).abs() < 0.1 * metres,
        "{moved} against {metres}"
    );
    press(h, "Fit");
    assert_eq!(
        (h.state().pieces.pattern_zoom, h.state().pieces.pattern_pan),
        (1.0, [0.0; 2])
    );
    let fitted = cut_drag(h);
    assert!((len(&fitted) - len(&before)).abs() < 1e-4);
}

/// The seam rows: two seams listed (the second's sides 30% apart), the second removed,
/// and a dart's row pressing it the other way.
fn seam_rows(h: &mut Harness<'static, App>) {
    // Two seams: A matched, B with sides 30% apart (shown as a warning).
    let seam = |label: &[u8], lengths| {
        let mut l = [0u8; 4];
        l[..label.len()].copy_from_slice(label);
        shared::sim_to_ui::SeamEntry {
            label: l,
            label_len: label.len() as u32,
            pairs: 12,
            open: 3,
            lengths,
            ..Default::default()
        }
    };
    let mut named = seam(b"A", [0.24, 0.24]);
    named.name_len = shared::sim_to_ui::put_text(&mut named.name, "left side");
    h.state_mut().store.seams = vec![named, seam(b"B", [0.3, 0.2])];
    h.state_mut().store.seams_total = 2;
    h.run_steps(2);
    h.get_by_label("A (left side)");
    h.get_by_label("12 pairs, 3 pulling · 240 / 240 mm");
    // Naming B: its row's Name opens the field with its name so far; OK sends it.
    h.get_all_by_label("Name").nth(1).unwrap().scroll_to_me();
    h.run_steps(20);
    h.get_all_by_label("Name").nth(1).unwrap().click();
    h.run_steps(2);
    assert_eq!(h.state().pieces.naming, Some((1, String::new())));
    h.state_mut().pieces.naming = Some((1, " right side ".into()));
    h.run_steps(1);
    press(h, "OK");
    let c = *commands(h).last().unwrap();
    assert_eq!(
        (c.op, c.a, c.text()),
        (op::NAME_SEAM, 1, Some("right side"))
    );
    assert_eq!(h.state().pieces.naming, None);
    h.get_by_label("B");
    h.get_by_label("12 pairs, 3 pulling · 300 / 200 mm");
    // Pairs that stopped closing are said, with how far apart they stay.
    assert!(h.query_by_label_contains("stopped closing").is_none());
    h.state_mut().store.seams[1].stalled = 3;
    h.state_mut().store.seams[1].stalled_gap = [0.0152, 0.0408];
    h.run_steps(2);
    h.get_by_label("3 stopped closing, 15-41 mm apart");
    // On a line of its own: the tools panel keeps its width (beside it, it went to 600
    // px and squeezed the view).
    let left = h.state().view.rect.unwrap().left();
    assert!(left < 320.0, "the view starts {left} px in");
    let removes = h.get_all_by_label("Remove").count();
    assert_eq!(removes, 2);
    h.get_all_by_label("Remove").nth(1).unwrap().scroll_to_me();
    h.run_steps(20);
    h.get_all_by_label("Remove").nth(1).unwrap().click();
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!((c.op, c.a), (op::REMOVE_SEAM, 1));
    // Only a dart's row can press it the other way: pressed toward its second leg,
    // the button asks for its first.
    assert!(h.query_by_label("Press other way").is_none());
    h.state_mut().store.seams[1].dart = shared::sim_to_ui::dart::SECOND;
    h.run_steps(2);
    h.get_by_label("Press other way").scroll_to_me();
    h.run_steps(20);
    h.get_by_label("Press other way").click();
    h.run_steps(2);
    let c = *commands(h).last().unwrap();
    assert_eq!((c.op, c.a, c.mode), (op::PRESS_DART, 1, 0));
}

/// Two drags in the open pattern view send one seam in the pattern plane.
fn seam_by_two_drags(h: &mut Harness<'static, App>) {
    // Two drags in the pattern view: a seam between the borders they follow, sent in
    // the pattern plane (the demo cloth's is its UV square, y down: x in 0..1, y in -1..0).
    let hint = h
        .get_by_label("Drag along a border, then along another: a seam joins them")
        .rect();
    let n = commands(h).len();
    let view = egui::Rect::from_min_size(
        egui::pos2(hint.left(), hint.bottom() + 8.0),
        egui::vec2(hint.width().max(300.0), 300.0),
    );
    let c = view.center();
    drag(h, c + egui::vec2(-60.0, -60.0), c + egui::vec2(-60.0, 60.0));
    assert_eq!(h.state().pieces.seam_sides.len(), 1);
    drag(h, c + egui::vec2(60.0, -60.0), c + egui::vec2(60.0, 60.0));
    let sent = commands(h);
    assert_eq!(sent.len(), n + 1, "one seam");
    let s = sent.last().unwrap();
    assert_eq!(s.op, op::SEAM_PLANE);
    // Side a runs down the view (pattern y falls), left of side b; the tolerance is metres.
    assert!(s.uv[1] > s.uv[3] && s.uv[0] < s.uv[4], "{:?}", s.uv);
    assert!(s.value > 0.0 && s.value <= 0.05, "{}", s.value);
    assert!(h.state().pieces.seam_sides.is_empty());
}

/// The scene panel's switch for xpbd's guard shows what cloth-sim reports and sends the
/// change; under vbd there is no switch (its contact is never crossed), only a note.
#[test]
fn the_guard_is_switched_from_the_scene_panel() {
    use shared::telemetry::{SimTelemetry, scene_model};
    let mut h = harness();
    let label = "Never cross (guard)";
    assert!(
        h.query_by_label(label).is_none(),
        "nothing heard: no switch"
    );
    let tel = |model, never_crosses| {
        Some(Box::new(SimTelemetry {
            model,
            never_crosses,
            ..Default::default()
        }))
    };
    h.state_mut().store.sim_tel = tel(scene_model::XPBD, 0);
    h.run_steps(2);
    assert!(
        h.query_by_label("Now: pieces of cloth over the cube, xpbd model")
            .is_some()
    );
    press(&mut h, label);
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::SET_GUARD, 1));
    // cloth-sim reports it on: pressed again, it goes off.
    h.state_mut().store.sim_tel = tel(scene_model::XPBD, 1);
    h.run_steps(2);
    press(&mut h, label);
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::SET_GUARD, 0));
    h.state_mut().store.sim_tel = tel(scene_model::VBD, 1);
    h.run_steps(2);
    assert!(h.query_by_label(label).is_none());
    assert!(
        h.query_by_label("Contact: never crossed (the vbd model)")
            .is_some()
    );
}

/// The scene panel's strain-limit switch sends the ratio shown (1.2x unless cloth-sim
/// reports another), and off; under vbd there is none.
#[test]
fn the_strain_limit_is_switched_from_the_scene_panel() {
    use shared::telemetry::{SimTelemetry, scene_model};
    let mut h = harness();
    let label = "Hold stretch under";
    let tel = |model, strain_limit| {
        Some(Box::new(SimTelemetry {
            model,
            strain_limit,
            ..Default::default()
        }))
    };
    h.state_mut().store.sim_tel = tel(scene_model::XPBD, 0.0);
    h.run_steps(2);
    press(&mut h, label);
    let c = *commands(&h).last().unwrap();
    assert_eq!(c.op, op::SET_STRAIN_LIMIT);
    assert!((c.value - 0.2).abs() < 1e-6, "{}", c.value);
    // cloth-sim reports it, then another's 1.35x: the ratio follows, and pressed again
    // the limit goes off.
    h.state_mut().store.sim_tel = tel(scene_model::XPBD, c.value);
    h.run_steps(2);
    h.state_mut().store.sim_tel = tel(scene_model::XPBD, 0.35);
    h.run_steps(2);
    assert!(h.query_by_value("1.35x").is_some(), "the ratio shown");
    // Dragged, the ratio stays where the hand left it (not snapped back to cloth-sim's)
    // and is sent once, when the drag ends.
    let sent = commands(&h).len();
    let at = h.get_by_value("1.35x").rect().center();
    h.hover_at(at);
    h.run_steps(1);
    h.drag_at(at);
    h.run_steps(1);
    for dx in [10.0, 20.0, 30.0] {
        h.hover_at(at + egui::vec2(dx, 0.0));
        h.run_steps(1);
    }
    assert_eq!(commands(&h).len(), sent, "nothing sent while dragging");
    h.drop_at(at + egui::vec2(30.0, 0.0));
    h.run_steps(2);
    let c = *commands(&h).last().unwrap();
    assert_eq!(commands(&h).len(), sent + 1);
    assert!(c.op == op::SET_STRAIN_LIMIT && c.value > 0.4, "{}", c.value);
    let dragged = format!("{:.2}x", 1.0 + c.value);
    assert!(h.query_by_value(&dragged).is_some(), "{dragged} shown");
    press(&mut h, label);
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.value), (op::SET_STRAIN_LIMIT, 0.0));
    h.state_mut().store.sim_tel = tel(scene_model::VBD, 0.0);
    h.run_steps(2);
    assert!(h.query_by_label(label).is_none());
}

/// A new scene can run another cloth model: the chooser starts at the running one, and
/// New scene sends the one chosen.
#[test]
fn a_new_scene_takes_the_model_chosen() {
    use shared::telemetry::{SimTelemetry, scene_model};
    let mut h = harness();
    h.state_mut().store.sim_tel = Some(Box::new(SimTelemetry {
        model: scene_model::XPBD,
        ..Default::default()
    }));
    h.run_steps(2);
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.rgba[0]), (op::RESET, 1 + scene_model::XPBD as u8));
    press(&mut h, "Model");
    press(&mut h, "vbd");
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.rgba[0]), (op::RESET, 1 + scene_model::VBD as u8));
}

/// A new scene can be a pattern's pieces: the path typed in the scene panel's Pattern
/// file field goes with the reset, and with the field empty again a square cloth.
#[test]
fn a_new_scene_can_be_a_pattern() {
    use egui::accesskit::Role;
    let mut h = harness();
    h.get_by_role_and_label(Role::TextInput, "Pattern file")
        .scroll_to_me();
    h.run_steps(20);
    h.get_by_role_and_label(Role::TextInput, "Pattern file")
        .focus();
    h.run_steps(1);
    h.get_by_role_and_label(Role::TextInput, "Pattern file")
        .type_text("patterns/dress.svg");
    h.run_steps(2);
    // The new lab's body is the cube: a pattern there is said to be cut for a person,
    // and one click makes the next scene the mannequin.
    assert_eq!(h.state().scene.body, shared::command::BodyChoice::Cube);
    press(&mut h, "Use the mannequin");
    assert!(
        h.query_by_label("Use the mannequin").is_none(),
        "the note goes once the body is a person"
    );
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.text()), (op::RESET, Some("patterns/dress.svg")));
    assert_eq!(c.b, shared::ui_to_sim::body::MANNEQUIN);
    // A GarmentCode pattern is cut for the human body: said over the mannequin too, and
    // one click makes the next scene that body.
    h.state_mut().scene.pattern = "patterns/shirt_specification.json".into();
    h.run_steps(2);
    press(&mut h, "Use the human body");
    assert!(
        h.query_by_label("Use the human body").is_none(),
        "the note goes once the body is its own"
    );
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!(c.b, shared::ui_to_sim::body::HUMAN);
    h.state_mut().scene.pattern.clear();
    h.run_steps(2);
    press(&mut h, "New scene");
    press(&mut h, "Click again to reset");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.text()), (op::RESET, Some("")));
    assert_eq!(c.a, 64, "the grid again");
    // cloth-sim lists the pattern its design was made from (a lab started with
    // --pattern): the field takes it, so New scene makes the garment again; a path typed
    // since stays until cloth-sim lists another.
    h.state_mut().store.source = "sim-core/assets/dress.svg".into();
    h.run_steps(2);
    assert_eq!(h.state().scene.pattern, "sim-core/assets/dress.svg");
    h.state_mut().scene.pattern = "mine.svg".into();
    h.run_steps(2);
    assert_eq!(h.state().scene.pattern, "mine.svg");
    h.state_mut().store.source.clear();
    h.run_steps(2);
    assert_eq!(h.state().scene.pattern, "");
}

/// Pause and Simulate: the button and Space send SET_SIMULATING, the button and the top
/// bar show the pause at once, and cloth-sim's telemetry decides what they show after.
#[test]
fn the_simulation_is_paused_and_run_again() {
    use shared::telemetry::SimTelemetry;
    let mut h = harness();
    let tel = |paused| {
        Some(Box::new(SimTelemetry {
            paused,
            ..Default::default()
        }))
    };
    h.state_mut().store.sim_tel = tel(0);
    h.run_steps(2);
    assert!(h.query_by_label("paused").is_none());
    press(&mut h, "Pause");
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::SET_SIMULATING, 0));
    // Shown as asked before cloth-sim says so.
    assert!(h.state().paused());
    assert!(h.query_by_label("paused").is_some());
    assert!(h.query_by_label("Simulate").is_some());
    h.state_mut().store.sim_tel = tel(1);
    h.run_steps(2);
    // A pinch while paused is told why nothing moves.
    let centre = view_centre(&h);
    assert!(!drag_up(&mut h, centre).is_empty());
    assert_eq!(h.state().status, ui::app::PAUSED_PINCH);
    // Space runs it again.
    h.key_press(egui::Key::Space);
    h.run_steps(2);
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.mode), (op::SET_SIMULATING, 1));
    assert!(!h.state().paused());
    h.state_mut().store.sim_tel = tel(0);
    h.run_steps(2);
    assert!(h.query_by_label("paused").is_none());
    assert!(h.query_by_label("Pause").is_some());
}

/// Scissors started beside the cloth, as scissors start beside the fabric to cut across
/// it: the pen goes down at the cloth's border (not a mouse step inside it, where the cut
/// would leave the border whole) and follows the stroke over the cloth; a stroke that
/// never meets the cloth is said to, and sends nothing.
#[test]
fn a_cut_stroke_begun_beside_the_cloth_starts_at_its_border() {
    let mut h = harness();
    h.get_by_label("Cut  (C)").click();
    h.run_steps(2);
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    // The demo cloth's left border (x = -0.5) on the screen, through its middle.
    let edge = h
        .state()
        .camera
        .to_screen(glam::Vec3::new(-0.5, 0.4, 0.0), size)
        .unwrap();
    let at = |dx: f32| rect.min + egui::vec2(edge.x + dx, edge.y);
    assert!(
        at(-60.0).x > rect.min.x + 5.0,
        "the view shows beside the cloth"
    );
    let before = h.state().emitted.len();
    h.hover_at(at(-60.0));
    h.run_steps(1);
    h.drag_at(at(-60.0));
    h.run_steps(1);
    // Mouse steps of 25 px: the first over the cloth lands 15 px inside its border.
    for k in 1..=6 {
        h.hover_at(at(-60.0 + 25.0 * k as f32));
        h.run_steps(1);
    }
    h.drop_at(at(90.0));
    h.run_steps(2);
    let pen = pen_since(&h, before);
    assert!(pen.len() >= 4, "{pen:?}");
    assert_eq!(pen[0].1, 1, "{pen:?}");
    assert_eq!(pen.last().unwrap().1, 0, "{pen:?}");
    let first = glam::Vec3::from(pen[0].0);
    assert!(
        (-0.504..-0.4995).contains(&first.x) && (first.y - 0.4).abs() < 1e-3,
        "the pen goes down just beside the border (x = -0.5): {first}"
    );
    assert!(pen[1].0[0] > -0.49, "then over the cloth: {pen:?}");

    // A stroke beside the cloth all along sends nothing.
    let before = h.state().emitted.len();
    let corner = rect.min + egui::vec2(5.0, 5.0);
    h.hover_at(corner);
    h.run_steps(1);
    h.drag_at(corner);
    h.run_steps(1);
    h.hover_at(corner + egui::vec2(0.0, 30.0));
    h.run_steps(1);
    h.drop_at(corner + egui::vec2(0.0, 40.0));
    h.run_steps(2);
    assert!(
        (h.state().emitted[before..].iter()).all(|e| !matches!(e, Emitted::Pointer(..))),
        "nothing sent"
    );
    h.get_by_label("Cut: the stroke never crossed the cloth");
}

/// A pinch whose first frame finds the mouse already off the cloth (a press and a long
/// mouse step in one frame, as the software renderer at 2 fps under load sees them) grabs
/// where the button went down; the studio said "nothing under the mouse to grab".
#[test]
fn a_pinch_grabs_where_the_button_went_down() {
    let mut h = harness();
    h.get_by_label("Pinch  (P)").click();
    h.run_steps(2);
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    let middle = h
        .state()
        .camera
        .to_screen(glam::Vec3::new(0.0, 0.4, 0.0), size)
        .unwrap();
    let middle = rect.min + egui::vec2(middle.x, middle.y);
    let corner = rect.min + egui::vec2(5.0, 5.0);
    let before = h.state().emitted.len();
    h.hover_at(middle);
    h.run_steps(1);
    h.drag_at(middle);
    h.hover_at(corner);
    h.run_steps(1);
    h.drop_at(corner);
    h.run_steps(2);
    let pen = pen_since(&h, before);
    assert!(!pen.is_empty(), "nothing grabbed");
    let first = glam::Vec3::from(pen[0].0);
    assert_eq!(pen[0].1, 1, "{pen:?}");
    assert!(
        first.distance(glam::Vec3::new(0.0, 0.4, 0.0)) < 0.02,
        "grabbed at {first}, not where the button went down"
    );
    assert_eq!(pen.last().unwrap().1, 0, "{pen:?}");
}

/// With Dart ticked in the open pattern view, a drag on the cloth in the 3D view from a
/// point out past the cloth's edge takes in a dart there, as a designer does on the form:
/// its line drawn meanwhile to the cloth's edge, then one DART_PLANE from the point's
/// place in the pattern, its line running on past where the drag left the cloth. A drag begun beside the cloth sends nothing and says why.
#[test]
fn a_dart_is_taken_in_by_a_drag_on_the_cloth_in_3d() {
    let mut h = harness();
    h.state_mut().pieces.pattern_open = true;
    h.state_mut().pieces.darting = true;
    h.run_steps(2);
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    let screen = |h: &Harness<'_, App>, p: glam::Vec3| {
        let s = h.state().camera.to_screen(p, size).unwrap();
        rect.min + egui::vec2(s.x, s.y)
    };
    // The demo cloth lies level at 0.4 m, 1 m square; its pattern place is (x + 0.5,
    // -(z + 0.5)). From its middle out past its edge at z = 0.5.
    let (a, b) = (
        screen(&h, glam::Vec3::new(0.0, 0.4, 0.0)),
        screen(&h, glam::Vec3::new(0.0, 0.4, 0.75)),
    );
    let n = commands(&h).len();
    h.hover_at(a);
    h.run_steps(1);
    h.drag_at(a);
    h.run_steps(1);
    for k in 1..=12 {
        h.hover_at(a + (b - a) * (k as f32 / 12.0));
        h.run_steps(1);
    }
    // Meanwhile the view draws the dart's line from its point to the cloth's edge.
    let d = h.state().view.dart.expect("a dart being dragged");
    let (start, now) = (glam::Vec3::from(d.start), glam::Vec3::from(d.now));
    assert!(
        start.distance(glam::Vec3::new(0.0, 0.4, 0.0)) < 0.02,
        "{start}"
    );
    assert!(now.z > 0.45 && now.x.abs() < 0.03, "{now}");
    h.drop_at(b);
    h.run_steps(2);
    let sent = commands(&h);
    assert_eq!(sent.len(), n + 1, "one dart");
    let c = sent.last().unwrap();
    assert_eq!(c.op, op::DART_PLANE);
    assert!((c.value - 0.04).abs() < 1e-6, "{}", c.value);
    let (point, toward) = ([c.uv[0], c.uv[1]], [c.uv[2], c.uv[3]]);
    assert!(
        (point[0] - 0.5).abs() < 0.02 && (point[1] + 0.5).abs() < 0.02,
        "{point:?}"
    );
    assert!(
        (toward[0] - 0.5).abs() < 0.05 && toward[1] < -1.0,
        "past the edge: {toward:?}"
    );
    assert!(pen_since(&h, 0).is_empty(), "the pen was not moved");
    // Begun beside the cloth: nothing sent, and said.
    let beside = screen(&h, glam::Vec3::new(0.0, 0.4, 0.9));
    drag(&mut h, beside, b + egui::vec2(0.0, 20.0));
    assert_eq!(commands(&h).len(), n + 1);
    assert!(
        h.state().status.contains("start the drag on the cloth"),
        "{}",
        h.state().status
    );
}

/// What the pen's button did (a cut stroke drawn with the mouse, say) reaches the status
/// line with the tool state, done or refused; the answer a newly started studio finds is
/// not news, and is not shown.
#[test]
fn the_pens_answers_reach_the_status_line() {
    use shared::domain::ScratchDomain;
    use shared::sim_to_ui::{ToolState, put_text};
    use shared::{Header, services};

    let domain = ScratchDomain::new(&format!("kt-pen-said-{}", std::process::id())).unwrap();
    let node = services::node(&domain, "test-sim").unwrap();
    let publisher = ports::publisher(&node, services::tool_state).unwrap();
    let mut h = connected_harness(&domain);
    let mut seq = 0;
    let mut state = |said: u32, ok: bool, m: &str| {
        let mut s = ToolState {
            header: Header::next(&mut seq),
            tool: tool::CUT,
            sew_first: u32::MAX,
            pen_said: said,
            pen_ok: u32::from(ok),
            ..ToolState::default()
        };
        s.pen_message_len = put_text(&mut s.pen_message, m);
        s
    };
    let shown = |h: &mut Harness<'_, App>, s: ToolState, text: &str| {
        for _ in 0..200 {
            publisher.send_copy(s).unwrap();
            h.run_steps(1);
            if h.query_all_by_label_contains(text).next().is_some() {
                return true;
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        false
    };
    // The first state carries an old answer: the studio takes the tool, not the news.
    let old = state(4, true, "Cut: 3 vertices split along the pen's stroke");
    for _ in 0..200 {
        publisher.send_copy(old).unwrap();
        h.run_steps(1);
        if h.state().store.tool.is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(h.state().store.tool.map(|t| t.pen_said), Some(4));
    assert!(
        !h.state().status.contains("3 vertices"),
        "{}",
        h.state().status
    );
    let done = state(5, true, "Cut: 40 vertices split along the pen's stroke");
    assert!(shown(&mut h, done, "Cut: 40 vertices split"));
    let refused = state(
        6,
        false,
        "cut stroke by the pen: the stroke missed the cloth",
    );
    assert!(shown(
        &mut h,
        refused,
        "Refused: cut stroke by the pen: the stroke"
    ));
    drop(h);
    drop(publisher);
    drop(node);
}

/// The texture lands on the cloth where cloth-sim paints it: its row `(1 - v) * height`
/// (the OBJ export's convention, and the brush's) is drawn where the cloth's `v` is. The
/// view drew it mirrored: a stroke across the dress's chest showed near its hem.
#[test]
fn paint_shows_where_it_was_painted() {
    let mut h = harness();
    // The demo cloth's v runs with z (v = z + 0.5): the texture's top half is v > 0.5,
    // the cloth's z > 0.
    {
        let t = &mut h.state_mut().store.texture;
        let (w, ht) = (t.width, t.height);
        let red = [200u8, 20, 20, 255].repeat(w * ht / 2);
        t.apply(w, ht, [0, 0, w, ht / 2], &red);
    }
    h.run_steps(2);
    let img = h.render().unwrap();
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    let colour = |z: f32| {
        let s = (h.state().camera)
            .to_screen(glam::Vec3::new(0.0, 0.4, z), size)
            .unwrap();
        let p = img
            .get_pixel((rect.min.x + s.x) as u32, (rect.min.y + s.y) as u32)
            .0;
        (p[0], p[1])
    };
    let (painted, plain) = (colour(0.25), colour(-0.25));
    assert!(
        painted.0 > 100 && painted.1 < 80,
        "z = 0.25 is painted: {painted:?}"
    );
    assert!(plain.1 > 100, "z = -0.25 is unpainted: {plain:?}");
}

/// The selection follows its piece when the list changes under it: a part given a
/// fabric of its own becomes a piece of its own at the end of cloth-sim's list, and
/// stays selected there; a piece renamed in place stays selected where it is.
#[test]
fn the_selection_follows_its_piece_when_the_list_changes() {
    use shared::sim_to_ui::ListedPiece;
    let listed = |names: &[&str]| -> Vec<ListedPiece> {
        (names.iter())
            .map(|&n| ListedPiece {
                name: n.into(),
                fabric: "cotton".into(),
                vertices: 100,
                triangles: 180,
                anchor: None,
            })
            .collect()
    };
    let mut h = harness();
    h.state_mut().store.pieces = listed(&["front", "front 2", "back"]);
    h.state_mut().store.pieces_total = 3;
    h.run_steps(1);
    press(&mut h, "front 2 · 100 vertices · cotton");
    assert_eq!(h.state().pieces.selected, Some(1));
    h.state_mut().store.pieces = listed(&["front", "back", "front 2"]);
    h.run_steps(2);
    assert_eq!(h.state().pieces.selected, Some(2));
    h.state_mut().store.pieces = listed(&["front", "back", "skirt"]);
    h.run_steps(2);
    assert_eq!(h.state().pieces.selected, Some(2));
    h.state_mut().store.pieces = listed(&["front"]);
    h.run_steps(2);
    assert_eq!(h.state().pieces.selected, None);
}

/// Pins cloth-sim lists are drawn in the 3D view (pink heads over the cloth, none
/// without pins), counted in the tools panel, and Free pins frees them all.
#[test]
fn pins_are_drawn_counted_and_freed() {
    let pink = |h: &mut Harness<'_, App>| {
        h.run_steps(2);
        let img = h.render().unwrap();
        let rect = h.state().view.rect.unwrap();
        let (x0, y0) = (rect.min.x as u32, rect.min.y as u32);
        (x0..rect.max.x as u32 - 1)
            .flat_map(|x| (y0..rect.max.y as u32 - 1).map(move |y| (x, y)))
            .filter(|&(x, y)| {
                let [r, g, b, _] = img.get_pixel(x, y).0.map(u32::from);
                // Pink: red and blue well over green (the cloth and body are grey).
                r > 150 && b > 90 && g + 50 < r && g + 20 < b
            })
            .count()
    };
    let mut h = harness();
    assert_eq!(pink(&mut h), 0, "no pins, no pin heads");
    h.get_by_label("No pins");
    // The demo cloth's middle vertex and one near a corner.
    let middle = (SIDE * SIDE / 2) as u32;
    h.state_mut().store.pins = vec![SIDE as u32 + 1, middle];
    h.state_mut().store.pins_total = 2;
    let heads = pink(&mut h);
    assert!(heads > 20, "{heads} pink pixels for two pin heads");
    h.get_by_label("2 pins hold the cloth");
    // A shift-click on the middle pin's head (over the cloth, not on the vertex the
    // cloth there is) frees that pin.
    press(&mut h, "Pin  (N)");
    let rect = h.state().view.rect.unwrap();
    let size = glam::Vec2::new(rect.width(), rect.height());
    let head = {
        let s = h.state();
        let (_, head, _) = ui::view3d::pin_head(&s.store, middle, s.camera.eye()).unwrap();
        s.camera.to_screen(head, size).unwrap()
    };
    h.event(egui::Event::ModifiersChanged(egui::Modifiers::SHIFT));
    click(&mut h, rect.min + egui::vec2(head.x, head.y));
    h.event(egui::Event::ModifiersChanged(egui::Modifiers::NONE));
    h.run_steps(1);
    let c = *commands(&h).last().unwrap();
    assert_eq!((c.op, c.a, c.mode), (op::PIN, middle, 0), "{c:?}");
    // A pin of a vertex the positions do not have is not drawn (nor a panic).
    h.state_mut().store.pins = vec![u32::MAX];
    assert_eq!(pink(&mut h), 0);
    press(&mut h, "Free pins");
    assert_eq!(commands(&h).last().unwrap().op, op::FREE_PINS);
}
