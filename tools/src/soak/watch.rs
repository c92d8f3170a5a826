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
    /// (sent ns, magnitude N, the loop's tick) of the last 12 s of forces.
    pub recent: VecDeque<(u64, f32, u64)>,
    pub last_model_ns: u64,
    /// The first model sent after [`Watch::watch_return`]'s time (ns): when the loop
    /// could re-engage at the earliest.
    pub first_model_after: Option<u64>,
    return_from: u64,
    pub pinching: bool,
    pub models_seen: u64,
    gaps_paused: bool,
    skip_gap: bool,
    pub gap_max_ms: f64,
    /// Each gap over 50 ms (what the host did meanwhile is added at the end).
    pub stalls: Vec<super::Stall>,
    /// The longest gap between models in each phase, ms (outside cloth-sim's faults).
    pub gap_max_by_phase: std::collections::BTreeMap<String, f64>,
    /// cloth-sim's longest frame (its own compute, from its telemetry) in each phase, ms:
    /// a gap far longer than any frame is time cloth-sim was not given, not time it took.
    pub frame_max_by_phase: std::collections::BTreeMap<String, f64>,
    /// cloth-sim's frame times as its last telemetry had them (they count from its start).
    sim_frames_last: Option<Histogram>,
    skip_frames_until: u64,
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
            first_model_after: None,
            return_from: u64::MAX,
            pinching: false,
            models_seen: 0,
            gaps_paused: false,
            skip_gap: true,
            gap_max_ms: 0.0,
            stalls: Vec::new(),
            gap_max_by_phase: std::collections::BTreeMap::new(),
            frame_max_by_phase: std::collections::BTreeMap::new(),
            sim_frames_last: None,
            skip_frames_until: 0,
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

    /// Notes the first model sent after `t` (ns) from now on ([`Watch::first_model_after`]).
    pub(super) fn watch_return(&mut self, t: u64) {
        self.return_from = t;
        self.first_model_after = None;
    }

    pub(super) fn resume_gaps(&mut self) {
        self.gaps_paused = false;
        self.skip_gap = true;
        // The telemetry of the next 2 s holds the frame a stop froze (seconds long).
        self.skip_frames_until = monotonic_ns() + 2_000_000_000;
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
                let m = self.gap_max_by_phase.entry(self.phase.into()).or_default();
                *m = m.max(gap);
                if gap > 50.0 {
                    self.stalls.push(super::Stall {
                        phase: self.phase.into(),
                        ms: gap,
                        from_ns: self.last_model_ns,
                        ..Default::default()
                    });
                }
            }
            self.skip_gap = false;
            if sent > self.return_from && self.first_model_after.is_none_or(|f| sent < f) {
                self.first_model_after = Some(sent);
            }
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
                let longest = frame_time_since(self.sim_frames_last.as_ref(), &t.frame_time);
                if !self.gaps_paused
                    && t.header.sent_ns > self.skip_frames_until
                    && let Some(ms) = longest
                {
                    let m = self
                        .frame_max_by_phase
                        .entry(self.phase.into())
                        .or_default();
                    *m = m.max(ms);
                }
                self.sim_frames_last = Some(t.frame_time);
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
            self.recent.push_back((sent, mag, f.tick));
        }
        while self
            .recent
            .front()
            .is_some_and(|&(t, _, _)| t + KEEP_NS < drained_at)
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

