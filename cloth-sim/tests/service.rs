//! `cloth-sim run`'s command service, in process over real iceoryx2: operations from a
//! client are carried out and answered; refused and malformed ones are answered with the
//! reason and change nothing.

#![allow(clippy::unwrap_used)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use cloth_sim::{ServiceConfig, run};
use shared::domain::ScratchDomain;
use shared::ports;
use shared::services;
use shared::telemetry::SimTelemetry;
use shared::ui_to_sim::{CommandReply, ToolCommand, op};
use shared::{Checked, Header};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

static STOP: AtomicBool = AtomicBool::new(false);

type Ask<'a> = &'a mut dyn FnMut(ToolCommand) -> CommandReply;
type Node = iceoryx2::prelude::Node<iceoryx2::prelude::ipc::Service>;

#[test]
fn commands_are_carried_out_and_answered() {
    let d = ScratchDomain::new(&format!("svc{}", std::process::id())).unwrap();
    let mut cfg = ServiceConfig::new(d.0.clone());
    cfg.autosave = std::env::temp_dir().join(format!("saiho-svc-{}.saiho", std::process::id()));
    // Only an edit saves within the test's time.
    cfg.autosave_every_s = 600.0;
    let _ = std::fs::remove_file(&cfg.autosave);
    let autosave = cfg.autosave.clone();
    // A backstop: the test stops cloth-sim itself. It takes 12 s here; a slow machine
    // running its telemetry waits (1 Hz) must not find cloth-sim gone.
    cfg.seconds = Some(60.0);
    let handle = std::thread::spawn(move || {
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 8;
        let sim = build_design(&scene).unwrap();
        run(sim, &cfg, &STOP, &mut |_| {}).unwrap()
    });
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let path = std::env::temp_dir().join(format!("saiho-svc-save-{}.saiho", std::process::id()));
    let extra = edits_refusals_and_save(&mut ask, &path, &autosave);
    exports_carry_their_seam_allowance(&mut ask);
    let (states, frames, _pen) = tool_state_and_the_pens_pin(&node, &mut ask);
    let meshes = paint_reaches_a_late_viewer(&node, &mut ask, &frames);
    reset_and_load(&mut ask, &meshes, &path);
    material_in_place(&node, &mut ask);
    guard_in_place(&node, &mut ask);
    new_scenes(&node, &mut ask);
    drop(states);
    STOP.store(true, Ordering::Relaxed);
    let stats = handle.join().unwrap();
    assert_eq!(stats.commands, 52 + extra);
    assert_eq!(stats.rejected, 11);
    let _ = std::fs::remove_file(&path);
    // The autosave, its previous good version, and the design the load replaced.
    let replaced = autosave.with_extension("before-reset.saiho");
    for f in [autosave.clone(), cloth_sim::backup_of(&autosave), replaced] {
        let _ = std::fs::remove_file(f);
    }
}

