//! What the soak watches and sends while it runs: every applied force checked against the
//! newest local model, the gaps between models, the haptic loop's lateness over each of
//! its lifetimes, cloth-sim's pinned-vertex count, and a pin every 100 ms as the edits
//! whose loss a cloth-sim kill is judged by.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

use iceoryx2::pending_response::PendingResponse;
use iceoryx2::prelude::ipc;

use super::{
    AppliedForce, Checked, CommandClient, EDIT_HZ, Header, Histogram, LocalModel, LoopTelemetry,
    STALE_NS, SimTelemetry, Sub, ToolCommand, monotonic_ns, op, ports, services,
};

type Pending = PendingResponse<ipc::Service, ToolCommand, (), shared::ui_to_sim::CommandReply, ()>;

/// How long the forces are kept for the fault checks, ns.
const KEEP_NS: u64 = 12_000_000_000;

pub(super) struct Watch {
    forces: Sub<AppliedForce>,
    models: Sub<LocalModel>,
    loop_tel: Sub<LoopTelemetry>,
    sim_tel: Sub<SimTelemetry>,
    client: CommandClient,
    pending: Vec<(Pending, Instant)>,
    seq: u64,
    /// Forces sent after the models were last drained: checked at the next pass.
    deferred: Vec<AppliedForce>,
    /// (sent ns, magnitude N) of the last 12 s of forces.
    pub recent: VecDeque<(u64, f32)>,
    pub last_model_ns: u64,
    pub pinching: bool,
    pub models_seen: u64,
    gaps_paused: bool,
    skip_gap: bool,
    pub gap_max_ms: f64,
    /// Gaps over 50 ms between models outside cloth-sim's faults: (phase, ms).
    pub stalls: Vec<(String, f64)>,
    pub stale_force_ticks: u64,
    /// The current haptic-loop lifetime's telemetry, and what the ended ones add up to.
    loop_last: Option<LoopTelemetry>,
    pub loop_lifetimes: u32,
    pub late_max_ns: u64,
    pub ticks: u64,
    /// What is going on (a fault's kind, or "steady"), and the lateness of the ticks in
    /// each (judged at the end, against the floor measured meanwhile).
    pub phase: &'static str,
    pub lateness_by_phase: std::collections::BTreeMap<String, Histogram>,
    /// The newest sim telemetry: (sent ns, pinned vertices).
    pub sim_tel_last: Option<(u64, u32)>,
    /// Edits: the next vertex to pin, when the last went, how many cloth-sim confirmed.
    next_pin: u64,
    last_pin: Instant,
    pub vertices: u64,
    pub acked: u64,
    pub edits: bool,
}

impl Watch {
    pub(super) fn open(
        node: &iceoryx2::prelude::Node<ipc::Service>,
        vertices: u64,
    ) -> Result<Self, String> {
        let e = |e: shared::ports::PortError| e.to_string();
        Ok(Self {
            forces: ports::subscriber(node, services::applied_force, None).map_err(e)?,
            models: ports::subscriber(node, services::local_model, None).map_err(e)?,
            loop_tel: ports::subscriber(node, services::haptic_telemetry, None).map_err(e)?,
            sim_tel: ports::subscriber(node, services::sim_telemetry, None).map_err(e)?,
            client: ports::command_client(node).map_err(e)?,
            pending: Vec::new(),
            seq: 0,
            deferred: Vec::new(),
            recent: VecDeque::with_capacity(16_384),
            last_model_ns: 0,
            pinching: false,
            models_seen: 0,
            gaps_paused: false,
            skip_gap: true,
            gap_max_ms: 0.0,
            stalls: Vec::new(),
            stale_force_ticks: 0,
            loop_last: None,
            loop_lifetimes: 0,
            late_max_ns: 0,
            ticks: 0,
            phase: "start",
            lateness_by_phase: std::collections::BTreeMap::new(),
            sim_tel_last: None,
            next_pin: 0,
            last_pin: Instant::now(),
            vertices,
            acked: 0,
            edits: true,
        })
    }

