//! `cloth-sim run`: the simulation as a process. It steps the design at a fixed frame
//! rate, follows the pen (device samples from haptic-loop: button 1 acts with the current
//! tool), answers the UI's commands, publishes the local model the haptic loop renders
//! force from and the cloth the UI draws, keeps going whoever comes and goes, and
//! autosaves the design so a restarted cloth-sim resumes where it was.
//!
//! One frame: take in the pen and the commands; let the pen act; publish the tool state
//! and a local model; step (the pen read again before every substep); publish the cloth,
//! the texture tiles, telemetry and the local model again; autosave; sleep to the next
//! frame.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use iceoryx2::port::update_connections::UpdateConnections;
use shared::command::Command;
use shared::ports::{SimPorts, SimSizes};
use shared::sim_to_haptic::LocalModel;
use shared::sim_to_ui::{ToolState, put_text};
use shared::telemetry::SimTelemetry;
use shared::ui_to_sim::CommandReply;
use shared::{Header, services};
use sim_core::design::{Design, TILE};
use sim_core::solver::{FrameStats, ModelKind, SleepRule};

use crate::autosave::Autosave;
use crate::commands::{carry_out, replacement, seam_tip, set_strain_limit};
use crate::config::{ServiceConfig, ServiceStats};
use crate::export::export;
use crate::pen::{PenFeed, Tools, pen_acts};
use crate::publish::{
    ClothOut, local_model, mid_frame_model, pinch_model, publish_body, publish_tile,
    scene_workspace,
};

mod pause;
mod telemetry;

/// The running service: its design, ports and everything it keeps between frames.
struct Service<'a> {
    cfg: &'a ServiceConfig,
    design: Design,
    ports: SimPorts,
    stats: ServiceStats,
    tools: Tools,
    feed: PenFeed,
    cloth_out: ClothOut,
    tel: Box<SimTelemetry>,
    /// When the telemetry was last sent, and the frame then.
    tel_at: (Instant, u64),
    tool_sent: Option<ToolState>,
    /// The mesh version, piece and seam counts, open stitches, whether they stalled and
    /// the fabrics the last piece list was sent for.
    pieces_sent: Option<(u64, usize, usize, usize, bool, u64)>,
    seq_pieces: u64,
    tile_cursor: usize,
    threads: usize,
    seq_model: u64,
    seq_reply: u64,
    seq_tool: u64,
    seq_tile: u64,
    seq_tel: u64,
    /// A command changed the design since the autosave last heard of it.
    edited: bool,
    /// Where the time went since the last local model was sent.
    laps: Laps,
    /// When a slow gap between models was last logged, and how many came since.
    slow_logged: (Option<Instant>, u32),
    /// The pen's workspace in the design's scene (`scene_workspace`; a new scene's
    /// replaces it).
    workspace: [f32; 4],
    /// The simulation is paused (SET_SIMULATING): frames step nothing, edits still apply.
    paused: bool,
    /// The telemetry goes out at the next frame, not a second after the last (a pause).
    tel_due: bool,
}

/// Two local models further apart than this are logged with where the time went (the
/// haptic loop lets the force fade once its model is 20 ms old).
const SLOW_MODEL_GAP: Duration = Duration::from_millis(30);
/// A gap between models this long is a stall (the soak's limit): logged at most once a
/// second.
const STALL_GAP: Duration = Duration::from_millis(50);
/// In a frame that has taken this long since the last local model, the next substep
/// sends another (the cloth as the substeps so far left it): frames slower than the
/// haptic loop's 20 ms limit (a cloth landing, a 16k-vertex drape) keep the pen's touch.
const MID_FRAME_MODEL: Duration = Duration::from_millis(5);