/// The autosave holds a design of `vertices` within a second of the edit that made it
/// (the periodic autosave is 10 minutes away).
fn the_edit_is_autosaved_at_once(autosave: &std::path::Path, vertices: usize) {
    let until = std::time::Instant::now() + std::time::Duration::from_secs(1);
    loop {
        let n = sim_core::design::Design::load_design_file(autosave).map(|d| d.sim.cloth.len());
        if n.as_ref().is_ok_and(|&n| n == vertices) {
            return;
        }
        assert!(
            std::time::Instant::now() < until,
            "not saved within 1 s: {n:?}"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Export writes the sewing pattern with the allowance asked for (0: cut on the sewing
/// line, no separate sewing line drawn); one outside 0-100 mm, or not a number, is
/// refused before anything is written.
fn exports_carry_their_seam_allowance(ask: Ask<'_>) {
    let dir = std::env::temp_dir().join(format!("saiho-svc-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let export = |allowance_mm: f32| {
        let c = shared::command::Command::Export {
            dir: dir.display().to_string(),
            allowance_mm,
        };
        c.to_wire(Header::default()).unwrap()
    };
    // Not a number is a malformed command; out of range, a refused export.
    for (bad, why) in [
        (f32::NAN, "not finite"),
        (-1.0, "seam allowance"),
        (200.0, "0-100 mm"),
    ] {
        let r = ask(export(bad));
        assert_eq!(r.ok, 0, "{bad}: {}", r.message());
        assert!(r.message().contains(why), "{}", r.message());
        assert!(!dir.exists(), "a refused export wrote {}", dir.display());
    }
    for (mm, sewing_line) in [(0.0, false), (15.0, true)] {
        let r = ask(export(mm));
        assert_eq!(r.ok, 1, "{}", r.message());
        let svg = std::fs::read_to_string(dir.join("pattern.svg")).unwrap();
        assert_eq!(svg.contains("class=\"sew\""), sewing_line, "{mm} mm");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A cut, refusals (sewing a vertex to itself, malformed requests), undo, a dart, and a
/// save; returns how many commands it sent beyond the 52 the test counts on (a dart
/// pressed back to its first leg, where the tailor's rule had pressed it to its second).
fn edits_refusals_and_save(
    ask: Ask<'_>,
    path: &std::path::Path,
    autosave: &std::path::Path,
) -> u64 {
    let centre = (4 * 9 + 4) as u32;
    let r = ask(ToolCommand {
        op: op::CUT_VERTEX,
        a: centre,
        vec: [1.0, 0.0, 0.0],
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(r.message().contains("new vertex 81"), "{}", r.message());
    assert_eq!(r.undo_depth, 1);
    the_edit_is_autosaved_at_once(autosave, 82);
    // Refused: sewing a vertex to itself. The reason comes back; nothing changes.
    let r = ask(ToolCommand {
        op: op::SEW,
        a: 0,
        b: 0,
        ..Default::default()
    });
    assert_eq!(r.ok, 0);
    assert!(r.message().contains("itself"), "{}", r.message());
    assert_eq!(r.undo_depth, 1);
    // Malformed: an unknown operation, a NaN vector.
    let r = ask(ToolCommand {
        op: 99,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("unknown operation 99"),
        "{}",
        r.message()
    );
    let r = ask(ToolCommand {
        op: op::PAINT,
        vec: [f32::NAN, 0.0, 0.0],
        value: 0.02,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("not finite"),
        "{}",
        r.message()
    );
    let r = ask(undo());
    assert!(r.ok == 1 && r.message() == "Undone: cut" && r.undo_depth == 0);
    // Scissors in the pattern plane: a line across the whole square cuts it in two.
    let across = shared::command::Command::CutPlane {
        from: [-0.7, 0.06],
        to: [0.7, 0.06],
    };
    let r = ask(across.to_wire(Header::default()).unwrap());
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(
        r.message().ends_with("the cloth is 2 pieces now"),
        "{}",
        r.message()
    );
    let r = ask(undo());
    assert!(r.ok == 1 && r.message() == "Undone: cut line" && r.undo_depth == 0);
    let extra = dart_pressed_and_undone(ask);
    let r = ask(simulating(1));
    assert_eq!(r.ok, 1, "{}", r.message());
    let mut save = ToolCommand {
        op: op::SAVE,
        ..Default::default()
    };
    assert!(save.set_text(path.to_str().unwrap()));
    let r = ask(save);
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(sim_core::design::Design::load_design_file(path).is_ok());
    extra
}

/// A dart in the pattern plane, pressed toward its other leg, both undone; a dart off the
/// cloth refused. Returns the commands sent beyond those counted on (see
/// `edits_refusals_and_save`). Leaves the cloth paused.
fn dart_pressed_and_undone(ask: Ask<'_>) -> u64 {
    // A dart in the pattern plane: one step, undone as one; off the cloth, refused. Paused
    // meanwhile: on the running cloth the dart's stitches can close and weld (each weld
    // an undo step of its own) between one command and the next, on a busy machine.
    let r = ask(simulating(0));
    assert!(
        r.ok == 1 && r.message().starts_with("Paused"),
        "{}",
        r.message()
    );
    let dart = |point: [f32; 2]| shared::command::Command::DartPlane {
        point,
        toward: [0.0, -0.9],
        width_m: 0.06,
    };
    let r = ask(dart([0.0, 0.0]).to_wire(Header::default()).unwrap());
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(
        r.message().starts_with("Dart: 60 mm wide") && r.undo_depth == 1,
        "{}",
        r.message()
    );
    // Pressed toward its other leg, one more step; a seam that is not there, refused. The
    // tailor's rule may have pressed the new dart toward its second leg already (it reads
    // where the cloth lies when the dart is taken), and pressing it so again is no step.
    let press = |seam: u32, second| shared::command::Command::PressDart { seam, second };
    let mut r = ask(press(0, true).to_wire(Header::default()).unwrap());
    let (mut leg, mut extra) = ("second", 0);
    if r.ok == 1 && r.undo_depth == 1 {
        r = ask(press(0, false).to_wire(Header::default()).unwrap());
        (leg, extra) = ("first", 1);
    }
    assert!(
        r.ok == 1
            && r.message()
                .contains(&format!("pressed toward its {leg} leg"))
            && r.undo_depth == 2,
        "{} (ok {}, undo depth {})",
        r.message(),
        r.ok,
        r.undo_depth
    );
    let r = ask(press(5, true).to_wire(Header::default()).unwrap());
    assert!(
        r.ok == 0 && r.message().contains("there is no seam 5") && r.undo_depth == 2,
        "{}",
        r.message()
    );
    let r = ask(undo());
    assert!(r.ok == 1 && r.message() == "Undone: press dart" && r.undo_depth == 1);
    let r = ask(undo());
    assert!(r.ok == 1 && r.message() == "Undone: dart" && r.undo_depth == 0);
    let r = ask(dart([3.0, 3.0]).to_wire(Header::default()).unwrap());
    assert!(
        r.ok == 0 && r.message().contains("no cloth under the dart's point") && r.undo_depth == 0,
        "{}",
        r.message()
    );
    extra
}

/// The tool lives in cloth-sim: set it, and a (late) viewer sees it; with PIN, the pen's
/// press pins the vertex under the tip. Returns the tool-state and frame subscribers and
/// the pen, for what follows.
fn tool_state_and_the_pens_pin(
    node: &Node,
    ask: Ask<'_>,
) -> (
    services::Sub<shared::sim_to_ui::ToolState>,
    services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
    services::Pub<shared::haptic_to_sim::DeviceSample>,
) {
    let r = ask(ToolCommand {
        op: op::SET_TOOL,
        a: shared::sim_to_ui::tool::PAINT,
        rgba: [1, 2, 3, 255],
        value: 0.02,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    // Said in words, not as a tool number.
    assert!(
        r.message().starts_with("Paint tool: ") && !r.message().contains("tool 4"),
        "{}",
        r.message()
    );
    let r = ask(ToolCommand {
        op: op::SET_TOOL,
        a: 42,
        value: 0.02,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("tool 42"),
        "{}",
        r.message()
    );
    let states = ports::subscriber(node, services::tool_state, None).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    let state = loop {
        if let Some(s) = states.receive().unwrap() {
            break *s;
        }
        assert!(Instant::now() < deadline, "no tool state");
        std::thread::sleep(Duration::from_millis(5));
    };
    assert_eq!(
        (state.tool, state.rgba, state.brush_m),
        (shared::sim_to_ui::tool::PAINT, [1, 2, 3, 255], 0.02)
    );
    // The pen's button acts with the current tool: with PIN, a press pins the vertex
    // under the tip (one more undoable operation).
    let r = ask(ToolCommand {
        op: op::SET_TOOL,
        a: shared::sim_to_ui::tool::PIN,
        value: 0.02,
        ..Default::default()
    });
    assert_eq!(r.ok, 1);
    let frames = ports::subscriber(node, services::cloth_frame, None).unwrap();
    let pen = ports::publisher(node, services::device).unwrap();
    let depth_before = state.undo_depth;
    let mut pen_seq = 0;
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut pressed = false;
    let mut at = [0.0; 3];
    loop {
        assert!(Instant::now() < deadline, "the pen's press did not pin");
        if let Some(f) = frames.receive().unwrap() {
            // Follow vertex 0 of the (falling) cloth with the tip; press, release, and
            // press again until a press pins: on a loaded machine the frame the tip
            // follows can be old enough that the cloth has fallen out of reach (a single
            // press then missed and the test timed out).
            let p = f.payload();
            at = [p[0], p[1], p[2]];
            let sample = shared::haptic_to_sim::DeviceSample {
                header: Header::next(&mut pen_seq),
                position: at,
                buttons: u32::from(!pressed),
                device_ok: 1,
                ..Default::default()
            };
            pen.send_copy(sample).unwrap();
            pressed = !pressed;
        }
        if let Some(s) = states.receive().unwrap()
            && s.undo_depth > depth_before
        {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    // The button up, whatever the last sample said.
    let up = shared::haptic_to_sim::DeviceSample {
        header: Header::next(&mut pen_seq),
        position: at,
        device_ok: 1,
        ..Default::default()
    };
    pen.send_copy(up).unwrap();
    (states, frames, pen)
}

/// Paint where vertex 0 is now; a texture viewer that starts afterwards rebuilds the whole
/// texture, paint included, from the tiles; a late viewer gets the mesh and the timing.
/// Returns the mesh subscriber.
fn paint_reaches_a_late_viewer(
    node: &Node,
    ask: Ask<'_>,
    frames: &services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
) -> services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader> {
    // Paint where vertex 0 is now; a texture viewer that starts afterwards rebuilds the
    // whole texture, paint included, from the tiles (changed ones, then round-robin).
    let at = loop {
        if let Some(f) = frames.receive().unwrap() {
            let p = f.payload();
            break [p[0], p[1], p[2]];
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let r = ask(ToolCommand {
        op: op::PAINT,
        vec: at,
        value: 0.05,
        rgba: [9, 200, 9, 255],
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    let tiles = ports::subscriber(node, services::texture, None).unwrap();
    let mut tex = vec![0u8; 4 * 1024 * 1024];
    let mut seen = std::collections::HashSet::new();
    let deadline = Instant::now() + Duration::from_secs(10);
    while seen.len() < 256 {
        assert!(
            Instant::now() < deadline,
            "only {} of 256 tiles",
            seen.len()
        );
        while let Some(t) = tiles.receive().unwrap() {
            let h = t.user_header();
            shared::sim_to_ui::check_tile(h, t.payload()).unwrap();
            for r in 0..h.h as usize {
                let dst = 4 * ((h.y0 as usize + r) * 1024 + h.x0 as usize);
                let src = 4 * r * h.w as usize;
                tex[dst..dst + 4 * h.w as usize]
                    .copy_from_slice(&t.payload()[src..src + 4 * h.w as usize]);
            }
            seen.insert((h.x0, h.y0));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let green = tex
        .chunks_exact(4)
        .filter(|p| p[1] > 150 && p[0] < 100)
        .count();
    assert!(green > 100, "{green} painted texels arrived");
    // A viewer that starts now still gets the mesh (sent once, kept as history).
    let meshes = ports::subscriber(node, services::cloth_mesh, None).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        if let Some(m) = meshes.receive().unwrap() {
            shared::sim_to_ui::check_mesh(m.user_header(), m.payload()).unwrap();
            assert_eq!(m.user_header().triangles, 2 * 8 * 8);
            break;
        }
        assert!(Instant::now() < deadline, "a late viewer got no mesh");
        std::thread::sleep(Duration::from_millis(5));
    }
    // Its timing, once a second.
    let tel = ports::subscriber(node, services::sim_telemetry, None).unwrap();
    let deadline = Instant::now() + Duration::from_secs(5);
    let t = loop {
        if let Some(t) = tel.receive().unwrap() {
            break *t;
        }
        assert!(Instant::now() < deadline, "no sim telemetry");
        std::thread::sleep(Duration::from_millis(10));
    };
    t.check().unwrap();
    // 81 vertices: the cut's extra vertex went with its undo.
    assert!(
        t.frame_time.total > 10 && t.rate_hz > 1.0 && t.vertices == 81,
        "frames {} rate {} vertices {}",
        t.frame_time.total,
        t.rate_hz,
        t.vertices
    );
    meshes
}

/// A new scene replaces the design (saved first); a bad reset or a missing file is
/// refused; loading the saved design brings the 8x8 cloth back.
fn reset_and_load(
    ask: Ask<'_>,
    meshes: &services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
    path: &std::path::Path,
) {
    // A new scene over the sphere with a 6-cell grid replaces the design (saved first)...
    let mut reset = ToolCommand {
        op: op::RESET,
        a: 6,
        b: shared::ui_to_sim::body::SPHERE,
        ..Default::default()
    };
    reset.uv[0] = 0.2;
    let r = ask(reset);
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(
        r.message().contains("6x6") && r.message().contains("sphere"),
        "{}",
        r.message()
    );
    let backup = std::env::temp_dir().join(format!(
        "saiho-svc-{}.before-reset.saiho",
        std::process::id()
    ));
    assert!(
        sim_core::design::Design::load_design_file(&backup).is_ok(),
        "the replaced design was not saved first"
    );
    let _ = std::fs::remove_file(&backup);
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        if let Some(m) = meshes.receive().unwrap()
            && m.user_header().triangles == 2 * 6 * 6
        {
            break;
        }
        assert!(Instant::now() < deadline, "no mesh of the new scene");
        std::thread::sleep(Duration::from_millis(5));
    }
    // ... a bad reset or a missing file is refused, and loading the saved design brings the
    // 8x8 cloth back.
    let r = ask(ToolCommand {
        op: op::RESET,
        b: 7,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("unknown body 7"),
        "{}",
        r.message()
    );
    let mut load = ToolCommand {
        op: op::LOAD,
        ..Default::default()
    };
    assert!(load.set_text("/nonexistent/saiho/design.saiho"));
    let r = ask(load);
    assert_eq!(r.ok, 0, "{}", r.message());
    assert!(load.set_text(path.to_str().unwrap()));
    let r = ask(load);
    assert_eq!(r.ok, 1, "{}", r.message());
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        if let Some(m) = meshes.receive().unwrap()
            && m.user_header().triangles == 2 * 8 * 8
        {
            break;
        }
        assert!(Instant::now() < deadline, "no mesh of the loaded design");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The material and substeps change in place; the telemetry says so within its second.
/// Bad substeps are refused.
fn material_in_place(node: &Node, ask: Ask<'_>) {
    // The material and substeps change in place; the telemetry says so within its
    // second. Bad substeps are refused.
    let telemetry = ports::subscriber(node, services::sim_telemetry, None).unwrap();
    let mut soft = ToolCommand {
        op: op::SET_MATERIAL,
        a: 7,
        ..Default::default()
    };
    soft.uv[1] = 500.0;
    let r = ask(soft);
    assert!(
        r.ok == 1 && r.message().contains("stretch 500 N/m") && r.message().contains("7 substeps"),
        "{}",
        r.message()
    );
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        if let Some(t) = telemetry.receive().unwrap()
            && t.substeps == 7
        {
            assert_eq!(t.material[1], 500.0);
            assert_eq!(t.material[0], 0.15, "density kept");
            break;
        }
        assert!(
            Instant::now() < deadline,
            "no telemetry of the new material"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let r = ask(ToolCommand {
        op: op::SET_MATERIAL,
        a: 500,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("substeps 500"),
        "{}",
        r.message()
    );
}

/// xpbd's guard goes on in place and the telemetry says so; a new scene keeps it; it
/// goes off again, and a new scene keeps it off. Likewise the strain limit, which a
/// material change does not undo and an out-of-range value or the vbd model refuses.
fn guard_in_place(node: &Node, ask: Ask<'_>) {
    let telemetry = ports::subscriber(node, services::sim_telemetry, None).unwrap();
    let wait_for =
        |what: &str, want: &dyn Fn(&SimTelemetry) -> bool| await_telemetry(&telemetry, what, want);
    // The loaded design kept its guard (the file has it), through the material change
    // above too: until 2026-11-29 that change dropped it, and the cloth crossed the cube.
    let r = ask(guard(1));
    assert!(
        r.ok == 1 && r.message().contains("The guard is on already"),
        "{}",
        r.message()
    );
    assert_eq!(ask(guard(0)).ok, 1);
    wait_for("the guard off", &|t| t.never_crosses == 0);
    let r = ask(guard(1));
    assert!(
        r.ok == 1 && r.message().starts_with("The guard is on"),
        "{}",
        r.message()
    );
    use shared::telemetry::scene_model;
    wait_for("the guard on", &|t| {
        t.model == scene_model::XPBD && t.never_crosses == 1
    });
    // The default material holds 1.2x; another ratio shows the limit is set.
    let r = ask(limit(0.3));
    assert!(
        r.ok == 1 && r.message().contains("1.30x"),
        "{}",
        r.message()
    );
    wait_for("the strain limit", &|t| t.strain_limit == 0.3);
    for bad in [0.001, 20.0, -0.2, f32::NAN] {
        let r = ask(limit(bad));
        let m = r.message();
        assert!(
            r.ok == 0 && (m.contains("strain limit") || m.contains("not finite")),
            "{m}"
        );
    }
    // A material change (here the damping) keeps the limit and the guard.
    let mut damp = ToolCommand {
        op: op::SET_MATERIAL,
        ..Default::default()
    };
    damp.uv[5] = 0.8;
    assert_eq!(ask(damp).ok, 1);
    wait_for("the damping, the limit and the guard kept", &|t| {
        t.material[5] == 0.8 && t.strain_limit == 0.3 && t.never_crosses == 1
    });
    let r = ask(ToolCommand {
        op: op::RESET,
        a: 6,
        b: shared::ui_to_sim::body::CUBE,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    wait_for("a new scene with the guard and the limit", &|t| {
        t.grid == 6 && t.never_crosses == 1 && t.strain_limit == 0.3
    });
    assert_eq!(ask(limit(0.0)).ok, 1);
    wait_for("the limit off", &|t| t.strain_limit == 0.0);
    assert_eq!(ask(guard(0)).ok, 1);
    wait_for("the guard off", &|t| t.never_crosses == 0);
    // A new scene keeps it as the designer left it: off (a new design has it on).
    let r = ask(ToolCommand {
        op: op::RESET,
        a: 7,
        b: shared::ui_to_sim::body::CUBE,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    wait_for("a new scene still without the guard", &|t| {
        t.grid == 7 && t.model == scene_model::XPBD && t.never_crosses == 0
    });
}

/// New scenes after [`guard_in_place`] (the guard and the limit off): a pattern's pieces,
/// then another model.
fn new_scenes(node: &Node, ask: Ask<'_>) {
    use shared::telemetry::scene_model;
    let telemetry = ports::subscriber(node, services::sim_telemetry, None).unwrap();
    let wait_for =
        |what: &str, want: &dyn Fn(&SimTelemetry) -> bool| await_telemetry(&telemetry, what, want);
    // A new scene of a pattern's pieces round the mannequin, sewn (protocol 11); with
    // the limit off the reply says what closes the seams.
    // Paused first (protocol 18): the new scene waits where it is placed.
    let r = ask(simulating(0));
    assert!(
        r.ok == 1 && r.message().starts_with("Paused:"),
        "{}",
        r.message()
    );
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    let mut pattern = ToolCommand {
        op: op::RESET,
        b: shared::ui_to_sim::body::MANNEQUIN,
        ..Default::default()
    };
    assert!(pattern.set_text(dress));
    let r = ask(pattern);
    let m = r.message();
    assert!(
        r.ok == 1
            && m.starts_with("Paused (simulate to drape it). New design")
            && m.contains("2 pieces of")
            && m.contains("4 seams stitched"),
        "{m}"
    );
    wait_for("the dress, paused", &|t| {
        t.grid == 0 && t.body == shared::telemetry::scene_body::MANNEQUIN && t.paused == 1
    });
    // The piece list names the pattern the design was made from (protocol 18).
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(node, services::pieces, None).unwrap();
    let source = |want: &str| wait_for_source(&lists, want);
    source(dress);
    paused_then_run(&telemetry, ask);
    // A new scene under another model.
    let mut vbd = ToolCommand {
        op: op::RESET,
        a: 6,
        b: shared::ui_to_sim::body::CUBE,
        ..Default::default()
    };
    vbd.rgba[0] = 1 + scene_model::VBD as u8;
    let r = ask(vbd);
    assert!(
        r.ok == 1 && r.message().contains("(vbd model)"),
        "{}",
        r.message()
    );
    wait_for("the vbd scene", &|t| {
        t.model == scene_model::VBD && t.never_crosses == 1
    });
    source("");
    // Under vbd there is no guard to switch off, and no strain limit.
    let r = ask(guard(0));
    assert!(r.ok == 0 && r.message().contains("vbd"), "{}", r.message());
    let r = ask(limit(0.2));
    assert!(r.ok == 0 && r.message().contains("vbd"), "{}", r.message());
}

/// While paused no frame is stepped (the telemetry's frame stays), a second pause is
/// said to be one, a bad mode is refused; run again, the dress's fresh seams float it
/// while they pull, and the frames go on.
fn paused_then_run(telemetry: &services::Sub<SimTelemetry>, ask: Ask<'_>) {
    let newest = || {
        let mut last = None;
        while let Some(t) = telemetry.receive().unwrap() {
            last = Some(*t);
        }
        last
    };
    // The frame of the next telemetry (a second after the one that said paused).
    let deadline = Instant::now() + Duration::from_secs(5);
    let frame = loop {
        if let Some(t) = newest() {
            break t.frame;
        }
        assert!(Instant::now() < deadline, "no telemetry while paused");
        std::thread::sleep(Duration::from_millis(20));
    };
    std::thread::sleep(Duration::from_millis(2200));
    let later = newest().expect("telemetry while paused");
    assert_eq!((later.paused, later.frame), (1, frame));
    let r = ask(simulating(0));
    assert!(
        r.ok == 1 && r.message().contains("Paused already"),
        "{}",
        r.message()
    );
    let r = ask(simulating(2));
    assert!(
        r.ok == 0 && r.message().contains("simulating 2"),
        "{}",
        r.message()
    );
    let r = ask(simulating(1));
    assert!(
        r.ok == 1
            && r.message()
                .contains("the new seams pull their pieces together"),
        "{}",
        r.message()
    );
    await_telemetry(telemetry, "running again", &|t| {
        t.paused == 0 && t.frame > frame
    });
}

/// UNDO.
fn undo() -> ToolCommand {
    ToolCommand {
        op: op::UNDO,
        ..Default::default()
    }
}

/// REDO.
fn redo() -> ToolCommand {
    ToolCommand {
        op: op::REDO,
        ..Default::default()
    }
}

/// SET_SIMULATING: 1 runs, 0 pauses.
fn simulating(mode: u32) -> ToolCommand {
    ToolCommand {
        op: op::SET_SIMULATING,
        mode,
        ..Default::default()
    }
}

/// SET_GUARD: `on` 1 or 0.
fn guard(on: u32) -> ToolCommand {
    ToolCommand {
        op: op::SET_GUARD,
        mode: on,
        ..Default::default()
    }
}

/// SET_STRAIN_LIMIT to `value` (0: none).
fn limit(value: f32) -> ToolCommand {
    ToolCommand {
        op: op::SET_STRAIN_LIMIT,
        value,
        ..Default::default()
    }
}

/// Waits up to 5 s for sim telemetry that `want`s.
fn await_telemetry(
    telemetry: &services::Sub<SimTelemetry>,
    what: &str,
    want: &dyn Fn(&SimTelemetry) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        if let Some(t) = telemetry.receive().unwrap()
            && want(&t)
        {
            return;
        }
        assert!(Instant::now() < deadline, "no telemetry of {what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A client of the command service that waits for the reply to each request (the server
/// may not be up yet: it retries until the request is delivered).
fn asker(
    client: iceoryx2::port::client::Client<
        iceoryx2::prelude::ipc::Service,
        ToolCommand,
        (),
        CommandReply,
        (),
    >,
) -> impl FnMut(ToolCommand) -> CommandReply {
    let mut seq = 0;
    move |mut c: ToolCommand| {
        c.header = Header::next(&mut seq);
        let deadline = Instant::now() + Duration::from_secs(10);
        let pending = loop {
            match client.send_copy(c) {
                Ok(p) if p.number_of_server_connections() > 0 => break p,
                _ if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
                _ => panic!("no server"),
            }
        };
        loop {
            if let Some(r) = pending.receive().unwrap() {
                r.check().unwrap();
                assert_eq!(r.request_seq, c.header.seq);
                return *r;
            }
            assert!(Instant::now() < deadline, "no reply");
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

/// cloth-sim's outputs and the pen, for the pen test.
struct PenRig {
    frames: services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
    meshes: services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
    states: services::Sub<shared::sim_to_ui::ToolState>,
    pen: services::Pub<shared::haptic_to_sim::DeviceSample>,
    pen_seq: u64,
}

/// The pen test's cloth: 17 x 17 vertices; vertex (row, column).
const PEN_N: usize = 17;

fn at(r: usize, c: usize) -> usize {
    r * PEN_N + c
}

impl PenRig {
    fn open(node: &Node) -> Self {
        Self {
            frames: ports::subscriber(node, services::cloth_frame, None).unwrap(),
            meshes: ports::subscriber(node, services::cloth_mesh, None).unwrap(),
            states: ports::subscriber(node, services::tool_state, None).unwrap(),
            pen: ports::publisher(node, services::device).unwrap(),
            pen_seq: 0,
        }
    }

    fn send(&mut self, p: [f32; 3], down: bool) {
        self.pen
            .send_copy(shared::haptic_to_sim::DeviceSample {
                header: Header::next(&mut self.pen_seq),
                position: p,
                buttons: u32::from(down),
                device_ok: 1,
                ..Default::default()
            })
            .unwrap();
    }

    /// The next cloth frame published: its header and positions.
    fn next_frame(&self) -> (shared::sim_to_ui::ClothFrameHeader, Vec<[f32; 3]>) {
        let deadline = Instant::now() + Duration::from_secs(10);
        while self.frames.receive().unwrap().is_some() {}
        loop {
            if let Some(f) = self.frames.receive().unwrap() {
                let h = *f.user_header();
                let x = f.payload()[..3 * h.vertices as usize]
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect();
                return (h, x);
            }
            assert!(Instant::now() < deadline, "no cloth frame");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    fn tool_state(&self) -> shared::sim_to_ui::ToolState {
        let mut last = None;
        let deadline = Instant::now() + Duration::from_secs(5);
        while last.is_none() || Instant::now() < deadline.min(Instant::now()) {
            while let Some(s) = self.states.receive().unwrap() {
                last = Some(*s);
            }
            if last.is_none() {
                assert!(Instant::now() < deadline, "no tool state");
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        last.unwrap()
    }
}

fn use_tool(ask: Ask<'_>, t: u32) {
    let r = ask(ToolCommand {
        op: op::SET_TOOL,
        a: t,
        rgba: [20, 40, 220, 255],
        value: 0.03,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
}

/// The pen's button with each tool, in one running cloth-sim: paint, cut along a stroke,
/// tear by pulling, two-press sew; the pinch follows the pen substep by substep.
#[test]
fn the_pens_button_acts_with_every_tool() {
    static STOP_TOOLS: AtomicBool = AtomicBool::new(false);
    let d = ScratchDomain::new(&format!("pen{}", std::process::id())).unwrap();
    let mut cfg = ServiceConfig::new(d.0.clone());
    cfg.autosave = std::env::temp_dir().join(format!("saiho-pen-{}.saiho", std::process::id()));
    cfg.seconds = Some(60.0);
    cfg.pinch_stiffness = 2000.0;
    let handle = std::thread::spawn(move || {
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 16;
        let sim = build_design(&scene).unwrap();
        run(sim, &cfg, &STOP_TOOLS, &mut |m| eprintln!("cloth-sim: {m}")).unwrap()
    });
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let mut rig = PenRig::open(&node);
    // Let the cloth land on the cube first.
    for _ in 0..60 {
        rig.next_frame();
    }
    paint_by_pen(&mut rig, &mut ask);
    tear_by_pen(&mut rig, &mut ask);
    cut_by_pen(&mut rig, &mut ask);
    sew_by_pen(&mut rig, &mut ask);
    STOP_TOOLS.store(true, Ordering::Relaxed);
    let stats = handle.join().unwrap();
    // The tear's pinch read the pen every substep, unlimited (no haptic loop).
    assert!(stats.pen_substeps >= 5, "{} substeps", stats.pen_substeps);
    assert_eq!(stats.coupled_substeps, 0, "no haptic loop: no limit");
    assert_eq!(stats.rejected, 0);
    // The autosave and the previous good one it keeps beside it.
    for f in ["saiho", "previous.saiho"] {
        let name = format!("saiho-pen-{}.{f}", std::process::id());
        let _ = std::fs::remove_file(std::env::temp_dir().join(name));
    }
}

fn paint_by_pen(rig: &mut PenRig, ask: Ask<'_>) {
    // Paint: a press on the cloth changes the texture.
    use_tool(ask, shared::sim_to_ui::tool::PAINT);
    let (h0, x) = rig.next_frame();
    rig.send(x[at(8, 8)], true);
    rig.next_frame();
    rig.next_frame();
    rig.send(x[at(8, 8)], false);
    let (h1, _) = rig.next_frame();
    assert!(
        h1.texture_version > h0.texture_version,
        "paint by pen: texture version {} -> {}",
        h0.texture_version,
        h1.texture_version
    );
}

/// Tearing at 2x rest length (set, then off until the tool turns it on): grab a corner
/// and pull it far away; edges tear (triangles are deleted).
fn tear_by_pen(rig: &mut PenRig, ask: Ask<'_>) {
    // Tearing at 2x rest length (set, then off until the tool turns it on).
    for mode in [1, 0] {
        let r = ask(ToolCommand {
            op: op::SET_TEAR,
            mode,
            value: 2.0,
            ..Default::default()
        });
        assert_eq!(r.ok, 1, "{}", r.message());
    }
    use_tool(ask, shared::sim_to_ui::tool::TEAR);
    // The mesh as it is now.
    let mut triangles = None;
    while let Some(m) = rig.meshes.receive().unwrap() {
        triangles = Some(m.user_header().triangles);
    }
    let triangles = triangles.expect("the current mesh");
    let (_, x) = rig.next_frame();
    let start = x[at(16, 16)];
    let mut torn = false;
    for k in 0..90 {
        let t = (k as f32 / 30.0).min(1.0);
        rig.send(
            [start[0] + 0.8 * t, start[1] - 0.2 * t, start[2] + 0.8 * t],
            true,
        );
        rig.next_frame();
        while let Some(m) = rig.meshes.receive().unwrap() {
            torn |= m.user_header().triangles < triangles;
        }
        if torn {
            break;
        }
    }
    rig.send(start, false);
    rig.next_frame();
    assert!(
        torn,
        "tear by pen: no triangle was torn off ({triangles} before)"
    );
}

fn cut_by_pen(rig: &mut PenRig, ask: Ask<'_>) {
    // Cut: hold and draw across row 8 from column 2 to 14; the cut happens on release.
    use_tool(ask, shared::sim_to_ui::tool::CUT);
    let (h0, x) = rig.next_frame();
    for c in 2..=14 {
        rig.send(x[at(8, c)], true);
        rig.next_frame();
    }
    rig.send(x[at(8, 14)], false);
    rig.next_frame();
    let (h1, _) = rig.next_frame();
    assert!(
        h1.vertices > h0.vertices && h1.topology != h0.topology,
        "cut by pen: {} -> {} vertices",
        h0.vertices,
        h1.vertices
    );
    // The studio is told what the stroke did (the tool state carries the pen's answer),
    // and why a stroke far from the cloth did nothing.
    let said =
        |s: &shared::sim_to_ui::ToolState| shared::sim_to_ui::check_tool_state(s).unwrap().unwrap();
    let s = rig.tool_state();
    let (ok, m) = said(&s);
    assert!(ok && m.starts_with("Cut: ") && m.contains("split"), "{m}");
    let far = [5.0, 5.0, 5.0];
    for _ in 0..3 {
        rig.send(far, true);
        rig.next_frame();
    }
    rig.send(far, false);
    rig.next_frame();
    rig.next_frame();
    let s2 = rig.tool_state();
    let (ok, m) = said(&s2);
    assert!(s2.pen_said > s.pen_said && !ok, "{m}");
    assert!(m.starts_with("cut stroke by the pen: "), "{m}");
}

fn sew_by_pen(rig: &mut PenRig, ask: Ask<'_>) {
    // Sew: press on a corner, then on the border vertex two along (a tuck).
    use_tool(ask, shared::sim_to_ui::tool::SEW);
    let depth = rig.tool_state().undo_depth;
    let (_, x) = rig.next_frame();
    rig.send(x[at(0, 0)], true);
    rig.next_frame();
    rig.send(x[at(0, 0)], false);
    rig.next_frame();
    let s = rig.tool_state();
    assert_eq!(
        s.sew_first,
        at(0, 0) as u32,
        "the first press picks a vertex"
    );
    let (_, x) = rig.next_frame();
    rig.send(x[at(0, 2)], true);
    rig.next_frame();
    rig.send(x[at(0, 2)], false);
    rig.next_frame();
    let s = rig.tool_state();
    assert!(
        s.sew_first == u32::MAX && s.undo_depth == depth + 1,
        "sew by pen: first {} depth {} -> {}",
        s.sew_first,
        depth,
        s.undo_depth
    );
}

/// With a haptic loop rendering the pinch, the cloth is pulled with the force the hand
/// was pulled back with (the reaction), not harder; the pen is read every substep.
#[test]
fn the_pinch_pulls_the_cloth_no_harder_than_the_rendered_force() {
    use shared::haptic_to_sim::{AppliedForce, DeviceSample};
    static STOP_PULL: AtomicBool = AtomicBool::new(false);
    let d = ScratchDomain::new(&format!("pull{}", std::process::id())).unwrap();
    let mut cfg = ServiceConfig::new(d.0.clone());
    cfg.autosave = std::env::temp_dir().join(format!("saiho-pull-{}.saiho", std::process::id()));
    cfg.seconds = Some(30.0);
    let handle = std::thread::spawn(move || {
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 8;
        let sim = build_design(&scene).unwrap();
        run(sim, &cfg, &STOP_PULL, &mut |_| {}).unwrap()
    });
    let node = services::node(&d, "haptic").unwrap();
    let frames = ports::subscriber(&node, services::cloth_frame, None).unwrap();
    let pen = ports::publisher(&node, services::device).unwrap();
    let applied = ports::publisher(&node, services::applied_force).unwrap();
    let (mut s1, mut s2) = (0, 0);
    let mut start = None;
    let mut pulled = 0;
    let deadline = Instant::now() + Duration::from_secs(20);
    // 40 frames of the corner pulled 0.5 m up while the "hand" feels 0.2 N.
    while pulled < 40 {
        assert!(Instant::now() < deadline, "the service stopped answering");
        let Some(f) = frames.receive().unwrap() else {
            // Between frames, the haptic loop's 1 kHz stream.
            if let Some(p) = start {
                let p: [f32; 3] = p;
                // The press lands where the corner is; then the pen rises.
                let lift = if pulled == 0 { 0.0 } else { 0.5 };
                pen.send_copy(DeviceSample {
                    header: Header::next(&mut s1),
                    position: [p[0], p[1] + lift, p[2]],
                    buttons: 1,
                    device_ok: 1,
                    ..Default::default()
                })
                .unwrap();
                applied
                    .send_copy(AppliedForce {
                        header: Header::next(&mut s2),
                        force: [0.0, -0.2, 0.0],
                        model_frame: 1,
                        ..Default::default()
                    })
                    .unwrap();
            }
            std::thread::sleep(Duration::from_millis(1));
            continue;
        };
        let p = f.payload();
        if start.is_none() && f.user_header().frame > 30 {
            start = Some([p[0], p[1], p[2]]);
            pen.send_copy(DeviceSample {
                header: Header::next(&mut s1),
                position: [p[0], p[1], p[2]],
                buttons: 1,
                device_ok: 1,
                ..Default::default()
            })
            .unwrap();
        } else if start.is_some() {
            pulled += 1;
        }
    }
    STOP_PULL.store(true, Ordering::Relaxed);
    let stats = handle.join().unwrap();
    assert_eq!(stats.pinches, 1);
    assert!(
        stats.coupled_substeps >= 5 * 30
            && stats.pen_substeps >= stats.coupled_substeps
            && stats.force_limited_substeps >= 5 * 20,
        "coupled {}, at the limit {}, of {} substeps",
        stats.coupled_substeps,
        stats.force_limited_substeps,
        stats.pen_substeps
    );
    // 0.5 m at 100 N/m would be 50 N; the limit is 0.2 N x 1.1 + 0.05 N.
    let limit = 0.2 * 1.1 + 0.05;
    assert!(
        stats.pinch_force_max_n > 0.5 * limit && stats.pinch_force_max_n <= limit + 1e-3,
        "largest pull {} N",
        stats.pinch_force_max_n
    );
    let _ = std::fs::remove_file(
        std::env::temp_dir().join(format!("saiho-pull-{}.saiho", std::process::id())),
    );
}

/// Pieces over the protocol: a rectangle added at the front is listed on `saiho/pieces`,
/// placed at the back, deleted; a pattern file adds all its pieces with their seams; a
/// piece that is not there is refused with the count.
#[test]
fn pieces_are_added_placed_listed_and_deleted_over_the_protocol() {
    use shared::ui_to_sim::{place, shape};
    let (d, stop) = dress_service("svcp");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    // The newest list with `n` pieces, waiting for it (kept: paused, it may be the last).
    let last = std::cell::RefCell::new(None);
    let names = |n: usize| -> Vec<String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            while let Some(l) = lists.receive().unwrap() {
                let p = shared::sim_to_ui::check_pieces(&l).unwrap();
                if p.len() == n {
                    *last.borrow_mut() = Some(*l);
                    return p.into_iter().map(|p| p.name).collect();
                }
            }
            assert!(Instant::now() < deadline, "no list of {n} pieces");
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    assert_eq!(names(2), ["front", "back"]);
    let telemetry = ports::subscriber(&node, services::sim_telemetry, None).unwrap();
    await_telemetry(&telemetry, "the dress running", &|t| t.paused == 0);
    // Added while the cloth runs, the piece pauses it (it would fall before it could be
    // sewn), and the answer says so first.
    let r = ask(ToolCommand {
        op: op::ADD_PIECE,
        mode: shape::RECTANGLE,
        a: place::FRONT,
        vec: [0.25, 0.2, 0.0],
        value: 0.05,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(
        r.message()
            .starts_with("Paused (simulate to drape it). Added rectangle at the front"),
        "{}",
        r.message()
    );
    await_telemetry(&telemetry, "the pause for the new piece", &|t| {
        t.paused == 1
    });
    assert_eq!(names(3), ["front", "back", "rectangle"]);
    moves_and_copies_pause_a_running_cloth(&mut ask, &names);
    let r = ask(ToolCommand {
        op: op::DELETE_PIECE,
        a: 9,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && r.message().contains("there is no piece 9"),
        "{}",
        r.message()
    );
    let r = ask(ToolCommand {
        op: op::DELETE_PIECE,
        a: 2,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    assert_eq!(names(2), ["front", "back"]);
    // The shipped dress pattern: two more pieces, sewn to each other.
    let mut file = ToolCommand {
        op: op::ADD_PIECE,
        mode: shape::FILE,
        a: place::FRONT,
        value: 0.08,
        ..Default::default()
    };
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    assert!(file.set_text(dress));
    let r = ask(file);
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(r.message().contains("4 seams stitched"), "{}", r.message());
    // The strain limit is on (the default material's): no tip (with it off, the reply
    // says what closes the seams: `new_scenes`).
    assert!(!r.message().contains("tip:"), "{}", r.message());
    assert_eq!(names(4).len(), 4);
    // Its seams are listed; the second is removed and the list says so.
    let seams = |n: usize| -> Vec<String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut kept = last.borrow_mut().take();
        loop {
            while let Some(l) = kept.take().or_else(|| lists.receive().unwrap().map(|l| *l)) {
                let s = shared::sim_to_ui::check_seams(&l).unwrap();
                if s.len() == n {
                    return s.iter().map(|s| s.label().to_string()).collect();
                }
            }
            assert!(Instant::now() < deadline, "no list of {n} seams");
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    assert_eq!(seams(4), ["A", "B", "C", "D"]);
    let r = ask(ToolCommand {
        op: op::REMOVE_SEAM,
        a: 1,
        ..Default::default()
    });
    assert!(
        r.ok == 1 && r.message().contains("Removed seam B"),
        "{}",
        r.message()
    );
    assert_eq!(seams(3), ["A", "B", "C"]);
    stop.finish();
}

/// After a rectangle (piece 2) was added, which paused the cloth: a move while paused
/// says nothing of a pause; running again, a refused move leaves it running and a copy
/// pauses it; undo takes the copy away.
fn moves_and_copies_pause_a_running_cloth(ask: Ask<'_>, names: &dyn Fn(usize) -> Vec<String>) {
    use shared::ui_to_sim::place;
    // Paused already, a move says nothing of a pause.
    let r = ask(ToolCommand {
        op: op::PLACE_PIECE,
        a: 2,
        b: place::BACK,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(
        r.message().starts_with("Placed rectangle"),
        "{}",
        r.message()
    );
    // Running again, a refused move does not pause; a copy does.
    let r = ask(simulating(1));
    assert_eq!(r.ok, 1, "{}", r.message());
    let r = ask(ToolCommand {
        op: op::PLACE_PIECE,
        a: 9,
        b: place::BACK,
        ..Default::default()
    });
    assert!(
        r.ok == 0 && !r.message().contains("Paused"),
        "{}",
        r.message()
    );
    // (The copy's answer below starts with the pause: the refused move left it running.)
    let r = ask(ToolCommand {
        op: op::DUPLICATE_PIECE,
        a: 2,
        b: place::FRONT,
        value: 0.05,
        ..Default::default()
    });
    assert!(
        r.ok == 1
            && r.message()
                .starts_with("Paused (simulate to drape it). Copied"),
        "{}",
        r.message()
    );
    assert_eq!(names(4).len(), 4);
    let r = ask(undo());
    assert_eq!(r.ok, 1, "{}", r.message());
    assert_eq!(names(3).len(), 3);
}

/// A piece made of another fabric over the protocol: the list says so at once, an
/// unknown fabric is refused, and undo takes it back.
#[test]
fn a_piece_gets_its_own_fabric_over_the_protocol() {
    let (d, stop) = dress_service("svcf");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    // Waits for a list whose pieces have these fabrics.
    let fabrics = |want: [&str; 2]| {
        let deadline = Instant::now() + Duration::from_secs(10);
        loop {
            while let Some(l) = lists.receive().unwrap() {
                let p = shared::sim_to_ui::check_pieces(&l).unwrap();
                if p.iter().map(|p| p.fabric.as_str()).eq(want) {
                    return;
                }
            }
            assert!(Instant::now() < deadline, "no list with fabrics {want:?}");
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    fabrics(["cotton", "cotton"]);
    let piece_fabric = |name: &str| {
        let mut c = ToolCommand {
            op: op::SET_PIECE_FABRIC,
            a: 1,
            ..Default::default()
        };
        assert!(c.set_text(name));
        c
    };
    let r = ask(piece_fabric("silk-charmeuse"));
    assert!(
        r.ok == 0 && r.message().contains("no fabric named"),
        "{}",
        r.message()
    );
    let r = ask(piece_fabric("jersey-interlock"));
    assert!(
        r.ok == 1 && r.message().contains("back is jersey-interlock"),
        "{}",
        r.message()
    );
    fabrics(["cotton", "jersey-interlock"]);
    let r = ask(undo());
    assert!(
        r.ok == 1 && r.message().contains("piece fabric"),
        "{}",
        r.message()
    );
    fabrics(["cotton", "cotton"]);
    stop.finish();
}

/// Waits for a piece list whose pieces and first seam (if any) are called so; returns
/// the pieces' vertex counts.
fn wait_for_names(
    lists: &services::Sub<shared::sim_to_ui::PieceList>,
    pieces: &[&str],
    seam: Option<&str>,
) -> Vec<u32> {
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut seen = String::new();
    loop {
        while let Some(l) = lists.receive().unwrap() {
            let p = shared::sim_to_ui::check_pieces(&l).unwrap();
            let s = shared::sim_to_ui::check_seams(&l).unwrap();
            seen = format!(
                "{:?} {:?}",
                p.iter().map(|p| &p.name).collect::<Vec<_>>(),
                s.iter().map(|s| s.name()).collect::<Vec<_>>()
            );
            if p.iter().map(|p| p.name.as_str()).eq(pieces.iter().copied())
                && s.first().map(|s| s.name()) == seam
            {
                return p.iter().map(|p| p.vertices).collect();
            }
        }
        assert!(
            Instant::now() < deadline,
            "no list with pieces {pieces:?} and seam A {seam:?}; the last: {seen}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A piece and a seam named over the protocol: the list says so at once (it did not
/// for a seam's name before protocol 21: the list went out again only when its counts
/// or fabrics changed), another piece's name and an empty one are refused, and undo
/// takes a piece's name back; the front cut in two, its lower part is named alone, then
/// given a fabric of its own and listed last as a piece of its own.
#[test]
fn a_piece_and_a_seam_named_over_the_protocol_are_listed_at_once() {
    let (d, stop) = dress_service("svcn");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    let listed = |pieces: &[&str], seam: Option<&str>| {
        wait_for_names(&lists, pieces, seam);
    };
    listed(&["front", "back"], None);
    let named = |op: u32, a: u32, name: &str| {
        let mut c = ToolCommand {
            op,
            a,
            ..Default::default()
        };
        assert!(c.set_text(name));
        c
    };
    let r = ask(named(op::NAME_PIECE, 0, "back"));
    assert!(
        r.ok == 0 && r.message().contains("a piece is called back already"),
        "{}",
        r.message()
    );
    let r = ask(named(op::NAME_PIECE, 0, " "));
    assert!(r.ok == 0 && r.message().contains("name"), "{}", r.message());
    let r = ask(named(op::NAME_PIECE, 0, "bodice front"));
    assert!(
        r.ok == 1 && r.message().contains("front is now called bodice front"),
        "{}",
        r.message()
    );
    listed(&["bodice front", "back"], None);
    let r = ask(undo());
    assert!(
        r.ok == 1 && r.message().contains("name piece"),
        "{}",
        r.message()
    );
    listed(&["front", "back"], None);
    let r = ask(redo());
    assert_eq!(r.ok, 1, "{}", r.message());
    listed(&["bodice front", "back"], None);
    // The front cut across its middle in the pattern (the studio's Cut tool), and its
    // lower part named alone: listed at once (a part's name changes no piece's name),
    // the upper part keeping its own. Paused, as a designer cuts and names, so that the
    // parts do not fall apart before the undo (which would then cross them and refuse).
    let r = ask(simulating(0));
    assert_eq!(r.ok, 1, "{}", r.message());
    let front = dress_front();
    let outline = &front.outline.loops[0];
    let xs = outline.iter().map(|p| p.x + front.offset.x);
    let (left, right) = xs.fold((f32::MAX, f32::MIN), |(a, b), x| (a.min(x), b.max(x)));
    let ys = outline.iter().map(|p| p.y + front.offset.y);
    let (low, high) = ys.fold((f32::MAX, f32::MIN), |(a, b), y| (a.min(y), b.max(y)));
    let y = 0.5 * (low + high);
    let r = ask(ToolCommand {
        op: op::CUT_PLANE,
        uv: [left - 0.02, y, right + 0.02, y, 0.0, 0.0, 0.0, 0.0],
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    listed(&["bodice front", "bodice front 2", "back"], None);
    let r = ask(named(op::NAME_PIECE, 1, "skirt front"));
    assert!(
        r.ok == 1
            && r.message()
                .contains("bodice front 2 is now called skirt front"),
        "{}",
        r.message()
    );
    listed(&["bodice front", "skirt front", "back"], None);
    // Given a fabric of its own, the part becomes a piece of its own, listed last.
    let r = ask(named(op::SET_PIECE_FABRIC, 1, "denim"));
    assert!(
        r.ok == 1 && r.message().contains("skirt front, a piece of its own now"),
        "{}",
        r.message()
    );
    listed(&["bodice front", "back", "skirt front"], None);
    for _ in 0..3 {
        let r = ask(undo());
        assert_eq!(r.ok, 1, "{}", r.message());
    }
    listed(&["bodice front", "back"], None);
    let r = ask(simulating(1));
    assert_eq!(r.ok, 1, "{}", r.message());
    // The shipped dress pattern again: two more pieces and their seams.
    let mut file = ToolCommand {
        op: op::ADD_PIECE,
        mode: shared::ui_to_sim::shape::FILE,
        a: shared::ui_to_sim::place::FRONT,
        value: 0.08,
        ..Default::default()
    };
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    assert!(file.set_text(dress));
    let r = ask(file);
    assert_eq!(r.ok, 1, "{}", r.message());
    let four = ["bodice front", "back", "front", "back (2)"];
    listed(&four, Some(""));
    let r = ask(named(op::NAME_SEAM, 0, "right shoulder"));
    assert_eq!(r.ok, 1, "{}", r.message());
    listed(&four, Some("right shoulder"));
    stop.finish();
}

/// A dart pressed the other way over the protocol (protocol 26): the list goes out again
/// at once with the dart's seam pressed toward its first leg (it was made pressed toward
/// the centre front, its second), though no count, name or mesh changed (the list's key
/// left the press out at first).
#[test]
fn a_dart_pressed_the_other_way_is_listed_at_once() {
    let (d, stop) = dress_service("svcd");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    let front = dress_front();
    let (lo, hi) = sim_core::mesh::bounds2(&front.outline.loops[0]);
    let x = 0.5 * (lo.x + hi.x) + front.offset.x;
    let r = ask(shared::command::Command::DartPlane {
        point: [x, lo.y + front.offset.y + 0.35],
        toward: [x - 0.05, lo.y + front.offset.y - 0.05],
        width_m: 0.1,
    }
    .to_wire(Header::default())
    .unwrap());
    assert_eq!(r.ok, 1, "{}", r.message());
    // The dart's seam is the last (the dress's own are sewn as it starts, or not yet).
    let press_of_last = |want: u32| {
        let deadline = Instant::now() + Duration::from_secs(10);
        let mut seen = Vec::new();
        loop {
            while let Some(l) = lists.receive().unwrap() {
                let s = shared::sim_to_ui::check_seams(&l).unwrap();
                seen = s.iter().map(|s| s.dart).collect();
                if seen.last() == Some(&want) && seen[..seen.len() - 1].iter().all(|&k| k == 0) {
                    return seen.len() as u32 - 1;
                }
            }
            assert!(
                Instant::now() < deadline,
                "no dart pressed {want} last: {seen:?}"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    // A new dart is pressed as a tailor presses it (this one, left of the middle and
    // leaning out, toward the centre front: its second leg here).
    let dart = press_of_last(shared::sim_to_ui::dart::SECOND);
    // Paused, so that nothing but the press changes.
    let r = ask(ToolCommand {
        op: op::SET_SIMULATING,
        mode: 0,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    let press = |seam: u32| {
        shared::command::Command::PressDart {
            seam,
            second: false,
        }
        .to_wire(Header::default())
        .unwrap()
    };
    let r = ask(press(dart));
    assert_eq!(r.ok, 1, "{}", r.message());
    assert_eq!(press_of_last(shared::sim_to_ui::dart::FIRST), dart);
    let r = ask(press(dart + 1));
    assert!(
        r.ok == 0 && r.message().contains("there is no seam"),
        "{}",
        r.message()
    );
    stop.finish();
}

/// A piece copied over the protocol (protocol 22), turned over and lower down: listed at
/// once under a new name, said where it went; a piece that is not there and a drop past
/// the knees are refused with nothing added; undo takes the copy away.
#[test]
fn a_copied_piece_is_listed_at_once_and_undo_takes_it_away() {
    let (d, stop) = dress_service("svcc");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    let two = ["front", "back"];
    wait_for_names(&lists, &two, None);
    let copy = |a: u32, drop: f32| ToolCommand {
        op: op::DUPLICATE_PIECE,
        a,
        b: shared::ui_to_sim::place::BACK,
        mode: 1,
        value: 0.08,
        vec: [0.0, 0.0, drop],
        ..Default::default()
    };
    let r = ask(copy(9, 0.0));
    assert!(
        r.ok == 0 && r.message().contains("there is no piece 9"),
        "{}",
        r.message()
    );
    let r = ask(copy(1, 1.5));
    assert!(
        r.ok == 0 && r.message().contains("1.5 m below"),
        "{}",
        r.message()
    );
    let r = ask(copy(1, 0.1));
    assert!(
        r.ok == 1
            && r.message()
                .contains("Copied back as back (2) at the back, 0.10 m lower"),
        "{}",
        r.message()
    );
    wait_for_names(&lists, &["front", "back", "back (2)"], None);
    let r = ask(undo());
    assert!(
        r.ok == 1 && r.message().contains("copy piece"),
        "{}",
        r.message()
    );
    let front = wait_for_names(&lists, &two, None)[0];
    // The back deleted: the telemetry counts the front's vertices alone (it counted the
    // solver's, a deleted piece's included, before).
    let tel: services::Sub<shared::telemetry::SimTelemetry> =
        ports::subscriber(&node, services::sim_telemetry, None).unwrap();
    let r = ask(ToolCommand {
        op: op::DELETE_PIECE,
        a: 1,
        ..Default::default()
    });
    assert!(
        r.ok == 1 && r.message().contains("Deleted back"),
        "{}",
        r.message()
    );
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut seen = 0;
    while seen != front {
        if let Some(t) = tel.receive().unwrap() {
            seen = t.vertices;
        }
        assert!(
            Instant::now() < deadline,
            "telemetry says {seen} vertices, the front has {front}"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    stop.finish();
}

/// A resumed design names the pattern it was made from (its file keeps it): the piece
/// list says so, so that the studio's New scene drapes the pattern again, and a design
/// saved and loaded again still names it (before, both named none).
#[test]
fn a_resumed_or_loaded_design_names_its_pattern() {
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    let (d, stop) = dress_service_with("svcs", dress);
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let lists: services::Sub<shared::sim_to_ui::PieceList> =
        ports::subscriber(&node, services::pieces, None).unwrap();
    let source = |want: &str| wait_for_source(&lists, want);
    source(dress);
    let file = std::env::temp_dir().join(format!("saiho-src-{}.saiho", std::process::id()));
    let path = |op: u32| {
        let mut c = ToolCommand {
            op,
            ..Default::default()
        };
        assert!(c.set_text(&file.display().to_string()));
        c
    };
    let r = ask(path(op::SAVE));
    assert_eq!(r.ok, 1, "{}", r.message());
    // A square scene names none; the saved dress, loaded, names its pattern again.
    let r = ask(ToolCommand {
        op: op::RESET,
        a: 8,
        b: shared::ui_to_sim::body::CUBE,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
    source("");
    let r = ask(path(op::LOAD));
    assert_eq!(r.ok, 1, "{}", r.message());
    source(dress);
    let _ = std::fs::remove_file(&file);
    stop.finish();
}

/// Waits (10 s at most) for a piece list naming `want` as the design's pattern.
fn wait_for_source(lists: &services::Sub<shared::sim_to_ui::PieceList>, want: &str) {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        if let Some(l) = lists.receive().unwrap()
            && shared::sim_to_ui::check_source(&l).unwrap() == want
        {
            return;
        }
        assert!(Instant::now() < deadline, "no piece list from {want:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// cloth-sim's service on its own thread over the dress (0.08 m triangles), in a scratch
/// domain named for `tag`, for at most a minute.
struct Service {
    stop: std::sync::Arc<AtomicBool>,
    handle: std::thread::JoinHandle<()>,
    /// Its autosave, and the previous good one beside it: removed when it finishes.
    files: [std::path::PathBuf; 2],
}

impl Service {
    fn finish(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.handle.join().unwrap();
        for f in &self.files {
            let _ = std::fs::remove_file(f);
        }
    }
}

/// The front piece of [`dress_service`]'s dress as it is built (in the pattern plane,
/// with its offset), to aim a cut or a dart at.
fn dress_front() -> sim_core::design::PieceRecord {
    dress_pieces().swap_remove(0)
}

/// [`dress_service`]'s pieces as built: the front, the back.
fn dress_pieces() -> Vec<sim_core::design::PieceRecord> {
    let mut scene = ScenarioConfig::new(ScenarioName::DressMannequin);
    scene.piece_edge = 0.08;
    build_design(&scene).unwrap().pieces
}

/// A seam made while the cloth runs floats it while the pairs pull together (a sleeve
/// set into a draped dress closed over the shoulder only so), and the answer says so;
/// one made while paused waits for Simulate to float it, as before.
#[test]
fn a_seam_made_on_a_running_cloth_floats_it_while_it_closes() {
    let (d, stop) = dress_service("svcw");
    let node = services::node(&d, "ui").unwrap();
    let mut ask = asker(ports::command_client(&node).unwrap());
    let telemetry = ports::subscriber(&node, services::sim_telemetry, None).unwrap();
    await_telemetry(&telemetry, "the dress running", &|t| t.paused == 0);
    let p = dress_pieces();
    // Each panel's armhole: its side above the side seam (22 cm of 75), top down.
    let armhole = |k: usize, right: bool| {
        let (lo, hi) = sim_core::mesh::bounds2(&p[k].outline.loops[0]);
        let x = if right { hi.x } else { lo.x } + p[k].offset.x;
        let top = hi.y + p[k].offset.y;
        [[x, top - 0.01], [x, top - 0.21]]
    };
    let seam = |a, b| {
        shared::command::Command::SeamPlane {
            a,
            b,
            tolerance_m: 0.03,
        }
        .to_wire(Header::default())
        .unwrap()
    };
    // Each answer: carried out, and saying `want`.
    let mut says = |c: ToolCommand, want: &str| {
        let r = ask(c);
        assert!(r.ok == 1 && r.message().contains(want), "{}", r.message());
    };
    let simulate = |on: u32| ToolCommand {
        op: op::SET_SIMULATING,
        mode: on,
        ..Default::default()
    };
    says(
        seam(armhole(0, false), armhole(1, true)),
        "they pull together (the cloth afloat, at most 1 s)",
    );
    says(simulate(0), "Paused");
    says(
        seam(armhole(0, true), armhole(1, false)),
        "of border vertices stitched; they pull together and",
    );
    says(simulate(1), "pull their pieces together before they fall");
    stop.finish();
}

fn dress_service(tag: &str) -> (ScratchDomain, Service) {
    dress_service_with(tag, "")
}

/// [`dress_service`] over a dress whose design names `source` as its pattern, as a
/// resumed autosave does.
fn dress_service_with(tag: &str, source: &str) -> (ScratchDomain, Service) {
    let source = source.to_string();
    let pid = std::process::id();
    let d = ScratchDomain::new(&format!("{tag}{pid}")).unwrap();
    let mut cfg = ServiceConfig::new(d.0.clone());
    cfg.autosave = std::env::temp_dir().join(format!("saiho-{tag}-{pid}.saiho"));
    cfg.seconds = Some(60.0);
    let files = [
        cfg.autosave.clone(),
        std::env::temp_dir().join(format!("saiho-{tag}-{pid}.previous.saiho")),
    ];
    let stop = std::sync::Arc::new(AtomicBool::new(false));
    let stop2 = stop.clone();
    let handle = std::thread::spawn(move || {
        let mut scene = ScenarioConfig::new(ScenarioName::DressMannequin);
        scene.piece_edge = 0.08;
        let mut sim = build_design(&scene).unwrap();
        sim.source = source;
        run(sim, &cfg, &stop2, &mut |_| {}).unwrap();
    });
    (
        d,
        Service {
            stop,
            handle,
            files,
        },
    )
}
