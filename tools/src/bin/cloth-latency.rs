//! cloth-latency: measures the system's latencies and writes JSON, CSV and a PNG plot.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use serde::Serialize;
use shared::domain::Domain;
use tools::latency::{self, Measured};

#[derive(Parser)]
#[command(
    name = "cloth-latency",
    version,
    about = "Measures Saiho's latencies: IPC round trips, the haptic loop's timing, the whole loop",
    long_about = "Measures Saiho's latencies and reports p50, p99, p99.9 and max (hdrhistogram).\n\n\
        ping  round trips over the project's device-sample service and raw iceoryx2, same run\n\
        loop  the haptic loop's period and compute time from its telemetry (needs haptic-loop)\n\
        e2e   device sample -> cloth-sim -> local model at the haptic loop, and device motion ->\n      \
        cloth frame (needs haptic-loop and cloth-sim)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Args, Clone)]
struct Common {
    /// How long to measure, s.
    #[arg(long, default_value_t = 10.0)]
    seconds: f64,
    /// iceoryx2 domain of the running system (default: $SAIHO_DOMAIN, else "default").
    /// `ping` uses its own private domain unless this is given.
    #[arg(long)]
    domain: Option<String>,
    /// Write the report as JSON here.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write the time series as CSV here (series,t_s,value_us).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Draw the histograms and the time series into this PNG.
    #[arg(long)]
    plot: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Round trips: the project's device-sample service against raw iceoryx2, interleaved.
    Ping {
        #[command(flatten)]
        common: Common,
        /// Round trips per second on each path.
        #[arg(long, default_value_t = 1000.0)]
        rate: f64,
    },
    /// The haptic loop's period, lateness and compute time, and missed ticks.
    Loop {
        #[command(flatten)]
        common: Common,
    },
    /// Whole-loop latencies: sample -> sim -> model used; motion -> cloth frame.
    E2e {
        #[command(flatten)]
        common: Common,
    },
    /// (internal) The echo side of `ping`, started by it as a child process.
    #[command(hide = true)]
    Pong {
        #[arg(long)]
        domain: String,
        #[arg(long)]
        seconds: f64,
    },
}

fn check_common(c: &Common) -> Result<(), String> {
    if !(c.seconds.is_finite() && c.seconds > 0.0 && c.seconds <= 24.0 * 3600.0) {
        return Err(format!(
            "--seconds must be between 0 and 86400, got {}",
            c.seconds
        ));
    }
    for p in [&c.json, &c.csv, &c.plot].into_iter().flatten() {
        if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty())
            && !dir.is_dir()
        {
            return Err(format!("{}: no such directory", dir.display()));
        }
    }
    Ok(())
}

fn write_outputs<R: Serialize + std::fmt::Debug>(
    c: &Common,
    title: &str,
    m: &Measured<R>,
) -> Result<(), String> {
    println!(
        "{}",
        serde_json::to_string_pretty(&m.report).map_err(|e| e.to_string())?
    );
    if let Some(p) = &c.json {
        tools::stats::write_json(p, &m.report)?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &c.csv {
        tools::stats::write_csv(p, &m.series)?;
        eprintln!("wrote {}", p.display());
    }
    if let Some(p) = &c.plot {
        tools::plot::draw(p, title, &m.hists, &m.series, "µs")?;
        eprintln!("wrote {}", p.display());
    }
    Ok(())
}

fn run(cli: Cli) -> Result<(), String> {
    let stop = shared::signals::termination_flag();
    let progress = &mut |m: &str| eprintln!("cloth-latency: {m}");
    match cli.command {
        Command::Pong { domain, seconds } => {
            let d = Domain::new(&domain).map_err(|e| e.to_string())?;
            latency::pong(&d, seconds, stop)?;
            Ok(())
        }
        Command::Ping { common, rate } => {
            check_common(&common)?;
            if !(rate.is_finite() && (1.0..=20_000.0).contains(&rate)) {
                return Err(format!("--rate must be 1 to 20000 per second, got {rate}"));
            }
            // A private domain, so the pings never reach a running cloth-sim as pen samples.
            let name = common
                .domain
                .clone()
                .unwrap_or_else(|| format!("latency{}", std::process::id()));
            let d = Domain::new(&name).map_err(|e| e.to_string())?;
            let exe = std::env::current_exe().map_err(|e| e.to_string())?;
            let mut child = std::process::Command::new(exe)
                .args(["pong", "--domain", &name, "--seconds"])
                .arg(format!("{}", common.seconds + 15.0))
                .spawn()
                .map_err(|e| format!("starting the echo process: {e}"))?;
            progress(&format!(
                "ping for {:.0} s at {rate}/s on each path (domain '{name}')",
                common.seconds
            ));
            let m = latency::ping(&d, common.seconds, rate, stop, progress);
            let _ = child.kill();
            let _ = child.wait();
            if common.domain.is_none() {
                d.remove_leftovers();
            }
            let m = m?;
            write_outputs(&common, "cloth-latency ping: one-way latency", &m)?;
            Ok(())
        }
        Command::Loop { common } => {
            check_common(&common)?;
            let d = Domain::from_arg_or_env(common.domain.as_deref()).map_err(|e| e.to_string())?;
            progress(&format!(
                "haptic loop timing for {:.0} s (domain '{}')",
                common.seconds,
                d.name()
            ));
            let m = latency::loop_(&d, common.seconds, stop)?;
            write_outputs(
                &common,
                "cloth-latency loop: haptic tick period and compute",
                &m,
            )
        }
        Command::E2e { common } => {
            check_common(&common)?;
            let d = Domain::from_arg_or_env(common.domain.as_deref()).map_err(|e| e.to_string())?;
            progress(&format!(
                "whole-loop latency for {:.0} s (domain '{}')",
                common.seconds,
                d.name()
            ));
            let m = latency::e2e(&d, common.seconds, stop)?;
            write_outputs(&common, "cloth-latency e2e: pen to cloth and back", &m)
        }
    }
}

fn main() -> ExitCode {
    match run(shared::cli::parse::<Cli>()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
