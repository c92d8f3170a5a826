//! The OpenHaptics backend against a stand-in libHD that this test compiles (C, with the
//! system's C compiler): a whole session in process (init, calibration check, force
//! output, servo frames with positions served and forces commanded, clean teardown), and
//! through the binary a device error that turns forces off with a log line.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::AtomicBool;

use haptic_loop::device::{HapticDevice, OpenHaptics, Workspace};
use haptic_loop::looper::{self, LoopConfig};
use shared::ports::{self, HapticPorts};

use shared::domain::ScratchDomain;
use shared::services;

/// Compiles the stand-in into a fresh directory; returns the .so path.
fn standin(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("saiho-hd-{}-{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let so = dir.join("libHD.so");
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/standin/libhd.c");
    let cc = std::env::var("CC").unwrap_or_else(|_| {
        let found = |c: &str| Command::new(c).arg("--version").output().is_ok();
        if found("cc") { "cc" } else { "gcc" }.into()
    });
    let out = Command::new(&cc)
        .args(["-shared", "-fPIC", "-O2", "-o"])
        .arg(&so)
        .arg(&src)
        .args(["-lm", "-lpthread", "-ldl"])
        .output()
        .unwrap_or_else(|e| panic!("cannot run the C compiler '{cc}': {e}"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    so
}

#[test]
fn a_whole_session_drives_the_standin() {
    let so = standin("session");
    let log = so.with_file_name("calls.log");
    let d = ScratchDomain::new(&format!("hd{}", std::process::id())).unwrap();
    let node = services::node(&d, "haptic").unwrap();
    let ports = HapticPorts::open(&node).unwrap();
    let samples = ports::subscriber(&node, services::device, None).unwrap();
    let ws = Workspace::default();
    {
        let (mut dev, notice) = OpenHaptics::open(so.to_str().unwrap(), ws).unwrap();
        assert!(notice.is_none(), "{notice:?}");
        let cfg = LoopConfig {
            max_ticks: Some(800),
            ..LoopConfig::default()
        };
        let stats = looper::run(
            &mut dev,
            &ports,
            &cfg,
            &AtomicBool::new(false),
            None,
            None,
            |_| {},
        );
        assert_eq!(stats.device_errors, 0);
        assert!(dev.frames() > 500, "{} servo frames", dev.frames());
        // The positions served (a 20 mm circle, mm) arrive mapped into the scene.
        let s = dev.read(0.001).unwrap();
        let r = ((s.position[0] - ws.centre[0]).powi(2) + (s.position[1] - ws.centre[1]).powi(2))
            .sqrt();
        assert!((r - ws.scale * 0.020).abs() < 1e-3, "radius {r}");
        assert_eq!(s.buttons & 1, 1, "button 1 is down from frame 300");
    }
    let mut last = None;
    while let Some(x) = samples.receive().unwrap() {
        last = Some(*x);
    }
    assert!(last.unwrap().device_ok == 1);
    let calls = std::fs::read_to_string(&log).unwrap();
    let order = [
        "hdInitDevice default",
        "hdCheckCalibration",
        "hdEnable 0x4000",
        "hdScheduleAsynchronous 65535",
        "hdStartScheduler",
        "hdStopScheduler",
        "hdUnschedule 7",
        "hdDisableDevice",
    ];
    let mut at = 0;
    for step in order {
        let k = calls[at..]
            .find(step)
            .unwrap_or_else(|| panic!("{step} missing or out of order:\n{calls}"));
        at += k + step.len();
    }
    let summary = calls.lines().last().unwrap();
    let field = |name: &str| -> f64 {
        let mut it = summary.split_whitespace();
        while let Some(w) = it.next() {
            if w == name {
                return it.next().unwrap().parse().unwrap();
            }
        }
        panic!("{name} not in {summary}");
    };
    assert!(
        field("frames") > 500.0 && field("forces") == field("frames"),
        "{summary}"
    );
    assert_eq!(field("bad_forces"), 0.0);
    assert_eq!(field("frame_errors"), 0.0, "every get/set inside a frame");
    assert!(field("max_force") <= 3.3);
    let _ = std::fs::remove_dir_all(so.parent().unwrap());
}

/// Runs the haptic-loop binary on libHD `lib` for `seconds` with the stand-in's `env`.
fn run_loop(
    lib: &std::path::Path,
    domain: &str,
    seconds: &str,
    env: &[(&str, &str)],
) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_haptic-loop"))
        .args([
            "--device",
            "openhaptics",
            "--domain",
            domain,
            "--seconds",
            seconds,
            "--hd-lib",
        ])
        .arg(lib)
        .envs(env.iter().copied())
        .output()
        .unwrap()
}

#[test]
fn a_device_error_turns_forces_off_with_a_log_line() {
    let so = standin("error");
    let d = format!("hde{}", std::process::id());
    let out = run_loop(&so, &d, "1", &[("SAIHO_STANDIN_ERROR_AT", "200")]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("device error, forces off: device error 0x0300"),
        "{err}"
    );
    // A position the device cannot reach (5 m off, then NaN) turns forces off too.
    let out = run_loop(&so, &d, "1", &[("SAIHO_STANDIN_GLITCH_AT", "200")]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(
            "forces off: device error 0x0000: the device reported a position outside its workspace"
        ),
        "{err}"
    );
    // A calibration that needs an update is updated, and said.
    let out = run_loop(&so, &d, "0.2", &[("SAIHO_STANDIN_CALIBRATION", "0x5001")]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("calibration was out of date"), "{err}");
    // A missing library is a clear error, not a crash.
    let out = run_loop(
        std::path::Path::new("/nonexistent/libHD.so"),
        &d,
        "0.1",
        &[],
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot load /nonexistent/libHD.so"));
    let _ = std::fs::remove_dir_all(so.parent().unwrap());
}
