//! The pen's model through a slow frame, in process over real iceoryx2: a frame that takes
//! longer than `MID_FRAME_MODEL` sends the touch planes between its substeps (the haptic
//! loop lets the force fade once its model is 20 ms old), built from the cloth as the
//! substeps left it and the pen's newest sample.

#![allow(clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use cloth_sim::{ServiceConfig, run};
use shared::domain::ScratchDomain;
use shared::haptic_to_sim::DeviceSample;
use shared::{Checked, Header, ports, services};
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

static STOP: AtomicBool = AtomicBool::new(false);

#[test]
fn a_slow_frame_keeps_the_pens_touch_fresh_between_its_substeps() {
    let d = ScratchDomain::new(&format!("touch{}", std::process::id())).unwrap();
    let autosave = std::env::temp_dir().join(format!("saiho-touch-{}.saiho", std::process::id()));
    let mut cfg = ServiceConfig::new(d.0.clone());
    cfg.autosave = autosave.clone();
    cfg.seconds = Some(60.0);
    let handle = std::thread::spawn(move || {
        // The cloth landing on the cube under the guard: its frames search once a
        // substep, tens of ms each in release, more in a debug build.
        let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
        scene.grid = 48;
        let sim = build_design(&scene).unwrap();
        run(sim, &cfg, &STOP, &mut |m| eprintln!("cloth-sim: {m}")).unwrap()
    });
    let node = services::node(&d, "haptic").unwrap();
    let models = ports::subscriber(&node, services::local_model, None).unwrap();
    let pen = ports::publisher(&node, services::device).unwrap();
    // The pen rests 1 cm over the middle of the cube's top (0.4 m), button up.
    let tip = [0.0, 0.41, 0.0];
    let mut seq = 0;
    let mut per_frame: BTreeMap<u64, Vec<[f32; 4]>> = BTreeMap::new();
    let deadline = Instant::now() + Duration::from_secs(45);
    while per_frame.len() < 40 {
        assert!(Instant::now() < deadline, "cloth-sim sent too few models");
        pen.send_copy(DeviceSample {
            header: Header::next(&mut seq),
            position: tip,
            device_ok: 1,
            ..Default::default()
        })
        .unwrap();
        while let Some(m) = models.receive().unwrap() {
            let m = *m;
            m.check().unwrap();
            assert_eq!(m.pinching, 0);
            let planes = &m.planes[..m.plane_count as usize];
            // The cube's top is the body's plane under the tip, once cloth-sim has the
            // pen's sample; every model of the frame carries it.
            if let Some(first) = planes.first().filter(|p| p[1] > 0.99 && p[3] > 0.3) {
                per_frame.entry(m.frame).or_default().push(*first);
            }
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    STOP.store(true, Ordering::Relaxed);
    let stats = handle.join().unwrap();
    for (frame, tops) in &per_frame {
        for p in tops {
            assert!((p[3] - 0.4).abs() < 1e-3, "frame {frame}: top at {}", p[3]);
        }
    }
    // Before and after each frame, and between the substeps of the slow ones.
    let most = per_frame.values().map(Vec::len).max().unwrap();
    assert!(
        stats.mid_frame_models > 0 && most > 2,
        "{} models sent mid-frame, at most {most} in a frame",
        stats.mid_frame_models
    );
    for f in ["saiho", "previous.saiho"] {
        let _ = std::fs::remove_file(autosave.with_extension(f));
    }
}
