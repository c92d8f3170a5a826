//! cloth-latency's three measurements.
//!
//! - `ping`: round trips over the project's device-sample service (its QoS, header stamping
//!   and checks) and, interleaved in the same run, over a raw iceoryx2 publish-subscribe
//!   pair with default settings and the same payload, against an echo in a child process.
//! - `loop`: the haptic loop's period, lateness and compute histograms over a window, from
//!   its telemetry, and the ticks it missed.
//! - `e2e`: device sample -> cloth-sim -> local model at the haptic loop (when first used,
//!   and the model's age at every tick), and device motion -> cloth frame.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use hdrhistogram::Histogram as Hdr;
use iceoryx2::prelude::*;
use serde::Serialize;
use shared::domain::Domain;
use shared::haptic_to_sim::DeviceSample;
use shared::telemetry::LoopTelemetry;
use shared::{Checked, Header, monotonic_ns, ports, services};

use crate::plot::{HistogramPlot, buckets_of};
use crate::stats::{Percentiles, Series, new_hdr, window};

const RAW_PING: &str = "saiho/latency/raw-ping";
const RAW_PONG: &str = "saiho/latency/raw-pong";
/// Round trips per path not counted at the start (warm-up).
const WARMUP: u64 = 200;

/// What a measurement produced: a JSON report, series for the CSV and plot, histograms.
pub struct Measured<R> {
    pub report: R,
    pub series: Vec<Series>,
    pub hists: Vec<HistogramPlot>,
}

/// The echo: returns every ping on both paths until `stop` or `seconds`. The project path
/// checks each sample as a real subscriber must.
pub fn pong(domain: &Domain, seconds: f64, stop: &AtomicBool) -> Result<u64, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "latency-pong").map_err(|e| e.to_string())?;
    let dev_sub = ports::subscriber(&node, services::device, None).map_err(|e| e.to_string())?;
    let echo_pub = ports::publisher(&node, services::device_echo).map_err(|e| e.to_string())?;
    let (raw_pub, raw_sub) =
        ports::raw_device_pair(&node, RAW_PONG, RAW_PING).map_err(|e| e.to_string())?;
    let end = Instant::now() + Duration::from_secs_f64(seconds);
    let mut echoed = 0u64;
    let mut idle = 0u32;
    while !stop.load(Ordering::Relaxed) && Instant::now() < end {
        let mut any = false;
        while let Ok(Some(s)) = dev_sub.receive() {
            if s.check().is_ok() {
                let _ = echo_pub.send_copy(*s);
                echoed += 1;
            }
            any = true;
        }
        while let Ok(Some(s)) = raw_sub.receive() {
            let _ = raw_pub.send_copy(*s);
            echoed += 1;
            any = true;
        }
        // Spin while busy; nap when nothing came for a while (the pinger has stopped).
        idle = if any { 0 } else { idle + 1 };
        if idle > 100_000 {
            std::thread::sleep(Duration::from_micros(200));
        } else {
            std::hint::spin_loop();
        }
    }
    Ok(echoed)
}

#[derive(Debug, Serialize)]
pub struct PathReport {
    /// Round trip, µs.
    pub rtt_us: Percentiles,
    /// Half the round trip, µs.
    pub one_way_us: Percentiles,
    pub lost: u64,
}

#[derive(Debug, Serialize)]
pub struct PingReport {
    pub seconds: f64,
    pub rate_hz: f64,
    pub payload_bytes: usize,
    /// The project's device-sample service (its QoS, header, checks).
    pub project: PathReport,
    /// Raw iceoryx2 publish-subscribe, default settings, same payload.
    pub raw: PathReport,
    /// project / raw one-way latency at p50 and p99 (target <= 1.2).
    pub ratio_p50: f64,
    pub ratio_p99: f64,
}

