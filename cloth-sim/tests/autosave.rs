//! A design is never lost: an autosave that cannot be read is moved aside under a name
//! that says why and the backup resumed instead; a save that fails is counted as a
//! failure and leaves no temporary file; the previous autosave stays as the backup.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use cloth_sim::{ServiceConfig, backup_of, resume_or, run, start_fresh};
use shared::domain::Domain;
use sim_core::design::Design;
use sim_core::design::file::FORMAT;
use sim_core::scenario::{ScenarioConfig, ScenarioName, build_design};

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("saiho-autosave-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn small(grid: usize) -> Design {
    let mut scene = ScenarioConfig::new(ScenarioName::DrapeCube);
    scene.grid = grid;
    build_design(&scene).unwrap()
}

fn config(autosave: &Path, domain: &str) -> ServiceConfig {
    let mut cfg = ServiceConfig::new(Domain::new(domain).unwrap());
    cfg.autosave = autosave.to_owned();
    cfg
}

/// Resumes with `cfg`; a fresh design would have a 4 x 4 cloth (25 vertices).
fn resume(cfg: &ServiceConfig) -> (Result<(Design, bool), String>, Vec<String>) {
    let mut lines = Vec::new();
    let r = resume_or(cfg, || Ok(small(4)), &mut |m| lines.push(m.to_string()));
    (r, lines)
}

/// The damaged forms of a good design file the issue found.
fn damaged(good: &[u8]) -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let mut flipped = good.to_vec();
    flipped[good.len() / 2] ^= 0x40;
    let mut newer = good.to_vec();
    newer[8..12].copy_from_slice(&(FORMAT + 1).to_le_bytes());
    vec![
        ("truncated", good[..good.len() / 3].to_vec(), "damaged"),
        ("bit-flipped", flipped, "damaged"),
        ("newer format", newer, "newer-format"),
        ("not a design", b"hello".to_vec(), "not-a-design"),
    ]
}

