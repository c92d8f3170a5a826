//! `cloth-sim run`'s command service, in process over real iceoryx2: operations from a
//! client are carried out and answered; refused and malformed ones are answered with the
//! reason and change nothing.

#![allow(clippy::unwrap_used)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use shared::domain::Domain;
use shared::services;
use shared::ui_to_sim::{CommandReply, ToolCommand, op};
use shared::{Checked, Header};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_simulation};
use sim_core::service::{ServiceConfig, run};

static STOP: AtomicBool = AtomicBool::new(false);

#[test]
fn commands_are_carried_out_and_answered() {
    let d = Domain::new(&format!("svc{}", std::process::id())).unwrap();
    let mut cfg = ServiceConfig::new(d.clone());
    cfg.autosave = std::env::temp_dir().join(format!("saiho-svc-{}.saiho", std::process::id()));
    cfg.seconds = Some(30.0);
    let handle = std::thread::spawn(move || {
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 8;
        let sim = build_simulation(&scene).unwrap();
        run(sim, &cfg, &STOP, &mut |_| {}).unwrap()
    });
    let node = services::node(&d, "ui").unwrap();
    let client = services::commands(&node)
        .unwrap()
        .client_builder()
        .create()
        .unwrap();
    let mut seq = 0;
    let mut ask = |mut c: ToolCommand| -> CommandReply {
        c.header = Header::next(&mut seq);
        let deadline = Instant::now() + Duration::from_secs(10);
        let pending = loop {
            // The server may not be up yet: retry until the request is delivered.
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
    };
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
    let r = ask(ToolCommand {
        op: op::UNDO,
        ..Default::default()
    });
    assert!(r.ok == 1 && r.message() == "undid cut" && r.undo_depth == 0);
    let path = std::env::temp_dir().join(format!("saiho-svc-save-{}.saiho", std::process::id()));
    let mut save = ToolCommand {
        op: op::SAVE,
        ..Default::default()
    };
    assert!(save.set_text(path.to_str().unwrap()));
    let r = ask(save);
    assert_eq!(r.ok, 1, "{}", r.message());
    assert!(sim_core::cloth::Simulation::load_design_file(&path).is_ok());
    // The tool lives in cloth-sim: set it, and a (late) viewer sees it.
    let r = ask(ToolCommand {
        op: op::SET_TOOL,
        a: shared::sim_to_ui::tool::PAINT,
        rgba: [1, 2, 3, 255],
        value: 0.02,
        ..Default::default()
    });
    assert_eq!(r.ok, 1, "{}", r.message());
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
    let states = services::tool_state(&node)
        .unwrap()
        .subscriber_builder()
        .create()
        .unwrap();
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
    let frames = services::cloth_frame(&node)
        .unwrap()
        .subscriber_builder()
        .create()
        .unwrap();
    let pen = services::device(&node)
        .unwrap()
        .publisher_builder()
        .create()
        .unwrap();
    let depth_before = state.undo_depth;
    let mut pen_seq = 0;
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut pressed = false;
    loop {
        assert!(Instant::now() < deadline, "the pen's press did not pin");
        if let Some(f) = frames.receive().unwrap() {
            // Follow vertex 0 of the (falling) cloth with the tip; press, then release.
            let p = f.payload();
            let sample = shared::haptic_to_sim::DeviceSample {
                header: Header::next(&mut pen_seq),
                position: [p[0], p[1], p[2]],
                buttons: u32::from(!pressed),
                device_ok: 1,
                ..Default::default()
            };
            pen.send_copy(sample).unwrap();
            pressed = true;
        }
        if let Some(s) = states.receive().unwrap()
            && s.undo_depth > depth_before
        {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
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
    let tiles = services::texture(&node)
        .unwrap()
        .subscriber_builder()
        .create()
        .unwrap();
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
    let meshes = services::cloth_mesh(&node)
        .unwrap()
        .subscriber_builder()
        .create()
        .unwrap();
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
    let tel = services::sim_telemetry(&node)
        .unwrap()
        .subscriber_builder()
        .create()
        .unwrap();
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
    STOP.store(true, Ordering::Relaxed);
    let stats = handle.join().unwrap();
    assert_eq!(stats.commands, 10);
    assert_eq!(stats.rejected, 3);
    let _ = std::fs::remove_file(&path);
}
