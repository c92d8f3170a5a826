//! The 1 kHz loop: absolute deadlines, then per tick: read the pen, take the newest valid
//! local model and pointer input, compute the proxy force, pass it through the safety,
//! command it, and publish the device sample and the applied force. Timing goes into
//! fixed histograms; telemetry and log lines are handled every 100 ticks, after the tick's
//! work is measured. The tick allocates nothing and takes no lock beyond the device and
//! iceoryx2 calls.

use std::sync::atomic::{AtomicBool, Ordering};

use shared::haptic_to_sim::{AppliedForce, DeviceSample};
use shared::ports::HapticPorts;
use shared::sim_to_haptic::LocalModel;
use shared::telemetry::LoopTelemetry;
use shared::{Checked, Header};

use crate::device::{DeviceError, DeviceState, HapticDevice, PointerTarget, Workspace};
use crate::hold_log::HoldLog;
use crate::proxy::{ProxyParams, proxy_force};
use crate::rt;
use crate::safety::{ForceSafety, Hold, SafetyLimits};
use crate::sim_watch::SimWatch;

#[derive(Clone, Debug)]
pub struct LoopConfig {
    pub period_ns: u64,
    /// Busy-wait before each deadline, ns.
    pub spin_ns: u64,
    /// Stop after this many ticks (None: until SIGINT/SIGTERM).
    pub max_ticks: Option<u64>,
    pub limits: SafetyLimits,
    pub proxy: ProxyParams,
}

impl Default for LoopConfig {
    fn default() -> Self {
        Self {
            period_ns: 1_000_000,
            spin_ns: 250_000,
            max_ticks: None,
            limits: SafetyLimits::default(),
            proxy: ProxyParams::default(),
        }
    }
}

/// What the loop saw, for its final log line and for tests.
#[derive(Clone, Debug, Default)]
pub struct LoopStats {
    pub telemetry: Box<LoopTelemetry>,
    pub rejected: u64,
    pub last_reject: Option<String>,
    pub last_force: [f32; 3],
    pub device_errors: u64,
}

/// What the loop keeps from tick to tick besides timing.
struct Tick {
    stats: LoopStats,
    safety: ForceSafety,
    /// The newest valid local model and when it arrived, ns.
    model: Option<(LocalModel, u64)>,
    model_new: bool,
    seq_sample: u64,
    seq_applied: u64,
    seq_tel: u64,
    hold_log: HoldLog,
    error_logged: Option<DeviceError>,
    reject_logged: u64,
    /// When the watcher first said cloth-sim had exited (0: it has not), ns: a model sent
    /// after it is a new cloth-sim's, whose pid the watcher does not know yet.
    gone_since: u64,
    /// Read the local model's publishers again at this tick's housekeeping.
    relist: bool,
    /// The workspace the device was last given (from the models), and the last one said
    /// in the log.
    workspace: Workspace,
    workspace_logged: Workspace,
}