/// Where the time between two local models goes: the time since the last mark, per named
/// part (and notes such as how late a sleep woke, which are not parts of the sum).
struct Laps {
    start: Instant,
    last: Instant,
    parts: [(&'static str, Duration); 10],
    n: usize,
}

impl Laps {
    fn start() -> Self {
        let now = Instant::now();
        Self {
            start: now,
            last: now,
            parts: [("", Duration::ZERO); 10],
            n: 0,
        }
    }

    /// Starts counting afresh from now.
    fn restart(&mut self) {
        *self = Self::start();
    }

    fn mark(&mut self, what: &'static str) {
        let now = Instant::now();
        if self.n < self.parts.len() {
            self.parts[self.n] = (what, now - self.last);
            self.n += 1;
        }
        self.last = now;
    }

    /// A figure beside the parts (not a lap: the clock is not marked).
    fn note(&mut self, what: &'static str, d: Duration) {
        if self.n < self.parts.len() {
            self.parts[self.n] = (what, d);
            self.n += 1;
        }
    }

    /// "62.1 ms (commands 0.0, ..., step 8.3, ...)" when more than `limit` has passed.
    fn slow(&self, limit: Duration) -> Option<String> {
        let total = self.start.elapsed();
        (total > limit).then(|| {
            let parts: Vec<String> = self.parts[..self.n]
                .iter()
                .map(|(w, d)| format!("{w} {:.1}", d.as_secs_f64() * 1e3))
                .collect();
            format!(
                "{:.1} ms ({} ms)",
                total.as_secs_f64() * 1e3,
                parts.join(", ")
            )
        })
    }
}

/// Runs the service until `stop` or `cfg.seconds`.
pub fn run(
    design: Design,
    cfg: &ServiceConfig,
    stop: &AtomicBool,
    log: &mut dyn FnMut(&str),
) -> Result<ServiceStats, String> {
    let _release = services::ReleaseOnDrop(cfg.domain.clone());
    // Held until this function returns (dropped before `_release`, which clears the
    // domain's directory): the haptic loop learns of a kill from it before the kernel
    // has torn this process down (`shared::life`).
    let _life = shared::life::LifeLock::hold(&cfg.domain)
        .inspect_err(|e| {
            log(&format!(
                "{e}; the haptic loop will see this process exit from the kernel's notice, a few ms later"
            ))
        })
        .ok();
    let node = services::node(&cfg.domain, "cloth-sim").map_err(|e| e.to_string())?;
    let body_floats = design
        .sim
        .body
        .as_ref()
        .map_or(1, |b| 3 * b.vertices.len() + 3 * b.triangles.len());
    let sizes = SimSizes {
        frame_floats: 6 * design.sim.cloth.len(),
        mesh_corners: 3 * design.sim.cloth.live.tri_count(),
        body_floats,
        tile_bytes: 4 * TILE * TILE,
    };
    let ports = SimPorts::open(&node, sizes).map_err(|e| e.to_string())?;
    // The body, once (a late viewer gets it from the history), and again after a reset.
    publish_body(&ports.body, &design)?;
    let mut s = Service {
        cfg,
        threads: design.sim.threads(),
        tel_at: (Instant::now(), design.sim.frame),
        design,
        ports,
        stats: ServiceStats::default(),
        tools: Tools::default(),
        feed: PenFeed::new(),
        cloth_out: ClothOut::default(),
        tel: Box::default(),
        tool_sent: None,
        pieces_sent: None,
        seq_pieces: 0,
        tile_cursor: 0,
        seq_model: 0,
        seq_reply: 0,
        seq_tool: 0,
        seq_tile: 0,
        seq_tel: 0,
        edited: false,
        laps: Laps::start(),
        slow_logged: (None, 0),
        workspace: [0.0; 4],
        paused: false,
        tel_due: false,
    };
    // A new design from `--pattern` names it; a resumed one keeps what its file says.
    if let Some(p) = &cfg.source {
        s.design.source = p.display().to_string();
    }
    s.workspace = scene_workspace(&s.design);
    let mut autosave = Autosave::start(&cfg.autosave, cfg.autosave_every_s)?;
    let period = Duration::from_secs_f64(1.0 / cfg.rate_hz.clamp(1.0, 1000.0));
    let started = Instant::now();
    let mut next = started + period;
    while !stop.load(Ordering::Relaxed)
        && cfg
            .seconds
            .is_none_or(|secs| started.elapsed().as_secs_f64() < secs)
    {
        let undo_before = s.design.history.undo_len();
        s.frame(&autosave, log)?;
        // A command, or the pen's operation (it goes on the history), changed the design.
        if std::mem::take(&mut s.edited) || s.design.history.undo_len() != undo_before {
            autosave.edited();
        }
        autosave.tick(&mut s.design, &mut s.stats, log);
        s.laps.mark("autosave");
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
            s.laps.mark("sleep");
            // Woken late: the CPU was busy elsewhere (another process, or the host).
            s.laps.note("woken late", next.elapsed());
            next += period;
        } else {
            next = now + period;
        }
    }
    autosave.finish(&mut s.design, &mut s.stats, log);
    Ok(s.stats)
}

/// Where local models go out: the haptic loop's port, the failures counted, and the
/// gap since the last one timed (`laps`), logged when slow.
struct ModelOut<'a> {
    ports: &'a SimPorts,
    stats: &'a mut ServiceStats,
    laps: &'a mut Laps,
    /// When a slow gap was last logged, and how many came since.
    slow_logged: &'a mut (Option<Instant>, u32),
}

