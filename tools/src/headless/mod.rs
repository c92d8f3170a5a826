//! The headless scenarios of cloth-lab: a scripted stand-in for the designer at cloth-ui,
//! driving the real cloth-sim through the same services the UI uses (cloth frames and
//! mesh in, commands out).
//!
//! fit-cube, the paper's experiment: wait for the cloth to drape over the cube; find the
//! cube's top face on the pattern (the vertices resting at the top); delete the four
//! corner squares beyond it (select on the pattern, delete); seam the two flaps that meet
//! at each vertical edge (two boundary paths drawn on the pattern); let the seams pull
//! shut; export.
//!
//! dress-mannequin (`dress`): the shipped dress sewn round the mannequin, its hem pulled
//! with the pen, its neckline cut, exported.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde::Serialize;
use shared::command::Command;
use shared::domain::Domain;
use shared::ports::{CommandClient, DesignerPorts};
use shared::sim_to_ui::{check_frame, check_mesh};
use shared::ui_to_sim::CommandReply;
use shared::{Checked, Header, services};

use crate::stats::{Percentiles, new_hdr};

mod dress;

pub use dress::{DRESS_SVG, DressReport, dress_mannequin};

/// Frames of draping before the operations (as `cloth-sim scenario fit-cube`).
pub const DRAPE_FRAMES: u64 = 240;
/// Frames after the seams are added, for them to pull shut and the cloth to settle.
pub const SEW_FRAMES: u64 = 360;

/// What the stand-in has seen of the cloth: per-vertex UV from the mesh, positions from
/// the newest frame.
struct Seen {
    frames: services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
    meshes: services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
    uv: Vec<[f32; 2]>,
    /// The mesh's corners, three a triangle.
    corners: Vec<shared::sim_to_ui::MeshCorner>,
    x: Vec<[f32; 3]>,
    frame: u64,
    topology: Option<u64>,
    last_note: Instant,
}

impl Seen {
    fn new(
        frames: services::SliceSub<f32, shared::sim_to_ui::ClothFrameHeader>,
        meshes: services::SliceSub<shared::sim_to_ui::MeshCorner, shared::sim_to_ui::MeshHeader>,
    ) -> Self {
        Self {
            frames,
            meshes,
            uv: Vec::new(),
            corners: Vec::new(),
            x: Vec::new(),
            frame: 0,
            topology: None,
            last_note: Instant::now(),
        }
    }

    /// Takes in what arrived; a message that fails its checks is an error.
    fn poll(&mut self) -> Result<(), String> {
        let pe = |e: &dyn std::fmt::Debug| format!("{e:?}");
        while let Some(m) = self.meshes.receive().map_err(|e| pe(&e))? {
            let h = m.user_header();
            check_mesh(h, m.payload()).map_err(|e| e.to_string())?;
            let mut u = vec![[f32::NAN; 2]; h.vertices as usize];
            for c in m.payload() {
                if let Some(slot) = u.get_mut(c.vertex as usize)
                    && slot[0].is_nan()
                {
                    *slot = [c.u, c.v];
                }
            }
            self.uv = u;
            self.corners = m.payload().to_vec();
            self.topology = Some(h.topology);
        }
        while let Some(f) = self.frames.receive().map_err(|e| pe(&e))? {
            let h = f.user_header();
            check_frame(h, f.payload()).map_err(|e| e.to_string())?;
            let n = h.vertices as usize;
            self.x = f.payload()[..3 * n]
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            self.frame = h.frame;
        }
        Ok(())
    }

