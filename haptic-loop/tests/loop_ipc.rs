//! The real loop over real iceoryx2 services in an isolated domain, with the simulated pen:
//! a pinch model makes it render the spring force (sign and magnitude); when the model
//! stops coming the force reaches zero within 10 ms of going stale while ticks continue;
//! malformed models are rejected with a reason.

#![allow(clippy::unwrap_used)]

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use haptic_loop::device::{SimDevice, Still, Workspace};
use haptic_loop::looper::{self, LoopConfig};
use shared::domain::{Domain, ScratchDomain};
use shared::haptic_to_sim::AppliedForce;
use shared::ports::{self, HapticPorts};
use shared::services;
use shared::sim_to_haptic::LocalModel;
use shared::{Header, monotonic_ns};

fn start_loop(d: Domain, ticks: u64) -> std::thread::JoinHandle<looper::LoopStats> {
    std::thread::spawn(move || start_loop_at(d, ticks, [0.0, 0.6, 0.0]).join().unwrap().0)
}

/// The loop with the simulated pen's hand held at `hand` (scene metres); its stats and
/// the lines it logged.
fn start_loop_at(
    d: Domain,
    ticks: u64,
    hand: [f32; 3],
) -> std::thread::JoinHandle<(looper::LoopStats, Vec<String>)> {
    std::thread::spawn(move || {
        let node = services::node(&d, "haptic").unwrap();
        let ports = HapticPorts::open(&node).unwrap();
        let cfg = LoopConfig {
            max_ticks: Some(ticks),
            ..LoopConfig::default()
        };
        let mut dev = SimDevice::new(Still(hand, 0), Workspace::default());
        let stop = AtomicBool::new(false);
        let mut lines = Vec::new();
        let stats = looper::run(&mut dev, &ports, &cfg, &stop, None, None, |l| {
            lines.push(l.to_string())
        });
        (stats, lines)
    })
}

#[test]
fn pinch_force_then_stale_model_ramps_to_zero_and_ticks_go_on() {
    let d = ScratchDomain::new(&format!("hl{}", std::process::id())).unwrap();
    let handle = start_loop(d.0.clone(), 1500);
    let node = services::node(&d, "fake-sim").unwrap();
    let model_pub = ports::publisher(&node, services::local_model).unwrap();
    let applied = ports::subscriber(&node, services::applied_force, None).unwrap();
    // The pinched vertex 1 cm above the pen, stiffness 100 N/m: 1 N up once ramped.
    let mut seq = 0;
    let mut samples = Vec::new();
    let t0 = monotonic_ns();
    while monotonic_ns() - t0 < 700_000_000 {
        model_pub
            .send_copy(LocalModel {
                header: Header::next(&mut seq),
                frame: seq,
                pinching: 1,
                stiffness: 100.0,
                vertex_position: [0.0, 0.61, 0.0],
                ..Default::default()
            })
            .unwrap();
        std::thread::sleep(Duration::from_millis(5));
        while let Some(s) = applied.receive().unwrap() {
            samples.push(*s);
        }
    }
    let last_sent = monotonic_ns();
    // A malformed model (NaN) is rejected, not used.
    let mut bad = LocalModel {
        header: Header::next(&mut seq),
        pinching: 1,
        stiffness: 100.0,
        ..Default::default()
    };
    bad.vertex_position[0] = f32::NAN;
    model_pub.send_copy(bad).unwrap();
    // Then silence: cloth-sim "dies".
    while monotonic_ns() - last_sent < 300_000_000 {
        std::thread::sleep(Duration::from_millis(2));
        while let Some(s) = applied.receive().unwrap() {
            samples.push(*s);
        }
    }
    let stats = handle.join().unwrap();
    // While pinching: the force points up (toward the vertex), about 1 N less the pen's
    // own give (the hand holds it with 150 N/m, so it rises a little toward the vertex).
    let pinching: Vec<&AppliedForce> = samples
        .iter()
        .filter(|s| s.header.sent_ns > t0 + 300_000_000 && s.header.sent_ns < last_sent)
        .collect();
    assert!(!pinching.is_empty());
    for s in &pinching {
        assert!(s.force[1] > 0.3 && s.force[1] < 1.05, "{:?}", s.force);
        assert!(s.force[0].abs() < 1e-3 && s.force[2].abs() < 1e-3);
    }
    // Stale after 20 ms, zero within 10 ms more (one tick of slack for the period).
    let zero_by = last_sent + 20_000_000 + 10_000_000 + 1_500_000;
    let after: Vec<&AppliedForce> = samples
        .iter()
        .filter(|s| s.header.sent_ns > zero_by)
        .collect();
    assert!(
        after.len() > 100,
        "the loop kept ticking: {} samples",
        after.len()
    );
    assert!(
        after.iter().all(|s| s.force == [0.0; 3]),
        "force not zero after staleness"
    );
    assert_eq!(stats.telemetry.ticks, 1500);
    assert!(stats.rejected >= 1);
    assert!(
        stats
            .last_reject
            .as_deref()
            .unwrap()
            .contains("vertex position")
    );
}

/// The pen reaches where the scene's workspace says: a hand at the mannequin's shoulder
/// (1.45 m up) leaves the pen at the default workspace's top (0.9 m) until cloth-sim's
/// model brings the mannequin's workspace, and then the pen gets there.
#[test]
fn the_models_workspace_lets_the_pen_reach_the_whole_body() {
    use shared::sim_to_haptic::workspace_covering;
    let d = ScratchDomain::new(&format!("hw{}", std::process::id())).unwrap();
    let handle = start_loop_at(d.0.clone(), 2000, [0.1, 1.45, 0.12]);
    let node = services::node(&d, "fake-sim").unwrap();
    let model_pub = ports::publisher(&node, services::local_model).unwrap();
    let pen = ports::subscriber(&node, services::device, None).unwrap();
    // The loop has started once its first sample comes (a slow machine takes a while).
    let t0 = monotonic_ns();
    while pen.receive().unwrap().is_none() {
        assert!(monotonic_ns() - t0 < 3_000_000_000, "no pen sample in 3 s");
        std::thread::sleep(Duration::from_millis(2));
    }
    let highest = |t: u64| {
        let t0 = monotonic_ns();
        let mut y = f32::NEG_INFINITY;
        while monotonic_ns() - t0 < t {
            std::thread::sleep(Duration::from_millis(2));
            while let Some(s) = pen.receive().unwrap() {
                y = y.max(s.position[1]);
            }
        }
        y
    };
    let before = highest(300_000_000);
    assert!((0.85..=0.9).contains(&before), "before: {before}");
    let workspace = workspace_covering([-0.25, 0.0, -0.15], [0.25, 1.77, 0.15]);
    let mut seq = 0;
    for _ in 0..10 {
        model_pub
            .send_copy(LocalModel {
                header: Header::next(&mut seq),
                workspace,
                ..Default::default()
            })
            .unwrap();
        std::thread::sleep(Duration::from_millis(5));
    }
    let after = highest(300_000_000);
    assert!(after > 1.4, "after the mannequin's workspace: {after}");
    let (stats, lines) = handle.join().unwrap();
    assert_eq!(stats.rejected, 0);
    // The lab engineer is told the mapping the scene brought.
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("the scene's workspace: the device mapped 16.")),
        "{lines:?}"
    );
}
