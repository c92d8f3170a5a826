//! The 1 kHz loop: absolute deadlines, then per tick: read the pen, take the newest valid
//! local model and pointer input, compute the proxy force, pass it through the safety,
//! command it, and publish the device sample and the applied force. Timing goes into
//! fixed histograms; telemetry and log lines are handled every 100 ticks, after the tick's
//! work is measured. The tick allocates nothing and takes no lock beyond the device and
//! iceoryx2 calls.

use std::sync::atomic::{AtomicBool, Ordering};

use shared::haptic_to_sim::{AppliedForce, DeviceSample};
use shared::services::{Pub, Sub};
use shared::sim_to_haptic::LocalModel;
use shared::telemetry::LoopTelemetry;
use shared::ui_to_haptic::PointerInput;
use shared::{Checked, Header};

use crate::device::HapticDevice;
use crate::proxy::{ProxyParams, proxy_force};
use crate::rt;
use crate::safety::{ForceSafety, Hold, SafetyLimits};

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

/// The loop's ports (created on the loop's thread: iceoryx2 ports are !Send).
pub struct Ports {
    pub device: Pub<DeviceSample>,
    pub applied: Pub<AppliedForce>,
    pub telemetry: Pub<LoopTelemetry>,
    pub model: Sub<LocalModel>,
    pub pointer: Sub<PointerInput>,
}

impl Ports {
    /// Creates the loop's ports on `node` (on the thread that will run the loop).
    pub fn open(
        node: &iceoryx2::prelude::Node<iceoryx2::prelude::ipc::Service>,
    ) -> Result<Self, String> {
        use shared::services;
        let svc = |e: services::ServiceError| e.to_string();
        let port = |e: &dyn std::fmt::Debug| format!("cannot create a port: {e:?}");
        Ok(Self {
            device: services::device(node)
                .map_err(svc)?
                .publisher_builder()
                .create()
                .map_err(|e| port(&e))?,
            applied: services::applied_force(node)
                .map_err(svc)?
                .publisher_builder()
                .create()
                .map_err(|e| port(&e))?,
            telemetry: services::haptic_telemetry(node)
                .map_err(svc)?
                .publisher_builder()
                .create()
                .map_err(|e| port(&e))?,
            model: services::local_model(node)
                .map_err(svc)?
                .subscriber_builder()
                .create()
                .map_err(|e| port(&e))?,
            pointer: services::pointer(node)
                .map_err(svc)?
                .subscriber_builder()
                .create()
                .map_err(|e| port(&e))?,
        })
    }
}