/// Waits for the echo of `seq` on `sub`, spinning, up to `timeout`; returns the round
/// trip in ns.
fn await_echo(
    sub: &impl Fn() -> Option<DeviceSample>,
    seq: u64,
    t0: u64,
    timeout: Duration,
) -> Option<u64> {
    let until = Instant::now() + timeout;
    loop {
        while let Some(s) = sub() {
            if s.header.seq == seq {
                return Some(monotonic_ns().saturating_sub(t0));
            }
        }
        if Instant::now() > until {
            return None;
        }
        std::hint::spin_loop();
    }
}

/// One path's round trips as they are measured.
struct PathStats {
    rtt: Hdr<u64>,
    lost: u64,
    series: Series,
}

impl PathStats {
    fn new(name: &str) -> Self {
        Self {
            rtt: new_hdr(),
            lost: 0,
            series: Series::new(name),
        }
    }

    /// A round trip at `t` s (`None`: lost); not counted while warming up.
    fn record(&mut self, rtt: Option<u64>, warm: bool, t: f64) {
        match rtt {
            Some(_) if !warm => {}
            Some(rtt) => {
                let _ = self.rtt.record(rtt.max(1));
                self.series.points.push((t, rtt as f64 / 2000.0));
            }
            None => self.lost += 1,
        }
    }

    /// Half of every round trip.
    fn one_way(&self) -> Hdr<u64> {
        let mut o = new_hdr();
        for v in self.rtt.iter_recorded() {
            let _ = o.record_n((v.value_iterated_to() / 2).max(1), v.count_at_value());
        }
        o
    }
}

/// Sends probes (sequence 0, never a measured ping) on both paths until the echo
/// answers on both, for up to 10 s.
fn await_connected(
    dev_pub: &services::Pub<DeviceSample>,
    raw_pub: &services::Pub<DeviceSample>,
    echo_sub: &services::Sub<DeviceSample>,
    raw_sub: &services::Sub<DeviceSample>,
) -> Result<(), String> {
    use iceoryx2::port::update_connections::UpdateConnections;
    let ready_by = Instant::now() + Duration::from_secs(10);
    loop {
        let _ = dev_pub.update_connections();
        let _ = raw_pub.update_connections();
        let probe = DeviceSample {
            header: Header {
                seq: 0,
                ..Header::next(&mut 0)
            },
            ..Default::default()
        };
        let a = dev_pub.send_copy(probe).unwrap_or(0);
        let b = raw_pub.send_copy(probe).unwrap_or(0);
        std::thread::sleep(Duration::from_millis(20));
        while echo_sub.receive().ok().flatten().is_some() {}
        while raw_sub.receive().ok().flatten().is_some() {}
        if a > 0 && b > 0 {
            return Ok(());
        }
        if Instant::now() > ready_by {
            return Err("the echo process did not connect within 10 s".into());
        }
    }
}

