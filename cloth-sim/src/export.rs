//! The EXPORT command: the design's files and `sim-report.json`, what cloth-sim measured.

use std::path::Path;

use shared::telemetry::{Histogram, SimTelemetry};
use sim_core::design::Design;
use sim_core::design::export::{export_garment_glb, export_glb, export_obj};
use sim_core::mesh::obj::write_obj;
use sim_core::scenario::Percentiles;
use sim_core::scenario::scripts::fit_gap;

use crate::config::ServiceStats;

/// What cloth-sim reports of the design it exports (`sim-report.json`).
#[derive(Debug, serde::Serialize)]
struct ExportReport {
    model: &'static str,
    body: String,
    vertices: usize,
    triangles: usize,
    frames: u64,
    frame_dt_s: f32,
    substeps: usize,
    /// Wall time of a whole frame since start, ms (telemetry histogram: 1 µs buckets up to
    /// 2 ms, 100 µs above).
    step_ms: Percentiles,
    collision_ms: Percentiles,
    max_penetration_m: f64,
    thickness_m: f32,
    kinetic_energy_final_j: f64,
    settled: bool,
    mesh_valid: bool,
    /// How far the threads are stretched from the pattern (`sim_core::solver::thread_stretch`, as
    /// in the scenario reports and the studio's stretch map): the median triangle's, the
    /// ninetieth percentile's and the most, `length / cut - 1`.
    thread_stretch_p50: f64,
    thread_stretch_p90: f64,
    thread_stretch_max: f64,
    /// Exact counts (`collision::crossings`): intersecting pairs of cloth triangles
    /// (sharing no vertex); intersecting (cloth, body) triangle pairs, and the cloth
    /// triangles among them.
    crossings_self: usize,
    crossings_body: usize,
    crossings_body_triangles: usize,
    seams: usize,
    seam_pairs_welded: u64,
    /// Over the cube's side panels (see `cloth-sim scenario fit-cube`), m.
    fit_gap_mean_m: Option<f64>,
    fit_gap_max_m: Option<f64>,
    undo_depth: usize,
    exported: Vec<String>,
}

fn histogram_ms(h: &Histogram) -> Percentiles {
    Percentiles {
        p50: h.quantile_ns(0.5) as f64 * 1e-6,
        p99: h.quantile_ns(0.99) as f64 * 1e-6,
        max: h.max_ns as f64 * 1e-6,
        mean: h.mean_ns() * 1e-6,
    }
}

/// Writes the design's exports and `sim-report.json` into `dir`, the sewing pattern with a
/// seam allowance of `allowance_mm` (refused outside 0-100 mm before anything is written).
pub(crate) fn export(
    design: &mut Design,
    dir: &Path,
    allowance_mm: f32,
    tel: &SimTelemetry,
    stats: &ServiceStats,
) -> Result<String, String> {
    use sim_core::design::sewing_pattern::MAX_ALLOWANCE_MM;
    // Checked before anything is written: a refused export leaves nothing behind.
    let allowance = allowance_mm as f64;
    if !(0.0..=MAX_ALLOWANCE_MM).contains(&allowance) {
        return Err(format!(
            "a seam allowance of {allowance_mm} mm: it must be 0-{MAX_ALLOWANCE_MM} mm"
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    design.refresh_png_cache().map_err(|e| e.to_string())?;
    let mut files = export_obj(design, dir, "cloth").map_err(|e| e.to_string())?;
    files.push(export_glb(design, dir, "cloth").map_err(|e| e.to_string())?);
    if !design.pieces.is_empty() {
        files.push(export_garment_glb(design, dir).map_err(|e| e.to_string())?);
    }
    files.extend(
        sim_core::design::sewing_pattern::export_pattern(design, dir, allowance)
            .map_err(|e| e.to_string())?,
    );
    let design_path = dir.join("design.saiho");
    design
        .save_design_file(&design_path)
        .map_err(|e| e.to_string())?;
    files.push(design_path);
    let sim = &design.sim;
    let (mut max_pen, mut gap, mut body_name) = (0.0f64, None, String::from("none"));
    if let Some(body) = &sim.body {
        max_pen = sim
            .cloth
            .x
            .iter()
            .map(|&p| body.penetration(p) as f64)
            .fold(0.0, f64::max);
        if body.name == "cube" {
            gap = Some(fit_gap(design, body));
        }
        body_name = body.name.clone();
        let path = dir.join("body.obj");
        write_obj(
            &path,
            &body.name,
            &body.vertices,
            None,
            &body.triangles,
            None,
        )
        .map_err(|e| format!("{}: {e}", path.display()))?;
        files.push(path);
    }
    let ke = sim.cloth.kinetic_energy();
    let threads = sim.cloth.thread_stretch();
    let crossings = sim.crossings();
    let mass: f64 = sim.cloth.mass.iter().map(|&m| m as f64).sum();
    let report = ExportReport {
        model: sim.model.name(),
        body: body_name,
        vertices: sim.cloth.len(),
        triangles: sim.cloth.live.tri_count(),
        frames: sim.frame,
        frame_dt_s: sim.env.frame_dt,
        substeps: sim.substeps,
        step_ms: histogram_ms(&tel.frame_time),
        collision_ms: histogram_ms(&tel.collision_time),
        max_penetration_m: max_pen,
        thickness_m: sim.material.thickness,
        kinetic_energy_final_j: ke,
        settled: ke <= 0.5 * mass * 0.01f64.powi(2),
        mesh_valid: design.validate().is_ok(),
        thread_stretch_p50: threads.p50,
        thread_stretch_p90: threads.p90,
        thread_stretch_max: threads.max,
        crossings_self: crossings.self_pairs,
        crossings_body: crossings.body_pairs,
        crossings_body_triangles: crossings.body_triangles,
        seams: design.seams.len(),
        seam_pairs_welded: stats.welds,
        fit_gap_mean_m: gap.map(|g| g.0),
        fit_gap_max_m: gap.map(|g| g.1),
        undo_depth: design.history.undo_steps(),
        exported: files.iter().map(|p| p.display().to_string()).collect(),
    };
    let path = dir.join("sim-report.json");
    let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(format!(
        "Exported {} files to {}",
        files.len() + 1,
        dir.display()
    ))
}