/// The longest frame recorded in `now` since `before` (two snapshots of cloth-sim's frame
/// times, which count from its start), ms: the new maximum when it grew, else the upper
/// edge of the highest bucket that grew (at most the maximum): to the millisecond from
/// 12 ms to 1 s. The top bucket is open (1 s and over): a frame there that set no new
/// maximum reads as its floor, 1 s, a lower bound (reading the maximum put a stop's 5 s
/// frame in later phases). `None` when
/// no frame was recorded in between; a count that went back is a restarted cloth-sim,
/// counted afresh.
pub(super) fn frame_time_since(before: Option<&Histogram>, now: &Histogram) -> Option<f64> {
    let before = before.filter(|b| b.total <= now.total);
    let grew = |b: usize| before.is_none_or(|h| now.counts[b] > h.counts[b]);
    if before.is_none_or(|h| now.max_ns > h.max_ns) && now.total > 0 {
        return Some(now.max_ns as f64 * 1e-6);
    }
    let b = (0..now.counts.len())
        .rev()
        .find(|&b| grew(b) && now.counts[b] > 0)?;
    let edge = if b + 1 < now.counts.len() {
        Histogram::bucket_floor_ns(b + 1).min(now.max_ns)
    } else {
        Histogram::bucket_floor_ns(b)
    };
    Some(edge as f64 * 1e-6)
}

/// From `after` (ns), the first force at zero after which every force is zero, ms after
/// `after`; `None` when the force never settled at zero.
pub(super) fn zero_from(recent: &VecDeque<(u64, f32, u64)>, after: u64) -> Option<u64> {
    let mut zero_at = None;
    for &(t, mag, _) in recent.iter().filter(|(t, _, _)| *t >= after) {
        if mag > 0.0 {
            zero_at = None;
        } else if zero_at.is_none() {
            zero_at = Some(t);
        }
    }
    zero_at
}

/// The haptic loop's peak force (a Touch's 3.3 N, haptic-loop's default limit), N.
const PEAK_N: f32 = 3.3;
/// The most of the peak the loop's ramp up gives in one tick (1% on time, 2% for a late
/// tick).
const RAMP_PER_TICK: f32 = 0.02;

