//! The real processes in an isolated domain with the simulated pen: the cloth comes to
//! rest over the cube and cloth-sim lets it sleep, still publishing its model; a scripted
//! pinch wakes it, reaches cloth-sim and the haptic loop renders the spring force toward
//! the pinched vertex; kill -9 of cloth-sim takes the force to zero within 10 ms of the model going
//! stale while the loop keeps ticking; a restarted cloth-sim resumes from its autosave.

#![allow(clippy::unwrap_used)]

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use shared::Checked;
use shared::domain::ScratchDomain;
use shared::haptic_to_sim::{AppliedForce, DeviceSample};
use shared::ports;
use shared::services;
use shared::sim_to_haptic::LocalModel;
use shared::telemetry::SimTelemetry;
use tests::{Proc, bin};

fn cloth_sim(domain: &str, autosave: &std::path::Path, fresh: bool) -> Proc {
    let mut c = Command::new(bin("cloth-sim"));
    c.args([
        "run",
        "--domain",
        domain,
        "--grid",
        "16",
        "--seconds",
        "60",
        "--autosave",
    ])
    .arg(autosave)
    .stdout(Stdio::null())
    .stderr(Stdio::piped());
    if fresh {
        c.arg("--fresh");
    }
    Proc(c.spawn().unwrap())
}

#[derive(Default)]
struct Observer {
    forces: Vec<AppliedForce>,
    pinch: Vec<(AppliedForce, LocalModel, DeviceSample)>,
    model: Option<LocalModel>,
    pen: Option<DeviceSample>,
    last_model_ns: u64,
    /// cloth-sim's telemetry as it came: (seconds since the start, asleep, frame).
    sleep: Vec<(f64, u32, u64)>,
}

/// What the test watches: the applied forces, local models and device samples (for the
/// pinch), and the cloth a viewer gets.
struct Watch {
    forces: services::Sub<AppliedForce>,
    models: services::Sub<LocalModel>,
    samples: services::Sub<DeviceSample>,
    telemetry: services::Sub<SimTelemetry>,
    frames: services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
    meshes: services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
}

impl Watch {
    fn open(node: &iceoryx2::prelude::Node<iceoryx2::prelude::ipc::Service>) -> Self {
        Self {
            forces: ports::subscriber(node, services::applied_force, None).unwrap(),
            models: ports::subscriber(node, services::local_model, None).unwrap(),
            samples: ports::subscriber(node, services::device, None).unwrap(),
            telemetry: ports::subscriber(node, services::sim_telemetry, None).unwrap(),
            frames: ports::subscriber(node, services::cloth_frame, None).unwrap(),
            meshes: ports::subscriber(node, services::cloth_mesh, None).unwrap(),
        }
    }

