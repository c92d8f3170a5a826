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
    // The domain given before the subcommand names the same lab as one after it.
    let out = Command::new(env!("CARGO_BIN_EXE_cloth-lab"))
        .args(["--domain", &domain, "stop"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains(&format!("domain '{domain}'")), "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_cloth-lab"))
        .args(["--headless", "--scenario", "nope", "--out", "/tmp"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown headless scenario"));
}

/// Runs a tool expecting it to refuse its command line: exit status 1, no panic, and
/// `expect` in what it says.
fn refused(bin: &str, args: &[&str], expect: &str) {
    let out = Command::new(bin).args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.contains(expect),
        "{args:?}: expected '{expect}' in: {err}"
    );
}

#[test]
fn bad_flags_are_refused_with_their_range() {
    let lab = env!("CARGO_BIN_EXE_cloth-lab");
    let grid = "must be a whole number between 1 and 1999 cells a side";
    for g in ["2000", "-3", "1e9", "1.5", "nan"] {
        refused(lab, &["--headless", "--grid", g], grid);
    }
    let prio = "must be a whole number between 1 and 99 (SCHED_FIFO)";
    refused(lab, &["--rt-priority", "0"], prio);
    refused(lab, &["--rt-priority", "100"], prio);
    refused(
        lab,
        &["--cpu", "-1"],
        "must be a whole number between 0 and 1023",
    );
    refused(lab, &["--cpu", "1023"], "is not a CPU this process may use");
    refused(lab, &["--seconds", "nan"], "--seconds must be between");
    refused(lab, &["--no-such-flag"], "unexpected argument");
    refused(
        lab,
        &["--model", "blender"],
        "[possible values: xpbd, vbd, seed, implicit]",
    );
    let latency = env!("CARGO_BIN_EXE_cloth-latency");
    refused(
        latency,
        &["ping", "--seconds", "nan"],
        "--seconds must be between",
    );
    refused(
        latency,
        &["ping", "--rate", "0"],
        "--rate must be 1 to 20000",
    );
}
