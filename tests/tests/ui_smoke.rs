//! The real cloth-ui under Xvfb with cloth-sim and the simulated pen: it takes a
//! screenshot after a few seconds, and the cloth is drawn in it (the cloth's off-white
//! against the dark background, in the middle of the window). Then the UI is killed and
//! started again while cloth-sim and haptic-loop keep going: the new one shows the
//! design too. And when its display goes away under it, cloth-ui says so and exits 1.

#![allow(clippy::unwrap_used)]

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use shared::domain::ScratchDomain;
use tests::{Proc, bin, under_xvfb};

fn shot(domain: &str, path: &std::path::Path) -> (String, u32, u32, Vec<u8>) {
    let out = under_xvfb(&bin("cloth-ui"))
        .args(["--domain", domain, "--exit-after", "4", "--screenshot"])
        .arg(path)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "cloth-ui failed: {log}");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = decoder.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (log, info.width, info.height, buf)
}

/// Pixels in the middle third of the picture that look like the lit cloth.
fn cloth_pixels(w: u32, h: u32, rgba: &[u8]) -> usize {
    let mut n = 0;
    for y in h / 3..2 * h / 3 {
        for x in w / 3..2 * w / 3 {
            let i = 4 * (y * w + x) as usize;
            let p = &rgba[i..i + 3];
            let (lo, hi) = (*p.iter().min().unwrap(), *p.iter().max().unwrap());
            if lo > 110 && hi - lo < 40 {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn cloth_ui_draws_the_cloth_under_xvfb_and_survives_a_restart() {
    let d = ScratchDomain::new(&format!("uismoke{}", std::process::id())).unwrap();
    let tmp = std::env::temp_dir().join(format!("saiho-uismoke-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let autosave = tmp.join("design.saiho");
    let _sim = Proc(
        std::process::Command::new(bin("cloth-sim"))
            .args([
                "run",
                "--domain",
                d.name(),
                "--grid",
                "32",
                "--fresh",
                "--seconds",
                "120",
            ])
            .arg("--autosave")
            .arg(&autosave)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let _haptic = Proc(
        std::process::Command::new(bin("haptic-loop"))
            .args(["--domain", d.name(), "--seconds", "120"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let first = tmp.join("first.png");
    let (log, w, h, px) = shot(d.name(), &first);
    assert!(w >= 800 && h >= 600, "{w}x{h}");
    let n = cloth_pixels(w, h, &px);
    assert!(
        n > 2000,
        "only {n} cloth pixels in the screenshot; log: {log}"
    );
    // A second UI, started after the first quit: the design is all there again.
    let second = tmp.join("second.png");
    let (log2, w2, h2, px2) = shot(d.name(), &second);
    let n2 = cloth_pixels(w2, h2, &px2);
    assert!(n2 > 2000, "the restarted UI shows only {n2} cloth pixels");
    // Mesh, positions, every texture tile, tool and material all reached it.
    assert!(
        log2.contains("the whole design (mesh, positions, seams, texture, tool, material) arrived"),
        "the restarted UI did not get the whole design: {log2}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// An X server killed under a running cloth-ui: winit panics inside the event loop; the
/// studio reports a lost display in one line and exits 1 (not 101 with a backtrace).
#[test]
fn cloth_ui_says_when_its_display_goes_away() {
    let d = ScratchDomain::new(&format!("uilost{}", std::process::id())).unwrap();
    // A display of its own: Xvfb writes the number it took to the descriptor given.
    let mut x = Proc(
        Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1280x1024x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb is missing: install xvfb (.ci/run does)"),
    );
    let mut number = String::new();
    BufReader::new(x.0.stdout.take().unwrap())
        .read_line(&mut number)
        .unwrap();
    let display = format!(":{}", number.trim());
    let mut ui = Proc(
        Command::new(bin("cloth-ui"))
            .args(["--domain", d.name(), "--exit-after", "120", "--log-fps"])
            .env("DISPLAY", &display)
            .env_remove("WAYLAND_DISPLAY")
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // Up when it reports its first second of frames.
    let mut err = BufReader::new(ui.0.stderr.take().unwrap());
    let mut log = String::new();
    let mut line = String::new();
    while !line.contains(" fps") {
        line.clear();
        assert!(
            err.read_line(&mut line).unwrap() > 0,
            "cloth-ui ended before drawing: {log}"
        );
        log.push_str(&line);
    }
    x.0.kill().unwrap();
    x.0.wait().unwrap();
    let t = Instant::now();
    let rest = std::thread::spawn(move || {
        let mut rest = String::new();
        let _ = std::io::Read::read_to_string(&mut err, &mut rest);
        rest
    });
    let status = loop {
        if let Some(s) = ui.0.try_wait().unwrap() {
            break s;
        }
        assert!(
            t.elapsed() < Duration::from_secs(30),
            "cloth-ui still running 30 s after its display went away"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    log.push_str(&rest.join().unwrap());
    assert_eq!(status.code(), Some(1), "{log}");
    assert!(log.contains("error: cloth-ui lost its display"), "{log}");
    assert!(!log.contains("panicked"), "{log}");
}
