//! cloth-lab: starts haptic-loop, cloth-sim and cloth-ui in one domain and supervises
//! them; or runs a headless scenario across the real processes.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand};
use shared::domain::Domain;
use tools::lab::{Role, Supervisor, have_display, request, sibling};

#[derive(Parser)]
#[command(
    name = "cloth-lab",
    version,
    about = "Runs the Saiho workstation: haptic-loop, cloth-sim and cloth-ui, supervised",
    long_about = "Runs the Saiho workstation: haptic-loop, cloth-sim and cloth-ui as supervised \
        child processes in one iceoryx2 domain, their logs prefixed. Ctrl-C (or q) stops all.\n\n\
        While it runs, type h, s or u to restart haptic-loop, cloth-sim or cloth-ui, or run \
        `cloth-lab restart ui` from another terminal; the other processes are not touched.\n\n\
        With --headless (or when there is no display) it runs a scenario across the real \
        processes with the simulated pen and a scripted stand-in for the designer."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Cmd>,
    /// Pen: sim (simulated), openhaptics (a Phantom/Touch through libHD), or replay:FILE.
    #[arg(long, default_value = "sim")]
    device: String,
    /// iceoryx2 domain (default: $SAIHO_DOMAIN, else "saiho").
    #[arg(long)]
    domain: Option<String>,
    /// Cloth grid (vertices per side minus one).
    #[arg(long, default_value_t = 64)]
    grid: usize,
    /// Body: cube, sphere, mannequin or FILE.obj.
    #[arg(long, default_value = "cube")]
    body: String,
    /// Simulated pen script (timed positions and buttons) for haptic-loop.
    #[arg(long)]
    script: Option<PathBuf>,
    /// Start a new design rather than resume the autosave.
    #[arg(long)]
    fresh: bool,
    /// Do not start cloth-ui (also: run the lab, not the headless scenario, without a
    /// display).
    #[arg(long)]
    no_ui: bool,
    /// haptic-loop real-time priority (SCHED_FIFO) and CPU, when permitted.
    #[arg(long)]
    rt_priority: Option<u32>,
    #[arg(long)]
    cpu: Option<usize>,
    /// Stop after this many seconds.
    #[arg(long)]
    seconds: Option<f64>,
    /// Run a scenario without a window (see --scenario and --out).
    #[arg(long)]
    headless: bool,
    /// The headless scenario.
    #[arg(long, default_value = "fit-cube")]
    scenario: String,
    /// Where the headless scenario writes its export and report.json.
    #[arg(long, default_value = "out/lab-fit-cube")]
    out: PathBuf,
}

#[derive(Subcommand)]
enum Cmd {
    /// Restart one process of the running lab (haptic, sim or ui).
    Restart {
        role: String,
        #[arg(long)]
        domain: Option<String>,
    },
    /// The running lab's processes.
    Status {
        #[arg(long)]
        domain: Option<String>,
    },
    /// Stop the running lab.
    Stop {
        #[arg(long)]
        domain: Option<String>,
    },
}

fn domain_of(arg: Option<&str>) -> Result<Domain, String> {
    Domain::from_arg_or_env(arg).map_err(|e| e.to_string())
}

fn control(line: &str, domain: Option<&str>) -> Result<(), String> {
    let reply = request(&domain_of(domain)?, line)?;
    match reply.strip_prefix("ok ") {
        Some(r) => {
            println!("{r}");
            Ok(())
        }
        None => Err(reply.strip_prefix("error ").unwrap_or(&reply).to_string()),
    }
}

fn haptic_args(cli: &Cli, domain: &Domain, script: Option<&PathBuf>) -> Vec<String> {
    let mut a = vec![
        "--domain".to_string(),
        domain.name().to_string(),
        "--device".into(),
        cli.device.clone(),
    ];
    if let Some(s) = script {
        a.extend(["--script".into(), s.display().to_string()]);
    }
    if let Some(p) = cli.rt_priority {
        a.extend(["--rt-priority".into(), p.to_string()]);
    }
    if let Some(c) = cli.cpu {
        a.extend(["--cpu".into(), c.to_string()]);
    }
    a
}

fn sim_args(cli: &Cli, domain: &Domain, fresh: bool, autosave: Option<&PathBuf>) -> Vec<String> {
    let mut a = vec![
        "run".to_string(),
        "--domain".into(),
        domain.name().into(),
        "--grid".into(),
        cli.grid.to_string(),
        "--body".into(),
        cli.body.clone(),
    ];
    if fresh {
        a.push("--fresh".into());
    }
    if let Some(p) = autosave {
        a.extend(["--autosave".into(), p.display().to_string()]);
    }
    a
}

