//! dress-mannequin across the processes: cloth-sim starts from the shipped dress pattern
//! (front and back placed round the mannequin and sewn at the shoulders and sides); the
//! stand-in lets it drape, pulls the front out at the chest with the pen (the simulated
//! pen, through the haptic loop, as the studio's mouse does: 1.25 m up, where the pen's
//! old fixed workspace never reached), cuts the front's neckline away on the pattern,
//! lets it settle, and exports the garment and its pattern.

use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use serde::Serialize;
use shared::Header;
use shared::command::Command;
use shared::domain::Domain;
use shared::ports::{self, DesignerPorts};
use shared::services::{self, Pub};
use shared::sim_to_ui::tool;
use shared::ui_to_haptic::PointerInput;

use super::{Seen, Ui, number_in};
use crate::stats::Percentiles;

/// The shipped dress pattern (the one `cloth-sim scenario dress-mannequin` drapes).
pub const DRESS_SVG: &str = include_str!("../../../sim-core/assets/dress.svg");
/// Frames for the pieces to be sewn and draped before the pen and the neckline.
pub const DRESS_FRAMES: u64 = 300;
/// Frames after the neckline cut, before the export.
pub const SETTLE_FRAMES: u64 = 180;
/// The front's neckline as `cloth-sim scenario dress-mannequin` cuts it: half its width
/// and its depth below the top edge, on the pattern, m.
const NECKLINE: [f32; 2] = [0.07, 0.08];
/// How far the pen pulls the front out, m.
const PULL: f32 = 0.08;

/// What the stand-in did, and how the commands went.
#[derive(Debug, Default, Serialize)]
pub struct DressReport {
    pub drape_frames: u64,
    /// The chest vertex the pen took, where it was, and how far it came out with the
    /// pen while held (toward where the hand went, `PULL` m), m.
    pub pen_vertex: u32,
    pub pen_vertex_at: [f32; 3],
    pub pen_pulled_m: f32,
    /// The front's neckline removed: its rectangle in UV, and the triangles removed.
    pub neckline_uv: [f32; 4],
    pub neckline_triangles: usize,
    pub commands: Vec<String>,
    pub command_rtt_us: Percentiles,
    pub sim_frames_seen: u64,
}

/// Runs the stand-in against cloth-sim (started on the dress pattern) in `domain`, and
/// exports into `out`.
pub fn dress_mannequin(
    domain: &Domain,
    out: &Path,
    stop: &AtomicBool,
    progress: &mut dyn FnMut(&str),
) -> Result<DressReport, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "lab-ui-standin").map_err(|e| e.to_string())?;
    let ports = DesignerPorts::open(&node).map_err(|e| e.to_string())?;
    let pointer = ports::publisher(&node, services::pointer).map_err(|e| e.to_string())?;
    let mut ui = Ui::new(ports.commands);
    let mut seen = Seen::new(ports.frames, ports.meshes);
    let mut report = DressReport::default();
    seen.wait(1, "waiting for cloth-sim", stop, progress)?;
    let first = seen.frame;
    seen.wait(first + DRESS_FRAMES, "sewing and draping", stop, progress)?;
    report.drape_frames = seen.frame - first;
    let mut pen = Pen {
        publisher: pointer,
        seq: 0,
    };
    pull_the_front(&mut ui, &mut pen, &mut seen, &mut report, stop, progress)?;
    let rect = neckline(&seen)?;
    report.neckline_uv = rect;
    let m = ui.must(
        Command::RemoveRegion {
            min: [rect[0], rect[1]],
            max: [rect[2], rect[3]],
        },
        stop,
    )?;
    report.neckline_triangles = number_in(&m);
    progress(&format!(
        "neckline cut: {} triangles; settling",
        report.neckline_triangles
    ));
    let cut_at = seen.frame;
    seen.wait(cut_at + SETTLE_FRAMES, "settling", stop, progress)?;
    ui.export(out, stop, progress)?;
    report.sim_frames_seen = seen.frame - first;
    report.command_rtt_us = Percentiles::of(&ui.rtt);
    report.commands = ui.log;
    Ok(report)
}

/// The simulated pen's hand, moved as the studio moves it (`saiho/pointer`).
struct Pen {
    publisher: Pub<PointerInput>,
    seq: u64,
}

impl Pen {
    /// Holds the hand at `target` with `buttons` for `secs`, sent every 10 ms, while
    /// taking in cloth-sim's frames.
    fn hold(
        &mut self,
        target: [f32; 3],
        buttons: u32,
        secs: f64,
        seen: &mut Seen,
    ) -> Result<(), String> {
        let until = Instant::now() + Duration::from_secs_f64(secs);
        while Instant::now() < until {
            self.publisher
                .send_copy(PointerInput {
                    header: Header::next(&mut self.seq),
                    target,
                    buttons,
                    _reserved: 0,
                    _pad: 0,
                })
                .map_err(|e| format!("the pen's pointer: {e:?}"))?;
            seen.poll()?;
            std::thread::sleep(Duration::from_millis(10));
        }
        Ok(())
    }
}

