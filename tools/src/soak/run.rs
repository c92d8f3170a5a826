//! The soak's course: start, faults in turn, a clean stop, the verdict.

use std::time::{Duration, Instant};

use super::watch::{Watch, ramp_envelope, zero_from};
use super::{
    FAULTS, FaultCount, Procs, Rng, SoakConfig, SoakReport, floor, kill9, monotonic_ns, pen_script,
    services, signal, stop,
};

/// Pumps the watch for `d`.
fn pump_for(w: &mut Watch, d: Duration) {
    let until = Instant::now() + d;
    while Instant::now() < until {
        w.pump();
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Pumps until `done` or `limit`; whether `done` came.
fn pump_until(w: &mut Watch, limit: Duration, done: &dyn Fn(&Watch) -> bool) -> bool {
    let until = Instant::now() + limit;
    while Instant::now() < until {
        w.pump();
        if done(w) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    false
}

/// The force after a cloth-sim fault at `t` (ns): settled at zero when, ms after the
/// fault and after the newest model went stale (20 ms).
fn force_zero(w: &Watch, r: &mut SoakReport, t: u64, last_model: u64) -> Option<f64> {
    if let Some(z) = zero_from(&w.recent, t) {
        let ms = z.saturating_sub(t) as f64 * 1e-6;
        r.force_zero_ms.push(ms);
        let stale = last_model + 20_000_000;
        r.force_zero_after_stale_ms_max = r
            .force_zero_after_stale_ms_max
            .max(z.saturating_sub(stale) as f64 * 1e-6);
        Some(ms)
    } else {
        r.failures
            .push("the force did not settle at zero after a cloth-sim fault".into());
        None
    }
}

/// The force's return when the loop re-engages after `after` (ns), against its ramp
/// ([`ramp_envelope`]).
fn ramp(w: &Watch, r: &mut SoakReport, after: u64) {
    if let Some((over, most, unseen)) = ramp_envelope(&w.recent, after, w.first_model_after) {
        r.ramp_over_limit_max = r.ramp_over_limit_max.max(over);
        r.ramps
            .push((w.phase.to_string(), over, f64::from(most), unseen));
    }
}

fn ui_kill(p: &mut Procs, w: &mut Watch, r: &mut SoakReport) -> Result<bool, String> {
    kill9(&mut p.ui);
    pump_for(w, Duration::from_millis(300));
    while p.ui_rx.try_recv().is_ok() {}
    p.spawn_ui()?;
    let until = Instant::now() + Duration::from_secs(15);
    while Instant::now() < until {
        w.pump();
        if let Ok(ms) = p.ui_rx.try_recv() {
            r.ui_design_ms.push(ms);
            return Ok(true);
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    Ok(false)
}

fn sim_kill(p: &mut Procs, w: &mut Watch, r: &mut SoakReport) -> Result<bool, String> {
    let acked = w.acked;
    let t = monotonic_ns();
    w.pause_gaps();
    w.edits = false;
    kill9(&mut p.sim);
    pump_for(w, Duration::from_millis(400));
    // Every model it sent before it died has been taken in by now.
    if let Some(ms) = force_zero(w, r, t, w.last_model_ns) {
        r.force_zero_after_kill_ms.push(ms);
    }
    let restart = monotonic_ns();
    w.watch_return(restart);
    p.spawn_sim(false)?;
    let back = pump_until(w, Duration::from_secs(60), &|w| w.last_model_ns > restart);
    r.resumed.push(back);
    if !back {
        return Ok(false);
    }
    w.resume_gaps();
    // The first telemetry of the new cloth-sim says what it resumed.
    let told = pump_until(w, Duration::from_secs(5), &|w| {
        w.sim_tel_last.is_some_and(|(at, _)| at > restart)
    });
    let restored = w.sim_tel_last.map_or(0, |(_, n)| u64::from(n));
    if told {
        r.edits_lost.push(acked.saturating_sub(restored));
        w.acked = restored;
    }
    w.edits = true;
    ramp(w, r, restart);
    Ok(told)
}

fn haptic_kill(p: &mut Procs, w: &mut Watch, r: &mut SoakReport) -> Result<bool, String> {
    let models = w.models_seen;
    kill9(&mut p.haptic);
    w.end_lifetime();
    // cloth-sim keeps stepping, and lets go of the pinch 0.1 s after the pen went silent
    // (a loaded machine's frames may come slower: up to 3 s is waited for).
    let released = pump_until(w, Duration::from_secs(3), &|w| {
        !w.pinching && w.models_seen > models + 20
    });
    r.pinch_released.push(released);
    let restart = monotonic_ns();
    p.spawn_haptic()?;
    // The pen's script starts over: it pinches again 2.2 s in.
    let back = pump_until(w, Duration::from_secs(10), &|w| {
        w.recent.iter().any(|&(t, m, _)| t > restart && m > 0.0)
    });
    // No ramp to measure here: the new loop engaged when its first model came, with the
    // pen in the air; the force rose as the pen came down (stale forces are counted
    // throughout).
    pump_for(w, Duration::from_millis(800));
    Ok(back)
}

fn sim_stop(p: &mut Procs, w: &mut Watch, r: &mut SoakReport) -> Result<bool, String> {
    let t = monotonic_ns();
    w.pause_gaps();
    signal(&p.sim, rustix::process::Signal::STOP);
    pump_for(w, Duration::from_secs(5));
    force_zero(w, r, t, w.last_model_ns);
    r.stop_models_after_ms
        .push(w.last_model_ns.saturating_sub(t) as f64 * 1e-6);
    let cont = monotonic_ns();
    w.watch_return(cont);
    signal(&p.sim, rustix::process::Signal::CONT);
    let back = pump_until(w, Duration::from_secs(10), &|w| w.last_model_ns > cont);
    if back {
        w.resume_gaps();
    }
    pump_for(w, Duration::from_millis(800));
    ramp(w, r, cont);
    Ok(back)
}

/// Runs the suite (see the module's doc); `progress` hears a line per fault.
pub fn soak(cfg: &SoakConfig, progress: &mut dyn FnMut(&str)) -> Result<SoakReport, String> {
    std::fs::create_dir_all(&cfg.out).map_err(|e| format!("{}: {e}", cfg.out.display()))?;
    let mut r = SoakReport {
        grid: cfg.grid,
        ..SoakReport::default()
    };
    progress("measuring the machine's timing floor (cyclictest)");
    (r.floor_quiet_us, r.floor_source) = floor(cfg.floor_s);
    // The haptic loop gets a CPU of its own, as cloth-lab gives it; cloth-sim and cloth-ui
    // keep to the rest.
    let plan = shared::cpus::plan();
    let script = cfg.out.join("pen.script");
    std::fs::write(&script, pen_script(cfg.minutes * 60.0 + 600.0))
        .map_err(|e| format!("{}: {e}", script.display()))?;
    let (ui_tx, ui_rx) = std::sync::mpsc::channel();
    let mut p = Procs {
        cfg: cfg.clone(),
        haptic_cpu: plan.as_ref().map(|(c, _)| *c),
        others: plan.map(|(_, rest)| shared::cpus::format_list(&rest)),
        script,
        autosave: cfg.out.join("soak.autosave.saiho"),
        display: None,
        xvfb: None,
        haptic: None,
        sim: None,
        ui: None,
        ui_rx,
        ui_tx,
    };
    let during = super::host::Beside::start();
    let result = course(&mut p, cfg, &mut r, progress);
    let host = during.map(super::host::Beside::end).unwrap_or_default();
    r.floor_by_cpu_us = host.max_us.clone();
    for s in &mut r.stalls {
        let to = s.from_ns + (s.ms * 1e6) as u64;
        if let Some((ms, cpu)) = host.held_within(s.from_ns, to) {
            s.host_held_ms = Some(ms);
            s.host_held_cpu = Some(cpu);
        }
    }
    r.floor_us = r.floor_by_cpu_us.iter().copied().max();
    r.haptic_cpu = p.haptic_cpu;
    // Late ticks, against the floor measured meanwhile (the quiet one when cyclictest
    // could not run beside the faults; none without cyclictest at all).
    // The floor measured beside the faults judges; without it, the quiet one. The ticks
    // over the quiet floor are counted too: a VM's floor under load can be far above it.
    let over = r.floor_us.or(r.floor_quiet_us).unwrap_or(0) * 1000 + 2_000_000;
    let over_quiet = r.floor_quiet_us.unwrap_or(0) * 1000 + 2_000_000;
    for (phase, h) in &r.lateness {
        let n = super::ticks_over(h, over);
        if n > 0 {
            r.late_ticks_by_phase.insert(phase.clone(), n);
        }
        r.haptic_ticks_over_floor_2ms += n;
        r.haptic_ticks_over_quiet_floor_2ms += super::ticks_over(h, over_quiet);
    }
    for c in [&mut p.ui, &mut p.haptic, &mut p.sim] {
        stop(c);
    }
    kill9(&mut p.xvfb);
    // The domain goes whether the course finished or not.
    services::release(&cfg.domain);
    result?;
    r.left_behind = left_behind(&cfg.domain);
    judge(&mut r);
    Ok(r)
}

/// Starts the processes and injects the faults.
fn course(
    p: &mut Procs,
    cfg: &SoakConfig,
    r: &mut SoakReport,
    progress: &mut dyn FnMut(&str),
) -> Result<(), String> {
    if cfg.ui {
        p.start_display()?;
    }
    p.spawn_sim(true)?;
    p.spawn_haptic()?;
    p.spawn_ui()?;
    let node = services::node(&cfg.domain, "soak").map_err(|e| e.to_string())?;
    let vertices = ((cfg.grid + 1) * (cfg.grid + 1)) as u64;
    let mut w = Watch::open(&node, vertices)?;
    progress("waiting for cloth-sim to build the cloth and publish");
    if !pump_until(&mut w, Duration::from_secs(120), &|w| w.models_seen > 30) {
        return Err("cloth-sim published no cloth within 120 s (see cloth-sim.log)".into());
    }
    let started = Instant::now();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ u64::from(std::process::id()));
    let interrupt = shared::signals::termination_flag();
    for i in 0..cfg.faults {
        if started.elapsed().as_secs_f64() > cfg.minutes * 60.0 {
            break;
        }
        // SIGINT or SIGTERM: stop injecting; the processes still stop cleanly below.
        if interrupt.load(std::sync::atomic::Ordering::Relaxed) {
            r.interrupted = true;
            progress("interrupted: stopping the processes and writing the report");
            break;
        }
        let kind = FAULTS[i % FAULTS.len()];
        if kind == "ui-kill" && p.ui.is_none() {
            continue;
        }
        // Normal work between faults, for a random 1-3 s (the moment of a kill is random
        // against the autosave's writes).
        w.phase = "steady";
        pump_for(&mut w, Duration::from_secs_f64(1.0 + 2.0 * rng.next()));
        w.phase = kind;
        let ok = match kind {
            "ui-kill" => ui_kill(p, &mut w, r)?,
            "sim-kill" => sim_kill(p, &mut w, r)?,
            "haptic-kill" => haptic_kill(p, &mut w, r)?,
            _ => sim_stop(p, &mut w, r)?,
        };
        let c: &mut FaultCount = r.faults.entry(kind.into()).or_default();
        c.injected += 1;
        c.recovered += u32::from(ok);
        progress(&format!(
            "{:.0} s: fault {} ({kind}) {}",
            started.elapsed().as_secs_f64(),
            i + 1,
            if ok { "recovered" } else { "NOT recovered" }
        ));
    }
    pump_for(&mut w, Duration::from_secs(1));
    w.end_lifetime();
    r.seconds = started.elapsed().as_secs_f64();
    r.haptic_late_max_us = w.late_max_ns / 1000;
    r.haptic_ticks = w.ticks;
    r.lateness = std::mem::take(&mut w.lateness_by_phase);
    r.sim_stall_max_ms = w.gap_max_ms;
    r.stalls = std::mem::take(&mut w.stalls);
    r.gap_max_ms_by_phase = std::mem::take(&mut w.gap_max_by_phase);
    r.sim_frame_max_ms_by_phase = std::mem::take(&mut w.frame_max_by_phase);
    r.stale_force_ticks = w.stale_force_ticks;
    r.edits_acked = w.acked;
    Ok(())
}

/// What of `domain` is left in /dev/shm and the runtime directory.
fn left_behind(domain: &shared::domain::Domain) -> Vec<String> {
    let mut left: Vec<String> = domain
        .shm_files()
        .into_iter()
        .map(|(p, _)| p.display().to_string())
        .collect();
    if let Ok(root) = domain.root_path()
        && root.exists()
    {
        left.push(root.display().to_string());
    }
    left
}

/// How far over its ramp a force may read from rounding alone: a force clamped to the
/// peak at the tick the ramp reaches it read 1.0000001 (3.3 N in `f32` over the peak
/// computed in `f32`), which is the ramp, not a force past it.
const RAMP_ROUNDING: f64 = 1e-5;

/// Each requirement the figures break, in words.
fn judge(r: &mut SoakReport) {
    let mut f = Vec::new();
    if r.interrupted {
        f.push("interrupted (SIGINT or SIGTERM) before the faults asked for were injected".into());
    }
    if r.haptic_ticks == 0 {
        f.push("the haptic loop never ran (see haptic-loop.log)".into());
    }
    if r.stale_force_ticks > 0 {
        f.push(format!(
            "{} ticks rendered force from a stale model",
            r.stale_force_ticks
        ));
    }
    let kill_max = r
        .force_zero_after_kill_ms
        .iter()
        .copied()
        .fold(0.0, f64::max);
    if kill_max > 10.0 {
        f.push(format!(
            "the force took {kill_max:.1} ms to reach zero after cloth-sim was killed (limit 10 ms)"
        ));
    }
    if r.force_zero_after_stale_ms_max > 12.0 {
        f.push(format!(
            "the force took {:.1} ms to reach zero once the model was stale (limit 10 ms and a tick)",
            r.force_zero_after_stale_ms_max
        ));
    }
    if r.haptic_ticks_over_floor_2ms > 0 {
        f.push(format!(
            "{} haptic ticks were later than the floor plus 2 ms",
            r.haptic_ticks_over_floor_2ms
        ));
    }
    if r.sim_stall_max_ms > 50.0 {
        f.push(format!(
            "cloth-sim stalled {:.0} ms (limit 50)",
            r.sim_stall_max_ms
        ));
    }
    if let Some(ms) = r.ui_design_ms.iter().copied().find(|&ms| ms > 1000.0) {
        f.push(format!(
            "a restarted cloth-ui had the design after {ms:.0} ms (limit 1000)"
        ));
    }
    let lost_limit = (super::EDIT_HZ * 1.0) as u64;
    if let Some(n) = r.edits_lost.iter().copied().find(|&n| n > lost_limit) {
        f.push(format!(
            "a cloth-sim kill lost {n} edits (more than 1 s of them)"
        ));
    }
    if r.resumed.iter().any(|b| !b) {
        f.push("a killed cloth-sim did not resume".into());
    }
    if r.pinch_released.iter().any(|b| !b) {
        f.push("cloth-sim kept the pinch (or stopped) after haptic-loop was killed".into());
    }
    if r.ramp_over_limit_max > 1.0 + RAMP_ROUNDING {
        f.push(format!(
            "a force came back faster than its ramp ({:.1} times the most the ramp lets through at its tick)",
            r.ramp_over_limit_max
        ));
    }
    for (kind, c) in &r.faults {
        if c.recovered < c.injected {
            f.push(format!(
                "{kind}: {} of {} recovered",
                c.recovered, c.injected
            ));
        }
    }
    if !r.left_behind.is_empty() {
        f.push(format!(
            "left behind after the clean stop: {}",
            r.left_behind.join(", ")
        ));
    }
    r.failures.extend(f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_force_at_its_ramp_to_the_rounding_passes_and_one_past_it_fails() {
        let ramp_failed = |over: f64| {
            let mut r = SoakReport {
                ramp_over_limit_max: over,
                ..SoakReport::default()
            };
            judge(&mut r);
            r.failures
                .iter()
                .any(|f| f.contains("faster than its ramp"))
        };
        assert!(!ramp_failed(0.5));
        assert!(
            !ramp_failed(1.000_000_119_209_289_6),
            "the peak force at the peak"
        );
        assert!(ramp_failed(1.01));
    }
}