/// Runs until `stop` is set or `max_ticks`; returns what it measured. With `sim`, the
/// force goes to zero within 2 ms once every process publishing the local model has
/// exited (otherwise only the model's age tells).
pub fn run<D: HapticDevice + PointerTarget>(
    dev: &mut D,
    ports: &HapticPorts,
    cfg: &LoopConfig,
    stop: &AtomicBool,
    sim: Option<&SimWatch>,
    mut recorder: Option<&mut crate::record::Recorder>,
    mut log: impl FnMut(&str),
) -> LoopStats {
    let mut k = Tick {
        stats: LoopStats::default(),
        safety: ForceSafety::new(cfg.limits),
        model: None,
        model_new: false,
        seq_sample: 0,
        seq_applied: 0,
        seq_tel: 0,
        hold_log: HoldLog::new(Hold::Stale),
        error_logged: None,
        reject_logged: 0,
        gone_since: 0,
        relist: true,
        workspace: Workspace::default(),
        workspace_logged: Workspace::default(),
    };
    let period = cfg.period_ns;
    let t0 = rt::now_ns();
    let mut deadline = t0 + period;
    let mut prev_start = deadline;
    let mut force = [0.0f32; 3];
    let mut tick = 0u64;
    loop {
        if stop.load(Ordering::Relaxed) || cfg.max_ticks.is_some_and(|m| tick >= m) {
            break;
        }
        rt::wait_until(deadline, cfg.spin_ns);
        let start = rt::now_ns();
        let t = &mut k.stats.telemetry;
        t.lateness.record(start.saturating_sub(deadline));
        if tick > 0 {
            t.period.record(start - prev_start);
        }
        let dt = ((start - prev_start) as f32 * 1e-9).clamp(0.0, 0.005);
        prev_start = start;
        tick += 1;

        k.receive(ports, dev, start);
        let state = dev.read(dt);
        if let (Some(r), Ok(s)) = (recorder.as_deref_mut(), &state) {
            r.push(crate::device::Record {
                t: (start - t0) as f64 * 1e-9,
                state: *s,
            });
        }
        let (hold, wanted) = k.wanted(cfg, &state, start, sim);
        force = k.safety.filter(wanted, dt, hold);
        let write = dev.write_force(force);
        k.publish(ports, tick, &state, &write, force);
        let end = rt::now_ns();
        let t = &mut k.stats.telemetry;
        t.compute.record(end - start);
        t.ticks = tick;

        // Housekeeping, every 100 ticks, after the tick's work.
        if tick.is_multiple_of(100) {
            k.housekeeping(ports, force, hold, &state, &write, &mut log);
        }
        // Who publishes the local model, for the watcher: every 100 ticks, and at once
        // when a model comes from what may be a new cloth-sim.
        if let Some(w) = sim
            && (tick.is_multiple_of(100) || std::mem::take(&mut k.relist))
        {
            w.watch(ports.model_publisher_pids());
        }
        if state.is_err() || write.is_err() {
            k.stats.device_errors += 1;
        }
        deadline += period;
        let now = rt::now_ns();
        if now > deadline + period {
            // More than a whole period late: count the ticks skipped, don't burst.
            let behind = (now - deadline) / period;
            k.stats.telemetry.missed += behind;
            deadline += behind * period;
        }
    }
    k.stats.last_force = force;
    k.stats
}

impl Tick {
    /// Takes the newest valid model and pointer input; rejects (and counts) bad ones.
    fn receive<D: HapticDevice + PointerTarget>(
        &mut self,
        ports: &HapticPorts,
        dev: &mut D,
        start: u64,
    ) {
        while let Ok(Some(s)) = ports.model.receive() {
            match s.check() {
                Ok(()) => {
                    self.model = Some((*s, start));
                    self.model_new = true;
                    // The scene's workspace (a new scene may bring another).
                    let ws = Workspace::from_wire(s.workspace);
                    if ws != self.workspace {
                        dev.set_workspace(ws);
                        self.workspace = ws;
                        self.safety.restart_ramp();
                    }
                }
                Err(e) => {
                    self.stats.rejected += 1;
                    if self.stats.last_reject.is_none() {
                        self.stats.last_reject = Some(e.to_string());
                    }
                }
            }
        }
        while let Ok(Some(s)) = ports.pointer.receive() {
            match s.check() {
                Ok(()) => dev.set_pointer(s.target, s.buttons),
                Err(_) => self.stats.rejected += 1,
            }
        }
    }

