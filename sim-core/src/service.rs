//! `cloth-sim run`: the simulation as a process. It steps the cloth at a fixed frame rate,
//! follows the pen (device samples from haptic-loop): button 1 pinches the cloth under the
//! tip and drags it; it publishes the local model the haptic loop renders force from (the
//! pinched vertex, or the cloth and body planes near the tip), keeps going whoever comes
//! and goes, and autosaves the design so a restarted cloth-sim resumes where it was.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use glam::Vec3;
use shared::domain::Domain;
use shared::haptic_to_sim::{AppliedForce, BUTTON_1, DeviceSample};
use shared::sim_to_haptic::{LocalModel, MAX_PLANES};
use shared::sim_to_ui::{ToolState, tool};
use shared::ui_to_sim::{CommandReply, ToolCommand, op};
use shared::{Checked, Header, services};

use crate::cloth::Simulation;
use crate::edit::PenInput;

#[derive(Clone, Debug)]
pub struct ServiceConfig {
    pub domain: Domain,
    /// Frames per second.
    pub rate_hz: f64,
    /// Where the design is autosaved, and resumed from at start.
    pub autosave: PathBuf,
    pub autosave_every_s: f64,
    /// Stop after this many seconds (None: until SIGINT/SIGTERM).
    pub seconds: Option<f64>,
    /// Pinch: grab radius (m) and spring stiffness (N/m).
    pub pinch_radius: f32,
    pub pinch_stiffness: f32,
    /// Limit the pinch's pull on the cloth to the force the haptic loop rendered (the
    /// reaction), when it sends one.
    pub couple_applied_force: bool,
    /// The scene a RESET command rebuilds (with its body, grid and material changes).
    pub scene: crate::scenario::ScenarioConfig,
}

impl ServiceConfig {
    pub fn new(domain: Domain) -> Self {
        let autosave = std::env::temp_dir()
            .join("saiho")
            .join(format!("{}.autosave.saiho", domain.name()));
        Self {
            domain,
            rate_hz: 60.0,
            autosave,
            autosave_every_s: 2.0,
            seconds: None,
            pinch_radius: 0.05,
            pinch_stiffness: 100.0,
            couple_applied_force: true,
            scene: crate::scenario::ScenarioConfig::new(crate::scenario::ScenarioName::DrapeCube),
        }
    }
}

#[derive(Debug, Default, Clone)]
pub struct ServiceStats {
    pub frames: u64,
    pub samples: u64,
    pub rejected: u64,
    pub pinches: u64,
    pub autosaves: u64,
    /// Commands from the UI answered.
    pub commands: u64,
    /// Substeps that took the pen from a sample of their own (pen read per substep).
    pub pen_substeps: u64,
    /// Substeps whose pinch had the haptic loop's applied force as its limit.
    pub coupled_substeps: u64,
    /// Of those, substeps in which the limit bound (the cloth was pulled at it).
    pub force_limited_substeps: u64,
    /// Applied-force messages received from the haptic loop.
    pub applied_forces: u64,
    /// Seam pairs welded.
    pub welds: u64,
    /// Largest pull of the pinch on the cloth in any substep, N.
    pub pinch_force_max_n: f32,
    /// Longest time an autosave held up a frame, ms.
    pub autosave_ms_max: f64,
    pub resumed: bool,
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// The local model for a pen at `tip`.
fn local_model(
    sim: &Simulation,
    tip: Vec3,
    pen_sent_ns: u64,
    seq: &mut u64,
    stiffness: f32,
) -> LocalModel {
    let mut m = LocalModel {
        header: Header::next(seq),
        frame: sim.frame,
        pen_sent_ns,
        stiffness,
        ..Default::default()
    };
    if let Some(p) = sim.pinch() {
        let i = p.vertex as usize;
        m.pinching = 1;
        m.vertex_position = sim.cloth.x[i].to_array();
        m.vertex_velocity = sim.cloth.v[i].to_array();
        return m;
    }
    let mut planes = Vec::with_capacity(MAX_PLANES);
    if let Some(body) = &sim.body
        && let Some(c) = body.contact(tip, 0.05, u32::MAX)
    {
        planes.push([c.normal.x, c.normal.y, c.normal.z, c.normal.dot(c.point)]);
    }
    // The cloth near the tip: a plane through the nearest vertex, facing the tip.
    if let Some(v) = sim.nearest_vertex(tip, 0.03) {
        let x = sim.cloth.x[v as usize];
        let mut n = sim.vertex_normal(v);
        if n.dot(tip - x) < 0.0 {
            n = -n;
        }
        if n != Vec3::ZERO {
            planes.push([n.x, n.y, n.z, n.dot(x)]);
        }
    }
    if let Some(f) = sim.env.floor {
        planes.push([0.0, 1.0, 0.0, f]);
    }
    m.plane_count = planes.len().min(MAX_PLANES) as u32;
    for (k, p) in planes.into_iter().take(MAX_PLANES).enumerate() {
        m.planes[k] = p;
    }
    m
}

/// The current tool and what a press of the pen is in the middle of.
#[derive(Debug)]
struct Tools {
    tool: u32,
    rgba: [u8; 4],
    brush_m: f32,
    sew_first: Option<u32>,
    was_down: bool,
    stroke: Vec<Vec3>,
    tear_was: bool,
}

impl Default for Tools {
    fn default() -> Self {
        Self {
            tool: tool::PINCH,
            rgba: [200, 30, 40, 255],
            brush_m: 0.01,
            sew_first: None,
            was_down: false,
            stroke: Vec::new(),
            tear_was: false,
        }
    }
}

/// The pen as cloth-sim sees it: the samples of the current frame interval (its path),
/// the newest one, and the newest force the haptic loop rendered.
#[derive(Debug, Default)]
struct PenFeed {
    /// Samples received since the last frame started, oldest first.
    path: Vec<DeviceSample>,
    latest: Option<DeviceSample>,
    applied: Option<AppliedForce>,
    /// The reason of the last rejected message, to log once.
    reject: Option<String>,
    reject_new: bool,
}

impl PenFeed {
    fn reject(&mut self, stats: &mut ServiceStats, e: shared::MessageError) {
        stats.rejected += 1;
        let e = e.to_string();
        if self.reject.as_ref() != Some(&e) {
            self.reject = Some(e);
            self.reject_new = true;
        }
    }

