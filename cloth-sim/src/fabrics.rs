//! `cloth-sim fabrics`, `cloth-sim scenario cusick` and `cloth-sim validate-fabrics`: the
//! fabric library, the drape test on one fabric, and every published drape against ours.

use std::path::{Path, PathBuf};

use sim_core::fabric::cusick::{self, CusickConfig, CusickResult, Standard};
use sim_core::fabric::shadow;
use sim_core::fabric::{Fabric, Library};
use sim_core::solver::{Material, ModelKind};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// `cloth-sim fabrics [--json]`.
pub fn list(json: bool) -> Res<()> {
    let lib = Library::builtin();
    if json {
        let rows: Vec<serde_json::Value> = lib
            .fabrics
            .iter()
            .map(|f| serde_json::json!({ "fabric": f, "si": f.si(), "material": f.material() }))
            .collect();
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    println!(
        "{:<24} {:>6} {:>9} {:>9} {:>7} {:>9} {:>9} {:>9} {:>6}  source",
        "name", "g/m²", "stretch", "N/m", "shear", "B warp", "B weft", "B bias", "DC"
    );
    println!(
        "{:<24} {:>6} {:>9} {:>9} {:>7} {:>9} {:>9} {:>9} {:>6}",
        "", "", "warp N/m", "weft", "N/m", "µN·m", "µN·m", "µN·m", "meas."
    );
    for f in &lib.fabrics {
        let s = f.si();
        println!(
            "{:<24} {:>6.0} {:>9.1} {:>9.1} {:>7.1} {:>9.2} {:>9.2} {:>9.2} {:>6}  {}",
            f.name,
            f.weight_gsm,
            s.stretch_warp,
            s.stretch_weft,
            s.shear,
            s.bend_warp * 1e6,
            s.bend_weft * 1e6,
            s.bend_bias * 1e6,
            f.dc_measured
                .map_or("-".into(), |d| format!("{:.1}", d * 100.0)),
            f.source
        );
    }
    println!(
        "{} fabrics; units and conversions: docs/fabrics.md; --json for every field",
        lib.fabrics.len()
    );
    Ok(())
}

/// What `scenario cusick` is asked.
pub struct CusickArgs {
    pub fabric: Option<String>,
    pub material: Material,
    pub standard: Standard,
    pub edge: f32,
    pub model: ModelKind,
    pub substeps: Option<usize>,
    pub out: PathBuf,
    pub quiet: bool,
    /// Run again on a mesh of half the triangle area to check convergence.
    pub refine: bool,
}

fn config(a: &CusickArgs, edge: f32) -> CusickConfig {
    let mut cfg = CusickConfig::new(a.material);
    cfg.standard = a.standard;
    cfg.edge = edge;
    cfg.model = a.model;
    cfg.substeps = a.substeps;
    cfg
}

fn run_one(a: &CusickArgs, edge: f32, label: &str) -> Res<CusickResult> {
    let quiet = a.quiet;
    let mut progress = |t: f32, ke: f64| {
        if !quiet {
            eprintln!("cusick {label}: {t:.0} s simulated, kinetic energy {ke:.2e} J");
        }
    };
    Ok(cusick::run(&config(a, edge), &mut progress)?)
}

/// `cloth-sim scenario cusick`: the drape test, its mesh-convergence check, and
/// DIR/report.json, DIR/shadow.png (top view) and DIR/cloth.obj.
pub fn scenario(a: CusickArgs) -> Res<()> {
    let name = a.fabric.clone().unwrap_or_else(|| "custom".into());
    let r = run_one(&a, a.edge, &format!("{name}, {:.1} mm mesh", a.edge * 1e3))?;
    let fine = if a.refine {
        let e = a.edge / std::f32::consts::SQRT_2;
        Some(run_one(&a, e, &format!("{name}, {:.1} mm mesh", e * 1e3))?)
    } else {
        None
    };
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let (big, disc) = a.standard.radii();
    let picture = shadow::top_view(&r.radii, disc, big, 600, big * 1.1);
    let png = sim_core::mesh::png::rgba_png(&picture, 600, 600)?;
    write(&a.out.join("shadow.png"), &png)?;
    let obj = a.out.join("cloth.obj");
    sim_core::mesh::obj::write_obj(&obj, "specimen", &r.positions, Some(&r.uvs), &r.tris, None)
        .map_err(|e| format!("{}: {e}", obj.display()))?;
    let measured = a
        .fabric
        .as_deref()
        .and_then(|n| Library::builtin().get(n).ok().cloned());
    let report = serde_json::json!({
        "scenario": "cusick",
        "fabric": name,
        "model": a.model.name(),
        "material": a.material,
        "drape_coefficient": r.drape_coefficient,
        "drape_coefficient_refined": fine.as_ref().map(|f| f.drape_coefficient),
        "converged": fine.as_ref().map(|f| (f.drape_coefficient - r.drape_coefficient).abs() < 0.01),
        "nodes": r.nodes,
        "nodes_refined": fine.as_ref().map(|f| f.nodes),
        "node_depths_m": r.node_depths_m,
        "dc_measured": measured.as_ref().and_then(|f| f.dc_measured),
        "nodes_measured": measured.as_ref().and_then(|f| f.nodes_measured),
        "run": r,
        "run_refined": fine,
    });
    write(
        &a.out.join("report.json"),
        (serde_json::to_string_pretty(&report)? + "\n").as_bytes(),
    )?;
    eprintln!(
        "cusick {name}: DC {:.1}%{} , {} nodes (mean depth {:.1} mm), settled {} after {:.1} s simulated in {:.1} s ({} vertices, frame p50 {:.2} ms), {} crossing pairs",
        r.drape_coefficient * 100.0,
        fine.as_ref().map_or(String::new(), |f| format!(
            " ({:.1}% on the {:.1} mm mesh)",
            f.drape_coefficient * 100.0,
            f.edge_m * 1e3
        )),
        r.nodes,
        r.node_depth_mean_m * 1e3,
        r.settled,
        r.simulated_s,
        r.wall_s,
        r.vertices,
        r.frame_ms_p50,
        r.crossings_self
    );
    eprintln!("wrote {}", a.out.join("report.json").display());
    Ok(())
}

fn write(path: &Path, bytes: &[u8]) -> Res<()> {
    std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()).into())
}