/// A device that can also take the UI's pointer as its hand target (the sim pen).
pub trait PointerTarget {
    fn set_pointer(&mut self, _target: [f32; 3], _buttons: u32) {}
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

/// Runs until `stop` is set or `max_ticks`; returns what it measured.
pub fn run<D: HapticDevice + PointerTarget>(
    dev: &mut D,
    ports: &Ports,
    cfg: &LoopConfig,
    stop: &AtomicBool,
    mut recorder: Option<&mut crate::record::Recorder>,
    mut log: impl FnMut(&str),
) -> LoopStats {
    let mut stats = LoopStats::default();
    let mut safety = ForceSafety::new(cfg.limits);
    let mut model: Option<(LocalModel, u64)> = None; // (model, received at ns)
    let mut model_new = false;
    let mut seq_sample = 0u64;
    let mut seq_applied = 0u64;
    let mut seq_tel = 0u64;
    let mut hold_was = Hold::Stale;
    let mut error_logged: Option<crate::device::DeviceError> = None;
    let mut reject_logged = 0u64;
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
        let t = &mut stats.telemetry;
        t.lateness.record(start.saturating_sub(deadline));
        if tick > 0 {
            t.period.record(start - prev_start);
        }
        let dt = ((start - prev_start) as f32 * 1e-9).clamp(0.0, 0.005);
        prev_start = start;
        tick += 1;

        // Newest valid model and pointer input; reject (and count) bad ones.
        while let Ok(Some(s)) = ports.model.receive() {
            match s.check() {
                Ok(()) => {
                    model = Some((*s, start));
                    model_new = true;
                }
                Err(e) => {
                    stats.rejected += 1;
                    if stats.last_reject.is_none() {
                        stats.last_reject = Some(e.to_string());
                    }
                }
            }
        }
        while let Ok(Some(s)) = ports.pointer.receive() {
            match s.check() {
                Ok(()) => dev.set_pointer(s.target, s.buttons),
                Err(_) => stats.rejected += 1,
            }
        }
        let state = dev.read(dt);
        if let (Some(r), Ok(s)) = (recorder.as_deref_mut(), &state) {
            r.push(crate::record::Record {
                t: (start - t0) as f64 * 1e-9,
                state: *s,
            });
        }
        let (hold, pen) = match &state {
            Ok(s) => {
                let age_s = model
                    .as_ref()
                    .map(|(m, _)| start.saturating_sub(m.header.sent_ns) as f32 * 1e-9);
                match age_s {
                    Some(a) if a <= cfg.limits.stale_after_s => (Hold::None, Some(*s)),
                    _ => (Hold::Stale, Some(*s)),
                }
            }
            Err(_) => (Hold::DeviceError, None),
        };
        let wanted = match (&model, pen) {
            (Some((m, _)), Some(p)) => {
                let age_ns = start.saturating_sub(m.header.sent_ns);
                let t = &mut stats.telemetry;
                t.model_age.record(age_ns);
                if std::mem::take(&mut model_new) && m.pen_sent_ns > 0 {
                    t.pen_to_model.record(start.saturating_sub(m.pen_sent_ns));
                }
                let age_s = age_ns as f32 * 1e-9;
                proxy_force(&cfg.proxy, m, age_s, p.position, p.velocity)
            }
            _ => [0.0; 3],
        };
        force = safety.filter(wanted, dt, hold);
        let write = dev.write_force(force);
        if let Some(p) = pen {
            let _ = ports.device.send_copy(DeviceSample {
                header: Header::next(&mut seq_sample),
                tick,
                position: p.position,
                velocity: p.velocity,
                buttons: p.buttons,
                device_ok: u32::from(write.is_ok()),
            });
        }
        let _ = ports.applied.send_copy(AppliedForce {
            header: Header::next(&mut seq_applied),
            tick,
            force,
            model_frame: model.as_ref().map_or(0, |(m, _)| m.frame as u32),
        });
        let end = rt::now_ns();
        let t = &mut stats.telemetry;
        t.compute.record(end - start);
        t.ticks = tick;

        // Housekeeping, every 100 ticks, after the tick's work.
        if tick.is_multiple_of(100) {
            t.header = Header::next(&mut seq_tel);
            t.force_n = (force[0] * force[0] + force[1] * force[1] + force[2] * force[2]).sqrt();
            t.model_fresh = u32::from(hold == Hold::None);
            let _ = ports.telemetry.send_copy(**t);
            // Compare without formatting; a log line only on a change.
            let err = match (&state, &write) {
                (Err(e), _) | (_, Err(e)) => Some(e),
                _ => None,
            };
            let same = match (&err, &error_logged) {
                (None, None) => true,
                (Some(a), Some(b)) => *a == b,
                _ => false,
            };
            if !same {
                match err {
                    Some(e) => log(&format!("device error, forces off: {e}")),
                    None => log("device recovered"),
                }
                error_logged = err.cloned();
            }
            if hold != hold_was {
                log(match hold {
                    Hold::None => "local model fresh: rendering force",
                    Hold::Stale => {
                        "local model stale (cloth-sim not sending): force ramped to zero"
                    }
                    Hold::DeviceError => "device error: force ramped to zero",
                });
                hold_was = hold;
            }
            if stats.rejected > reject_logged {
                log(&format!(
                    "rejected {} malformed messages (first: {})",
                    stats.rejected - reject_logged,
                    stats.last_reject.as_deref().unwrap_or("?")
                ));
                reject_logged = stats.rejected;
            }
        }
        if state.is_err() || write.is_err() {
            stats.device_errors += 1;
        }
        deadline += period;
        let now = rt::now_ns();
        if now > deadline + period {
            // More than a whole period late: count the ticks skipped, don't burst.
            let behind = (now - deadline) / period;
            stats.telemetry.missed += behind;
            deadline += behind * period;
        }
    }
    stats.last_force = force;
    stats
}
