//! The tools against a short real run with the simulated pen: cloth-latency's three
//! measurements write valid JSON, CSV and PNG; cloth-lab restarts one process without
//! touching the haptic loop, whose ticks go on without a gap.

#![allow(clippy::unwrap_used)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};
use shared::Checked;
use shared::domain::{Domain, ScratchDomain};
use shared::ports;
use shared::services;
use tests::{Proc, bin};

fn spawn(name: &str, args: &[&str]) -> Proc {
    Proc(
        Command::new(bin(name))
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    )
}

/// Runs cloth-latency with `args` plus the three outputs into `dir/NAME.*`; returns the
/// JSON after checking the CSV and the PNG.
fn latency(dir: &Path, name: &str, args: &[&str]) -> Value {
    let (json, csv, png) = (
        dir.join(format!("{name}.json")),
        dir.join(format!("{name}.csv")),
        dir.join(format!("{name}.png")),
    );
    let out = Command::new(bin("cloth-latency"))
        .args(args)
        .arg("--json")
        .arg(&json)
        .arg("--csv")
        .arg(&csv)
        .arg("--plot")
        .arg(&png)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "cloth-latency {name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // The same report on stdout.
    let printed: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(printed, v);
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("series,t_s,value_us\n"), "{name} csv");
    assert!(text.lines().count() > 3, "{name} csv has no rows");
    // A real picture: 1200 x 900, not one flat colour.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (1200, 900));
    let px = &buf[..info.buffer_size()];
    let dark = px.chunks(3).filter(|p| p.iter().all(|&c| c < 100)).count();
    let coloured = px
        .chunks(3)
        .filter(|p| p.iter().max().unwrap() - p.iter().min().unwrap() > 100)
        .count();
    assert!(
        dark > 1000 && coloured > 200,
        "{name} plot: {dark} dark, {coloured} coloured pixels"
    );
    v
}

fn pct(v: &Value, key: &str) -> (f64, f64, f64, f64) {
    let p = &v[key];
    let f = |k: &str| p[k].as_f64().unwrap_or_else(|| panic!("{key}.{k} in {v}"));
    (f("p50"), f("p99"), f("p999"), f("max"))
}

