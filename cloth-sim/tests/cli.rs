//! The `cloth-sim` binary: scenarios produce their files; bad input gives a clear error
//! and a non-zero exit, never a panic.

// Test helpers: a failed unwrap is a failed test, with its location.
#![allow(clippy::unwrap_used)]

use std::path::PathBuf;
use std::process::{Command, Output};

fn cloth_sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_cloth-sim"))
        .args(args)
        .output()
        .expect("run cloth-sim")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("saiho-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn fails_cleanly(args: &[&str], expect: &str) {
    let out = cloth_sim(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.to_lowercase().contains(&expect.to_lowercase()),
        "{args:?}: expected '{expect}' in: {err}"
    );
}

#[test]
fn help_is_available_everywhere() {
    for args in [
        &["--help"][..],
        &["scenario", "--help"],
        &["max-realtime-grid", "--help"],
    ] {
        let out = cloth_sim(args);
        assert!(out.status.success());
        assert!(String::from_utf8_lossy(&out.stdout).contains("Usage"));
    }
}

#[test]
fn drape_cube_writes_report_and_meshes() {
    let dir = tmp("drape");
    let out = cloth_sim(&[
        "scenario",
        "drape-cube",
        "--out",
        dir.to_str().unwrap(),
        "--grid",
        "12",
        "--frames",
        "30",
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    for key in [
        "scenario",
        "model",
        "vertices",
        "triangles",
        "frames",
        "frame_dt_s",
        "substeps",
        "step_ms",
        "max_penetration_m",
        "kinetic_energy_final_j",
        "mesh_valid",
    ] {
        assert!(report.get(key).is_some(), "report lacks {key}");
    }
    for key in ["p50", "p99", "max", "mean"] {
        assert!(report["step_ms"][key].as_f64().unwrap() > 0.0);
    }
    let ms = |k: &str| report["step_ms"][k].as_f64().unwrap();
    assert!(
        ms("mean") <= ms("max"),
        "the mean frame is no longer than the longest"
    );
    // Each frame's time, in order: as many as frames, the longest the max.
    let each: Vec<f64> = report["frame_ms"]
        .as_array()
        .expect("frame_ms")
        .iter()
        .map(|t| t.as_f64().unwrap())
        .collect();
    assert_eq!(each.len(), 30);
    let longest = each.iter().copied().fold(0.0, f64::max);
    assert!(
        (longest - ms("max")).abs() <= 0.006,
        "{longest} against {}",
        ms("max")
    );
    let (strain, strain_max) = (
        report["strain_mean"].as_f64().unwrap(),
        report["strain_max"].as_f64().unwrap(),
    );
    assert!(
        strain.abs() < 0.1 && strain_max >= strain,
        "strain {strain}, max {strain_max}"
    );
    // The threads' stretch: its percentiles in order.
    let t = |k: &str| report[k].as_f64().unwrap();
    let (p50, p90, most) = (
        t("thread_stretch_p50"),
        t("thread_stretch_p90"),
        t("thread_stretch_max"),
    );
    assert!(
        p50 <= p90 && p90 <= most && most < 1.0,
        "{p50} {p90} {most}"
    );
    assert_eq!(report["vertices"], 169);
    assert_eq!(report["frames"], 30);
    assert_eq!(report["mesh_valid"], true);
    let cloth = std::fs::read_to_string(dir.join("cloth.obj")).unwrap();
    assert_eq!(cloth.lines().filter(|l| l.starts_with("v ")).count(), 169);
    // UVs per triangle corner (a sewn vertex can have two), so three per face.
    assert_eq!(
        cloth.lines().filter(|l| l.starts_with("vt ")).count(),
        3 * 288
    );
    assert_eq!(cloth.lines().filter(|l| l.starts_with("f ")).count(), 288);
    assert!(cloth.contains("mtllib cloth.mtl"));
    for f in ["cloth.mtl", "cloth.png", "design.saiho"] {
        assert!(dir.join(f).is_file(), "{f} missing");
    }
    assert!(
        std::fs::read_to_string(dir.join("body.obj"))
            .unwrap()
            .lines()
            .any(|l| l.starts_with("f "))
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_cloth_can_come_from_an_obj_file() {
    let dir = tmp("objcloth");
    // A 0.6 m square, 6 x 6 cells, with UVs.
    let mut s = String::new();
    for j in 0..=6 {
        for i in 0..=6 {
            s += &format!(
                "v {} 0 {}\nvt {} {}\n",
                i as f32 * 0.1,
                j as f32 * 0.1,
                i as f32 / 6.0,
                j as f32 / 6.0
            );
        }
    }
    for j in 0..6 {
        for i in 0..6 {
            let a = j * 7 + i + 1;
            s += &format!(
                "f {a}/{a} {}/{} {}/{}\nf {}/{} {}/{} {}/{}\n",
                a + 7,
                a + 7,
                a + 1,
                a + 1,
                a + 1,
                a + 1,
                a + 7,
                a + 7,
                a + 8,
                a + 8
            );
        }
    }
    let path = dir.join("square.obj");
    std::fs::write(&path, s).unwrap();
    let out = cloth_sim(&[
        "scenario",
        "drape-cube",
        "--out",
        dir.to_str().unwrap(),
        "--cloth",
        path.to_str().unwrap(),
        "--frames",
        "20",
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(r["vertices"], 49);
    assert_eq!(r["triangles"], 72);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn every_model_and_body_runs() {
    let obj = tmp("body").join("tetra.obj");
    // A closed, outward-wound tetrahedron, 0.5 m.
    std::fs::write(
        &obj,
        "v 0 0 0\nv 0.5 0 0\nv 0 0 0.5\nv 0 0.5 0\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n",
    )
    .unwrap();
    // The same tetrahedron wound inside out: turned outward, and the user is told.
    let inside_out = tmp("body").join("inside-out.obj");
    std::fs::write(
        &inside_out,
        "v 0 0 0\nv 0.5 0 0\nv 0 0 0.5\nv 0 0.5 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let dir = tmp("inside-out");
    let out = cloth_sim(&drape_args(
        dir.to_str().unwrap(),
        &[
            "--grid",
            "8",
            "--frames",
            "5",
            "--body",
            inside_out.to_str().unwrap(),
            "--quiet",
        ],
    ));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("wound inside out") && err.contains("turned it outward"),
        "{err}"
    );
    std::fs::remove_dir_all(dir).ok();
    for (model, body) in [
        ("seed", "cube"),
        ("implicit", "sphere"),
        ("xpbd", "mannequin"),
        ("xpbd", obj.to_str().unwrap()),
    ] {
        let dir = tmp(&format!("m-{model}"));
        let out = cloth_sim(&[
            "scenario",
            "drape-cube",
            "--out",
            dir.to_str().unwrap(),
            "--grid",
            "8",
            "--frames",
            "5",
            "--model",
            model,
            "--body",
            body,
            "--quiet",
        ]);
        assert!(
            out.status.success(),
            "{model}/{body}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let r: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap())
                .unwrap();
        assert_eq!(r["model"], model);
        std::fs::remove_dir_all(dir).ok();
    }
    std::fs::remove_dir_all(tmp("body")).ok();
}

/// `cloth-sim scenario drape-cube --out DIR` and `extra`.
fn drape_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["scenario", "drape-cube", "--out", out];
    v.extend_from_slice(extra);
    v
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = tmp("bad");
    let o = dir.to_str().unwrap();
    fails_cleanly(&drape_args(o, &["--grid", "0"]), "grid");
    fails_cleanly(&drape_args(o, &["--density", "-0.1"]), "density");
    fails_cleanly(&drape_args(o, &["--density", "NaN"]), "density");
    fails_cleanly(&drape_args(o, &["--body", "teapot"]), "unknown body");
    fails_cleanly(&drape_args(o, &["--model", "magic"]), "unknown model");
    fails_cleanly(
        &["scenario", "fold-laundry", "--out", o],
        "unknown scenario",
    );
    fails_cleanly(&drape_args(o, &["--frames", "0"]), "frames");
    fails_cleanly(
        &drape_args(o, &["--model", "seed", "--substeps", "1"]),
        "unstable",
    );
    fails_cleanly(
        &drape_args(o, &["--body", "/no/such/file.obj"]),
        "cannot read",
    );
    let nan = dir.join("nan.obj");
    std::fs::write(&nan, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n").unwrap();
    fails_cleanly(
        &drape_args(o, &["--body", nan.to_str().unwrap()]),
        "line 3: vertex 3 is not finite",
    );
    let degenerate = dir.join("flat.obj");
    std::fs::write(&degenerate, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
    fails_cleanly(
        &drape_args(o, &["--body", degenerate.to_str().unwrap()]),
        "the face on line 4 has no area",
    );
    let nonmanifold = dir.join("fin.obj");
    std::fs::write(
        &nonmanifold,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    fails_cleanly(
        &drape_args(o, &["--body", nonmanifold.to_str().unwrap()]),
        "shared by 3",
    );
    fails_cleanly(&drape_args(o, &["--cloth", nan.to_str().unwrap()]), "cloth");
    // A body with a hole, named where the file has it; a sheet that encloses nothing.
    let open = dir.join("open.obj");
    std::fs::write(
        &open,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n",
    )
    .unwrap();
    fails_cleanly(
        &drape_args(o, &["--body", open.to_str().unwrap()]),
        "is not a solid body: it is not closed: the edge from vertex 2 to vertex 3 has a face on one side only (line 5)",
    );
    // A cloth that crosses itself: two squares, one through the other.
    let crossed = dir.join("crossed.obj");
    std::fs::write(
        &crossed,
        "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv 0.5 0.5 1.5\nv 0.5 -0.5 1.5\n\
         f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n",
    )
    .unwrap();
    fails_cleanly(
        &drape_args(o, &["--cloth", crossed.to_str().unwrap()]),
        "pairs of its triangles intersect",
    );
    // Absurd values get one line with the accepted range, before any work: no abort on
    // a huge allocation, no hang, no output directory left behind.
    let never = dir.join("never");
    let n = never.to_str().unwrap();
    for (args, expect) in [
        (
            &["--frames", "1000000000000"][..],
            "--frames <FRAMES>': must be a whole number between 1 and 1000000",
        ),
        (
            &["--substeps", "1000000000"],
            "--substeps <SUBSTEPS>': must be a whole number between 1 and 10000 per frame",
        ),
        (
            &["--substeps", "1e9"],
            "must be a whole number between 1 and 10000 per frame",
        ),
        (&["--frames", "1.5"], "must be a whole number between 1 and"),
        (&["--density", "1e9"], "density must be between"),
        (&["--threads", "7"], "whole number between 1 and 2"),
        (
            &["--grid", "2000"],
            "whole number between 1 and 1999 cells a side",
        ),
        (
            &["--grid", "-3"],
            "whole number between 1 and 1999 cells a side",
        ),
        (
            &["--grid", "nan"],
            "whole number between 1 and 1999 cells a side",
        ),
        (&["--cloth-size", "NaN"], "cloth size"),
    ] {
        fails_cleanly(&drape_args(n, args), expect);
        assert!(!never.exists(), "{args:?} left an output directory");
    }
    let garbage = dir.join("garbage.obj");
    std::fs::write(&garbage, "f 1 2 3\nv x y z\n").unwrap();
    fails_cleanly(
        &drape_args(o, &["--body", garbage.to_str().unwrap()]),
        "line 1: vertex 1 does not exist",
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_run_flags_are_a_clear_error_before_any_work() {
    let dir = tmp("run-bad");
    let autosave = dir.join("a.saiho");
    let a = autosave.to_str().unwrap();
    for (args, expect) in [
        (&["--rate", "nan"][..], "rate must be between 1 and 1000"),
        (&["--rate", "0"], "rate must be between 1 and 1000"),
        (&["--seconds", "nan"], "seconds must be between"),
        (&["--threads", "7"], "whole number between 1 and 2"),
        (&["--grid", "100000"], "whole number between 1 and 1999"),
        (&["--substeps", "-1"], "whole number between 1 and 10000"),
        (&["--pinch-stiffness", "-3"], "pinch stiffness"),
        (&["--cpus", "0-"], "not a CPU list"),
        (
            &["--no-guard", "--model", "vbd"],
            "--no-guard is the xpbd model's",
        ),
        (&["--guard", "--no-guard"], "cannot be used with"),
        (
            &["--pattern", "/nonexistent/x.svg", "--fresh"],
            "cannot read /nonexistent/x.svg",
        ),
    ] {
        let mut all = vec!["run", "--domain", "clibad", "--autosave", a];
        all.extend_from_slice(args);
        if !args.contains(&"--seconds") {
            all.extend(["--seconds", "5"]);
        }
        fails_cleanly(&all, expect);
        assert!(!autosave.exists(), "{args:?} wrote an autosave");
    }
    // An autosave path that is a directory.
    fails_cleanly(
        &[
            "run",
            "--domain",
            "clibad",
            "--autosave",
            dir.to_str().unwrap(),
            "--seconds",
            "1",
        ],
        "a file, not a directory",
    );
    std::fs::remove_dir_all(dir).ok();
}

/// `cloth-sim run --pattern FILE` starts a new design of the pattern's pieces, placed
/// and sewn; a resumed design stays as it is, and the log says so.
#[test]
fn run_starts_a_design_from_a_pattern() {
    let dir = tmp("run-pattern");
    let autosave = dir.join("a.saiho");
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    let domain = format!("rp{}", std::process::id());
    let run = |fresh: bool| {
        let mut args = vec![
            "run",
            "--domain",
            &domain,
            "--body",
            "mannequin",
            "--pattern",
            dress,
            "--seconds",
            "1",
            "--autosave",
            autosave.to_str().unwrap(),
        ];
        if fresh {
            args.push("--fresh");
        }
        let out = cloth_sim(&args);
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(out.status.success(), "{err}");
        err
    };
    let said = run(true);
    assert!(
        said.contains("the 2 pieces of") && said.contains("4 seams stitched"),
        "{said}"
    );
    let d = sim_core::design::Design::load_design_file(&autosave).unwrap();
    let names: Vec<&str> = d.pieces.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["front", "back"]);
    assert_eq!(d.seams.len(), 4);
    let said = run(false);
    assert!(said.contains("the resumed design stays as it is"), "{said}");
    std::fs::remove_dir_all(dir).ok();
}

/// The numbers in `cloth-sim crossings`' line: self pairs, body triangles, body pairs.
fn crossing_counts(args: &[&str]) -> (u64, u64, u64) {
    let out = cloth_sim(args);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let before = |marker: &str| -> u64 {
        let head = &text[..text
            .find(marker)
            .unwrap_or_else(|| panic!("{marker}: {text}"))];
        head.rsplit(' ')
            .find(|w| !w.is_empty())
            .unwrap()
            .parse()
            .unwrap()
    };
    if !text.contains("cross the body") {
        return (before(" intersecting pairs"), 0, 0);
    }
    (
        before(" intersecting pairs"),
        before(" of its triangles cross"),
        before(" pairs ("),
    )
}

#[test]
fn crossings_are_counted_exactly_in_reports_and_in_any_obj() {
    let dir = tmp("crossings");
    // Two triangles far from the cube, one piercing the other, and one through the
    // cube's top face (y = 0.4).
    let obj = dir.join("soup.obj");
    std::fs::write(
        &obj,
        "v 1 0 0\nv 2 0 0\nv 1 0 1\n\
         v 1.2 -0.5 0.2\nv 1.3 0.5 0.2\nv 1.25 0.5 0.3\n\
         v -0.1 0.3 0\nv 0.1 0.5 0\nv 0 0.5 0.1\n\
         f 1 2 3\nf 4 5 6\nf 7 8 9\n",
    )
    .unwrap();
    let o = obj.to_str().unwrap();
    let (selfp, body_tris, body_pairs) = crossing_counts(&["crossings", o, "--body", "cube"]);
    assert_eq!((selfp, body_tris), (1, 1));
    assert!(body_pairs >= 1);
    assert_eq!(crossing_counts(&["crossings", o]).0, 1);

    // A scenario's report counts what its exported OBJ shows, and the most seen.
    let d = dir.join("drape");
    let out = cloth_sim(&[
        "scenario",
        "drape-cube",
        "--out",
        d.to_str().unwrap(),
        "--grid",
        "24",
        "--frames",
        "150",
        "--check-every",
        "25",
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("report.json")).unwrap()).unwrap();
    let n = |k: &str| r[k].as_u64().unwrap_or_else(|| panic!("{k} in {r}"));
    let (selfp, body_tris, body_pairs) = crossing_counts(&[
        "crossings",
        d.join("cloth.obj").to_str().unwrap(),
        "--body",
        d.join("body.obj").to_str().unwrap(),
    ]);
    assert_eq!(selfp, n("crossings_self"));
    assert_eq!(body_pairs, n("crossings_body"));
    assert_eq!(body_tris, n("crossings_body_triangles"));
    assert!(n("crossings_self_max") >= n("crossings_self"));
    assert!(n("crossings_body_max") >= n("crossings_body"));
    assert_eq!(n("check_every"), 25);
    std::fs::remove_dir_all(dir).ok();
}

/// Runs a scenario (`args` after `scenario`, `--out dir` added), which must succeed, and
/// returns its report.
fn scenario_report(dir: &std::path::Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["scenario"];
    all.extend_from_slice(args);
    all.extend(["--out", dir.to_str().unwrap(), "--quiet"]);
    let out = cloth_sim(&all);
    assert!(
        out.status.success(),
        "{all:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// Runs `export-pattern` (`args` after it), which must succeed; returns each piece's
/// sewing-line loop lengths as it printed them ("piece 1: 1 outline (4000.0 mm), ..."),
/// and what it printed.
fn exported_lengths(args: &[&str]) -> (Vec<Vec<f64>>, String) {
    let mut all = vec!["export-pattern"];
    all.extend_from_slice(args);
    let out = cloth_sim(&all);
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lengths = stdout
        .lines()
        .filter_map(|l| l.split_once('(')?.1.split_once(" mm)"))
        .map(|(lens, _)| lens.split(" + ").map(|x| x.parse().unwrap()).collect())
        .collect();
    (lengths, stdout)
}

#[test]
fn fold_lies_on_the_floor_and_the_scenarios_that_act_on_a_body_need_one() {
    let dir = tmp("fold");
    let o = dir.to_str().unwrap();
    fails_cleanly(
        &["scenario", "tear", "--body", "floor", "--out", o, "--quiet"],
        "body must be cube, sphere, mannequin, mannequin-apose, human or an .obj",
    );
    assert!(!dir.join("report.json").exists());
    let r = scenario_report(&dir, &["fold", "--model", "vbd", "--grid", "10"]);
    assert_eq!(r["body"], "floor");
    assert_eq!(r["folds"], 2, "{r}");
    // The folded cloth lies on itself, and no layer passes through another.
    assert!(r["layers_max"].as_u64().unwrap() >= 2, "{r}");
    assert!(r["self_contacts"].as_u64().unwrap() > 0, "{r}");
    assert_eq!(r["crossings_self"], 0, "{r}");
    assert!(!dir.join("body.obj").exists());
    std::fs::remove_dir_all(dir).ok();
}

/// Reads `dir/pattern.svg` and `dir/pattern.dxf` with readers that are not ours (Python's
/// XML parser, and `ezdxf`, which `.ci/run` installs) and prints, per piece, its sewing
/// line's loop lengths in mm: "svg L1 L2 ..." then "dxf L1 L2 ..." lines; then the
/// notches each reader found and the DXF's turn points: "marks SVG DXF TURNS".
const READ_PATTERN: &str = r#"
import sys, math, re, xml.etree.ElementTree as ET
import ezdxf
d = sys.argv[1]
def per(pts):
    return sum(math.dist(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts)))
ns = {"s": "http://www.w3.org/2000/svg"}
svg = ET.parse(d + "/pattern.svg").getroot()
for g in svg.findall("s:g", ns):
    sew = [p for p in g.findall("s:path", ns) if p.get("class") == "sew"][0]
    loops = [l for l in sew.get("d").split("Z") if l.strip()]
    lens = []
    for l in loops:
        pts = [tuple(map(float, xy.split(","))) for xy in re.findall(r"[-\d.]+,[-\d.]+", l)]
        lens.append(per(pts))
    print("svg", " ".join(f"{x:.2f}" for x in lens))
doc = ezdxf.readfile(d + "/pattern.dxf")
inserts = [e.dxf.name for e in doc.modelspace() if e.dxftype() == "INSERT"]
for name in inserts:
    b = doc.blocks[name]
    lens = [per([(v.dxf.location.x, v.dxf.location.y) for v in e.vertices])
            for e in b if e.dxftype() == "POLYLINE" and e.dxf.layer == "14"]
    assert any(e.dxftype() == "POLYLINE" and e.dxf.layer == "1" for e in b), "no boundary"
    assert any(e.dxftype() == "TEXT" and e.dxf.text.startswith("Piece Name:") for e in b)
    assert any(e.dxftype() == "LINE" and e.dxf.layer == "7" for e in b), "no grain line"
    assert any(e.dxftype() == "TEXT" and e.dxf.text.startswith("Material:") for e in b)
    print("dxf", " ".join(f"{x:.2f}" for x in lens))
svg_notches = sum(1 for l in svg.iter("{http://www.w3.org/2000/svg}line") if l.get("class") == "notch")
blocks = [doc.blocks[name] for name in inserts]
dxf_notches = sum(1 for b in blocks for e in b if e.dxftype() == "LINE" and e.dxf.layer == "4")
turns = sum(1 for b in blocks for e in b if e.dxftype() == "POINT" and e.dxf.layer == "2")
print("marks", svg_notches, dxf_notches, turns)
"#;

/// The SVG and DXF in `p` read by readers that are not ours give loops of the lengths
/// we printed (`ours`), to 0.5 mm.
fn check_with_independent_readers(p: &std::path::Path, ours: &[Vec<f64>]) {
    // The Python that has ezdxf: the one on PATH (pip), else the system's (apt).
    let python = ["python3", "/usr/bin/python3"]
        .into_iter()
        .find(|py| {
            Command::new(py)
                .args(["-c", "import ezdxf"])
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .expect(
            "a python3 with ezdxf: python3 -m pip install ezdxf, or apt-get install python3-ezdxf",
        );
    let read = Command::new(python)
        .args(["-c", READ_PATTERN, p.to_str().unwrap()])
        .output()
        .expect("python3 (the independent readers run in it)");
    let text = String::from_utf8_lossy(&read.stdout).to_string();
    assert!(
        read.status.success(),
        "the SVG or DXF did not read (ezdxf: python3 -m pip install ezdxf): {}",
        String::from_utf8_lossy(&read.stderr)
    );
    // The balance notches, the same in both; the turn points of the outlines' corners.
    let marks: Vec<usize> = (text.lines())
        .find_map(|l| l.strip_prefix("marks"))
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .unwrap_or_default();
    assert!(
        marks.len() == 3 && marks[0] == marks[1] && marks[0] > 0 && marks[2] >= 4,
        "notches in the SVG and DXF, turn points: {marks:?}"
    );
    for kind in ["svg", "dxf"] {
        let theirs: Vec<Vec<f64>> = text
            .lines()
            .filter_map(|l| l.strip_prefix(kind))
            .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(theirs.len(), ours.len(), "{kind}: {text}");
        for (a, b) in theirs.iter().zip(ours) {
            assert_eq!(a.len(), b.len(), "{kind}: {text}");
            for (x, y) in a.iter().zip(b) {
                assert!((x - y).abs() < 0.5, "{kind}: {x} mm against our {y} mm");
            }
        }
    }
}

/// `svg` read back as pieces (the sewing line, not the cut line around it), meshed,
/// draped a moment and written out again gives one outline of `expected` mm, to 0.5 mm.
fn assert_reads_back(dir: &std::path::Path, svg: &std::path::Path, expected: f64) {
    let back = dir.join("back");
    let args = [
        "drape-cube",
        "--piece",
        svg.to_str().unwrap(),
        "--piece-edge",
        "0.05",
    ];
    scenario_report(&back, &[&args[..], &["--frames", "2"]].concat());
    let design = back.join("design.saiho");
    let (again, text) =
        exported_lengths(&[design.to_str().unwrap(), "--out", back.to_str().unwrap()]);
    assert_eq!(again.len(), 1, "{text}");
    assert!(
        (again[0][0] - expected).abs() < 0.5,
        "{text} against {expected} mm"
    );
}

#[test]
fn the_pattern_out_opens_in_other_readers_with_the_lengths_we_cut() {
    let dir = tmp("pattern");
    let o = dir.to_str().unwrap();
    scenario_report(&dir, &["fit-cube", "--grid", "12", "--frames", "250"]);
    assert!(dir.join("pattern.svg").is_file() && dir.join("pattern.dxf").is_file());
    let p = dir.join("again");
    let design = dir.join("design.saiho");
    let (d, ps) = (design.to_str().unwrap(), p.to_str().unwrap());
    // "piece 1: 1 outline (4000.0 mm), 8 seam segments": fit-cube's cross-shaped piece,
    // whose cut corners keep the square's perimeter, with its four seams' sides marked.
    let (ours, stdout) = exported_lengths(&[d, "--out", ps, "--allowance", "15"]);
    assert_eq!(ours.len(), 1, "{stdout}");
    assert!((ours[0][0] - 4000.0).abs() < 0.5, "{stdout}");
    assert!(!stdout.contains(" 0 seam segments"), "{stdout}");
    check_with_independent_readers(&p, &ours);
    assert_reads_back(&dir, &p.join("pattern.svg"), ours[0][0]);
    let empty = dir.join("lines.svg");
    std::fs::write(
        &empty,
        r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M0,0 L10,10"/></svg>"#,
    )
    .unwrap();
    fails_cleanly(
        &[
            "scenario",
            "drape-cube",
            "--piece",
            empty.to_str().unwrap(),
            "--out",
            o,
        ],
        "no closed shape",
    );
    fails_cleanly(
        &[
            "export-pattern",
            design.to_str().unwrap(),
            "--out",
            o,
            "--allowance",
            "-1",
        ],
        "allowance must be between 0 and 100 mm",
    );
    fails_cleanly(
        &[
            "export-pattern",
            dir.join("missing.saiho").to_str().unwrap(),
            "--out",
            o,
        ],
        "missing.saiho",
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_piece_from_its_outline_drapes_and_comes_back_out_as_its_pattern() {
    let dir = tmp("piece");
    let o = dir.to_str().unwrap();
    let r = scenario_report(
        &dir,
        &[
            "drape-cube",
            "--piece",
            "ellipse:0.8x0.5",
            "--piece-edge",
            "0.04",
            "--frames",
            "20",
        ],
    );
    assert!(r["triangles"].as_u64().unwrap() > 200, "{r}");
    // The pattern out is the ellipse again: its perimeter (Ramanujan) 2,069.4 mm, less
    // the little its 4 cm chords cut off.
    let svg = std::fs::read_to_string(dir.join("pattern.svg")).unwrap();
    assert_eq!(svg.matches("class=\"piece\"").count(), 1);
    let design = dir.join("design.saiho");
    let (lengths, text) = exported_lengths(&[design.to_str().unwrap(), "--out", o]);
    assert_eq!(lengths.len(), 1, "{text}");
    assert!((2060.0..2069.4).contains(&lengths[0][0]), "{text}");
    fails_cleanly(
        &["scenario", "drape-cube", "--piece", "circle:1", "--out", o],
        "rect:WxH or ellipse:WxH",
    );
    fails_cleanly(
        &[
            "scenario",
            "drape-cube",
            "--piece",
            "rect:1x1",
            "--cloth",
            "x.obj",
            "--out",
            o,
        ],
        "one of --cloth",
    );
    fails_cleanly(
        &[
            "scenario",
            "drape-cube",
            "--piece",
            "rect:1x1",
            "--piece-edge",
            "nan",
            "--out",
            o,
        ],
        "piece edge must be between",
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn dress_mannequin_sews_two_panels_round_the_torso_without_crossing() {
    let dir = tmp("dress");
    let o = dir.to_str().unwrap();
    let r = scenario_report(
        &dir,
        &[
            "dress-mannequin",
            "--model",
            "vbd",
            "--piece-edge",
            "0.05",
            "--frames",
            "150",
        ],
    );
    assert_eq!(r["pieces"], 2, "{r}");
    assert_eq!(r["seams"], 4, "{r}");
    assert!(r["sews"].as_u64().unwrap() > 0, "no stitch welded: {r}");
    let welded = r["seam_pairs_welded"].as_u64().unwrap();
    let pairs = r["seam_pairs"].as_u64().unwrap();
    assert!(
        welded >= r["sews"].as_u64().unwrap() && welded <= pairs,
        "{r}"
    );
    // 28-29 of 36 in three runs (2026-11-26); the pairs left open are listed.
    assert!(10 * welded >= 7 * pairs, "{welded} of {pairs} welded: {r}");
    let open = r["seam_pairs_open"].as_array().unwrap();
    assert_eq!(open.len() as u64, pairs - welded, "{r}");
    for o in open {
        assert!(o["gap_m"].as_f64().unwrap() > 0.0, "{o}");
        assert!(o["stalled"].is_boolean(), "{o}");
        assert!(
            ["nothing", "body", "cloth"].contains(&o["between"].as_str().unwrap_or("")),
            "{o}"
        );
        assert!(
            ["A", "B", "C", "D"].contains(&o["seam"].as_str().unwrap()),
            "{o}"
        );
    }
    assert!(r["torso_coverage"].as_f64().unwrap() >= 0.9, "{r}");
    assert!(r["seam_length_mismatch_m"].as_f64().unwrap() < 1e-3, "{r}");
    assert_eq!(
        (r["crossings_self"].clone(), r["crossings_body"].clone()),
        (0.into(), 0.into()),
        "{r}"
    );
    // The pattern: both panels, each seam's label on both.
    let svg = std::fs::read_to_string(dir.join("pattern.svg")).unwrap();
    assert_eq!(svg.matches("class=\"piece\"").count(), 2);
    let groups: Vec<&str> = svg.split("<g id=\"piece-").skip(1).collect();
    for label in ["A", "B", "C", "D"] {
        for g in &groups {
            assert!(
                g.contains(&format!("data-seam=\"{label}\"")),
                "seam {label}"
            );
        }
    }
    // The pieces keep their names in the pattern out.
    assert!(svg.contains("<title>front</title>") && svg.contains("<title>back</title>"));
    // The pattern out read back in, seams and all, placed, sewn and draped again.
    for file in ["pattern.svg", "pattern.dxf"] {
        let again = dir.join(format!("again-{file}"));
        let pattern = dir.join(file);
        let r = scenario_report(
            &again,
            &[
                "drape-pattern",
                pattern.to_str().unwrap(),
                "--model",
                "vbd",
                "--piece-edge",
                "0.05",
                "--frames",
                "30",
            ],
        );
        assert_eq!(r["pieces"], 2, "{file}: {r}");
        assert_eq!(r["seams"], 4, "{file}: {r}");
        assert_eq!(
            (r["crossings_self"].clone(), r["crossings_body"].clone()),
            (0.into(), 0.into()),
            "{file}: {r}"
        );
    }
    fails_cleanly(
        &[
            "scenario",
            "dress-mannequin",
            "--piece",
            "rect:1x1",
            "--out",
            o,
        ],
        "the pattern's own pieces",
    );
    fails_cleanly(
        &["scenario", "drape-pattern", "--out", o],
        "a pattern file (--pattern FILE) for drape-pattern",
    );
    let report = dir.join("report.json");
    fails_cleanly(
        &[
            "scenario",
            "drape-pattern",
            report.to_str().unwrap(),
            "--out",
            o,
        ],
        "GarmentCode specification: no \"pattern\"",
    );
    std::fs::remove_dir_all(dir).ok();
}

/// Under the default model the dress's cotton is held under 1.2x (the default material's
/// strain limit) and every seam closes: the shipped pattern's scooped neck lets the
/// shoulder seams' neck ends meet. At 5 cm triangles the straight neck left both neck
/// ends open (34 of 36), and the scooped one without the limit three pairs of seam A.
/// The limit is off when asked, under vbd, and for a knit; a named fabric brings its own.
#[test]
fn the_default_dress_closes_every_seam_with_its_cotton_held() {
    let dir = tmp("dress-default");
    let r = scenario_report(
        &dir,
        &["dress-mannequin", "--piece-edge", "0.05", "--frames", "300"],
    );
    assert_eq!(r["model"], "xpbd", "{r}");
    assert!(
        (r["strain_limit"].as_f64().unwrap() - 0.2).abs() < 1e-6,
        "{r}"
    );
    assert_eq!(r["seam_pairs_welded"], r["seam_pairs"], "{r}");
    assert_eq!(r["settled"], true, "{r}");
    assert!(r["strain_max"].as_f64().unwrap() < 0.5, "{r}");
    assert!(r["torso_coverage"].as_f64().unwrap() >= 0.9, "{r}");
    assert_eq!(
        (r["crossings_self"].clone(), r["crossings_body"].clone()),
        (0.into(), 0.into()),
        "{r}"
    );
    for off in [
        &["--strain-limit", "0"][..],
        &["--model", "vbd"],
        &["--fabric", "jersey-interlock"],
    ] {
        let mut args = vec!["dress-mannequin", "--piece-edge", "0.05", "--frames", "2"];
        args.extend_from_slice(off);
        let r = scenario_report(&dir, &args);
        assert_eq!(r["strain_limit"].as_f64(), Some(0.0), "{off:?}: {r}");
    }
    // drape-pattern runs without it unless asked (a pattern from elsewhere closes its
    // seams by stretching).
    let dress = concat!(env!("CARGO_MANIFEST_DIR"), "/../sim-core/assets/dress.svg");
    for (asked, limit) in [(&[][..], 0.0), (&["--strain-limit", "0.2"][..], 0.2)] {
        let args = [
            "drape-pattern",
            dress,
            "--piece-edge",
            "0.05",
            "--frames",
            "2",
        ];
        let r = scenario_report(&dir, &[&args[..], asked].concat());
        let got = r["strain_limit"].as_f64().unwrap();
        assert!((got - limit).abs() < 1e-6, "{asked:?}: {r}");
    }
    // A GarmentCode pattern drapes on its own body, the human one, which it fits: with
    // the limit. On the mannequin it is a pattern from elsewhere again.
    let gc = dir.join("two_panels_specification.json");
    std::fs::write(&gc, TWO_GC_PANELS).unwrap();
    let gc = gc.to_str().unwrap();
    for (body, named, limit) in [
        (&[][..], "human", 0.2),
        (&["--body", "mannequin"][..], "mannequin", 0.0),
    ] {
        let args = ["drape-pattern", gc, "--piece-edge", "0.05", "--frames", "2"];
        let r = scenario_report(&dir, &[&args[..], body].concat());
        assert_eq!(r["body"], named, "{r}");
        let got = r["strain_limit"].as_f64().unwrap();
        assert!((got - limit).abs() < 1e-6, "{body:?}: {r}");
        assert_eq!(r["seams"], 2, "{r}");
    }
    for (fabric, own) in [("denim", 0.2), ("wool-stretch-twill", 0.3)] {
        let args = ["dress-mannequin", "--piece-edge", "0.05", "--frames", "2"];
        let r = scenario_report(&dir, &[&args[..], &["--fabric", fabric]].concat());
        let got = r["strain_limit"].as_f64().unwrap();
        assert!((got - own).abs() < 1e-6, "{fabric}: {r}");
    }
    std::fs::remove_dir_all(dir).ok();
}

/// GarmentCode's format, two 40 x 50 cm panels in front of and behind its body's waist,
/// sewn at both sides.
const TWO_GC_PANELS: &str = r#"{"pattern": {"panels": {
  "front": {"vertices": [[-20, 0], [20, 0], [20, 50], [-20, 50]],
            "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
            "translation": [0, 80, 25], "rotation": [0, 0, 0]},
  "back": {"vertices": [[-20, 0], [20, 0], [20, 50], [-20, 50]],
           "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
           "translation": [0, 80, -25], "rotation": [0, 180, 0]}},
  "stitches": [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 3}],
               [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 1}]]},
  "properties": {"units_in_meter": 100}}"#;

/// The drape test from the command line: three specimens averaged, the same on a finer
/// mesh to check convergence, the shadow and the first specimen's mesh.
#[test]
fn cusick_averages_three_specimens_and_checks_a_finer_mesh() {
    let d = tmp("cusick");
    let r = scenario_report(&d, &["cusick", "--fabric", "denim", "--piece-edge", "0.02"]);
    assert_eq!(r["specimens"], 3);
    let each: Vec<f64> = r["drape_coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(each.len(), 3);
    let dc = r["drape_coefficient"].as_f64().unwrap();
    assert!((dc - each.iter().sum::<f64>() / 3.0).abs() < 1e-12, "{r}");
    assert!(dc > 0.2 && dc < 1.0, "denim stands stiff: {dc}");
    assert_eq!(r["runs"].as_array().unwrap().len(), 3);
    assert_eq!(r["runs_refined"].as_array().unwrap().len(), 3);
    let fine = r["drape_coefficient_refined"].as_f64().unwrap();
    assert_eq!(r["converged"], (fine - dc).abs() < 0.01);
    assert_eq!(r["settled"], true);
    assert!(r["dc_measured"].is_null(), "denim's drape was not measured");
    for f in ["shadow.png", "cloth.obj"] {
        assert!(d.join(f).metadata().unwrap().len() > 100, "{f}");
    }
    std::fs::remove_dir_all(d).ok();
}