    /// Takes whatever arrived (never blocks).
    fn drain(
        &mut self,
        device: &services::Sub<DeviceSample>,
        applied: &services::Sub<AppliedForce>,
        stats: &mut ServiceStats,
    ) {
        while let Ok(Some(s)) = device.receive() {
            match s.check() {
                Ok(()) => {
                    if self.path.len() == self.path.capacity() && !self.path.is_empty() {
                        self.path.remove(0);
                    }
                    self.path.push(*s);
                    self.latest = Some(*s);
                    stats.samples += 1;
                }
                Err(e) => self.reject(stats, e),
            }
        }
        while let Ok(Some(s)) = applied.receive() {
            match s.check() {
                Ok(()) => {
                    self.applied = Some(*s);
                    stats.applied_forces += 1;
                }
                Err(e) => self.reject(stats, e),
            }
        }
    }

    /// The pen for substep `k` of `n`: the frame's path replayed at substep rate (the last
    /// substep takes the newest sample), and the pull limit from the applied force.
    fn input(&self, k: usize, n: usize, cfg: &ServiceConfig) -> Option<PenInput> {
        if self.path.is_empty() {
            return None;
        }
        let i = ((k + 1) * self.path.len())
            .div_ceil(n.max(1))
            .clamp(1, self.path.len())
            - 1;
        let force_limit = match (&self.applied, cfg.couple_applied_force) {
            (Some(a), true) => {
                let age_s = shared::monotonic_ns().saturating_sub(a.header.sent_ns) as f64 * 1e-9;
                // What the hand was pulled with, plus a margin against the lag between
                // the two; nothing once the haptic loop stopped rendering.
                Some(if age_s <= APPLIED_STALE_S {
                    v3(a.force).length() * 1.1 + 0.05
                } else {
                    0.0
                })
            }
            _ => None,
        };
        Some(PenInput {
            target: v3(self.path[i].position),
            force_limit,
        })
    }
}

/// An applied force older than this no longer limits the pinch to its size: the haptic
/// loop is gone, so the cloth gets no pull at all.
const APPLIED_STALE_S: f64 = 0.02;

/// What button 1 does with the current tool this frame.
fn pen_acts(
    sim: &mut Simulation,
    t: &mut Tools,
    p: &DeviceSample,
    cfg: &ServiceConfig,
    stats: &mut ServiceStats,
    log: &mut dyn FnMut(&str),
) {
    let tip = v3(p.position);
    let down = p.buttons & BUTTON_1 != 0;
    let (pressed, released) = (down && !t.was_down, !down && t.was_down);
    t.was_down = down;
    let mut report = |r: Result<String, crate::edit::EditError>| match r {
        Ok(m) => log(&m),
        Err(e) => log(&format!("pen: {e}")),
    };
    match t.tool {
        tool::PINCH | tool::TEAR => {
            if pressed {
                if t.tool == tool::TEAR {
                    t.tear_was = sim.tear.enabled;
                    sim.tear.enabled = true;
                }
                if sim
                    .pinch_begin(tip, cfg.pinch_radius, 0.0, cfg.pinch_stiffness)
                    .is_ok()
                {
                    stats.pinches += 1;
                }
            } else if down {
                sim.pinch_move(tip);
            } else if released {
                sim.pinch_end();
                if t.tool == tool::TEAR {
                    sim.tear.enabled = t.tear_was;
                }
            }
        }
        tool::CUT => {
            if down {
                t.stroke.push(tip);
            } else if released {
                let stroke = std::mem::take(&mut t.stroke);
                report(
                    sim.cut_stroke(&stroke, 0.02)
                        .map(|n| format!("pen: cut through {n} vertices")),
                );
            }
        }
        // Each frame's dab is undoable on its own; refusals (off the cloth) are quiet.
        tool::PAINT if down => {
            let _ = sim.paint(tip, t.brush_m, t.rgba);
        }
        tool::SEW => {
            if pressed && let Some(v) = sim.nearest_vertex(tip, cfg.pinch_radius) {
                match t.sew_first.take() {
                    None => t.sew_first = Some(v),
                    Some(a) => report(sim.sew(a, v).map(|_| format!("pen: sewed {a} and {v}"))),
                }
            }
        }
        tool::PIN => {
            if pressed && let Some(v) = sim.nearest_vertex(tip, cfg.pinch_radius) {
                let on = !sim.cloth.is_pinned(v as usize);
                report(
                    sim.set_pin(v, on)
                        .map(|_| format!("pen: vertex {v} pinned {on}")),
                );
            }
        }
        _ => {}
    }
}

/// Carries out one command from the UI; the message says what happened or why not.
fn command(sim: &mut Simulation, c: &ToolCommand) -> Result<String, String> {
    use crate::edit::TearMode;
    let e = |e: crate::edit::EditError| e.to_string();
    let mode = if c.mode == 1 {
        TearMode::Split
    } else {
        TearMode::Delete
    };
    match c.op {
        op::CUT_VERTEX => sim
            .cut_vertex(c.a, v3(c.vec))
            .map(|n| format!("cut vertex {} (new vertex {n})", c.a))
            .map_err(e),
        op::SEW => sim
            .sew(c.a, c.b)
            .map(|_| format!("sewed {} and {}", c.a, c.b))
            .map_err(e),
        op::TEAR => sim
            .tear_edge(c.a, c.b, mode)
            .map(|_| format!("tore edge ({}, {})", c.a, c.b))
            .map_err(e),
        op::PIN => sim
            .set_pin(c.a, c.mode == 1)
            .map(|_| {
                format!(
                    "vertex {} {}",
                    c.a,
                    if c.mode == 1 { "pinned" } else { "freed" }
                )
            })
            .map_err(e),
        op::PAINT => sim
            .paint(v3(c.vec), c.value, c.rgba)
            .map(|_| "painted".to_string())
            .map_err(e),
        op::REMOVE_REGION => {
            let u = c.uv;
            sim.remove_region(glam::Vec2::new(u[0], u[1]), glam::Vec2::new(u[2], u[3]))
                .map(|n| format!("removed {n} triangles"))
                .map_err(e)
        }
        op::SEAM => {
            let u = c.uv;
            let p = |i: usize| glam::Vec2::new(u[i], u[i + 1]);
            sim.seam_on_pattern([p(0), p(2)], [p(4), p(6)], c.value)
                .map(|n| format!("seam of {n} stitched pairs"))
                .map_err(e)
        }
        op::SET_MATERIAL => {
            let mut m = sim.material;
            material_from(&mut m, c);
            let substeps = (c.a != 0).then_some(c.a as usize);
            sim.set_material(m, substeps)
                .map_err(|e| format!("material not changed: {e}"))?;
            Ok(format!(
                "material: density {} kg/m², stretch {} N/m, shear {} N/m, bending {} N m, \
                 friction {}, damping {}/s; {} substeps",
                m.density, m.stretch, m.shear, m.bending, m.friction, m.damping, sim.substeps
            ))
        }
        op::UNDO => sim.undo().map(|l| format!("undid {l}")).map_err(e),
        op::REDO => sim.redo().map(|l| format!("redid {l}")).map_err(e),
        op::SET_TEAR => {
            if c.mode != 0 && c.value <= 1.0 {
                return Err(format!("tear threshold must be above 1, got {}", c.value));
            }
            sim.tear.enabled = c.mode != 0;
            sim.tear.mode = if c.mode == 2 {
                TearMode::Split
            } else {
                TearMode::Delete
            };
            if c.mode != 0 {
                sim.tear.threshold = c.value;
            }
            Ok(if c.mode == 0 {
                "tearing off".into()
            } else {
                format!("tearing on at {}x", c.value)
            })
        }
        op::SAVE => {
            let path = c.text().unwrap_or_default().to_string();
            sim.refresh_png_cache()
                .and_then(|_| sim.save_design_file(std::path::Path::new(&path)))
                .map(|_| format!("saved {path}"))
                .map_err(|e| e.to_string())
        }
        other => Err(format!("unknown operation {other}")),
    }
}

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
    step_ms: crate::scenario::Percentiles,
    collision_ms: crate::scenario::Percentiles,
    max_penetration_m: f64,
    thickness_m: f32,
    kinetic_energy_final_j: f64,
    settled: bool,
    mesh_valid: bool,
    seams: usize,
    seam_pairs_welded: u64,
    /// Over the cube's side panels (see `cloth-sim scenario fit-cube`), m.
    fit_gap_mean_m: Option<f64>,
    fit_gap_max_m: Option<f64>,
    undo_depth: usize,
    exported: Vec<String>,
}