/// Pings for `seconds` at `rate_hz`, alternating the two paths, against an echo that
/// `spawn_pong` starts in another process (it must run [`pong`] in `domain`).
pub fn ping(
    domain: &Domain,
    seconds: f64,
    rate_hz: f64,
    stop: &AtomicBool,
    progress: &mut dyn FnMut(&str),
) -> Result<Measured<PingReport>, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "latency-ping").map_err(|e| e.to_string())?;
    let dev_pub = ports::publisher(&node, services::device).map_err(|e| e.to_string())?;
    let echo_sub =
        ports::subscriber(&node, services::device_echo, None).map_err(|e| e.to_string())?;
    let (raw_pub, raw_sub) =
        ports::raw_device_pair(&node, RAW_PING, RAW_PONG).map_err(|e| e.to_string())?;
    await_connected(&dev_pub, &raw_pub, &echo_sub, &raw_sub)?;
    let project_rx = || echo_sub.receive().ok().flatten().map(|s| *s);
    let raw_rx = || raw_sub.receive().ok().flatten().map(|s| *s);
    let mut proj = PathStats::new("project one-way");
    let mut raw = PathStats::new("raw one-way");
    let period = Duration::from_secs_f64(1.0 / rate_hz.clamp(1.0, 20_000.0));
    let started = Instant::now();
    let mut next = started;
    let mut seq = 0u64;
    let mut raw_seq = 0u64;
    let mut last_progress = Instant::now();
    while !stop.load(Ordering::Relaxed) && started.elapsed().as_secs_f64() < seconds {
        let t = started.elapsed().as_secs_f64();
        // The first 200 round trips of each path warm caches and page mappings: not counted.
        let warm = seq > WARMUP;
        // The two paths alternate which goes first after the pause, so neither always
        // pays for waking up.
        let project_first = (seq + raw_seq) % 4 < 2;
        for turn in 0..2 {
            if (turn == 0) == project_first {
                // The project's path: a header stamped as haptic-loop does.
                let s = DeviceSample {
                    header: Header::next(&mut seq),
                    device_ok: 1,
                    position: [0.1, 0.6, 0.0],
                    ..Default::default()
                };
                let t0 = s.header.sent_ns;
                let _ = dev_pub.send_copy(s);
                let rtt = await_echo(&project_rx, s.header.seq, t0, Duration::from_millis(100));
                proj.record(rtt, warm, t);
            } else {
                // The raw path: the same payload, a plain counter.
                raw_seq += 1;
                let r = DeviceSample {
                    header: Header {
                        seq: raw_seq,
                        ..Header::next(&mut 0)
                    },
                    device_ok: 1,
                    position: [0.1, 0.6, 0.0],
                    ..Default::default()
                };
                let t0 = monotonic_ns();
                let _ = raw_pub.send_copy(r);
                let rtt = await_echo(&raw_rx, raw_seq, t0, Duration::from_millis(100));
                raw.record(rtt, warm, t);
            }
        }
        if last_progress.elapsed() >= Duration::from_secs(5) {
            progress(&format!(
                "{:.0} s: {} round trips",
                started.elapsed().as_secs_f64(),
                proj.rtt.len() + raw.rtt.len()
            ));
            last_progress = Instant::now();
        }
        next += period;
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else {
            next = now;
        }
    }
    for (path, p) in [("project", &proj), ("raw", &raw)] {
        if p.rtt.is_empty() && p.lost == 0 {
            return Err(format!(
                "measured nothing: the run was too short; the first {WARMUP} round trips of \
                 each path warm up and are not counted (give more --seconds)"
            ));
        }
        if p.rtt.is_empty() {
            return Err(format!(
                "measured nothing: none of the pings on the {path} path came back in {:.0} s \
                 ({} lost) in domain '{}'. The echo process did not answer: it may not have \
                 started in time on a saturated machine, or it runs in another domain",
                started.elapsed().as_secs_f64(),
                p.lost,
                domain.name()
            ));
        }
    }
    Ok(ping_report(
        proj,
        raw,
        started.elapsed().as_secs_f64(),
        rate_hz,
    ))
}

/// The report, histograms and series of a finished ping.
fn ping_report(
    proj: PathStats,
    raw: PathStats,
    seconds: f64,
    rate_hz: f64,
) -> Measured<PingReport> {
    let (ow_proj, ow_raw) = (proj.one_way(), raw.one_way());
    let (pp, pr) = (Percentiles::of(&ow_proj), Percentiles::of(&ow_raw));
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    let report = PingReport {
        seconds,
        rate_hz,
        payload_bytes: std::mem::size_of::<DeviceSample>(),
        project: PathReport {
            rtt_us: Percentiles::of(&proj.rtt),
            one_way_us: pp,
            lost: proj.lost,
        },
        raw: PathReport {
            rtt_us: Percentiles::of(&raw.rtt),
            one_way_us: pr,
            lost: raw.lost,
        },
        ratio_p50: ratio(pp.p50, pr.p50),
        ratio_p99: ratio(pp.p99, pr.p99),
    };
    Measured {
        report,
        hists: vec![
            HistogramPlot {
                name: "project one-way".into(),
                buckets: buckets_of(&ow_proj),
            },
            HistogramPlot {
                name: "raw one-way".into(),
                buckets: buckets_of(&ow_raw),
            },
        ],
        series: vec![proj.series, raw.series],
    }
}