impl ModelOut<'_> {
    /// Sends `m`, and logs where the time went when the last model went out
    /// [`SLOW_MODEL_GAP`] ago or more.
    fn send(&mut self, m: LocalModel, log: &mut dyn FnMut(&str)) {
        if let Some(slow) = self.laps.slow(SLOW_MODEL_GAP) {
            // The first, then at most one every 10 s with how many there were between:
            // a machine too slow for its cloth would otherwise log every frame. A stall
            // (a gap of `STALL_GAP` or more, which the soak counts against cloth-sim) is
            // logged at most once a second, so that a lone one's lines say where its time
            // went (a 128 x 128 cloth landing on one core stalls in most frames: 220
            // lines in 45 s when each was logged).
            let stall = self.laps.start.elapsed() >= STALL_GAP;
            let (last, quiet) = &mut *self.slow_logged;
            *quiet += 1;
            let since = |s: u64| last.is_none_or(|t| t.elapsed() >= Duration::from_secs(s));
            if (stall && since(1)) || since(10) {
                let more = if *quiet > 1 {
                    format!(" ({} such gaps since the last line)", *quiet)
                } else {
                    String::new()
                };
                log(&format!(
                    "the pen's model went out {slow} after the last{more}: the haptic loop \
                     fades the force once its model is 20 ms old"
                ));
                *last = Some(Instant::now());
                *quiet = 0;
            }
        }
        self.laps.restart();
        if let Err(e) = self.ports.model.send_copy(m) {
            self.stats.model_send_failures += 1;
            if self.stats.model_send_failures == 1 {
                log(&format!(
                    "sending the pen's model failed: {e:?} (counted from now on)"
                ));
            }
        }
    }
}

