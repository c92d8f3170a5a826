//! haptic-loop's command line: every flag checked before the device opens, one line with
//! the accepted range, exit status 1.

#![allow(clippy::unwrap_used)]

use std::process::Command;

fn refused(args: &[&str], expect: &str) {
    let out = Command::new(env!("CARGO_BIN_EXE_haptic-loop"))
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.contains(expect),
        "{args:?}: expected '{expect}' in: {err}"
    );
    // Refused before any work: no device opened, so no real-time line either.
    assert!(!err.contains("real-time"), "{args:?} started: {err}");
}

#[test]
fn bad_flags_are_refused_with_their_range_before_the_device_opens() {
    let prio = "must be a whole number between 1 and 99 (SCHED_FIFO)";
    for p in ["0", "100", "-5", "8.5", "nan"] {
        refused(&["--rt-priority", p], prio);
    }
    refused(
        &["--cpu", "-1"],
        "must be a whole number between 0 and 1023",
    );
    refused(&["--cpu", "1023"], "is not a CPU this process may use");
    refused(
        &["--spin-us", "5000"],
        "must be a whole number between 0 and 1000 µs",
    );
    refused(&["--seconds", "nan"], "--seconds must be between");
    refused(&["--device", "teapot"], "device");
}