    /// Takes in models, samples and forces until `until` after `t0`.
    fn collect(&self, o: &mut Observer, t0: Instant, until: Duration) {
        while t0.elapsed() < until {
            while let Some(m) = self.models.receive().unwrap() {
                m.check().unwrap();
                o.last_model_ns = m.header.sent_ns;
                o.model = Some(*m);
            }
            while let Some(s) = self.samples.receive().unwrap() {
                o.pen = Some(*s);
            }
            while let Some(t) = self.telemetry.receive().unwrap() {
                t.check().unwrap();
                o.sleep
                    .push((t0.elapsed().as_secs_f64(), t.asleep, t.frame));
            }
            while let Some(f) = self.forces.receive().unwrap() {
                o.forces.push(*f);
                if let (Some(m), Some(p)) = (o.model.as_ref(), o.pen.as_ref())
                    && m.pinching == 1
                {
                    o.pinch.push((*f, *m, *p));
                }
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}

#[test]
fn pinch_force_kill_and_resume() {
    let d = ScratchDomain::new(&format!("e2e{}", std::process::id())).unwrap();
    let tmp = std::env::temp_dir().join(format!("saiho-e2e-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let autosave = tmp.join("design.saiho");
    let script = tmp.join("lift.script");
    // Rest 8 s over the cube (the 16 x 16 cloth comes to rest and sleeps in about
    // 4.5 s), touch the cloth, press, lift 12 cm, hold.
    std::fs::write(
        &script,
        "0 0 0.60 0 0\n8.0 0 0.60 0 0\n9.0 0 0.41 0 0\n9.2 0 0.41 0 1\n10.5 0 0.53 0 1\n60 0 0.53 0 1\n",
    )
    .unwrap();
    let node = services::node(&d, "observer").unwrap();
    let watch = Watch::open(&node);
    let mut sim = cloth_sim(d.name(), &autosave, true);
    let _haptic = Proc(
        Command::new(bin("haptic-loop"))
            .args(["--domain", d.name(), "--seconds", "60", "--script"])
            .arg(&script)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let t0 = Instant::now();
    let mut o = Observer::default();
    watch.collect(&mut o, t0, Duration::from_secs(13));
    it_slept_then_the_pinch_woke_it(&o);
    the_spring_pulls_the_pen_back(&o);
    // kill -9 cloth-sim: the model goes stale; the force is zero 20 ms + 10 ms later.
    // The cloth reaches a viewer: positions and normals every frame, the mesh once.
    the_cloth_reached_a_viewer(&watch);
    let frame_before = o.model.unwrap().frame;
    sim.0.kill().unwrap();
    sim.0.wait().unwrap();
    let from = o.forces.len();
    watch.collect(&mut o, t0, t0.elapsed() + Duration::from_millis(600));
    the_force_is_zero_once_stale(&o, from);
    // Restart: it resumes from the autosave (the frame counter goes on from it).
    let sim2 = cloth_sim(d.name(), &autosave, false);
    it_resumes(&watch, sim2, o.last_model_ns, frame_before);
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Before the pen came down the resting cloth slept, with frames still counted (its model
/// stayed fresh for the haptic loop); once the pinch held it (from 9.2 s; telemetry a
/// second late at most), it was awake.
fn it_slept_then_the_pinch_woke_it(o: &Observer) {
    let before: Vec<_> = o.sleep.iter().filter(|s| s.0 < 8.5).collect();
    let slept = before.iter().filter(|s| s.1 == 1).count();
    assert!(
        slept > 0,
        "never asleep before the pen came down: {:?}",
        o.sleep
    );
    let frames: Vec<u64> = before.iter().map(|s| s.2).collect();
    assert!(
        frames.windows(2).all(|w| w[1] > w[0]),
        "frames stalled: {frames:?}"
    );
    let held: Vec<_> = o.sleep.iter().filter(|s| s.0 > 10.5).collect();
    assert!(
        !held.is_empty() && held.iter().all(|s| s.1 == 0),
        "{:?}",
        o.sleep
    );
}

/// The pinch reached cloth-sim (it reports pinching) and the loop renders a spring that
/// pulls the lifted pen back toward the cloth: force along (vertex - pen).
fn the_spring_pulls_the_pen_back(o: &Observer) {
    assert!(o.pinch.len() > 500, "{} pinched ticks", o.pinch.len());
    let late: Vec<_> = o.pinch.iter().rev().take(300).collect();
    for (f, m, p) in &late {
        let d: Vec<f32> = (0..3)
            .map(|i| m.vertex_position[i] - p.position[i])
            .collect();
        let along = f.force[0] * d[0] + f.force[1] * d[1] + f.force[2] * d[2];
        let mag = (f.force.iter().map(|c| c * c).sum::<f32>()).sqrt();
        assert!(
            along > 0.0 && mag > 0.05 && mag <= 3.3 + 1e-4,
            "{:?} {:?}",
            f.force,
            d
        );
    }
}

fn the_cloth_reached_a_viewer(watch: &Watch) {
    let f = watch.frames.receive().unwrap().expect("a cloth frame");
    shared::sim_to_ui::check_frame(f.user_header(), f.payload()).unwrap();
    assert_eq!(f.user_header().vertices, 17 * 17);
    let m = watch.meshes.receive().unwrap().expect("the cloth mesh");
    shared::sim_to_ui::check_mesh(m.user_header(), m.payload()).unwrap();
    assert_eq!(m.user_header().triangles, 2 * 16 * 16);
    assert_eq!(m.user_header().topology, f.user_header().topology);
}

/// After the last model, the loop kept ticking with zero force (forces from `from` on).
fn the_force_is_zero_once_stale(o: &Observer, from: usize) {
    let after = &o.forces[from..];
    let zero_after = o.last_model_ns + 31_500_000;
    let late: Vec<&AppliedForce> = after
        .iter()
        .filter(|f| f.header.sent_ns > zero_after)
        .collect();
    assert!(
        late.len() > 300,
        "the loop kept ticking: {} samples",
        late.len()
    );
    assert!(late.iter().all(|f| f.force == [0.0; 3]));
    let ticks: Vec<u64> = late.iter().map(|f| f.tick).collect();
    assert!(ticks.windows(2).all(|w| w[1] > w[0]));
}

/// The restarted cloth-sim publishes models again, from a frame near where it was.
fn it_resumes(watch: &Watch, mut sim2: Proc, last_model_ns: u64, frame_before: u64) {
    let deadline = Instant::now() + Duration::from_secs(20);
    let mut resumed_frame = None;
    while Instant::now() < deadline && resumed_frame.is_none() {
        while let Some(m) = watch.models.receive().unwrap() {
            if m.header.sent_ns > last_model_ns {
                resumed_frame = Some(m.frame);
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let resumed_frame = resumed_frame.expect("the restarted cloth-sim publishes");
    assert!(
        resumed_frame > 60 && resumed_frame + 200 > frame_before,
        "resumed at frame {resumed_frame}, was at {frame_before} (autosave every 2 s)"
    );
    let mut err = String::new();
    sim2.0.kill().unwrap();
    use std::io::Read;
    sim2.0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(err.contains("resumed"), "{err}");
}