/// The force's return once the loop re-engages after `after` (ns), against its ramp: over
/// the first 100 ms from the first force back (within 100 ms of `after`), each force over
/// the most the ramp lets through at its tick, `min(1, 2% x n)` of the peak at the n-th
/// tick. At most 1 with the ramp (about 0.5 on time); a force back whole reads its size
/// over 2% of the peak (15 for 1 N). Forces that fall (a pen that lets go, a later model
/// that lets the stretched pinch go) cannot read high, which the first measure, a ratio
/// of two forces, could: after 5 s stopped a let-go 5-20 ms after the return read 97%.
///
/// The ticks are counted from the last force sent before `engaged`, the first model's
/// send time after the fault (the loop cannot re-engage before it): a bound the ramp
/// cannot beat, whatever the watcher missed. Counting from the first force seen read a
/// ramp under way as a force back at once when the host held the watcher past its
/// buffer (17.6 in a 400-fault run whose host held CPUs 40-100 ms); counting from the
/// last zero force reads a pen that touches the cloth long after the loop re-engaged,
/// the gain up, as the peak a few ticks into a ramp (the likely reading of 10.0 in the
/// next run). Without `engaged` the last zero force before the return is the start.
///
/// Returns that maximum, the largest force in those 100 ms (a ramp is seen only where
/// there was force to ramp) and the loop's ticks between that start and the first force
/// back that the watcher did not see; `None` when the force did not come back so soon (a
/// new pinch later is no re-engagement).
pub(super) fn ramp_envelope(
    recent: &VecDeque<(u64, f32, u64)>,
    after: u64,
    engaged: Option<u64>,
) -> Option<(f64, f32, u64)> {
    const MS: u64 = 1_000_000;
    let first = recent
        .iter()
        .position(|(t, m, _)| *t >= after && *m > 0.0)?;
    let (t1, _, tick1) = recent[first];
    if t1 > after + 100 * MS {
        return None;
    }
    // The last tick (of the same lifetime: an earlier one) sent before the model the
    // loop re-engaged on; without it, the zero force seen just before the return; else
    // the first force seen is taken as the first back.
    let before_model = engaged.and_then(|e| {
        recent
            .range(..first)
            .rev()
            .take_while(|&&(_, _, tick)| tick < tick1)
            .find(|&&(t, _, _)| t < e)
            .map(|&(_, _, tick)| tick)
    });
    let base = match (before_model, first.checked_sub(1).map(|i| recent[i])) {
        (Some(tick), _) => tick,
        (None, Some((_, m, tick))) if m == 0.0 && tick < tick1 => tick,
        _ => tick1.saturating_sub(1),
    };
    let seen = recent
        .range(..first)
        .rev()
        .take_while(|&&(_, _, tick)| tick > base && tick < tick1)
        .count() as u64;
    let mut over = 0.0f64;
    let mut most = 0.0f32;
    for &(_, m, tick) in recent
        .iter()
        .skip(first)
        .take_while(|(t, _, _)| *t <= t1 + 100 * MS)
    {
        let n = tick.saturating_sub(base).max(1);
        let allowed = (RAMP_PER_TICK * n as f32).min(1.0) * PEAK_N;
        over = over.max(f64::from(m / allowed));
        most = most.max(m);
    }
    Some((over, most, (tick1 - base - 1).saturating_sub(seen)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_frame_between_two_snapshots() {
        let mut h = Histogram::default();
        assert_eq!(frame_time_since(None, &h), None);
        h.record(30_000_000);
        h.record(4_000_000);
        let a = h;
        assert_eq!(frame_time_since(None, &a), Some(30.0));
        // Only shorter frames since: the highest bucket that grew, not the old maximum.
        h.record(5_020_000);
        h.record(1_000_000);
        let ms = frame_time_since(Some(&a), &h).unwrap();
        assert!((5.02..=5.13).contains(&ms), "{ms}");
        // Nothing new.
        assert_eq!(frame_time_since(Some(&h), &h), None);
        // A stop's 5 s frame, then a 20 ms one: the top of its 1 ms bucket, not 5 s.
        h.record(5_000_000_000);
        let stopped = h;
        h.record(20_000_000);
        assert_eq!(frame_time_since(Some(&stopped), &h), Some(21.0));
        // Another stop's frame of 3 s: the open top bucket's floor, 1 s, not 5 s.
        let twenty = h;
        h.record(3_000_000_000);
        assert_eq!(frame_time_since(Some(&twenty), &h), Some(1000.0));
        // A restarted cloth-sim counts from zero again.
        let mut fresh = Histogram::default();
        fresh.record(2_000_000);
        assert_eq!(frame_time_since(Some(&h), &fresh), Some(2.0));
    }

    #[test]
    fn the_force_settles_at_zero_and_ramps() {
        let ms = 1_000_000u64;
        let mut r = VecDeque::new();
        // 1 N until 100 ms, zero after 115 ms; back at 300 ms, ramping over 100 ms, from
        // a model that holds until 350 ms.
        for k in 0..1000u64 {
            let t = k * ms;
            let f = if k < 115 {
                if k < 100 { 1.0 } else { 0.5 }
            } else if k < 300 {
                0.0
            } else {
                ((k - 300 + 1) as f32 / 100.0).min(1.0)
            };
            r.push_back((t, f, k));
        }
        assert_eq!(zero_from(&r, 100 * ms), None, "it came back");
        let cut: VecDeque<_> = r
            .iter()
            .copied()
            .filter(|(t, _, _)| *t < 300 * ms)
            .collect();
        assert_eq!(zero_from(&cut, 100 * ms), Some(115 * ms));
        // The loop back at 290 ms, ramping from 300 ms at 1% of 1 N a tick: well inside
        // the ramp's limit (2% of 3.3 N a tick, the whole 3.3 N from the 50th tick on);
        // the most is 1 N at the 100th tick.
        let (over, most, unseen) = ramp_envelope(&r, 290 * ms, None).unwrap();
        assert_eq!(unseen, 0);
        assert!((over - 1.0 / 3.3).abs() < 1e-3, "{over}");
        assert_eq!(most, 1.0);
        // No ramp: 1 N at once is 15 times the first tick's limit.
        let step: VecDeque<_> = (0..1000u64).map(|k| (k * ms, 1.0, k)).collect();
        let (over, _, _) = ramp_envelope(&step, 290 * ms, None).unwrap();
        assert!((15.0..15.2).contains(&over), "{over}");
        // Back only 200 ms later: a new pinch, not measured.
        assert_eq!(ramp_envelope(&r, 190 * ms, None), None);
        // 300 N wanted, ramped at 1% of the peak a tick, then let go 8 ms later: the
        // ratio of two forces read this as a return without its ramp; the limit does not.
        let letgo: VecDeque<_> = (0..1000u64)
            .map(|k| {
                let f = if k < 300 {
                    0.0
                } else if k < 308 {
                    0.033 * (k - 300 + 1) as f32
                } else {
                    0.001
                };
                (k * ms, f, k)
            })
            .collect();
        let (over, most, _) = ramp_envelope(&letgo, 290 * ms, None).unwrap();
        assert!(over <= 0.5 + 1e-6, "{over}");
        assert!((most - 0.264).abs() < 1e-4, "{most}");
        // The peak at once, then let go: caught.
        let kick: VecDeque<_> = (0..1000u64)
            .map(|k| (k * ms, if (300..308).contains(&k) { 3.3 } else { 0.0 }, k))
            .collect();
        let (over, _, _) = ramp_envelope(&kick, 290 * ms, None).unwrap();
        assert!(over > 40.0, "{over}");
        // A late tick (the loop held 18 ms: ticks 1 and 2 are 18 ms apart) may take 2%.
        let late: VecDeque<_> = (0..100u64)
            .map(|k| {
                let t = if k == 0 { 300 * ms } else { (317 + k) * ms };
                (t, (0.066 * (k + 1) as f32).min(3.3), k + 5000)
            })
            .collect();
        let (over, _, _) = ramp_envelope(&late, 290 * ms, None).unwrap();
        assert!((over - 1.0).abs() < 1e-5, "{over}");
        // The watcher held up 20 ms as the force came back: ticks 300-319 of a ramp at
        // 1% of the peak a tick (to 1 N) are not seen. From the zero at tick 299 the ramp holds
        // (0.5); from the first force seen (21% of the peak) it would read 10.5.
        let held: VecDeque<_> = (0..1000u64)
            .filter(|k| !(300..320).contains(k))
            .map(|k| {
                let f = if k < 300 {
                    0.0
                } else {
                    (0.033 * (k - 299) as f32).min(1.0)
                };
                (k * ms, f, k)
            })
            .collect();
        let (over, _, unseen) = ramp_envelope(&held, 290 * ms, None).unwrap();
        assert!((over - 0.5).abs() < 1e-3, "{over}");
        assert_eq!(unseen, 20);
        // The same forces with a force seen before them (the fade's last, before the return
        // was looked for): counted
        // from the first force seen, as a force back at once.
        let mut no_zero = held.clone();
        no_zero[299].1 = 0.5;
        let (over, _, unseen) = ramp_envelope(&no_zero, 299 * ms + 1, None).unwrap();
        assert!((over - 10.5).abs() < 1e-3, "{over}");
        assert_eq!(unseen, 0);
        // The loop re-engages on a model sent at 300 ms, with the pen in the air: no force
        // while the gain ramps up, then the pen touches at 395 ms and the whole peak is
        // there 95 ticks into the ramp. Counted from the last tick before that model: 1.
        // Counted from the last zero force, as before, this read 50 (10 in a soak).
        let touch: VecDeque<_> = (0..1000u64)
            .map(|k| (k * ms, if k >= 395 { 3.3 } else { 0.0 }, k))
            .collect();
        let (over, _, unseen) = ramp_envelope(&touch, 299 * ms, Some(300 * ms)).unwrap();
        assert!((over - 1.0).abs() < 1e-6, "{over}");
        assert_eq!(unseen, 0);
        let (over, _, _) = ramp_envelope(&touch, 299 * ms, None).unwrap();
        assert!((over - 50.0).abs() < 1e-3, "{over}");
        // A force back whole on the model's tick is still caught.
        let (over, _, _) = ramp_envelope(&touch, 299 * ms, Some(394 * ms + 1)).unwrap();
        assert!((over - 50.0).abs() < 1e-3, "{over}");
    }
}