fn run_lab(cli: &Cli) -> Result<(), String> {
    let domain = domain_of(cli.domain.as_deref())?;
    let mut sup = Supervisor::new(domain.clone())?;
    sup.add(Role::Haptic, haptic_args(cli, &domain, cli.script.as_ref()));
    sup.add(Role::Sim, sim_args(cli, &domain, cli.fresh, None));
    if !cli.no_ui {
        if sibling("cloth-ui")?.is_file() {
            sup.add(Role::Ui, vec!["--domain".into(), domain.name().into()]);
        } else {
            eprintln!(
                "cloth-lab: cloth-ui is not built next to cloth-lab; running haptic-loop and cloth-sim only"
            );
        }
    }
    sup.start_all()?;
    eprintln!(
        "cloth-lab: domain '{}'. Keys: h / s / u restart haptic-loop / cloth-sim / cloth-ui, q quits. \
         From another terminal: cloth-lab restart ui --domain {}",
        domain.name(),
        domain.name()
    );
    if std::io::stdin().is_terminal() {
        sup.read_terminal();
    }
    let stop = shared::signals::termination_flag();
    let until = cli
        .seconds
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let failures = sup.supervise(&|| stop.load(Ordering::Relaxed), until);
    if failures.is_empty() {
        eprintln!("cloth-lab: stopped");
        Ok(())
    } else {
        Err(failures.join("; "))
    }
}

fn run_headless(cli: &Cli) -> Result<(), String> {
    if cli.scenario != "fit-cube" {
        return Err(format!(
            "unknown headless scenario '{}' (fit-cube)",
            cli.scenario
        ));
    }
    if cli.body != "cube" {
        return Err("the fit-cube scenario drapes over the cube (--body cube)".into());
    }
    std::fs::create_dir_all(&cli.out).map_err(|e| format!("{}: {e}", cli.out.display()))?;
    // A private domain unless one is given, so a running lab is never disturbed.
    let domain = match &cli.domain {
        Some(d) => domain_of(Some(d))?,
        None => domain_of(Some(&format!("lab{}", std::process::id())))?,
    };
    let started = Instant::now();
    let autosave = cli.out.join("autosave.saiho");
    let mut sup = Supervisor::new(domain.clone())?;
    sup.add(Role::Haptic, haptic_args(cli, &domain, cli.script.as_ref()));
    sup.add(Role::Sim, sim_args(cli, &domain, true, Some(&autosave)));
    sup.start_all()?;
    eprintln!(
        "cloth-lab: headless {} in domain '{}': haptic-loop ({}), cloth-sim (grid {}), a scripted designer in place of cloth-ui",
        cli.scenario,
        domain.name(),
        cli.device,
        cli.grid
    );
    let done = Arc::new(AtomicBool::new(false));
    let stop = shared::signals::termination_flag();
    let worker = {
        let (domain, out, done) = (domain.clone(), cli.out.clone(), done.clone());
        std::thread::spawn(move || {
            let r = tools::headless::fit_cube(&domain, &out, stop, &mut |m| {
                eprintln!("cloth-lab: {m}")
            })
            .and_then(|standin| {
                let haptic = tools::latency::loop_snapshot(&domain, Duration::from_secs(3))?;
                Ok((standin, haptic))
            });
            done.store(true, Ordering::Relaxed);
            r
        })
    };
    let failures = sup.supervise(
        &|| stop.load(Ordering::Relaxed) || done.load(Ordering::Relaxed),
        None,
    );
    done.store(true, Ordering::Relaxed);
    let result = worker
        .join()
        .map_err(|_| "the scripted designer panicked".to_string())?;
    if !failures.is_empty() {
        return Err(failures.join("; "));
    }
    let (standin, haptic) = result?;
    domain.remove_leftovers();
    let sim_path = cli.out.join("sim-report.json");
    let sim: serde_json::Value = std::fs::read_to_string(&sim_path)
        .map_err(|e| format!("{}: {e}", sim_path.display()))
        .and_then(|t| {
            serde_json::from_str(&t).map_err(|e| format!("{}: {e}", sim_path.display()))
        })?;
    let mut report = serde_json::Map::new();
    report.insert("scenario".into(), "fit-cube".into());
    report.insert(
        "processes".into(),
        serde_json::json!(["haptic-loop", "cloth-sim", "scripted designer (cloth-lab)"]),
    );
    report.insert("device".into(), cli.device.clone().into());
    report.insert("grid".into(), cli.grid.into());
    if let serde_json::Value::Object(m) = sim {
        report.extend(m);
    }
    let json = |e: serde_json::Error| e.to_string();
    report.insert(
        "stand_in".into(),
        serde_json::to_value(&standin).map_err(json)?,
    );
    report.insert(
        "latency".into(),
        serde_json::to_value(tools::latency::LoopSummary::of(&haptic)).map_err(json)?,
    );
    report.insert("wall_s".into(), started.elapsed().as_secs_f64().into());
    let path = cli.out.join("report.json");
    tools::stats::write_json(&path, &serde_json::Value::Object(report))?;
    eprintln!("cloth-lab: wrote {}", path.display());
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match &cli.command {
        Some(Cmd::Restart { role, domain }) => Role::parse(role)
            .and_then(|r| control(&format!("restart {}", r.name()), domain.as_deref())),
        Some(Cmd::Status { domain }) => control("status", domain.as_deref()),
        Some(Cmd::Stop { domain }) => control("stop", domain.as_deref()),
        None if cli.headless => run_headless(&cli),
        None if !have_display() && !cli.no_ui => {
            eprintln!(
                "cloth-lab: no display (DISPLAY and WAYLAND_DISPLAY are unset), so no window: \
                 running the headless fit-cube scenario into {} instead",
                cli.out.display()
            );
            run_headless(&cli)
        }
        None => run_lab(&cli),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
