//! `haptic-loop`: the 1 kHz haptic process.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use haptic_loop::device::{OpenHaptics, Replay, Script, SimDevice, Still, TargetSource, Workspace};
use haptic_loop::looper::{self, LoopConfig};
use haptic_loop::rt;
use shared::cli::whole_in;
use shared::domain::Domain;
use shared::ports::HapticPorts;
use shared::services;

#[derive(Parser)]
#[command(
    name = "haptic-loop",
    version,
    about = "Saiho haptic loop: owns the device, renders force at 1 kHz from the local model cloth-sim sends"
)]
struct Args {
    /// Device: sim (a simulated pen), openhaptics (a Phantom/Touch through libHD.so) or
    /// replay:FILE (a recorded device log).
    #[arg(long, default_value = "sim")]
    device: String,
    /// Domain (iceoryx2 prefix) to run in; default $SAIHO_DOMAIN, else "default".
    #[arg(long)]
    domain: Option<String>,
    /// sim device: timed hand targets, lines `t x y z buttons` (s, m, bit mask).
    #[arg(long)]
    script: Option<PathBuf>,
    /// Stop after this many seconds (default: run until SIGINT/SIGTERM).
    #[arg(long)]
    seconds: Option<f64>,
    /// SCHED_FIFO priority of the loop (1-99). Real time is on by default: SCHED_FIFO,
    /// locked memory and a CPU of its own, each where permitted; one line says what it got.
    #[arg(long, default_value_t = 80, allow_negative_numbers = true,
          value_parser = whole_in::<i32>(1, 99, " (SCHED_FIFO)"))]
    rt_priority: i32,
    /// CPU to pin the loop to (default: the highest this process may use, when there are
    /// two or more).
    #[arg(long, allow_negative_numbers = true, value_parser = whole_in::<usize>(0, 1023, ""))]
    cpu: Option<usize>,
    /// No real-time scheduling, memory locking or pinning (ticks may be late under load).
    #[arg(long)]
    no_rt: bool,
    /// Busy-wait before each deadline, µs (absorbs the kernel's wake-up jitter; on this
    /// VM 250 keeps the period error's p99.9 under 100 µs).
    #[arg(long, default_value_t = 250, allow_negative_numbers = true,
          value_parser = whole_in::<u64>(0, 1000, " µs (the period is 1000 µs)"))]
    spin_us: u64,
    /// Record every tick's pen state to this device log (replay it with
    /// --device replay:FILE).
    #[arg(long)]
    record: Option<PathBuf>,
    /// openhaptics: the HDAPI library to load.
    #[arg(long, default_value = "libHD.so")]
    hd_lib: String,
}

enum Target {
    Still(Still),
    Script(Script),
}

impl TargetSource for Target {
    fn target(&mut self, t: f64) -> ([f32; 3], u32) {
        match self {
            Target::Still(s) => s.target(t),
            Target::Script(s) => s.target(t),
        }
    }
}

fn log(msg: &str) {
    eprintln!("haptic-loop: {msg}");
}

/// Every flag checked before any work: one line with the accepted range.
fn validate(a: &Args) -> Result<(), String> {
    // --rt-priority, --cpu's range and --spin-us are checked as they are parsed.
    if let Some(c) = a.cpu
        && !shared::cpus::allowed().contains(&c)
    {
        return Err(format!(
            "--cpu {c} is not a CPU this process may use ({})",
            shared::cpus::format_list(&shared::cpus::allowed())
        ));
    }
    if let Some(s) = a.seconds
        && !(s > 0.0 && s <= 1.0e7)
    {
        return Err(format!("--seconds must be between 0 and 10000000, got {s}"));
    }
    Ok(())
}

/// Real time for the loop's thread unless `--no-rt`; one line says what it got.
fn real_time(a: &Args) {
    if a.no_rt {
        log("real-time off (--no-rt): ticks may be late under load");
        return;
    }
    let cpu = a.cpu.or(shared::cpus::plan().map(|(h, _)| h));
    log(&rt::realtime(a.rt_priority, cpu).line());
}

/// The device `--device` names, opened as far as it can be before the loop.
enum Dev {
    Sim(Target),
    OpenHaptics,
    Replay(Replay),
}