    /// Why force is held back (if it is), and the proxy's force before the safety.
    fn wanted(
        &mut self,
        cfg: &LoopConfig,
        state: &Result<DeviceState, DeviceError>,
        start: u64,
        sim: Option<&SimWatch>,
    ) -> (Hold, [f32; 3]) {
        // Gone: every process publishing the model has exited, and the model is not one a
        // new cloth-sim sent since (that one's pid is read at once, below).
        let gone = if sim.is_some_and(SimWatch::gone) {
            if self.gone_since == 0 {
                self.gone_since = start;
            }
            let newer = self
                .model
                .as_ref()
                .is_some_and(|(m, _)| m.header.sent_ns > self.gone_since);
            if newer {
                self.relist = true;
            }
            !newer
        } else {
            self.gone_since = 0;
            false
        };
        let (hold, pen) = match state {
            Ok(s) if gone => (Hold::Gone, Some(*s)),
            Ok(s) => {
                let age_s = self
                    .model
                    .as_ref()
                    .map(|(m, _)| start.saturating_sub(m.header.sent_ns) as f32 * 1e-9);
                let l = &cfg.limits;
                match age_s {
                    Some(a) if a <= l.stale_after_s => (Hold::None, Some(*s)),
                    // Past the ramp too: the tick itself came late; no stale force at all.
                    Some(a) if a > l.stale_after_s + l.stale_ramp_s => (Hold::Expired, Some(*s)),
                    _ => (Hold::Stale, Some(*s)),
                }
            }
            Err(_) => (Hold::DeviceError, None),
        };
        let wanted = match (&self.model, pen) {
            (Some((m, _)), Some(p)) => {
                let age_ns = start.saturating_sub(m.header.sent_ns);
                let t = &mut self.stats.telemetry;
                t.model_age.record(age_ns);
                if std::mem::take(&mut self.model_new) && m.pen_sent_ns > 0 {
                    t.pen_to_model.record(start.saturating_sub(m.pen_sent_ns));
                }
                let age_s = age_ns as f32 * 1e-9;
                proxy_force(&cfg.proxy, m, age_s, p.position, p.velocity)
            }
            _ => [0.0; 3],
        };
        (hold, wanted)
    }

    /// Sends the device sample (when the pen was read) and the applied force.
    fn publish(
        &mut self,
        ports: &HapticPorts,
        tick: u64,
        state: &Result<DeviceState, DeviceError>,
        write: &Result<(), DeviceError>,
        force: [f32; 3],
    ) {
        if let Ok(p) = state {
            let _ = ports.device.send_copy(DeviceSample {
                header: Header::next(&mut self.seq_sample),
                tick,
                position: p.position,
                velocity: p.velocity,
                buttons: p.buttons,
                device_ok: u32::from(write.is_ok()),
            });
        }
        let _ = ports.applied.send_copy(AppliedForce {
            header: Header::next(&mut self.seq_applied),
            tick,
            force,
            model_frame: self.model.as_ref().map_or(0, |(m, _)| m.frame as u32),
        });
    }

    /// Telemetry, and a log line when the device, the model's freshness or the count of
    /// rejected messages changed (compared without formatting).
    fn housekeeping(
        &mut self,
        ports: &HapticPorts,
        force: [f32; 3],
        hold: Hold,
        state: &Result<DeviceState, DeviceError>,
        write: &Result<(), DeviceError>,
        log: &mut impl FnMut(&str),
    ) {
        let t = &mut self.stats.telemetry;
        t.header = Header::next(&mut self.seq_tel);
        t.force_n = (force[0] * force[0] + force[1] * force[1] + force[2] * force[2]).sqrt();
        t.model_fresh = u32::from(hold == Hold::None);
        let _ = ports.telemetry.send_copy(**t);
        let err = match (state, write) {
            (Err(e), _) | (_, Err(e)) => Some(e),
            _ => None,
        };
        let same = match (&err, &self.error_logged) {
            (None, None) => true,
            (Some(a), Some(b)) => *a == b,
            _ => false,
        };
        if !same {
            match err {
                Some(e) => log(&format!("device error, forces off: {e}")),
                None => log("device recovered"),
            }
            self.error_logged = err.cloned();
        }
        if self.workspace != self.workspace_logged {
            let (c, s) = (self.workspace.centre, self.workspace.scale);
            log(&format!(
                "the scene's workspace: the device mapped {s:.1}x around ({:.2}, {:.2}, {:.2}) m",
                c[0], c[1], c[2]
            ));
            self.workspace_logged = self.workspace;
        }
        self.hold_log.note(hold, self.stats.telemetry.ticks, log);
        if self.stats.rejected > self.reject_logged {
            log(&format!(
                "rejected {} malformed messages (first: {})",
                self.stats.rejected - self.reject_logged,
                self.stats.last_reject.as_deref().unwrap_or("?")
            ));
            self.reject_logged = self.stats.rejected;
        }
    }
}