    /// Waits until cloth-sim's frame `until`, with mesh and positions that match.
    fn wait(
        &mut self,
        until: u64,
        what: &str,
        stop: &AtomicBool,
        progress: &mut dyn FnMut(&str),
    ) -> Result<(), String> {
        let deadline = Instant::now() + Duration::from_secs_f64(30.0 + until as f64 / 10.0);
        while self.frame < until || self.topology.is_none() || self.uv.len() != self.x.len() {
            if stop.load(Ordering::Relaxed) {
                return Err(format!(
                    "interrupted while {what}: the scenario did not finish (no export)"
                ));
            }
            if Instant::now() > deadline {
                return Err(format!(
                    "cloth-sim stalled while {what}: frame {} of {until}",
                    self.frame
                ));
            }
            self.poll()?;
            if self.last_note.elapsed() >= Duration::from_secs(2) {
                progress(&format!("{what}: frame {}/{until}", self.frame));
                self.last_note = Instant::now();
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        Ok(())
    }
}

/// What the stand-in did and how the command round trips went.
#[derive(Debug, Default, Serialize)]
pub struct StandInReport {
    pub drape_frames: u64,
    /// The cube's top face on the pattern, (u0, v0, u1, v1).
    pub top_face_uv: [f32; 4],
    /// The cut lines on the pattern, just outside the top face.
    pub cut_lines_uv: [f32; 4],
    pub regions_removed: usize,
    pub triangles_removed: usize,
    pub seams: usize,
    pub seam_pairs: usize,
    /// Every command and its reply.
    pub commands: Vec<String>,
    /// Command -> reply round trips, µs.
    pub command_rtt_us: Percentiles,
    pub sim_frames_seen: u64,
}

struct Ui {
    client: CommandClient,
    seq: u64,
    rtt: hdrhistogram::Histogram<u64>,
    log: Vec<String>,
}

impl Ui {
    fn new(client: CommandClient) -> Self {
        Self {
            client,
            seq: 0,
            rtt: new_hdr(),
            log: Vec::new(),
        }
    }

    fn ask(&mut self, command: &Command, stop: &AtomicBool) -> Result<CommandReply, String> {
        let c = command
            .to_wire(Header::next(&mut self.seq))
            .map_err(|e| e.to_string())?;
        let t0 = Instant::now();
        let deadline = t0 + Duration::from_secs(20);
        let pending = loop {
            match self.client.send_copy(c) {
                Ok(p) if p.number_of_server_connections() > 0 => break p,
                _ if Instant::now() < deadline && !stop.load(Ordering::Relaxed) => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                _ => return Err("cloth-sim does not answer commands".into()),
            }
        };
        loop {
            if let Some(r) = pending.receive().map_err(|e| format!("{e:?}"))? {
                r.check().map_err(|e| e.to_string())?;
                let _ = self.rtt.record(t0.elapsed().as_nanos().max(1) as u64);
                let r = *r;
                self.log.push(format!(
                    "op {}: {} {}",
                    c.op,
                    if r.ok == 1 { "done:" } else { "refused:" },
                    r.message()
                ));
                return Ok(r);
            }
            if Instant::now() > deadline || stop.load(Ordering::Relaxed) {
                return Err("no reply from cloth-sim within 20 s".into());
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// Has cloth-sim export the design into `out`.
    fn export(
        &mut self,
        out: &Path,
        stop: &AtomicBool,
        progress: &mut dyn FnMut(&str),
    ) -> Result<(), String> {
        let dir = out
            .canonicalize()
            .map_err(|e| format!("{}: {e}", out.display()))?;
        let m = self.must(
            Command::Export {
                dir: dir.display().to_string(),
                allowance_mm: shared::command::DEFAULT_ALLOWANCE_MM,
            },
            stop,
        )?;
        progress(&m);
        Ok(())
    }

    fn must(&mut self, c: Command, stop: &AtomicBool) -> Result<String, String> {
        let r = self.ask(&c, stop)?;
        if r.ok == 1 {
            Ok(r.message().to_string())
        } else {
            Err(format!("cloth-sim refused op {}: {}", c.op(), r.message()))
        }
    }
}

/// The first number in a reply such as "Cut away: 123 triangles removed from the pattern".
fn number_in(msg: &str) -> usize {
    msg.split_whitespace()
        .find_map(|w| w.parse().ok())
        .unwrap_or(0)
}

/// The draped cloth as seen on the pattern: the cube's top face, the cut lines one grid
/// step outside it, and the pattern's extent.
struct Layout {
    top_face: [f32; 4],
    cut_lines: [f32; 4],
    cell: f32,
    u_range: (f32, f32),
    v_range: (f32, f32),
}

impl Layout {
    /// Finds the top face on the pattern: the vertices resting within 5 mm of the highest.
    fn of(uv: &[[f32; 2]], x: &[[f32; 3]]) -> Result<Self, String> {
        let ymax = x.iter().map(|p| p[1]).fold(f32::MIN, f32::max);
        let top: Vec<usize> = (0..x.len())
            .filter(|&i| x[i][1] > ymax - 0.005 && uv[i][0].is_finite())
            .collect();
        if top.len() < 4 {
            return Err("the cloth does not rest on a flat top: is the body the cube?".into());
        }
        let (mut u0, mut v0, mut u1, mut v1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
        for &i in &top {
            u0 = u0.min(uv[i][0]);
            u1 = u1.max(uv[i][0]);
            v0 = v0.min(uv[i][1]);
            v1 = v1.max(uv[i][1]);
        }
        // The pattern's grid step: the smallest gap between distinct u values.
        let mut us: Vec<f32> = uv.iter().map(|p| p[0]).filter(|u| u.is_finite()).collect();
        us.sort_by(f32::total_cmp);
        us.dedup_by(|a, b| (*a - *b).abs() < 1e-5);
        let cell = us.windows(2).map(|w| w[1] - w[0]).fold(f32::MAX, f32::min);
        if !(cell.is_finite() && cell > 0.0) {
            return Err("cannot find the pattern's grid step".into());
        }
        let vs = uv.iter().map(|p| p[1]).filter(|v| v.is_finite());
        let v_range = vs.fold((f32::MAX, f32::MIN), |(a, b), v| (a.min(v), b.max(v)));
        // Cut on the top face's outermost grid lines: those resting at the top's height
        // lie on the cube's edges or just past them, so the flaps below are as wide as
        // the faces they hang against (to a grid step). A grid line further out (as here
        // until 2026-11-28) left each flap a step too wide, which the seams took up only
        // by pulling the cloth through the cube's edges, where nothing stopped it.
        Ok(Self {
            top_face: [u0, v0, u1, v1],
            cut_lines: [u0, v0, u1, v1],
            cell,
            u_range: (us[0], us[us.len() - 1]),
            v_range,
        })
    }

    /// Each corner: its direction on the pattern and where its two cut lines cross.
    fn corners(&self) -> [(f32, f32, f32, f32); 4] {
        let [cu0, cv0, cu1, cv1] = self.cut_lines;
        [(1.0f32, 1.0f32), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)].map(|(su, sv)| {
            let eu = if su > 0.0 { cu1 } else { cu0 };
            let ev = if sv > 0.0 { cv1 } else { cv0 };
            (su, sv, eu, ev)
        })
    }
}

/// Deletes the four corner squares beyond the cut lines (select on the pattern, delete).
fn cut_corners(
    ui: &mut Ui,
    layout: &Layout,
    report: &mut StandInReport,
    stop: &AtomicBool,
) -> Result<(), String> {
    let far = 10.0;
    for (su, sv, eu, ev) in layout.corners() {
        let m = ui.must(
            Command::RemoveRegion {
                min: [eu, ev],
                max: [eu + su * far, ev + sv * far],
            },
            stop,
        )?;
        report.regions_removed += 1;
        report.triangles_removed += number_in(&m);
    }
    Ok(())
}

/// Seams the two flaps that meet at each vertical edge: path A along the cut line across
/// u, path B along the one across v, both from the corner of the top face outwards.
fn seam_flaps(
    ui: &mut Ui,
    layout: &Layout,
    report: &mut StandInReport,
    stop: &AtomicBool,
) -> Result<(), String> {
    for (su, sv, eu, ev) in layout.corners() {
        let edge_u = if su > 0.0 {
            layout.u_range.1
        } else {
            layout.u_range.0
        };
        let end_v = if sv > 0.0 {
            layout.v_range.1
        } else {
            layout.v_range.0
        };
        let m = ui.must(
            Command::Seam {
                a: [[eu, ev], [eu, end_v]],
                b: [[eu, ev], [edge_u, ev]],
                tolerance: 0.25 * layout.cell,
            },
            stop,
        )?;
        report.seams += 1;
        report.seam_pairs += number_in(&m);
    }
    Ok(())
}

/// Runs the stand-in against cloth-sim in `domain` and exports into `out`.
pub fn fit_cube(
    domain: &Domain,
    out: &Path,
    stop: &AtomicBool,
    progress: &mut dyn FnMut(&str),
) -> Result<StandInReport, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "lab-ui-standin").map_err(|e| e.to_string())?;
    let ports = DesignerPorts::open(&node).map_err(|e| e.to_string())?;
    let mut ui = Ui::new(ports.commands);
    let mut report = StandInReport::default();
    let mut seen = Seen::new(ports.frames, ports.meshes);
    seen.wait(1, "waiting for cloth-sim", stop, progress)?;
    let first = seen.frame;
    seen.wait(first + DRAPE_FRAMES, "draping", stop, progress)?;
    report.drape_frames = seen.frame - first;
    let layout = Layout::of(&seen.uv, &seen.x)?;
    report.top_face_uv = layout.top_face;
    report.cut_lines_uv = layout.cut_lines;
    let [u0, v0, u1, v1] = layout.top_face;
    progress(&format!(
        "draped after {} frames; top face on the pattern u {u0:.3}..{u1:.3}, v {v0:.3}..{v1:.3}; cutting the corners",
        report.drape_frames
    ));
    cut_corners(&mut ui, &layout, &mut report, stop)?;
    seam_flaps(&mut ui, &layout, &mut report, stop)?;
    progress(&format!(
        "{} corners cut ({} triangles), {} seams of {} stitched pairs; letting them pull shut",
        report.regions_removed, report.triangles_removed, report.seams, report.seam_pairs
    ));
    let sewn_from = seen.frame;
    seen.wait(sewn_from + SEW_FRAMES, "sewing", stop, progress)?;
    ui.export(out, stop, progress)?;
    report.sim_frames_seen = seen.frame - first;
    report.command_rtt_us = Percentiles::of(&ui.rtt);
    report.commands = ui.log;
    Ok(report)
}