/// One row of the validation.
#[derive(serde::Serialize)]
struct Row {
    name: String,
    dc_measured: f64,
    dc_sim: f64,
    nodes_measured: Option<u32>,
    nodes_sim: usize,
    dc_source_sim: Option<f64>,
    settled: bool,
    wall_s: f64,
}

/// `cloth-sim validate-fabrics`: the drape test on every fabric whose source measured its
/// drape, beside the measurement; a Markdown table on stdout, `--json FILE` for tools.
pub fn validate(model: ModelKind, edge: f32, json: Option<PathBuf>, quiet: bool) -> Res<()> {
    let lib = Library::builtin();
    let measured: Vec<&Fabric> = lib
        .fabrics
        .iter()
        .filter(|f| f.dc_measured.is_some())
        .collect();
    let mut rows = Vec::new();
    for (k, f) in measured.iter().enumerate() {
        if !quiet {
            eprintln!(
                "validate-fabrics: {} ({}/{})",
                f.name,
                k + 1,
                measured.len()
            );
        }
        let mut cfg = CusickConfig::new(f.material());
        cfg.edge = edge;
        cfg.model = model;
        let r = cusick::run(&cfg, &mut |_, _| {})?;
        rows.push(Row {
            name: f.name.clone(),
            dc_measured: f.dc_measured.unwrap_or(0.0),
            dc_sim: r.drape_coefficient,
            nodes_measured: f.nodes_measured,
            nodes_sim: r.nodes,
            dc_source_sim: f.dc_source_sim,
            settled: r.settled,
            wall_s: r.wall_s,
        });
    }
    let mae = |pick: &dyn Fn(&Row) -> Option<f64>| -> Option<f64> {
        let errs: Vec<f64> = rows
            .iter()
            .filter_map(|r| pick(r).map(|s| (s - r.dc_measured).abs() * 100.0))
            .collect();
        (!errs.is_empty()).then(|| errs.iter().sum::<f64>() / errs.len() as f64)
    };
    let mae_dc = mae(&|r| Some(r.dc_sim));
    let mae_source = mae(&|r| r.dc_source_sim);
    println!(
        "| fabric | DC measured | DC ours | error | DC source's simulator | nodes measured | nodes ours | settled | time |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {:.1} | {:.1} | {:+.1} | {} | {} | {} | {} | {:.1} s |",
            r.name,
            r.dc_measured * 100.0,
            r.dc_sim * 100.0,
            (r.dc_sim - r.dc_measured) * 100.0,
            r.dc_source_sim
                .map_or("-".into(), |d| format!("{:.1}", d * 100.0)),
            r.nodes_measured.map_or("-".into(), |n| n.to_string()),
            r.nodes_sim,
            r.settled,
            r.wall_s
        );
    }
    println!(
        "\nmean absolute DC error over {} fabrics: ours {} points; the source's simulator {} points",
        rows.len(),
        mae_dc.map_or("-".into(), |m| format!("{m:.1}")),
        mae_source.map_or("-".into(), |m| format!("{m:.1}"))
    );
    if let Some(path) = json {
        let doc = serde_json::json!({
            "model": model.name(),
            "edge_m": edge,
            "fabrics": rows,
            "mae_dc": mae_dc,
            "mae_dc_source_sim": mae_source,
        });
        write(
            &path,
            (serde_json::to_string_pretty(&doc)? + "\n").as_bytes(),
        )?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