/// Pinches the front at the middle of the chest with the pen and pulls it `PULL` m out,
/// then lets go: the pen reaches the garment on the mannequin (its workspace is the
/// scene's).
fn pull_the_front(
    ui: &mut Ui,
    pen: &mut Pen,
    seen: &mut Seen,
    report: &mut DressReport,
    stop: &AtomicBool,
    progress: &mut dyn FnMut(&str),
) -> Result<(), String> {
    ui.must(
        Command::SetTool {
            tool: tool::PINCH,
            rgba: [0, 0, 0, 255],
            brush_m: 0.02,
        },
        stop,
    )?;
    // The middle of the chest: of the vertices 1.2-1.3 m up near the middle, the one
    // furthest in front.
    let v = (0..seen.x.len())
        .filter(|&i| (1.2..1.3).contains(&seen.x[i][1]) && seen.x[i][0].abs() < 0.05)
        .max_by(|&a, &b| seen.x[a][2].total_cmp(&seen.x[b][2]))
        .ok_or("no cloth on the chest: did the dress drape?")?;
    let at = seen.x[v];
    let out = |d: f32| [at[0], at[1], at[2] + d];
    pen.hold(out(0.03), 0, 0.6, seen)?;
    pen.hold(out(0.0), 0, 0.4, seen)?;
    pen.hold(out(0.0), 1, 0.3, seen)?;
    for k in 1..=20 {
        pen.hold(out(PULL * k as f32 / 20.0), 1, 0.05, seen)?;
    }
    pen.hold(out(PULL), 1, 0.8, seen)?;
    let pulled = seen.x.get(v).map_or(0.0, |p| p[2] - at[2]);
    pen.hold(out(PULL), 0, 0.3, seen)?;
    pen.hold(out(0.2), 0, 0.5, seen)?;
    report.pen_vertex = v as u32;
    report.pen_vertex_at = at;
    report.pen_pulled_m = pulled;
    progress(&format!(
        "the pen pulled the front at ({:.2}, {:.2}, {:.2}) m out by {:.0} mm",
        at[0],
        at[1],
        at[2],
        1e3 * pulled
    ));
    Ok(())
}

/// The front's neckline in UV: the front piece is the pattern island of the corner of
/// the front-most cloth vertex at chest height; the neckline is the square of
/// `NECKLINE` below the middle of its top edge on the pattern (as the in-process scenario
/// cuts it), mapped to the island's UVs.
fn neckline(seen: &Seen) -> Result<[f32; 4], String> {
    let seed_vertex = (0..seen.x.len())
        .filter(|&i| (1.2..1.4).contains(&seen.x[i][1]))
        .max_by(|&a, &b| seen.x[a][2].total_cmp(&seen.x[b][2]))
        .ok_or("no cloth at chest height")?;
    let corners = &seen.corners;
    let seed = corners
        .iter()
        .position(|c| c.vertex as usize == seed_vertex)
        .ok_or("the chest vertex is in no triangle")?;
    let island = island_of(corners, seed);
    let (mut p0, mut p1) = ([f32::MAX; 2], [f32::MIN; 2]);
    let (mut t0, mut t1) = ([f32::MAX; 2], [f32::MIN; 2]);
    for &k in &island {
        let c = &corners[k];
        for a in 0..2 {
            p0[a] = p0[a].min(c.pattern[a]);
            p1[a] = p1[a].max(c.pattern[a]);
        }
        for (a, t) in [c.u, c.v].into_iter().enumerate() {
            t0[a] = t0[a].min(t);
            t1[a] = t1[a].max(t);
        }
    }
    // Each UV axis follows its pattern axis, either way round: the corner at the
    // pattern's least x (y) says at which end of u (v) it lies.
    let lowest = |a: usize| {
        let k = island
            .iter()
            .copied()
            .min_by(|&i, &j| corners[i].pattern[a].total_cmp(&corners[j].pattern[a]))
            .unwrap_or(seed);
        let t = [corners[k].u, corners[k].v][a];
        (t - t0[a]).abs() <= (t - t1[a]).abs()
    };
    let to_uv = |a: usize, p: f32| {
        let s = (p - p0[a]) / (p1[a] - p0[a]).max(1e-6);
        if lowest(a) {
            t0[a] + s * (t1[a] - t0[a])
        } else {
            t1[a] - s * (t1[a] - t0[a])
        }
    };
    let mid = 0.5 * (p0[0] + p1[0]);
    let (x0, x1) = (mid - NECKLINE[0], mid + NECKLINE[0]);
    let (y0, y1) = (p1[1] - NECKLINE[1], p1[1] + 0.01);
    let (u0, u1) = (to_uv(0, x0), to_uv(0, x1));
    let (v0, v1) = (to_uv(1, y0), to_uv(1, y1));
    Ok([u0.min(u1), v0.min(v1), u0.max(u1), v0.max(v1)])
}

/// The corners of the pattern island of corner `seed`: joined within a triangle, and
/// where two corners are the same vertex at the same UV (a weld joins vertices of
/// different pieces, at different UVs).
fn island_of(corners: &[shared::sim_to_ui::MeshCorner], seed: usize) -> Vec<usize> {
    fn root(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    fn join(p: &mut [usize], a: usize, b: usize) {
        let (ra, rb) = (root(p, a), root(p, b));
        p[ra] = rb;
    }
    let mut parent: Vec<usize> = (0..corners.len()).collect();
    let mut first = HashMap::new();
    for (k, c) in corners.iter().enumerate() {
        if k % 3 != 0 {
            join(&mut parent, k, k - k % 3);
        }
        let key = (c.vertex, c.u.to_bits(), c.v.to_bits());
        if let Some(&f) = first.get(&key) {
            join(&mut parent, k, f);
        } else {
            first.insert(key, k);
        }
    }
    let r = root(&mut parent, seed);
    (0..corners.len())
        .filter(|&k| root(&mut parent, k) == r)
        .collect()
}