impl Service<'_> {
    /// One frame, up to the autosave; where its time went.
    fn frame(&mut self, autosave: &Autosave, log: &mut dyn FnMut(&str)) -> Result<(), String> {
        self.feed.next_frame();
        self.feed
            .drain(&self.ports.device, &self.ports.applied, &mut self.stats);
        // After the pacing sleep (most of a frame at rest), the model again before the
        // commands, which can take tens of ms (a cut, a new piece) on top of it.
        if self.laps.start.elapsed() >= MID_FRAME_MODEL {
            self.send_local_model(log);
        }
        self.serve_commands(log);
        self.laps.mark("commands");
        if self.feed.let_go_if_gone() {
            log("the pen went silent (is haptic-loop running?): its buttons read as released");
        }
        if let Some(p) = self.feed.latest {
            pen_acts(
                &mut self.design,
                &mut self.tools,
                &p,
                self.cfg,
                &mut self.stats,
                log,
            );
        }
        self.laps.mark("pen");
        self.publish_tool_state();
        self.laps.mark("connections");
        self.publish_pieces();
        self.laps.mark("pieces");
        // The local model goes out before the frame too (the state now, with the newest
        // tip): a 60 Hz frame that takes 8-12 ms would otherwise leave gaps near the
        // haptic loop's 20 ms staleness limit between models.
        self.send_local_model(log);
        // The newest pen sample that goes into this frame: while pinching, those the
        // substeps read; otherwise the one its operations acted on (a slow frame reads
        // newer ones for the touch models it sends, which do not move the cloth).
        let (pinching, (_, acted_ns)) = (self.design.sim.pinch().is_some(), self.feed.tip());
        // Paused, nothing moves: the cloth goes out as the edits leave it.
        let fs = if self.paused {
            None
        } else {
            Some(self.step(log)?)
        };
        self.laps.mark("step");
        self.record(fs.as_ref(), autosave);
        self.stats.frames += u64::from(fs.is_some());
        let pen_sent_ns = if pinching {
            self.feed.tip().1
        } else {
            acted_ns
        };
        if let Err(e) = self.cloth_out.publish(
            &self.design,
            &self.ports.frame,
            &self.ports.mesh,
            pen_sent_ns,
        ) {
            log(&format!("publishing the cloth failed: {e}"));
        }
        self.laps.mark("cloth out");
        self.publish_texture(log);
        self.laps.mark("texture");
        if let Some(why) = self.feed.take_new_reject() {
            log(&format!("rejected a message from haptic-loop: {why}"));
        }
        self.send_local_model(log);
        Ok(())
    }

    /// Answers every command that arrived.
    fn serve_commands(&mut self, log: &mut dyn FnMut(&str)) {
        while let Ok(Some(req)) = self.ports.commands.receive() {
            let wire = *req.payload();
            let (ok, msg) = match Command::from_wire(&wire) {
                Err(e) => {
                    self.stats.rejected += 1;
                    (false, e.to_string())
                }
                Ok(c) => match self.command(&c, log) {
                    Ok(m) => {
                        self.edited = true;
                        (true, m)
                    }
                    Err(m) => (false, m),
                },
            };
            self.stats.commands += 1;
            let reply = CommandReply::new(
                Header::next(&mut self.seq_reply),
                wire.header.seq,
                ok,
                self.design.history.undo_steps(),
                &msg,
            );
            let _ = req.send_copy(reply);
        }
    }

    /// Carries out one checked command.
    fn command(&mut self, c: &Command, log: &mut dyn FnMut(&str)) -> Result<String, String> {
        match c {
            Command::SetTool {
                tool,
                rgba,
                brush_m,
            } => {
                (self.tools).switch(&mut self.design, *tool, *rgba, *brush_m);
                Ok(shared::sim_to_ui::tool::sentence(*tool).to_string())
            }
            Command::Reset { .. } | Command::Load { .. } => {
                // A new xpbd scene keeps the guard as the designer left it (on, unless
                // switched off); a loaded design has its own (the file keeps it), unless
                // cloth-sim was started with `--guard` or `--no-guard`.
                let guard = match c {
                    Command::Reset { .. } if self.design.sim.model == ModelKind::Xpbd => {
                        Some(self.design.guarded())
                    }
                    Command::Reset { .. } => Some(self.cfg.scene.guard),
                    _ => self.cfg.guard_forced,
                };
                // And its strain limit, which the material of a new scene (cloth-sim's,
                // changed as RESET asks) does not carry.
                let limit = matches!(c, Command::Reset { .. })
                    .then_some(self.design.sim.material)
                    .filter(|_| self.design.sim.model == ModelKind::Xpbd)
                    .map(|m| m.strain_limit);
                let (next, what, saved) = replacement(&mut self.design, c, self.cfg)?;
                self.design = next;
                // A loaded design names its own pattern (its file keeps it).
                match c {
                    Command::Reset {
                        pattern: Some(p), ..
                    } => self.design.source = p.clone(),
                    Command::Reset { .. } => self.design.source.clear(),
                    _ => {}
                }
                self.workspace = scene_workspace(&self.design);
                self.design.sim.set_threads(self.threads);
                if let Some(on) = guard {
                    self.design.sim.set_guard(on);
                }
                if let Some(limit) = limit
                    && self.design.sim.model == ModelKind::Xpbd
                    && limit != self.design.sim.material.strain_limit
                    && let Err(e) = set_strain_limit(&mut self.design, limit)
                {
                    log(&format!("the new scene's strain limit: {e}"));
                }
                // The tip after the limit is carried over, which it depends on.
                let tip = match c {
                    Command::Reset {
                        pattern: Some(_), ..
                    } if !self.design.seams.is_empty() => seam_tip(&self.design),
                    _ => "",
                };
                let paused = if self.paused {
                    pause::PAUSED_FOR_IT
                } else {
                    ""
                };
                let m = format!(
                    "{paused}{what}{tip}; the previous design is saved in {}",
                    saved.display()
                );
                // The new design counts its own frames (a loaded one may be behind): the
                // rate starts over with it.
                self.tel_at = (Instant::now(), self.design.sim.frame);
                self.cloth_out.mesh_sent = None;
                // Another design may have the same mesh version and piece count.
                self.pieces_sent = None;
                self.tools.sew_first = None;
                if let Err(e) = publish_body(&self.ports.body, &self.design) {
                    log(&format!("publishing the body failed: {e}"));
                }
                log(&m);
                Ok(m)
            }
            Command::Export { dir, allowance_mm } => export(
                &mut self.design,
                std::path::Path::new(dir),
                *allowance_mm,
                &self.tel,
                &self.stats,
            ),
            Command::SetSimulating { on } => Ok(self.set_simulating(*on)),
            Command::AddPiece { .. }
            | Command::PlacePiece { .. }
            | Command::DuplicatePiece { .. } => self.hold_for_piece(c),
            Command::Seam { .. } | Command::SeamPlane { .. } => self.float_new_seam(c),
            other => carry_out(&mut self.design, other),
        }
    }

    /// The piece list, when the mesh, the pieces, their names or fabrics, the seams'
    /// names, darts' presses or their open or stalled pairs, or the pins changed (the history gives a
    /// late UI the last one).
    fn publish_pieces(&mut self) {
        use std::hash::{Hash, Hasher};
        let d = &self.design;
        let mut records = std::collections::hash_map::DefaultHasher::new();
        for p in &d.pieces {
            (&p.name, &p.fabric, p.parts.len()).hash(&mut records);
            for part in &p.parts {
                part.name.hash(&mut records);
            }
        }
        for s in &d.seams {
            (&s.name, s.press_second).hash(&mut records);
        }
        // The pins (a pin of a deleted piece's vertex is not listed; the mesh's version
        // covers that).
        let cloth = &d.sim.cloth;
        for (v, _) in cloth.pinned.iter().enumerate().filter(|(_, p)| **p) {
            v.hash(&mut records);
        }
        let key = (
            d.sim.cloth.live.version(),
            d.pieces.len(),
            d.seams.len(),
            d.seams
                .iter()
                .map(|s| s.open_pairs().count())
                .sum::<usize>(),
            d.stitches_stalled(),
            records.finish(),
        );
        let _ = self.ports.pieces.update_connections();
        if self.pieces_sent == Some(key) {
            return;
        }
        let mut list = crate::publish::piece_list(&self.design, &mut self.seq_pieces);
        list.source_len = shared::sim_to_ui::put_text(&mut list.source, &self.design.source);
        if self.ports.pieces.send_copy(list).is_ok() {
            self.pieces_sent = Some(key);
        }
    }

    /// The tool state, when it changed (a late UI gets it from the history).
    fn publish_tool_state(&mut self) {
        let mut state = ToolState {
            header: Header::default(),
            tool: self.tools.tool,
            rgba: self.tools.rgba,
            brush_m: self.tools.brush_m,
            undo_depth: self.design.history.undo_steps() as u32,
            redo_depth: self.design.history.redo_steps() as u32,
            sew_first: self.tools.sew_first.unwrap_or(u32::MAX),
            pen_said: self.tools.said,
            pen_ok: u32::from(self.tools.last_said.0),
            ..ToolState::default()
        };
        state.pen_message_len = put_text(&mut state.pen_message, &self.tools.last_said.1);
        // Late subscribers get the history (last tool state, mesh, body, telemetry) when a
        // publisher updates its connections; these send on change or once a second, so do
        // it every frame: a restarted viewer then has everything within a frame or two.
        let p = &self.ports;
        let _ = p.tool.update_connections();
        let _ = p.mesh.update_connections();
        let _ = p.body.update_connections();
        let _ = p.telemetry.update_connections();
        if self.tool_sent != Some(state) {
            let _ = p.tool.send_copy(ToolState {
                header: Header::next(&mut self.seq_tool),
                ..state
            });
            self.tool_sent = Some(state);
        }
    }

    /// Sends the local model (`ModelOut::send`).
    fn send_local_model(&mut self, log: &mut dyn FnMut(&str)) {
        let (tip, sent_ns) = self.feed.tip();
        let m = local_model(
            &self.design,
            tip,
            sent_ns,
            &mut self.seq_model,
            (self.cfg.pinch_stiffness, self.workspace),
        );
        let mut out = ModelOut {
            ports: &self.ports,
            stats: &mut self.stats,
            laps: &mut self.laps,
            slow_logged: &mut self.slow_logged,
        };
        out.send(m, log);
    }

    /// Steps one frame; while pinching, the pen is read again before each substep, so
    /// samples that arrive while the frame is computed join the path, and the pinched
    /// vertex goes to the haptic loop as its local model before each substep. Not
    /// pinching, a frame slower than [`MID_FRAME_MODEL`] sends the touch planes between
    /// its substeps; and while a long contact search runs (on a thread of its own), the
    /// model goes out every [`MID_FRAME_MODEL`] (the solver's heartbeat). A frame slower
    /// than the loop's 20 ms staleness limit (a 16k-vertex cloth under the guard takes
    /// 20-150 ms, a cloth landing on one core 30-90) then lets the pen's force fade less
    /// often.
    fn step(&mut self, log: &mut dyn FnMut(&str)) -> Result<FrameStats, String> {
        // Every design the service holds (a new scene, a loaded file) sleeps at rest
        // unless `--no-sleep`.
        self.design.sim.sleep = self.cfg.sleep.then(SleepRule::default);
        // A long contact search tells the pen path, which sends the model from it; only
        // with a second solver thread's CPU to run it beside: on one CPU shared with the
        // studio, cloth-sim stepped a fifth fewer frames (docs/performance.md).
        self.design.sim.heartbeat = (self.design.sim.threads() > 1).then_some(MID_FRAME_MODEL);
        let pinching = self.design.sim.pinch().is_some();
        let frame = self.design.sim.frame;
        let told = self.design.sim.notices.len();
        let floor = self.design.sim.env.floor;
        let (feed, cfg, seq) = (&mut self.feed, self.cfg, &mut self.seq_model);
        let spring = (cfg.pinch_stiffness, self.workspace);
        let mut out = ModelOut {
            ports: &self.ports,
            stats: &mut self.stats,
            laps: &mut self.laps,
            slow_logged: &mut self.slow_logged,
        };
        // When the pinched vertex last went out as the substeps left it.
        let mut told_at = Instant::now();
        let fs = self
            .design
            .step_with(&mut |b| {
                if !pinching || b.heartbeat {
                    if out.laps.start.elapsed() >= MID_FRAME_MODEL {
                        out.laps.mark("step so far");
                        // The newest pen (its buttons act at the next frame, as ever).
                        feed.drain(&out.ports.device, &out.ports.applied, out.stats);
                        let pen = (feed.tip(), told_at.elapsed());
                        out.send(mid_frame_model(b, (frame, floor), pen, seq, spring), log);
                        out.stats.mid_frame_models += 1;
                    }
                    return None;
                }
                feed.drain(&out.ports.device, &out.ports.applied, out.stats);
                if let Some(held) = b.held {
                    let (_, sent_ns) = feed.tip();
                    out.laps.mark("step so far");
                    out.send(pinch_model(frame, held, sent_ns, seq, spring), log);
                    told_at = Instant::now();
                }
                let input = feed.input(b.substep, b.substeps, cfg)?;
                out.stats.pen_substeps += 1;
                if input.force_limit.is_some() {
                    out.stats.coupled_substeps += 1;
                }
                Some(input)
            })
            .map_err(|e| format!("the simulation failed: {e}"))?;
        // What the frame found to tell (pairs that stopped closing, `design::stalls`).
        for n in self.design.sim.notices.get(told..).unwrap_or_default() {
            log(&format!("note: {n}"));
        }
        Ok(fs)
    }
    /// Texture: changed tiles now, and 8 more round-robin so a late viewer fills in.
    fn publish_texture(&mut self, log: &mut dyn FnMut(&str)) {
        let tex = &mut self.design.texture;
        let mut tiles = tex.take_dirty();
        let (tx, ty) = (tex.tiles_x(), tex.tiles_y());
        for _ in 0..8 {
            tiles.push((self.tile_cursor % tx, (self.tile_cursor / tx) % ty));
            self.tile_cursor = (self.tile_cursor + 1) % (tx * ty);
        }
        for (x, y) in tiles {
            if let Err(e) = publish_tile(tex, &self.ports.texture, x, y, &mut self.seq_tile) {
                log(&format!("publishing the texture failed: {e}"));
                break;
            }
        }
    }
}
