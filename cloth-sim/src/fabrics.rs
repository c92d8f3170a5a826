//! `cloth-sim fabrics`, `cloth-sim scenario cusick` and `cloth-sim validate-fabrics`: the
//! fabric library, the drape test on one fabric, and every published drape against ours.

use std::path::{Path, PathBuf};

use sim_core::fabric::cusick::{self, CusickConfig, SPECIMENS, Specimens, Standard};
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
        "{:<24} {:>6} {:>9} {:>9} {:>7} {:>9} {:>9} {:>9} {:>6} {:>6}  source",
        "name", "g/m²", "stretch", "N/m", "shear", "B warp", "B weft", "B bias", "limit", "DC"
    );
    println!(
        "{:<24} {:>6} {:>9} {:>9} {:>7} {:>9} {:>9} {:>9} {:>6} {:>6}",
        "", "", "warp N/m", "weft", "N/m", "µN·m", "µN·m", "µN·m", "x rest", "meas."
    );
    for f in &lib.fabrics {
        let s = f.si();
        println!(
            "{:<24} {:>6.0} {:>9.1} {:>9.1} {:>7.1} {:>9.2} {:>9.2} {:>9.2} {:>6} {:>6}  {}",
            f.name,
            f.weight_gsm,
            s.stretch_warp,
            s.stretch_weft,
            s.shear,
            s.bend_warp * 1e6,
            s.bend_weft * 1e6,
            s.bend_bias * 1e6,
            if s.strain_limit > 0.0 {
                format!("{:.2}", 1.0 + s.strain_limit)
            } else {
                "none".into()
            },
            f.dc_measured
                .map_or("-".into(), |d| format!("{:.1}", d * 100.0)),
            f.source
        );
    }
    println!(
        "{} fabrics; limit: the most a triangle stretches under the xpbd model; units and \
         conversions: docs/fabrics.md; --json for every field",
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

/// The drape test's specimens on a mesh of `edge`.
fn run_specimens(a: &CusickArgs, edge: f32, label: &str) -> Res<Specimens> {
    let quiet = a.quiet;
    let mut progress = |k: usize, t: f32, ke: f64| {
        if !quiet {
            eprintln!(
                "cusick {label}, specimen {} of {SPECIMENS}: {t:.0} s simulated, kinetic energy {ke:.2e} J",
                k + 1
            );
        }
    };
    Ok(cusick::run_specimens(
        &config(a, edge),
        SPECIMENS,
        &mut progress,
    )?)
}

/// `cloth-sim scenario cusick`: the drape test, its mesh-convergence check, and
/// DIR/report.json, DIR/shadow.png (top view) and DIR/cloth.obj.
pub fn scenario(a: CusickArgs) -> Res<()> {
    let name = a.fabric.clone().unwrap_or_else(|| "custom".into());
    let all = run_specimens(&a, a.edge, &format!("{name}, {:.1} mm mesh", a.edge * 1e3))?;
    let fine = if a.refine {
        let e = a.edge / std::f32::consts::SQRT_2;
        Some(run_specimens(
            &a,
            e,
            &format!("{name}, {:.1} mm mesh", e * 1e3),
        )?)
    } else {
        None
    };
    // The pictures and the mesh are the first specimen's.
    let r = &all.runs[0];
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
        "specimens": all.runs.len(),
        "drape_coefficient": all.drape_coefficient(),
        "drape_coefficients": all.runs.iter().map(|r| r.drape_coefficient).collect::<Vec<_>>(),
        "drape_coefficient_spread": all.spread(),
        "drape_coefficient_refined": fine.as_ref().map(Specimens::drape_coefficient),
        "converged": fine.as_ref().map(|f| (f.drape_coefficient() - all.drape_coefficient()).abs() < 0.01),
        "nodes": all.nodes(),
        "nodes_each": all.runs.iter().map(|r| r.nodes).collect::<Vec<_>>(),
        "nodes_refined": fine.as_ref().map(Specimens::nodes),
        "node_depths_m": r.node_depths_m,
        "settled": all.settled(),
        "dc_measured": measured.as_ref().and_then(|f| f.dc_measured),
        "nodes_measured": measured.as_ref().and_then(|f| f.nodes_measured),
        "runs": all.runs,
        "runs_refined": fine.as_ref().map(|f| &f.runs),
    });
    write(
        &a.out.join("report.json"),
        (serde_json::to_string_pretty(&report)? + "\n").as_bytes(),
    )?;
    let each: Vec<String> = all
        .runs
        .iter()
        .map(|r| format!("{:.1}", r.drape_coefficient * 100.0))
        .collect();
    eprintln!(
        "cusick {name}: DC {:.1}% (specimens {}){}, {} nodes, settled {}, each specimen in {:.1} s at most ({} vertices), {} crossing pairs",
        all.drape_coefficient() * 100.0,
        each.join(", "),
        fine.as_ref().map_or(String::new(), |f| format!(
            "; {:.1}% on the {:.1} mm mesh",
            f.drape_coefficient() * 100.0,
            f.runs[0].edge_m * 1e3
        )),
        all.nodes(),
        all.settled(),
        all.slowest_s(),
        r.vertices,
        all.runs.iter().map(|r| r.crossings_self).sum::<usize>()
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
    /// The mean over the specimens, and their highest minus lowest.
    dc_sim: f64,
    dc_sim_spread: f64,
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
        let r = cusick::run_specimens(&cfg, SPECIMENS, &mut |_, _, _| {})?;
        rows.push(Row {
            name: f.name.clone(),
            dc_measured: f.dc_measured.unwrap_or(0.0),
            dc_sim: r.drape_coefficient(),
            dc_sim_spread: r.spread(),
            nodes_measured: f.nodes_measured,
            nodes_sim: r.nodes(),
            dc_source_sim: f.dc_source_sim,
            settled: r.settled(),
            wall_s: r.slowest_s(),
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
        "| fabric | DC measured | DC ours (spread) | error | DC source's simulator | nodes measured | nodes ours | settled | time a specimen |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {:.1} | {:.1} ({:.1}) | {:+.1} | {} | {} | {} | {} | {:.1} s |",
            r.name,
            r.dc_measured * 100.0,
            r.dc_sim * 100.0,
            r.dc_sim_spread * 100.0,
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
            "specimens": SPECIMENS,
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