fn histogram_ms(h: &shared::telemetry::Histogram) -> crate::scenario::Percentiles {
    crate::scenario::Percentiles {
        p50: h.quantile_ns(0.5) as f64 * 1e-6,
        p99: h.quantile_ns(0.99) as f64 * 1e-6,
        max: h.max_ns as f64 * 1e-6,
    }
}

/// Writes the design's exports and `sim-report.json` into `dir`.
fn export(
    sim: &mut Simulation,
    dir: &std::path::Path,
    tel: &shared::telemetry::SimTelemetry,
    stats: &ServiceStats,
) -> Result<String, String> {
    use crate::edit::export::{export_glb, export_obj};
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    sim.refresh_png_cache().map_err(|e| e.to_string())?;
    let mut files = export_obj(sim, dir, "cloth").map_err(|e| e.to_string())?;
    files.push(export_glb(sim, dir, "cloth").map_err(|e| e.to_string())?);
    let design = dir.join("design.saiho");
    sim.save_design_file(&design).map_err(|e| e.to_string())?;
    files.push(design);
    let (mut max_pen, mut gap, mut body_name) = (0.0f64, None, String::from("none"));
    if let Some(body) = &sim.body {
        max_pen = sim
            .cloth
            .x
            .iter()
            .map(|&p| body.penetration(p) as f64)
            .fold(0.0, f64::max);
        if body.name == "cube" {
            gap = Some(crate::scenario::scripts::fit_gap(sim, body));
        }
        body_name = body.name.clone();
        let path = dir.join("body.obj");
        crate::mesh::obj::write_obj(
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
        mesh_valid: sim.validate().is_ok(),
        seams: sim.seams.len(),
        seam_pairs_welded: stats.welds,
        fit_gap_mean_m: gap.map(|g| g.0),
        fit_gap_max_m: gap.map(|g| g.1),
        undo_depth: sim.history.undo_len(),
        exported: files.iter().map(|p| p.display().to_string()).collect(),
    };
    let path = dir.join("sim-report.json");
    let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&path, json + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(format!(
        "exported {} files to {}",
        files.len() + 1,
        dir.display()
    ))
}

/// Publishes the body's triangles (nothing when there is no body).
fn publish_body(
    body_pub: &services::SlicePub<f32, shared::sim_to_ui::BodyMeshHeader>,
    sim: &Simulation,
) -> Result<(), String> {
    let Some(b) = &sim.body else { return Ok(()) };
    let (v, t) = (b.vertices.len(), b.triangles.len());
    let mut s = body_pub
        .loan_slice_uninit(3 * v + 3 * t)
        .map_err(|e| format!("{e:?}"))?;
    *s.user_header_mut() = shared::sim_to_ui::BodyMeshHeader {
        header: Header::next(&mut 0),
        vertices: v as u32,
        triangles: t as u32,
    };
    let s = s.write_from_fn(|i| {
        if i < 3 * v {
            b.vertices[i / 3][i % 3]
        } else {
            let j = i - 3 * v;
            b.triangles[j / 3][j % 3] as f32
        }
    });
    s.send().map_err(|e| format!("{e:?}"))?;
    Ok(())
}

/// The material of a RESET or SET_MATERIAL: `uv[0..6]` = density, stretch, shear,
/// bending, friction, damping; 0 keeps the value in `m`.
fn material_from(m: &mut crate::cloth::Material, c: &ToolCommand) {
    let set = |field: &mut f32, v: f32| {
        if v > 0.0 {
            *field = v;
        }
    };
    set(&mut m.density, c.uv[0]);
    set(&mut m.stretch, c.uv[1]);
    set(&mut m.shear, c.uv[2]);
    set(&mut m.bending, c.uv[3]);
    set(&mut m.friction, c.uv[4]);
    set(&mut m.damping, c.uv[5]);
}

/// The design that replaces the current one for a RESET or LOAD command (the current one
/// is saved first, so a reset loses nothing).
fn replacement(
    sim: &mut Simulation,
    c: &ToolCommand,
    cfg: &ServiceConfig,
) -> Result<(Simulation, String), String> {
    use crate::body::BodyKind;
    let next = if c.op == op::LOAD {
        let path = std::path::PathBuf::from(c.text().unwrap_or_default());
        let s = Simulation::load_design_file(&path).map_err(|e| e.to_string())?;
        (s, format!("loaded {}", path.display()))
    } else {
        let mut scene = cfg.scene.clone();
        scene.body = match c.b {
            shared::ui_to_sim::body::SPHERE => BodyKind::Sphere,
            shared::ui_to_sim::body::MANNEQUIN => BodyKind::Mannequin,
            _ => BodyKind::Cube,
        };
        if c.a != 0 {
            scene.grid = c.a as usize;
        }
        material_from(&mut scene.material, c);
        if c.mode != 0 {
            scene.substeps = Some(c.mode as usize);
        }
        let s = crate::scenario::build_simulation(&scene).map_err(|e| e.to_string())?;
        let msg = format!(
            "new design: {}x{} cloth over the {}",
            scene.grid,
            scene.grid,
            scene.body.name()
        );
        (s, msg)
    };
    let backup = cfg.autosave.with_extension("before-reset.saiho");
    sim.refresh_png_cache()
        .and_then(|_| sim.save_design_file(&backup))
        .map_err(|e| {
            format!("the current design could not be saved first ({e}); nothing changed")
        })?;
    Ok((
        next.0,
        format!("{}; the previous design is in {}", next.1, backup.display()),
    ))
}

/// Publishes texture tile `(x, y)` (in tiles).
fn publish_tile(
    tex: &crate::edit::Texture,
    tile_pub: &services::SlicePub<u8, shared::sim_to_ui::TextureTile>,
    x: usize,
    y: usize,
    seq: &mut u64,
) -> Result<(), String> {
    use crate::edit::TILE;
    let (x0, y0) = (x * TILE, y * TILE);
    let (w, h) = (TILE.min(tex.width - x0), TILE.min(tex.height - y0));
    let mut s = tile_pub
        .loan_slice_uninit(4 * w * h)
        .map_err(|e| format!("{e:?}"))?;
    *s.user_header_mut() = shared::sim_to_ui::TextureTile {
        header: Header::next(seq),
        texture_version: tex.version,
        width: tex.width as u32,
        height: tex.height as u32,
        x0: x0 as u32,
        y0: y0 as u32,
        w: w as u32,
        h: h as u32,
    };
    let row = 4 * w;
    let s = s.write_from_fn(|i| {
        let (r, c) = (i / row, i % row);
        tex.rgba[4 * ((y0 + r) * tex.width + x0) + c]
    });
    s.send().map_err(|e| format!("{e:?}"))?;
    Ok(())
}

/// Publishes this frame's positions and normals, and the mesh when its topology changed.
fn publish_cloth(
    sim: &Simulation,
    frame_pub: &services::SlicePub<f32, shared::sim_to_ui::ClothFrameHeader>,
    mesh_pub: &services::SlicePub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
    normals: &mut Vec<Vec3>,
    pen_sent_ns: u64,
    seq_frame: &mut u64,
    seq_mesh: &mut u64,
    mesh_sent: &mut Option<u64>,
) -> Result<(), String> {
    use shared::sim_to_ui::{ClothFrameHeader, MeshCorner, MeshHeader};
    let live = &sim.cloth.live;
    let n = sim.cloth.len();
    let topology = live.version();
    if *mesh_sent != Some(topology) {
        let t = live.tri_count();
        let mut s = mesh_pub
            .loan_slice_uninit(3 * t)
            .map_err(|e| format!("{e:?}"))?;
        *s.user_header_mut() = MeshHeader {
            header: Header::next(seq_mesh),
            topology,
            vertices: n as u32,
            triangles: t as u32,
        };
        let mut corners = live.iter().flat_map(|(_, tri)| {
            (0..3).map(move |k| MeshCorner {
                vertex: tri.v[k],
                u: tri.uv[k].x,
                v: tri.uv[k].y,
            })
        });
        let s = s.write_from_fn(|_| corners.next().unwrap_or_default());
        s.send().map_err(|e| format!("{e:?}"))?;
        *mesh_sent = Some(topology);
    }
    normals.clear();
    normals.resize(n, Vec3::ZERO);
    for (_, t) in live.iter() {
        let [a, b, c] = t.v.map(|i| sim.cloth.x[i as usize]);
        let nn = (b - a).cross(c - a);
        for &i in &t.v {
            normals[i as usize] += nn;
        }
    }
    let stitches: Vec<(u32, u32)> = sim.seams.iter().flat_map(|s| s.open_pairs()).collect();
    let mut s = frame_pub
        .loan_slice_uninit(6 * n + 2 * stitches.len())
        .map_err(|e| format!("{e:?}"))?;
    *s.user_header_mut() = ClothFrameHeader {
        header: Header::next(seq_frame),
        frame: sim.frame,
        topology,
        texture_version: sim.texture.version,
        pen_sent_ns,
        vertices: n as u32,
        stitches: stitches.len() as u32,
    };
    let x = &sim.cloth.x;
    let s = s.write_from_fn(|i| {
        if i < 3 * n {
            x[i / 3][i % 3]
        } else if i < 6 * n {
            let j = i - 3 * n;
            normals[j / 3].normalize_or(Vec3::Y)[j % 3]
        } else {
            let (a, b) = stitches[(i - 6 * n) / 2];
            (if i % 2 == 0 { a } else { b }) as f32
        }
    });
    s.send().map_err(|e| format!("{e:?}"))?;
    Ok(())
}

/// Resumes from the autosave if there is a valid one, else builds the scene with `fresh`.
pub fn resume_or(
    cfg: &ServiceConfig,
    fresh: impl FnOnce() -> Result<Simulation, String>,
    log: &mut dyn FnMut(&str),
) -> Result<(Simulation, bool), String> {
    if cfg.autosave.is_file() {
        match Simulation::load_design_file(&cfg.autosave) {
            Ok(s) => {
                log(&format!(
                    "resumed the design from {}",
                    cfg.autosave.display()
                ));
                return Ok((s, true));
            }
            Err(e) => log(&format!(
                "autosave {} not used: {e}; starting a new design",
                cfg.autosave.display()
            )),
        }
    }
    Ok((fresh()?, false))
}

/// Runs the service until `stop` or `cfg.seconds`.
pub fn run(
    mut sim: Simulation,
    cfg: &ServiceConfig,
    stop: &AtomicBool,
    log: &mut dyn FnMut(&str),
) -> Result<ServiceStats, String> {
    let mut stats = ServiceStats::default();
    let node = services::node(&cfg.domain, "cloth-sim").map_err(|e| e.to_string())?;
    let pe = |e: &dyn std::fmt::Debug| format!("{e:?}");
    let device = services::device(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .buffer_size(32)
        .create()
        .map_err(|e| pe(&e))?;
    let applied_sub = services::applied_force(&node)
        .map_err(|e| e.to_string())?
        .subscriber_builder()
        .create()
        .map_err(|e| pe(&e))?;
    let model_pub = services::local_model(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|e| pe(&e))?;
    use iceoryx2::prelude::AllocationStrategy;
    let frame_pub = services::cloth_frame(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .initial_max_slice_len(6 * sim.cloth.len())
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .map_err(|e| pe(&e))?;
    let mesh_pub = services::cloth_mesh(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .initial_max_slice_len(3 * sim.cloth.live.tri_count())
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .map_err(|e| pe(&e))?;
    // The body, once (a late viewer gets it from the history), and again after a reset.
    let body_pub = services::body_mesh(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .initial_max_slice_len(
            sim.body
                .as_ref()
                .map_or(1, |b| 3 * b.vertices.len() + 3 * b.triangles.len())
                .max(1),
        )
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .map_err(|e| pe(&e))?;
    publish_body(&body_pub, &sim)?;
    let server = services::commands(&node)
        .map_err(|e| e.to_string())?
        .server_builder()
        .create()
        .map_err(|e| pe(&e))?;
    let mut seq_reply = 0u64;
    let tool_pub = services::tool_state(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|e| pe(&e))?;
    let mut tools = Tools::default();
    let mut seq_tool = 0u64;
    let mut tool_sent: Option<ToolState> = None;
    let tile_pub = services::texture(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .initial_max_slice_len(4 * crate::edit::TILE * crate::edit::TILE)
        .create()
        .map_err(|e| pe(&e))?;
    let mut seq_tile = 0u64;
    let tel_pub = services::sim_telemetry(&node)
        .map_err(|e| e.to_string())?
        .publisher_builder()
        .create()
        .map_err(|e| pe(&e))?;
    let mut tel = Box::<shared::telemetry::SimTelemetry>::default();
    let mut seq_tel = 0u64;
    let mut tel_at = (Instant::now(), sim.frame);
    let mut tile_cursor = 0usize;
    let mut seq_frame = 0u64;
    let mut seq_mesh = 0u64;
    let mut mesh_sent: Option<u64> = None;
    let threads = sim.threads();
    let mut normals: Vec<Vec3> = Vec::new();
    if let Some(dir) = cfg.autosave.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let period = Duration::from_secs_f64(1.0 / cfg.rate_hz.clamp(1.0, 1000.0));
    let started = Instant::now();
    let mut next = started + period;
    let mut last_save = Instant::now();
    // The autosave's file write runs on its own thread: the frame only serialises.
    let (save_tx, save_rx) = std::sync::mpsc::sync_channel::<Vec<u8>>(1);
    let save_path = cfg.autosave.clone();
    let writer = std::thread::spawn(move || -> Vec<String> {
        let mut errors = Vec::new();
        for bytes in save_rx {
            let tmp = save_path.with_extension("saiho.tmp");
            if let Err(e) =
                std::fs::write(&tmp, &bytes).and_then(|_| std::fs::rename(&tmp, &save_path))
            {
                errors.push(format!("autosave to {} failed: {e}", save_path.display()));
            }
        }
        errors
    });
    let mut save_ms: Vec<f64> = Vec::new();
    let mut seq = 0u64;
    let mut feed = PenFeed {
        path: Vec::with_capacity(64),
        ..Default::default()
    };
    while !stop.load(Ordering::Relaxed)
        && cfg
            .seconds
            .is_none_or(|s| started.elapsed().as_secs_f64() < s)
    {
        // The path starts afresh with the newest sample of the last frame.
        if let Some(last) = feed.path.last().copied() {
            feed.path.clear();
            feed.path.push(last);
        }
        feed.drain(&device, &applied_sub, &mut stats);
        while let Ok(Some(req)) = server.receive() {
            let cmd = *req.payload();
            let (ok, msg) = match cmd.check() {
                Err(e) => {
                    stats.rejected += 1;
                    (false, e.to_string())
                }
                Ok(()) if cmd.op == op::SET_TOOL => {
                    tools.tool = cmd.a;
                    tools.rgba = cmd.rgba;
                    tools.brush_m = cmd.value;
                    tools.sew_first = None;
                    (true, format!("tool {}", cmd.a))
                }
                Ok(()) if cmd.op == op::RESET || cmd.op == op::LOAD => {
                    match replacement(&mut sim, &cmd, cfg) {
                        Ok((next, m)) => {
                            sim = next;
                            sim.set_threads(threads);
                            // The new design counts its own frames (a loaded one may
                            // be behind): the rate starts over with it.
                            tel_at = (Instant::now(), sim.frame);
                            mesh_sent = None;
                            tools.sew_first = None;
                            if let Err(e) = publish_body(&body_pub, &sim) {
                                log(&format!("publishing the body failed: {e}"));
                            }
                            log(&m);
                            (true, m)
                        }
                        Err(m) => (false, m),
                    }
                }
                Ok(()) if cmd.op == op::EXPORT => {
                    let dir = std::path::PathBuf::from(cmd.text().unwrap_or_default());
                    match export(&mut sim, &dir, &tel, &stats) {
                        Ok(m) => (true, m),
                        Err(m) => (false, m),
                    }
                }
                Ok(()) => match command(&mut sim, &cmd) {
                    Ok(m) => (true, m),
                    Err(m) => (false, m),
                },
            };
            stats.commands += 1;
            let reply = CommandReply::new(
                Header::next(&mut seq_reply),
                cmd.header.seq,
                ok,
                sim.history.undo_len(),
                &msg,
            );
            let _ = req.send_copy(reply);
        }
        if let Some(p) = feed.latest {
            pen_acts(&mut sim, &mut tools, &p, cfg, &mut stats, log);
        }
        // The tool state, when it changed (a late UI gets it from the history).
        let state = ToolState {
            header: Header::default(),
            tool: tools.tool,
            rgba: tools.rgba,
            brush_m: tools.brush_m,
            undo_depth: sim.history.undo_len() as u32,
            redo_depth: sim.history.redo_len() as u32,
            sew_first: tools.sew_first.unwrap_or(u32::MAX),
        };
        // Late subscribers get the history (last tool state, mesh, body, telemetry) when a
        // publisher updates its connections; these send on change or once a second, so do
        // it every frame: a restarted viewer then has everything within a frame or two.
        {
            use iceoryx2::port::update_connections::UpdateConnections;
            let _ = tool_pub.update_connections();
            let _ = mesh_pub.update_connections();
            let _ = body_pub.update_connections();
            let _ = tel_pub.update_connections();
        }
        if tool_sent != Some(state) {
            let _ = tool_pub.send_copy(ToolState {
                header: Header::next(&mut seq_tool),
                ..state
            });
            tool_sent = Some(state);
        }
        // The local model goes out before the frame too (the state now, with the newest
        // tip): a 60 Hz frame that takes 8-12 ms would otherwise leave gaps near the
        // haptic loop's 20 ms staleness limit between models.
        let _ = model_pub.send_copy(local_model(
            &sim,
            feed.latest
                .map_or(Vec3::splat(f32::INFINITY), |p| v3(p.position)),
            feed.latest.map_or(0, |p| p.header.sent_ns),
            &mut seq,
            cfg.pinch_stiffness,
        ));
        // The pen is read again before each substep: samples that arrive while the frame
        // is computed join the path.
        let pinching = sim.pinch().is_some();
        let fs = match sim.step_with(&mut |k, n| {
            if !pinching {
                return None;
            }
            feed.drain(&device, &applied_sub, &mut stats);
            let input = feed.input(k, n, cfg)?;
            stats.pen_substeps += 1;
            if input.force_limit.is_some() {
                stats.coupled_substeps += 1;
            }
            Some(input)
        }) {
            Ok(fs) => fs,
            Err(e) => return Err(format!("the simulation failed: {e}")),
        };
        stats.welds += fs.welded as u64;
        stats.force_limited_substeps += sim.pinch_limited_substeps() as u64;
        for f in sim.pinch_forces() {
            stats.pinch_force_max_n = stats.pinch_force_max_n.max(f.length());
        }
        tel.frame_time.record((fs.wall_ms * 1e6) as u64);
        tel.collision_time.record((fs.collision_ms * 1e6) as u64);
        if tel_at.0.elapsed().as_secs_f64() >= 1.0 {
            let frames = sim.frame.saturating_sub(tel_at.1);
            tel.header = Header::next(&mut seq_tel);
            tel.frame = sim.frame;
            tel.vertices = sim.cloth.len() as u32;
            tel.triangles = sim.cloth.live.tri_count() as u32;
            tel.rate_hz = (frames as f64 / tel_at.0.elapsed().as_secs_f64()) as f32;
            tel.autosave_ms_max = save_ms.iter().copied().fold(0.0, f64::max) as f32;
            tel.substeps = sim.substeps as u32;
            let m = &sim.material;
            tel.material = [
                m.density, m.stretch, m.shear, m.bending, m.friction, m.damping,
            ];
            let _ = tel_pub.send_copy(*tel);
            tel_at = (Instant::now(), sim.frame);
        }
        stats.frames += 1;
        let pen_sent_ns = feed.latest.map_or(0, |p| p.header.sent_ns);
        if let Err(e) = publish_cloth(
            &sim,
            &frame_pub,
            &mesh_pub,
            &mut normals,
            pen_sent_ns,
            &mut seq_frame,
            &mut seq_mesh,
            &mut mesh_sent,
        ) {
            log(&format!("publishing the cloth failed: {e}"));
        }
        // Texture: changed tiles now, and 8 more round-robin so a late viewer fills in.
        {
            let mut tiles = sim.texture.take_dirty();
            let (tx, ty) = (sim.texture.tiles_x(), sim.texture.tiles_y());
            for _ in 0..8 {
                tiles.push((tile_cursor % tx, (tile_cursor / tx) % ty));
                tile_cursor = (tile_cursor + 1) % (tx * ty);
            }
            for (x, y) in tiles {
                if let Err(e) = publish_tile(&sim.texture, &tile_pub, x, y, &mut seq_tile) {
                    log(&format!("publishing the texture failed: {e}"));
                    break;
                }
            }
        }
        if feed.reject_new {
            log(&format!(
                "rejected a message from haptic-loop: {}",
                feed.reject.as_deref().unwrap_or("?")
            ));
            feed.reject_new = false;
        }
        let tip = feed
            .latest
            .map_or(Vec3::splat(f32::INFINITY), |p| v3(p.position));
        let _ = model_pub.send_copy(local_model(
            &sim,
            tip,
            pen_sent_ns,
            &mut seq,
            cfg.pinch_stiffness,
        ));
        if last_save.elapsed().as_secs_f64() >= cfg.autosave_every_s {
            let t = Instant::now();
            match sim.refresh_png_cache().and_then(|_| sim.save_design()) {
                // A full channel means the writer is still busy: skip this one.
                Ok(bytes) => {
                    if save_tx.try_send(bytes).is_ok() {
                        stats.autosaves += 1;
                    }
                }
                Err(e) => log(&format!("autosave failed: {e}")),
            }
            save_ms.push(t.elapsed().as_secs_f64() * 1e3);
            last_save = Instant::now();
        }
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
            next += period;
        } else {
            next = now + period;
        }
    }
    drop(save_tx);
    for e in writer.join().unwrap_or_default() {
        log(&e);
    }
    if let Err(e) = sim
        .refresh_png_cache()
        .and_then(|_| sim.save_design_file(&cfg.autosave))
    {
        log(&format!("final autosave failed: {e}"));
    } else {
        stats.autosaves += 1;
    }
    if !save_ms.is_empty() {
        save_ms.sort_by(f64::total_cmp);
        stats.autosave_ms_max = save_ms[save_ms.len() - 1];
    }
    Ok(stats)
}