    /// Gaps between models are not cloth-sim stalling while it is killed or stopped.
    pub(super) fn pause_gaps(&mut self) {
        self.gaps_paused = true;
    }

    pub(super) fn resume_gaps(&mut self) {
        self.gaps_paused = false;
        self.skip_gap = true;
    }

    /// Takes in everything that arrived and sends the next edit when due.
    pub(super) fn pump(&mut self) {
        let drained_at = monotonic_ns();
        while let Ok(Some(m)) = self.models.receive() {
            if m.check().is_err() {
                continue;
            }
            let sent = m.header.sent_ns;
            if !self.gaps_paused && !self.skip_gap && self.last_model_ns > 0 {
                let gap = sent.saturating_sub(self.last_model_ns) as f64 * 1e-6;
                self.gap_max_ms = self.gap_max_ms.max(gap);
                if gap > 50.0 {
                    self.stalls.push((self.phase.into(), gap));
                }
            }
            self.skip_gap = false;
            self.last_model_ns = self.last_model_ns.max(sent);
            self.pinching = m.pinching == 1;
            self.models_seen += 1;
        }
        self.take_forces(drained_at);
        while let Ok(Some(t)) = self.loop_tel.receive() {
            if t.check().is_ok() {
                self.loop_telemetry(*t);
            }
        }
        while let Ok(Some(t)) = self.sim_tel.receive() {
            if t.check().is_ok() {
                self.sim_tel_last = Some((t.header.sent_ns, t.pinned));
            }
        }
        self.edit();
    }

    /// Forces sent before the models were drained are checked against the newest model:
    /// one rendered from a model older than the limit is a stale force.
    fn take_forces(&mut self, drained_at: u64) {
        let mut all = std::mem::take(&mut self.deferred);
        while let Ok(Some(f)) = self.forces.receive() {
            if f.check().is_ok() {
                all.push(*f);
            }
        }
        for f in all {
            let sent = f.header.sent_ns;
            if sent > drained_at {
                self.deferred.push(f);
                continue;
            }
            let mag = f.force.iter().map(|c| c * c).sum::<f32>().sqrt();
            if mag > 0.0 && sent > self.last_model_ns + STALE_NS {
                self.stale_force_ticks += 1;
            }
            self.recent.push_back((sent, mag));
        }
        while self
            .recent
            .front()
            .is_some_and(|&(t, _)| t + KEEP_NS < drained_at)
        {
            self.recent.pop_front();
        }
    }

    /// A haptic-loop lifetime ends when the tick count goes back: its totals are added.
    fn loop_telemetry(&mut self, t: LoopTelemetry) {
        if let Some(last) = self.loop_last
            && t.ticks < last.ticks
        {
            self.end_lifetime();
        }
        let h = self.lateness_by_phase.entry(self.phase.into()).or_default();
        for (b, c) in t.lateness.counts.iter().enumerate() {
            let before = self.loop_last.map_or(0, |l| l.lateness.counts[b]);
            h.counts[b] = h.counts[b].saturating_add(c.saturating_sub(before));
        }
        self.late_max_ns = self.late_max_ns.max(t.lateness.max_ns);
        if self.loop_last.is_none() {
            self.loop_lifetimes += 1;
        }
        self.loop_last = Some(t);
    }

    /// Adds the current haptic-loop lifetime to the totals.
    pub(super) fn end_lifetime(&mut self) {
        if let Some(last) = self.loop_last.take() {
            self.late_max_ns = self.late_max_ns.max(last.lateness.max_ns);
            self.ticks += last.ticks;
        }
    }

