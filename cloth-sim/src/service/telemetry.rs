//! The service's telemetry: the frame counted, and `saiho/telemetry/sim` once a second
//! (at once after a pause or a run).

use std::time::Instant;

use shared::Header;
use sim_core::design::Design;
use sim_core::solver::FrameStats;

use super::Service;
use crate::autosave::Autosave;
use crate::commands::model_code;

impl Service<'_> {
    /// Counts the frame, and sends the telemetry once a second.
    /// (`None`: paused, no frame stepped.)
    pub(super) fn record(&mut self, fs: Option<&FrameStats>, autosave: &Autosave) {
        let sim = &self.design.sim;
        let tel = &mut self.tel;
        if let Some(fs) = fs {
            self.stats.welds += fs.welded as u64;
            self.stats.force_limited_substeps += sim.pinch_limited_substeps() as u64;
            for f in sim.pinch_forces() {
                self.stats.pinch_force_max_n = self.stats.pinch_force_max_n.max(f.length());
            }
            tel.frame_time.record((fs.wall_ms * 1e6) as u64);
            tel.collision_time.record((fs.collision_ms * 1e6) as u64);
        }
        if std::mem::take(&mut self.tel_due) || self.tel_at.0.elapsed().as_secs_f64() >= 1.0 {
            let frames = sim.frame.saturating_sub(self.tel_at.1);
            tel.header = Header::next(&mut self.seq_tel);
            tel.frame = sim.frame;
            // The vertices some triangle uses: a deleted piece's stay in the solver's
            // arrays (undo brings them back) but are no cloth.
            let live = &sim.cloth.live;
            tel.vertices = (0..sim.cloth.len() as u32)
                .filter(|&v| live.vertex_alive(v))
                .count() as u32;
            tel.triangles = sim.cloth.live.tri_count() as u32;
            tel.rate_hz = (frames as f64 / self.tel_at.0.elapsed().as_secs_f64()) as f32;
            tel.autosave_ms_max = autosave.hold_max_ms() as f32;
            tel.substeps = sim.substeps as u32;
            tel.pinned = sim.cloth.pinned.iter().filter(|&&p| p).count() as u32;
            let m = &sim.material;
            tel.material = [
                m.density,
                m.stretch,
                m.shear,
                m.bending,
                m.friction,
                m.damping,
                m.shear_damping,
                m.bend_damping,
            ];
            (tel.body, tel.grid) = scene_of(&self.design);
            tel.model = model_code(sim.model);
            tel.never_crosses = u32::from(sim.never_crosses());
            tel.strain_limit = sim.material.strain_limit;
            tel.asleep = u32::from(sim.asleep());
            tel.paused = u32::from(self.paused);
            let _ = self.ports.telemetry.send_copy(**tel);
            self.tel_at = (Instant::now(), sim.frame);
        }
    }
}

/// The running design's body (`shared::telemetry::scene_body`) and, when its pattern is
/// a square grid, that grid's cells a side (0 otherwise): what the UI's Scene panel shows.
fn scene_of(design: &Design) -> (u32, u32) {
    use shared::telemetry::scene_body;
    let body = match design.sim.body.as_ref().map(|b| b.name.as_str()) {
        None => scene_body::NONE,
        Some("cube") => scene_body::CUBE,
        Some("sphere") => scene_body::SPHERE,
        Some("mannequin") => scene_body::MANNEQUIN,
        Some("mannequin-apose") => scene_body::MANNEQUIN_APOSE,
        Some("human") => scene_body::HUMAN,
        Some(_) => scene_body::FILE,
    };
    let rest = &design.sim.cloth.rest;
    let side = (rest.positions.len() as f64).sqrt().round() as usize;
    let grid = match side.checked_sub(1) {
        Some(g)
            if g >= 1
                && side * side == rest.positions.len()
                && rest.triangles.len() == 2 * g * g =>
        {
            g as u32
        }
        _ => 0,
    };
    (body, grid)
}