fn device_of(a: &Args) -> Result<Dev, String> {
    Ok(match (&a.device[..], &a.script) {
        ("sim", None) => Dev::Sim(Target::Still(Still(Workspace::default().centre, 0))),
        ("sim", Some(p)) => {
            let text = std::fs::read_to_string(p)
                .map_err(|e| format!("cannot read script {}: {e}", p.display()))?;
            Dev::Sim(Target::Script(
                Script::parse(&text).map_err(|e| format!("{}: {e}", p.display()))?,
            ))
        }
        ("openhaptics", _) => Dev::OpenHaptics,
        (d, _) if d.starts_with("replay:") => {
            Dev::Replay(Replay::open(std::path::Path::new(&d["replay:".len()..]))?)
        }
        (d, _) => {
            return Err(format!(
                "unknown device '{d}' (expected sim, openhaptics or replay:FILE)"
            ));
        }
    })
}

fn run(a: Args) -> Result<(), String> {
    validate(&a)?;
    let domain = Domain::from_arg_or_env(a.domain.as_deref()).map_err(|e| e.to_string())?;
    let dev = device_of(&a)?;
    let stop = rt::termination_flag();
    let _release = services::ReleaseOnDrop(domain.clone());
    let node = services::node(&domain, "haptic-loop").map_err(|e| e.to_string())?;
    let ports = HapticPorts::open(&node).map_err(|e| e.to_string())?;
    // The recorder's writer thread first, so it does not inherit the loop's priority and CPU.
    let mut recorder = match &a.record {
        Some(p) => Some(haptic_loop::record::Recorder::create(p)?),
        None => None,
    };
    // The watchers of cloth-sim's process and life lock too: ordinary threads, not the
    // loop's priority.
    let life = match shared::life::LifeWatch::new(&domain) {
        Ok(l) => Some(l),
        Err(e) => {
            log(&format!(
                "cloth-sim's life lock cannot be watched ({e}); its exit is seen from the kernel's notice, a few ms later"
            ));
            None
        }
    };
    let watch = haptic_loop::sim_watch::SimWatch::start(life);
    real_time(&a);
    let cfg = LoopConfig {
        spin_ns: a.spin_us * 1000,
        max_ticks: a.seconds.map(|s| (s * 1000.0) as u64),
        ..LoopConfig::default()
    };
    // One loop for every kind of device (each its own type).
    macro_rules! run_on {
        ($d:expr) => {
            looper::run($d, &ports, &cfg, stop, Some(&watch), recorder.as_mut(), log)
        };
    }
    let stats = match dev {
        Dev::Sim(source) => {
            let mut d = SimDevice::new(source, Workspace::default());
            log(&format!("device sim, domain '{}', 1 kHz", domain.name()));
            run_on!(&mut d)
        }
        Dev::Replay(mut d) => {
            if let Some(n) = d.cut_at_line {
                log(&format!(
                    "the device log was cut short at line {n} (its writer was stopped mid-record); replaying the {} whole records before it",
                    d.len()
                ));
            }
            log(&format!(
                "device replay ({:.1} s of log), domain '{}', 1 kHz",
                d.duration(),
                domain.name()
            ));
            run_on!(&mut d)
        }
        Dev::OpenHaptics => {
            let (mut d, notice) =
                OpenHaptics::open(&a.hd_lib, Workspace::default()).map_err(|e| e.to_string())?;
            if let Some(n) = notice {
                log(&n);
            }
            log(&format!(
                "device openhaptics ({}), domain '{}', 1 kHz",
                a.hd_lib,
                domain.name()
            ));
            let s = run_on!(&mut d);
            log(&format!("{} servo frames", d.frames()));
            s
        }
    };
    if let Some(r) = recorder {
        let dropped = r.dropped;
        let n = r.finish()?;
        log(&format!("device log: {n} ticks written, {dropped} dropped"));
    }
    let t = &stats.telemetry;
    log(&format!(
        "stopped after {} ticks: missed {}, lateness p50 {} us p99 {} us p99.9 {} us max {} us, period p50 {} us p99.9 {} us max {} us, compute p99 {} us, {} messages rejected",
        t.ticks,
        t.missed,
        t.lateness.quantile_ns(0.5) / 1000,
        t.lateness.quantile_ns(0.99) / 1000,
        t.lateness.quantile_ns(0.999) / 1000,
        t.lateness.max_ns / 1000,
        t.period.quantile_ns(0.5) / 1000,
        t.period.quantile_ns(0.999) / 1000,
        t.period.max_ns / 1000,
        t.compute.quantile_ns(0.99) / 1000,
        stats.rejected
    ));
    Ok(())
}

fn main() -> ExitCode {
    match run(shared::cli::parse::<Args>()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("haptic-loop: error: {e}");
            ExitCode::FAILURE
        }
    }
}