/// `--fresh` starts a new design and keeps the last one as the backup. Until
/// 2026-11-29 it moved the autosave to the backup and then resumed the backup: every
/// `cloth-lab --fresh` went on with the old design.
#[test]
fn a_fresh_start_keeps_the_last_design_as_the_backup_and_starts_anew() {
    let d = dir("fresh");
    let autosave = d.join("lab.autosave.saiho");
    let cfg = config(&autosave, &format!("fr{}", std::process::id()));
    let old = small(6).save_design().unwrap();
    std::fs::write(&autosave, &old).unwrap();
    let mut log = Vec::new();
    let design = start_fresh(&cfg, || Ok(small(4)), &mut |m| log.push(m.to_string())).unwrap();
    assert_eq!(design.sim.cloth.len(), 25, "the new 4 x 4 design: {log:?}");
    assert_eq!(std::fs::read(backup_of(&autosave)).unwrap(), old);
    assert!(!autosave.exists());
    assert!(log.len() == 1 && log[0].contains("kept as"), "{log:?}");
    // What the next start without --fresh resumes, until the new design is autosaved.
    let (r, _) = resume(&cfg);
    assert_eq!(r.unwrap().0.sim.cloth.len(), 49);
    // A new design that cannot be made moves nothing.
    std::fs::write(&autosave, &old).unwrap();
    let r = start_fresh(&cfg, || Err("no such pattern".into()), &mut |_| {});
    assert_eq!(r.err().as_deref(), Some("no such pattern"));
    assert_eq!(std::fs::read(&autosave).unwrap(), old, "the autosave stays");
    std::fs::remove_file(&autosave).unwrap();
    // With nothing there, nothing is moved or said.
    std::fs::remove_file(backup_of(&autosave)).unwrap();
    let mut log = Vec::new();
    let design = start_fresh(&cfg, || Ok(small(4)), &mut |m| log.push(m.to_string())).unwrap();
    assert_eq!(design.sim.cloth.len(), 25);
    assert!(log.is_empty() && !backup_of(&autosave).exists(), "{log:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn an_unreadable_autosave_is_kept_aside_and_the_backup_resumed() {
    let d = dir("resume");
    let autosave = d.join("lab.autosave.saiho");
    let cfg = config(&autosave, &format!("as{}", std::process::id()));
    let good = {
        let design = small(6);
        design.save_design().unwrap()
    };
    for (case, bytes, why) in damaged(&good) {
        // With a good backup: the damaged autosave is moved aside, the backup resumed.
        std::fs::write(&autosave, &bytes).unwrap();
        std::fs::write(backup_of(&autosave), &good).unwrap();
        let (r, log) = resume(&cfg);
        let (design, resumed) = r.unwrap();
        assert!(resumed, "{case}: {log:?}");
        assert_eq!(design.sim.cloth.len(), 49, "{case}: the 6 x 6 backup");
        let kept = d.join(format!("lab.autosave.{why}.saiho"));
        assert_eq!(
            std::fs::read(&kept).unwrap(),
            bytes,
            "{case}: kept byte for byte"
        );
        assert!(
            !autosave.exists(),
            "{case}: not left in place to be overwritten"
        );
        assert!(
            log.iter()
                .any(|l| l.contains("kept as") && l.contains(&kept.display().to_string())),
            "{case}: the log says where: {log:?}"
        );
        std::fs::remove_file(&kept).unwrap();
        // Without one: both damaged files are kept, and a new design starts.
        std::fs::write(&autosave, &bytes).unwrap();
        std::fs::write(backup_of(&autosave), &bytes).unwrap();
        let (r, log) = resume(&cfg);
        let (design, resumed) = r.unwrap();
        assert!(!resumed && design.sim.cloth.len() == 25, "{case}: {log:?}");
        assert_eq!(std::fs::read(&kept).unwrap(), bytes);
        let kept_backup = d.join(format!("lab.autosave.previous.{why}.saiho"));
        assert_eq!(std::fs::read(&kept_backup).unwrap(), bytes, "{case}");
        std::fs::remove_file(&kept).unwrap();
        std::fs::remove_file(&kept_backup).unwrap();
    }
    // A second damaged file never replaces the first one kept.
    std::fs::write(&autosave, b"first").unwrap();
    let _ = resume(&cfg);
    std::fs::write(&autosave, b"second").unwrap();
    let _ = resume(&cfg);
    assert_eq!(
        std::fs::read(d.join("lab.autosave.not-a-design.saiho")).unwrap(),
        b"first"
    );
    assert_eq!(
        std::fs::read(d.join("lab.autosave.not-a-design.2.saiho")).unwrap(),
        b"second"
    );
    // An autosave path that is a directory is refused at start, with the reason.
    let (r, _) = resume(&config(&d, "asdir"));
    assert!(r.unwrap_err().contains("is a directory"));
    let _ = std::fs::remove_dir_all(&d);
}

static STOP: AtomicBool = AtomicBool::new(false);

#[test]
fn the_previous_autosave_stays_as_the_backup() {
    let d = dir("backup");
    let autosave = d.join("run.autosave.saiho");
    let domain = format!("asb{}", std::process::id());
    let mut cfg = config(&autosave, &domain);
    cfg.autosave_every_s = 0.2;
    cfg.seconds = Some(2.0);
    let stats = run(small(6), &cfg, &STOP, &mut |_| {}).unwrap();
    // The designs are the user's alone.
    use std::os::unix::fs::PermissionsExt;
    for f in [autosave.clone(), backup_of(&autosave)] {
        let mode = std::fs::metadata(&f).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600, "{}", f.display());
    }
    // A clean stop, alone in its domain, leaves nothing of it in /dev/shm or the runtime
    // directory.
    let d_ = Domain::new(&domain).unwrap();
    let shm: Vec<String> = std::fs::read_dir("/dev/shm")
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(&d_.prefix()))
        .collect();
    assert!(shm.is_empty(), "left in /dev/shm: {shm:?}");
    let root = shared::paths::runtime_dir()
        .unwrap()
        .join("iceoryx2")
        .join(&domain);
    assert!(!root.exists(), "{} left", root.display());
    assert!(
        stats.autosaves >= 3 && stats.autosave_failures == 0,
        "{stats:?}"
    );
    let now = Design::load_design_file(&autosave).unwrap();
    let before = Design::load_design_file(&backup_of(&autosave)).unwrap();
    assert!(
        before.sim.frame < now.sim.frame,
        "the backup is the autosave before"
    );
    let left: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_failing_autosave_is_counted_as_a_failure_and_leaves_nothing_behind() {
    let d = dir("fail");
    let autosave = d.join("gone.autosave.saiho");
    let mut cfg = config(&autosave, &format!("asf{}", std::process::id()));
    cfg.autosave_every_s = 0.2;
    cfg.seconds = Some(1.5);
    // Once the first autosave is written, its place is taken by a directory.
    let blocker = autosave.clone();
    let t = std::thread::spawn(move || {
        while !blocker.is_file() {
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        std::fs::remove_file(&blocker).unwrap();
        std::fs::create_dir_all(&blocker).unwrap();
    });
    let mut log = Vec::new();
    let stats = run(small(6), &cfg, &STOP, &mut |m| log.push(m.to_string())).unwrap();
    t.join().unwrap();
    // The first write counted; the ones into the directory, the last included, failed.
    assert!(stats.autosaves >= 1, "{stats:?} {log:?}");
    assert!(stats.autosave_failures >= 2, "{stats:?}");
    assert!(
        log.iter()
            .filter(|l| l.starts_with("autosave failed"))
            .count()
            == 1
            && log.iter().any(|l| l.starts_with("final autosave failed")),
        "one line for the repeated failure, one for the last: {log:?}"
    );
    assert!(autosave.is_dir(), "the directory is left as it is");
    let tmp: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("tmp"))
        .collect();
    assert!(tmp.is_empty(), "temporary files left: {tmp:?}");
    let _ = std::fs::remove_dir_all(&d);
}