#[test]
fn cloth_latency_measures_a_real_run() {
    let d = ScratchDomain::new(&format!("lat{}", std::process::id())).unwrap();
    let tmp = std::env::temp_dir().join(format!("saiho-lat-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let autosave = tmp.join("design.saiho");
    let _sim = spawn(
        "cloth-sim",
        &[
            "run",
            "--domain",
            d.name(),
            "--grid",
            "16",
            "--fresh",
            "--seconds",
            "60",
            "--autosave",
            autosave.to_str().unwrap(),
        ],
    );
    let _haptic = spawn("haptic-loop", &["--domain", d.name(), "--seconds", "60"]);

    let l = latency(
        &tmp,
        "loop",
        &["loop", "--domain", d.name(), "--seconds", "2"],
    );
    let ticks = l["ticks"].as_u64().unwrap();
    assert!((1500..=2500).contains(&ticks), "{ticks} ticks in 2 s");
    assert!(l["missed"].as_u64().is_some());
    let (p50, p99, p999, max) = pct(&l, "period_us");
    assert!((900.0..1100.0).contains(&p50), "period p50 {p50}");
    assert!(p50 <= p99 && p99 <= p999 && p999 <= max);
    let (c50, ..) = pct(&l, "compute_us");
    assert!(c50 > 0.0 && c50 < 1000.0, "compute p50 {c50}");

    let e = latency(
        &tmp,
        "e2e",
        &["e2e", "--domain", d.name(), "--seconds", "2"],
    );
    assert!(e["frames"].as_u64().unwrap() > 30, "{e}");
    let (m50, ..) = pct(&e, "sample_to_model_used_us");
    // At least one tick, at most a few frames.
    assert!(
        (500.0..100_000.0).contains(&m50),
        "sample -> model used p50 {m50}"
    );
    let (f50, ..) = pct(&e, "motion_to_frame_published_us");
    assert!(f50 > 0.0 && f50 < 100_000.0, "motion -> frame p50 {f50}");

    // ping runs its own echo process in a private domain.
    let p = latency(&tmp, "ping", &["ping", "--seconds", "1", "--rate", "2000"]);
    for path in ["project", "raw"] {
        let (r50, ..) = pct(&p[path], "one_way_us");
        assert!(r50 > 0.0 && r50 < 1000.0, "{path} one-way p50 {r50}");
        // About 1,800 of the 2,000 asked for on a quiet machine; under the whole test
        // suite's load it once got fewer than 500 in the second: a hundred is a real
        // run, not a rate to meet.
        let count = p[path]["rtt_us"]["count"].as_u64().unwrap();
        assert!(count > 100, "{path}: {count} round trips");
    }
    assert!(p["ratio_p50"].as_f64().unwrap() > 0.0);
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn cloth_latency_says_when_nothing_runs() {
    let out = Command::new(bin("cloth-latency"))
        .args([
            "loop",
            "--domain",
            &format!("none{}", std::process::id()),
            "--seconds",
            "1",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no haptic-loop telemetry"), "{err}");
    let out = Command::new(bin("cloth-latency"))
        .args(["ping", "--seconds=0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--seconds"));
}

/// cloth-lab (under Xvfb, so with cloth-ui) restarts the UI and then cloth-sim on request;
/// the haptic loop is never restarted and its ticks go on without a gap: its telemetry's
/// sequence numbers are consecutive and each step is 100 ticks, before, across and after
/// the restarts.
#[test]
fn lab_restart_leaves_the_haptic_loop_ticking() {
    let d = ScratchDomain::new(&format!("lab{}", std::process::id())).unwrap();
    // The autosave goes to a state directory of the test's, not the user's.
    let state = std::env::temp_dir().join(format!("saiho-labstate-{}", std::process::id()));
    let mut lab = Proc(
        tests::under_xvfb(&bin("cloth-lab"))
            .env("XDG_STATE_HOME", &state)
            .args([
                "--domain",
                d.name(),
                "--grid",
                "8",
                "--fresh",
                "--seconds",
                "90",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let node = services::node(&d, "observer").unwrap();
    let tel = ports::subscriber(&node, services::haptic_telemetry, None).unwrap();
    let mut seen: Vec<(u64, u64)> = Vec::new(); // (seq, ticks)
    let collect = |until: Instant, seen: &mut Vec<(u64, u64)>| {
        while Instant::now() < until {
            while let Some(t) = tel.receive().unwrap() {
                t.check().unwrap();
                seen.push((t.header.seq, t.ticks));
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    };
    let deadline = Instant::now() + Duration::from_secs(30);
    while seen.len() < 5 {
        assert!(
            Instant::now() < deadline,
            "no haptic telemetry through cloth-lab"
        );
        collect(Instant::now() + Duration::from_millis(100), &mut seen);
    }
    // The UI must be up before it is swapped.
    let until = Instant::now() + Duration::from_secs(30);
    while !lab_status(&d).contains("cloth-ui: running") {
        assert!(
            Instant::now() < until,
            "cloth-ui did not start: {}",
            lab_status(&d)
        );
        collect(Instant::now() + Duration::from_millis(200), &mut seen);
    }
    // The status requests above paused the reading (a gap there is ours, not the loop's):
    // the check covers what follows, across both restarts.
    seen.clear();
    collect(Instant::now() + Duration::from_millis(1500), &mut seen);
    for role in ["ui", "sim"] {
        restart(&d, role, &mut || {
            collect(Instant::now() + Duration::from_millis(20), &mut seen)
        });
        collect(Instant::now() + Duration::from_millis(1500), &mut seen);
    }
    restarted_once_each_and_no_tick_lost(&lab_status(&d), &seen);
    bad_request_then_stop(&d, &mut lab);
    // The autosave went where XDG_STATE_HOME says, in a directory of the user's alone.
    use std::os::unix::fs::PermissionsExt;
    let saved = state.join("saiho");
    let mode = std::fs::metadata(&saved).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o700);
    assert!(saved.join(format!("{}.autosave.saiho", d.name())).is_file());
    let _ = std::fs::remove_dir_all(&state);
}

/// A request to the running lab through its control socket.
fn lab_ctl(d: &Domain, args: &[&str]) -> std::process::Output {
    Command::new(bin("cloth-lab"))
        .args(args)
        .args(["--domain", d.name()])
        .output()
        .unwrap()
}

fn lab_status(d: &Domain) -> String {
    String::from_utf8_lossy(&lab_ctl(d, &["status"]).stdout).to_string()
}

/// Restarts `role` through the lab. The request runs on its own thread while this one
/// keeps reading the telemetry (`read`; its buffer is small: a pause here would lose
/// messages, not the loop).
fn restart(d: &Domain, role: &'static str, read: &mut dyn FnMut()) {
    let lab_bin = bin("cloth-lab");
    let name = d.name().to_string();
    let req = std::thread::spawn(move || {
        Command::new(lab_bin)
            .args(["restart", role, "--domain", &name])
            .output()
            .unwrap()
    });
    while !req.is_finished() {
        read();
    }
    let out = req.join().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("restarted cloth-"));
}

/// The lab's status after the two restarts, and the loop's telemetry across them:
/// consecutive sequence numbers, 100 ticks a step.
fn restarted_once_each_and_no_tick_lost(s: &str, seen: &[(u64, u64)]) {
    for want in [
        "haptic-loop: running, pid",
        "cloth-sim: running",
        "cloth-ui: running",
    ] {
        assert!(s.contains(want), "{s}");
    }
    assert!(
        s.contains("(started 1x)") && s.matches("(started 2x)").count() == 2,
        "{s}"
    );
    assert!(
        seen.len() >= 40,
        "the haptic loop published {} times",
        seen.len()
    );
    for w in seen.windows(2) {
        assert_eq!(
            w[1].0,
            w[0].0 + 1,
            "a telemetry message went missing: {w:?}"
        );
        assert_eq!(w[1].1, w[0].1 + 100, "the tick count jumped: {w:?}");
    }
}

/// A bad request is refused with the reason; stop ends the lab cleanly.
fn bad_request_then_stop(d: &Domain, lab: &mut Proc) {
    let out = lab_ctl(d, &["restart", "everything"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown process"));
    let out = lab_ctl(d, &["stop"]);
    assert!(out.status.success());
    let until = Instant::now() + Duration::from_secs(15);
    let status = loop {
        if let Some(s) = lab.0.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < until, "cloth-lab did not stop");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "cloth-lab exit: {status:?}");
}

/// Runs `cloth-lab --headless` with `args` into `out_dir`; checks it succeeded and wrote
/// every export; its report and log.
fn lab_headless(args: &[&str], out_dir: &Path) -> (Value, String) {
    let out = Command::new(bin("cloth-lab"))
        .arg("--headless")
        .args(args)
        .arg("--out")
        .arg(out_dir)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{log}");
    for f in [
        "cloth.obj",
        "cloth.mtl",
        "cloth.png",
        "cloth.glb",
        "pattern.svg",
        "pattern.dxf",
        "design.saiho",
        "body.obj",
    ] {
        assert!(out_dir.join(f).is_file(), "{f} missing; {log}");
    }
    let report = std::fs::read_to_string(out_dir.join("report.json")).unwrap();
    (serde_json::from_str(&report).unwrap(), log)
}

/// `cloth-lab --headless`: the paper's fit-cube across the real processes, driven through
/// the command service (select and delete the corners on the pattern, seam the flaps,
/// export), with the report and exports written. Grid 40, whose lines fall on the cube's
/// faces: the scripted designer cuts on the grid lines at the top face's edges, and on a
/// coarser grid (32: 19 mm outside each face) the flaps are that much too wide to hug the
/// cube (a 23 mm mean standoff, with the guard that no longer lets them be pulled through).
#[test]
fn lab_headless_fit_cube_drives_the_real_processes() {
    let out_dir = std::env::temp_dir().join(format!("saiho-lab-fit-{}", std::process::id()));
    let (r, log) = lab_headless(&["--grid", "40"], &out_dir);
    assert_eq!(r["scenario"], "fit-cube");
    assert_eq!(r["mesh_valid"], true, "{r}");
    // The default xpbd has its guard: nothing crosses (652 body-crossing pairs before).
    assert_eq!(
        (&r["crossings_self"], &r["crossings_body"]),
        (&json!(0), &json!(0)),
        "{r}"
    );
    assert_eq!(r["stand_in"]["regions_removed"], 4);
    assert_eq!(r["seams"], 4);
    let pairs = r["stand_in"]["seam_pairs"].as_u64().unwrap();
    let welded = r["seam_pairs_welded"].as_u64().unwrap();
    assert!(
        pairs >= 16 && welded * 10 >= pairs * 9,
        "{welded} of {pairs} welded"
    );
    let th = r["thickness_m"].as_f64().unwrap();
    assert!(r["max_penetration_m"].as_f64().unwrap() <= th, "{r}");
    // The fitted panels hang close to the cube's faces (plain draping: about 12 mm).
    assert!(r["fit_gap_mean_m"].as_f64().unwrap() < 0.006, "{r}");
    // cloth-sim's measure of the threads' stretch reaches the lab's report: nine in ten
    // triangles under the strain limit's 20%.
    assert!(r["thread_stretch_p90"].as_f64().unwrap() < 0.2, "{r}");
    assert!(r["latency"]["ticks"].as_u64().unwrap() > 3000, "{r}");
    assert!(
        r["latency"]["sample_to_model_used_us"]["count"]
            .as_u64()
            .unwrap()
            > 100
    );
    assert!(r["step_ms"]["p50"].as_f64().is_some());
    // Real time by default: the lab asked for it, and the loop said what it got (SCHED_FIFO
    // where permitted, otherwise why not).
    assert!(log.contains("asking real-time for haptic-loop"), "{log}");
    assert!(
        log.contains("haptic-loop: real-time: SCHED_FIFO")
            || log.contains("haptic-loop: real-time not permitted"),
        "{log}"
    );
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// `cloth-lab --headless --scenario dress-mannequin`: the shipped dress sewn round the
/// mannequin across the real processes; the scripted designer pulls the front out at the
/// chest with the simulated pen (1.25 m up: the pen's workspace is the scene's, where the
/// old fixed one stopped at 0.9 m and pinched nothing), cuts the neckline away on the
/// pattern and exports the garment and its pattern.
#[test]
fn lab_headless_dress_mannequin_sews_pulls_and_cuts_across_the_processes() {
    let out_dir = std::env::temp_dir().join(format!("saiho-lab-dress-{}", std::process::id()));
    let (r, log) = lab_headless(&["--scenario", "dress-mannequin"], &out_dir);
    assert_eq!(r["scenario"], "dress-mannequin");
    assert_eq!(r["body"], "mannequin");
    assert_eq!(r["mesh_valid"], true, "{r}");
    assert_eq!(
        (&r["crossings_self"], &r["crossings_body"]),
        (&json!(0), &json!(0)),
        "{r}"
    );
    assert_eq!(r["seams"], 4, "{r}");
    // Of the 90 pairs the dress's conforming mesh has at its 3 cm edges, all but two.
    assert!(r["seam_pairs_welded"].as_u64().unwrap() >= 88, "{r}");
    let s = &r["stand_in"];
    assert!(s["pen_vertex_at"][1].as_f64().unwrap() > 1.2, "{s}");
    assert!(s["pen_pulled_m"].as_f64().unwrap() > 0.005, "{s}");
    assert!(s["neckline_triangles"].as_u64().unwrap() > 20, "{s}");
    assert!(log.contains("1 pinches"), "{log}");
    // The garment as its pieces, a named mesh each, beside the one-mesh cloth.glb.
    let glb = std::fs::read(out_dir.join("garment.glb")).unwrap();
    assert_eq!(&glb[0..4], b"glTF");
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let names: Vec<&str> = (gltf["nodes"].as_array().unwrap().iter())
        .map(|n| n["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"front") && names.contains(&"back"),
        "{names:?}"
    );
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// A process that fails at start stops the lab at once, and the lab says why; bad flags
/// are refused before anything starts.
#[test]
fn the_lab_stops_at_once_when_a_process_fails_at_start() {
    let domain = format!("labfail{}", std::process::id());
    let mut child = Command::new(bin("cloth-lab"))
        .args([
            "--no-ui",
            "--body",
            "teapot",
            "--seconds",
            "60",
            "--domain",
            &domain,
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Far less than the 60 s it was asked to run, and than the 30 s a headless lab used
    // to wait for a cloth-sim that had already exited.
    let until = Instant::now() + Duration::from_secs(20);
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        assert!(Instant::now() < until, "the lab kept running");
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut log = String::new();
    use std::io::Read;
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut log)
        .unwrap();
    assert!(!status.success());
    assert!(
        log.contains("cloth-sim failed") && log.contains("unknown body 'teapot'"),
        "{log}"
    );
    let out = Command::new(bin("cloth-lab"))
        .args(["--headless", "--grid", "100000"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("between 1 and 1999"),
        "{err}"
    );
}
