//! The real cloth-ui under Xvfb with cloth-sim and the simulated pen: it takes a
//! screenshot after a few seconds, and the cloth is drawn in it (the cloth's off-white
//! against the dark background, in the middle of the window). Then the UI is killed and
//! started again while cloth-sim and haptic-loop keep going: the new one shows the
//! design too.

#![allow(clippy::unwrap_used)]

use std::process::Stdio;

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
