//! The two tools' command lines: help, and clear errors when there is nothing to talk to.
//! (Being an integration test of this package also makes `cargo test --workspace` build
//! `cloth-lab` and `cloth-latency`, which the system tests in `tests/` run.)

#![allow(clippy::unwrap_used)]

use std::process::Command;

#[test]
fn help_and_clear_errors() {
    for bin in [
        env!("CARGO_BIN_EXE_cloth-lab"),
        env!("CARGO_BIN_EXE_cloth-latency"),
    ] {
        let out = Command::new(bin).arg("--help").output().unwrap();
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("Usage"));
    }
    let domain = format!("nolab{}", std::process::id());
    let out = Command::new(env!("CARGO_BIN_EXE_cloth-lab"))
        .args(["restart", "ui", "--domain", &domain])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no cloth-lab is running"), "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_cloth-lab"))
        .args(["--headless", "--scenario", "nope", "--out", "/tmp"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown headless scenario"));
}