    /// A pin every 1/EDIT_HZ s to the next vertex, while cloth-sim answers; replies that
    /// say done are counted.
    fn edit(&mut self) {
        let mut acked = 0;
        self.pending.retain(|(p, at)| match p.receive() {
            Ok(Some(r)) => {
                acked += u64::from(r.check().is_ok() && r.ok == 1);
                false
            }
            _ => at.elapsed() < Duration::from_secs(2),
        });
        self.acked += acked;
        if !self.edits || self.last_pin.elapsed().as_secs_f64() < 1.0 / EDIT_HZ {
            return;
        }
        self.last_pin = Instant::now();
        if self.next_pin + 1 >= self.vertices {
            return;
        }
        // Scattered over the cloth: a stride coprime with the vertex count.
        let v = (self.next_pin * 7919) % self.vertices;
        let c = ToolCommand {
            header: Header::next(&mut self.seq),
            op: op::PIN,
            a: v as u32,
            mode: 1,
            ..ToolCommand::default()
        };
        if let Ok(p) = self.client.send_copy(c)
            && p.number_of_server_connections() > 0
        {
            self.pending.push((p, Instant::now()));
            self.next_pin += 1;
        }
    }
}

/// From `after` (ns), the first force at zero after which every force is zero, ms after
/// `after`; `None` when the force never settled at zero.
pub(super) fn zero_from(recent: &VecDeque<(u64, f32)>, after: u64) -> Option<u64> {
    let mut zero_at = None;
    for &(t, mag) in recent.iter().filter(|(t, _)| *t >= after) {
        if mag > 0.0 {
            zero_at = None;
        } else if zero_at.is_none() {
            zero_at = Some(t);
        }
    }
    zero_at
}

/// The force's return once the loop re-engages after `after` (ns): the first force back
/// (within 100 ms of `after`) over the largest 100-200 ms later, when the loop's 100 ms
/// ramp is done. With the ramp it comes back at a few percent; without, at about the
/// whole. `None` when it did not come back so soon (a new pinch later is no
/// re-engagement) or had let go again by then.
pub(super) fn ramp_ratio(recent: &VecDeque<(u64, f32)>, after: u64) -> Option<f64> {
    let &(t1, first) = recent
        .iter()
        .find(|(t, m)| *t >= after && *m > 0.0)
        .filter(|(t, _)| *t <= after + 100_000_000)?;
    let full = recent
        .iter()
        .filter(|(t, _)| *t >= t1 + 100_000_000 && *t < t1 + 200_000_000)
        .map(|&(_, m)| m)
        .fold(0.0f32, f32::max);
    (full > 0.05).then(|| f64::from(first / full))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_force_settles_at_zero_and_ramps() {
        let ms = 1_000_000u64;
        let mut r = VecDeque::new();
        // 1 N until 100 ms, zero after 115 ms; back at 300 ms, ramping over 100 ms.
        for k in 0..1000u64 {
            let t = k * ms;
            let f = if k < 115 {
                if k < 100 { 1.0 } else { 0.5 }
            } else if k < 300 {
                0.0
            } else {
                ((k - 300) as f32 / 100.0).min(1.0)
            };
            r.push_back((t, f));
        }
        assert_eq!(zero_from(&r, 100 * ms), None, "it came back");
        let cut: VecDeque<_> = r.iter().copied().filter(|(t, _)| *t < 300 * ms).collect();
        assert_eq!(zero_from(&cut, 100 * ms), Some(115 * ms));
        // The loop back at 290 ms, ramping from 300 ms: its first force is 1% of the
        // force once the ramp is done.
        let ratio = ramp_ratio(&r, 290 * ms).unwrap();
        assert!((0.005..0.02).contains(&ratio), "{ratio}");
        // No ramp: the full force at once.
        let step: VecDeque<_> = (0..1000u64).map(|k| (k * ms, 1.0)).collect();
        assert_eq!(ramp_ratio(&step, 290 * ms), Some(1.0));
        // Back only 200 ms later: a new pinch, not measured.
        assert_eq!(ramp_ratio(&r, 190 * ms), None);
    }
}