/// Waits up to `timeout` for the first message from `recv`.
fn first<T>(
    recv: &mut dyn FnMut() -> Option<T>,
    timeout: Duration,
    what: &str,
    domain: &Domain,
) -> Result<T, String> {
    let until = Instant::now() + timeout;
    loop {
        if let Some(t) = recv() {
            return Ok(t);
        }
        if Instant::now() > until {
            return Err(format!(
                "no {what} in domain '{}' within {:.0} s: is it running there (cloth-lab, or --domain)?",
                domain.name(),
                timeout.as_secs_f64()
            ));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[derive(Debug, Serialize)]
pub struct LoopReport {
    pub seconds: f64,
    /// Ticks in the window.
    pub ticks: u64,
    /// Ticks skipped because a tick started more than a period late.
    pub missed: u64,
    pub period_us: Percentiles,
    /// Tick start minus its deadline.
    pub lateness_us: Percentiles,
    pub compute_us: Percentiles,
    /// Ticks later than 2 ms (period above 2 ms).
    pub periods_over_2ms: u64,
}

fn loop_sub(
    node: &Node<ipc::Service>,
) -> Result<iceoryx2::port::subscriber::Subscriber<ipc::Service, LoopTelemetry, ()>, String> {
    ports::subscriber(node, services::haptic_telemetry, None).map_err(|e| e.to_string())
}

/// Receives the newest valid loop telemetry, if any arrived.
fn newest(
    sub: &iceoryx2::port::subscriber::Subscriber<ipc::Service, LoopTelemetry, ()>,
    rejected: &mut u64,
) -> Option<Box<LoopTelemetry>> {
    let mut out = None;
    while let Ok(Some(s)) = sub.receive() {
        match s.check() {
            Ok(()) => out = Some(Box::new(*s)),
            Err(_) => *rejected += 1,
        }
    }
    out
}

/// The haptic loop's timing over `seconds`, from its telemetry (10 per second).
pub fn loop_(
    domain: &Domain,
    seconds: f64,
    stop: &AtomicBool,
) -> Result<Measured<LoopReport>, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "latency-loop").map_err(|e| e.to_string())?;
    let sub = loop_sub(&node)?;
    let mut rejected = 0;
    let first_t = first(
        &mut || newest(&sub, &mut rejected),
        Duration::from_secs(5),
        "haptic-loop telemetry",
        domain,
    )?;
    let started = Instant::now();
    let mut prev = first_t.clone();
    let mut s_period = Series::new("period max");
    let mut s_compute = Series::new("compute max");
    while !stop.load(Ordering::Relaxed) && started.elapsed().as_secs_f64() < seconds {
        std::thread::sleep(Duration::from_millis(20));
        if let Some(t) = newest(&sub, &mut rejected) {
            let at = started.elapsed().as_secs_f64();
            let w = window(Some(&prev.period), &t.period);
            if !w.is_empty() {
                s_period.points.push((at, w.max() as f64 / 1000.0));
            }
            let w = window(Some(&prev.compute), &t.compute);
            if !w.is_empty() {
                s_compute.points.push((at, w.max() as f64 / 1000.0));
            }
            prev = t;
        }
    }
    let last = prev;
    if last.header.seq == first_t.header.seq {
        return Err(format!(
            "haptic-loop telemetry stopped in domain '{}' during the window",
            domain.name()
        ));
    }
    let period = window(Some(&first_t.period), &last.period);
    let report = LoopReport {
        seconds: started.elapsed().as_secs_f64(),
        ticks: last.ticks - first_t.ticks,
        missed: last.missed - first_t.missed,
        period_us: Percentiles::of(&period),
        lateness_us: Percentiles::of(&window(Some(&first_t.lateness), &last.lateness)),
        compute_us: Percentiles::of(&window(Some(&first_t.compute), &last.compute)),
        periods_over_2ms: period.count_between(2_000_001, u64::MAX / 2),
    };
    let compute = window(Some(&first_t.compute), &last.compute);
    Ok(Measured {
        report,
        hists: vec![
            HistogramPlot {
                name: "period".into(),
                buckets: buckets_of(&period),
            },
            HistogramPlot {
                name: "compute".into(),
                buckets: buckets_of(&compute),
            },
        ],
        series: vec![s_period, s_compute],
    })
}

#[derive(Debug, Serialize)]
pub struct E2eReport {
    pub seconds: f64,
    /// Device sample sent -> cloth-sim built a local model from it -> the haptic loop's
    /// first tick that used that model, µs (from the loop's telemetry).
    pub sample_to_model_used_us: Percentiles,
    /// Age of the local model at each tick that used it, µs.
    pub model_age_us: Percentiles,
    /// Device sample sent -> cloth frame published with it, µs.
    pub motion_to_frame_published_us: Percentiles,
    /// Device sample sent -> cloth frame received here (a viewer), µs.
    pub motion_to_frame_received_us: Percentiles,
    pub frames: u64,
    /// cloth-sim's whole-frame compute time over the window, µs (its telemetry; absent
    /// when it sent none).
    pub sim_frame_us: Option<Percentiles>,
}

/// The whole loop's latencies over `seconds`, in a running system.
pub fn e2e(
    domain: &Domain,
    seconds: f64,
    stop: &AtomicBool,
) -> Result<Measured<E2eReport>, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "latency-e2e").map_err(|e| e.to_string())?;
    let sub = loop_sub(&node)?;
    let frames =
        ports::subscriber(&node, services::cloth_frame, None).map_err(|e| e.to_string())?;
    let sim_tel =
        ports::subscriber(&node, services::sim_telemetry, None).map_err(|e| e.to_string())?;
    let mut sim_first: Option<Box<shared::telemetry::SimTelemetry>> = None;
    let mut sim_last: Option<Box<shared::telemetry::SimTelemetry>> = None;
    let mut rejected = 0;
    let first_t = first(
        &mut || newest(&sub, &mut rejected),
        Duration::from_secs(5),
        "haptic-loop telemetry",
        domain,
    )?;
    let started = Instant::now();
    let (mut h_pub, mut h_recv) = (new_hdr(), new_hdr());
    let mut s_pub = Series::new("motion -> frame published");
    let mut s_loop = Series::new("sample -> model used (p50 per 100 ms)");
    let mut prev = first_t.clone();
    let mut n_frames = 0u64;
    while !stop.load(Ordering::Relaxed) && started.elapsed().as_secs_f64() < seconds {
        while let Ok(Some(f)) = frames.receive() {
            let now = monotonic_ns();
            let h = f.user_header();
            if h.header.check().is_err() || h.pen_sent_ns == 0 {
                continue;
            }
            n_frames += 1;
            let published = h.header.sent_ns.saturating_sub(h.pen_sent_ns);
            let _ = h_pub.record(published.max(1));
            let _ = h_recv.record(now.saturating_sub(h.pen_sent_ns).max(1));
            s_pub
                .points
                .push((started.elapsed().as_secs_f64(), published as f64 / 1000.0));
        }
        while let Ok(Some(t)) = sim_tel.receive() {
            if t.check().is_ok() {
                let t = Box::new(*t);
                if sim_first.is_none() {
                    sim_first = Some(t);
                } else {
                    sim_last = Some(t);
                }
            }
        }
        if let Some(t) = newest(&sub, &mut rejected) {
            let w = window(Some(&prev.pen_to_model), &t.pen_to_model);
            if !w.is_empty() {
                s_loop.points.push((
                    started.elapsed().as_secs_f64(),
                    w.value_at_quantile(0.5) as f64 / 1000.0,
                ));
            }
            prev = t;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    if n_frames == 0 {
        return Err(format!(
            "no cloth frames with pen samples in domain '{}': are cloth-sim and haptic-loop running?",
            domain.name()
        ));
    }
    let loop_w = window(Some(&first_t.pen_to_model), &prev.pen_to_model);
    let report = E2eReport {
        seconds: started.elapsed().as_secs_f64(),
        sample_to_model_used_us: Percentiles::of(&loop_w),
        model_age_us: Percentiles::of(&window(Some(&first_t.model_age), &prev.model_age)),
        motion_to_frame_published_us: Percentiles::of(&h_pub),
        motion_to_frame_received_us: Percentiles::of(&h_recv),
        frames: n_frames,
        sim_frame_us: sim_first
            .zip(sim_last)
            .map(|(a, b)| Percentiles::of(&window(Some(&a.frame_time), &b.frame_time))),
    };
    Ok(Measured {
        report,
        hists: vec![
            HistogramPlot {
                name: "sample -> model used".into(),
                buckets: buckets_of(&loop_w),
            },
            HistogramPlot {
                name: "motion -> frame published".into(),
                buckets: buckets_of(&h_pub),
            },
        ],
        series: vec![s_loop, s_pub],
    })
}

/// The haptic loop's telemetry now (cumulative since it started), waiting up to `timeout`.
pub fn loop_snapshot(domain: &Domain, timeout: Duration) -> Result<Box<LoopTelemetry>, String> {
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(domain, "latency-snapshot").map_err(|e| e.to_string())?;
    let sub = loop_sub(&node)?;
    let mut rejected = 0;
    first(
        &mut || newest(&sub, &mut rejected),
        timeout,
        "haptic-loop telemetry",
        domain,
    )
}

/// The haptic loop's figures since it started, from one telemetry snapshot.
#[derive(Debug, Serialize)]
pub struct LoopSummary {
    pub ticks: u64,
    pub missed: u64,
    pub period_us: Percentiles,
    pub compute_us: Percentiles,
    /// Age of the local model at each tick that used it.
    pub model_age_us: Percentiles,
    /// Device sample -> cloth-sim -> local model first used at the haptic loop.
    pub sample_to_model_used_us: Percentiles,
}

impl LoopSummary {
    pub fn of(t: &LoopTelemetry) -> Self {
        Self {
            ticks: t.ticks,
            missed: t.missed,
            period_us: Percentiles::of(&window(None, &t.period)),
            compute_us: Percentiles::of(&window(None, &t.compute)),
            model_age_us: Percentiles::of(&window(None, &t.model_age)),
            sample_to_model_used_us: Percentiles::of(&window(None, &t.pen_to_model)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An echo that connects but never answers (a saturated machine's): ping measured
    /// nothing, and says so as an error instead of reporting zeros.
    #[test]
    fn a_ping_that_measured_nothing_fails_and_says_why() {
        let domain = Domain::new(&format!("lpn{}", std::process::id())).unwrap();
        let node = services::node(&domain, "silent-echo").unwrap();
        let _dev = ports::subscriber(&node, services::device, None).unwrap();
        let _raw = ports::raw_device_pair(&node, RAW_PONG, RAW_PING).unwrap();
        let stop = AtomicBool::new(false);
        let r = ping(&domain, 0.5, 1000.0, &stop, &mut |_| {});
        let Err(e) = r else {
            panic!("nothing measured is an error")
        };
        assert!(
            e.starts_with("measured nothing") && e.contains("lost") && e.contains("project"),
            "{e}"
        );
        drop((_dev, _raw, node));
        domain.remove_leftovers();
    }
}
