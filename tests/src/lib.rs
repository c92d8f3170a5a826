//! Saiho system tests: see `tests/` for tests that run the real binaries (`cloth-sim run`,
//! `haptic-loop`, `cloth-latency`, `cloth-lab`) in isolated iceoryx2 domains with the
//! simulated pen. This library holds what they share: finding (and, when stale, building)
//! the binaries, and a child process killed on drop.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::{Child, Command};

/// Newest modification time of the files under `dir`.
pub fn newest(dir: &std::path::Path) -> std::time::SystemTime {
    let mut t = std::time::SystemTime::UNIX_EPOCH;
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd.flatten() {
            let p = e.path();
            let m = if p.is_dir() {
                newest(&p)
            } else {
                e.metadata().and_then(|m| m.modified()).unwrap_or(t)
            };
            t = t.max(m);
        }
    }
    t
}

/// The workspace's binaries. `cargo test --workspace` has just built them; when they are
/// older than the sources (this test run alone after an edit), they are rebuilt first.
/// The binaries the system tests run.
pub const BINS: [&str; 5] = [
    "cloth-sim",
    "haptic-loop",
    "cloth-latency",
    "cloth-lab",
    "cloth-ui",
];

pub fn bin(name: &str) -> PathBuf {
    static BUILT: std::sync::Once = std::sync::Once::new();
    let dir = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    BUILT.call_once(|| {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
        let sources = [
            "sim-core/src",
            "cloth-sim/src",
            "haptic-loop/src",
            "shared/src",
            "tools/src",
            "ui/src",
        ]
        .iter()
        .map(|d| newest(&root.join(d)))
        .max()
        .unwrap();
        let fresh = BINS.iter().all(|b| {
            std::fs::metadata(dir.join(b))
                .and_then(|m| m.modified())
                .is_ok_and(|t| t >= sources)
        });
        if !fresh {
            let status = Command::new(env!("CARGO"))
                .args([
                    "build",
                    "--bins",
                    "-p",
                    "cloth-sim",
                    "-p",
                    "haptic-loop",
                    "-p",
                    "tools",
                    "-p",
                    "ui",
                ])
                .status()
                .unwrap();
            assert!(status.success(), "building the binaries failed");
        }
    });
    let path = dir.join(name);
    assert!(path.is_file(), "{} missing", path.display());
    path
}

pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The command that runs a program under a fresh Xvfb display (24-bit screen), or a clear
/// failure when Xvfb is missing (`.ci/run` installs it).
pub fn under_xvfb(program: &std::path::Path) -> Command {
    let found = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        found,
        "xvfb-run is missing: install xvfb (and Mesa: libgl1-mesa-dri libegl-mesa0 libvulkan1 mesa-vulkan-drivers)"
    );
    let mut c = Command::new("xvfb-run");
    c.args(["-a", "-s", "-screen 0 1280x1024x24"]).arg(program);
    c
}
