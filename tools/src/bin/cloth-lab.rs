//! cloth-lab: starts haptic-loop, cloth-sim and cloth-ui in one domain and supervises
//! them; or runs a headless scenario across the real processes.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::{Parser, Subcommand};
use shared::cli::whole_in;
use shared::domain::Domain;
use tools::cpu_plan::Plan;
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
    /// iceoryx2 domain (default: $SAIHO_DOMAIN, else "default").
    #[arg(long)]
    domain: Option<String>,
    /// Cloth grid (vertices per side minus one).
    // The same limit as cloth-sim's --grid ((1999 + 1)^2 vertices).
    #[arg(long, default_value_t = 64, allow_negative_numbers = true,
          value_parser = whole_in::<usize>(1, 1999, " cells a side"))]
    grid: usize,
    /// Body: cube, sphere, mannequin, mannequin-apose (arms held out), human (GarmentCode's
    /// average body) or FILE.obj. Default: the cube, or the body the --pattern is cut for
    /// (human for a GarmentCode pattern, the one an SVG names; cloth-sim's choice).
    #[arg(long)]
    body: Option<String>,
    /// Cloth model of a new design (cloth-sim's --model): xpbd (the default: real time,
    /// with its guard the cloth never crosses itself or the body), vbd (never crosses,
    /// strain under 1%; several times slower, see docs/models.md), seed (the paper's
    /// mass-spring) or implicit. A resumed design keeps its own (with --fresh for a new
    /// one).
    #[arg(long, value_parser = ["xpbd", "vbd", "seed", "implicit"])]
    model: Option<String>,
    /// XPBD with its guard (cloth-sim's --guard, the default for a new design): given, a
    /// resumed design takes it too, whatever its file says.
    #[arg(long, conflicts_with = "no_guard")]
    guard: bool,
    /// Plain XPBD (cloth-sim's --no-guard): the cloth can cross itself and the body's
    /// edges, at a fraction of the guard's frame time (docs/collision.md).
    #[arg(long)]
    no_guard: bool,
    /// The cloth's fabric, from the library (`cloth-sim fabrics` lists them).
    #[arg(long)]
    fabric: Option<String>,
    /// XPBD: the most a triangle may stretch past its rest length, held hard each substep
    /// (cloth-sim's --strain-limit; 0.2, the default: 1.2x; a fabric's own with --fabric;
    /// 0: off). Given, a resumed design takes it too; the studio's Hold stretch under
    /// changes it while running.
    #[arg(long, allow_negative_numbers = true)]
    strain_limit: Option<f32>,
    /// Simulated pen script (timed positions and buttons) for haptic-loop.
    #[arg(long)]
    script: Option<PathBuf>,
    /// Start a new design rather than resume the autosave.
    #[arg(long)]
    fresh: bool,
    /// A new design is this pattern's pieces (SVG, DXF or GarmentCode JSON) placed round
    /// the body and sewn (cloth-sim's --pattern): `--body mannequin --pattern
    /// sim-core/assets/dress.svg --fresh` starts with the dress. A
    /// resumed design stays as it is.
    #[arg(long, value_name = "FILE")]
    pattern: Option<PathBuf>,
    /// Do not start cloth-ui (also: run the lab, not the headless scenario, without a
    /// display).
    #[arg(long)]
    no_ui: bool,
    /// haptic-loop's SCHED_FIFO priority (1-99). Real time is on by default: haptic-loop
    /// gets SCHED_FIFO, locked memory and a CPU of its own where permitted, and cloth-sim
    /// and cloth-ui keep off that CPU.
    #[arg(long, default_value_t = 80, allow_negative_numbers = true,
          value_parser = whole_in::<u32>(1, 99, " (SCHED_FIFO)"))]
    rt_priority: u32,
    /// haptic-loop's CPU (default: the highest this process may use, with two or more).
    #[arg(long, allow_negative_numbers = true, value_parser = whole_in::<usize>(0, 1023, ""))]
    cpu: Option<usize>,
    /// No real-time scheduling or CPU of its own for haptic-loop.
    #[arg(long)]
    no_rt: bool,
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
    /// The fault-and-soak suite: the three processes in a domain of their own, the pen
    /// pinching, and in turn kill -9 of cloth-ui, of cloth-sim (at random moments, autosave
    /// writes included), of haptic-loop, and SIGSTOP of cloth-sim for 5 s; writes
    /// soak-report.json and soak-summary.txt, and exits 1 when a requirement was broken
    /// (docs/reliability.md).
    Soak(SoakArgs),
}

#[derive(clap::Args)]
struct SoakArgs {
    /// Stop injecting after this many minutes.
    #[arg(long, default_value_t = 10.0)]
    minutes: f64,
    /// Stop after this many faults (the four kinds in turn).
    #[arg(long, default_value_t = 400, value_parser = whole_in::<usize>(1, 1_000_000, " faults"))]
    faults: usize,
    /// Cloth grid (cells a side).
    #[arg(long, default_value_t = 128, value_parser = whole_in::<usize>(2, 256, " cells a side"))]
    grid: usize,
    /// Seconds of cyclictest first, for the machine's timing floor (0: none).
    #[arg(long, default_value_t = 10.0)]
    floor_seconds: f64,
    /// No cloth-ui (and no ui-kill faults).
    #[arg(long)]
    no_ui: bool,
    /// Where the report, the logs and the autosave go.
    #[arg(long, default_value = "out/soak")]
    out: PathBuf,
    /// The domain (default: soak-PID, removed at the end).
    #[arg(long)]
    domain: Option<String>,
}

/// `cloth-lab soak`.
fn run_soak(a: &SoakArgs) -> Result<(), String> {
    let sane = a.minutes > 0.0 && a.minutes <= 10_000.0 && (0.0..=600.0).contains(&a.floor_seconds);
    if !sane {
        return Err("--minutes must be in (0, 10000] and --floor-seconds in [0, 600]".into());
    }
    let name = a
        .domain
        .clone()
        .unwrap_or_else(|| format!("soak-{}", std::process::id()));
    let cfg = tools::soak::SoakConfig {
        domain: Domain::new(&name).map_err(|e| e.to_string())?,
        out: a.out.clone(),
        faults: a.faults,
        minutes: a.minutes,
        grid: a.grid,
        ui: !a.no_ui,
        floor_s: a.floor_seconds,
    };
    let r = tools::soak::soak(&cfg, &mut |m| eprintln!("cloth-lab soak: {m}"))?;
    let json = serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?;
    let report = a.out.join("soak-report.json");
    std::fs::write(&report, json).map_err(|e| format!("{}: {e}", report.display()))?;
    let text = tools::soak::summary(&r);
    let summary = a.out.join("soak-summary.txt");
    std::fs::write(&summary, &text).map_err(|e| format!("{}: {e}", summary.display()))?;
    print!("{text}");
    if r.failures.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} requirement(s) broken; see {}",
            r.failures.len(),
            report.display()
        ))
    }
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

/// The lab's CPUs ([`Plan`]), unless real time is off or there is only one CPU. Beside
/// the studio cloth-sim keeps off the loop's CPU even on two.
fn cpu_plan(cli: &Cli) -> Option<Plan> {
    let studio = !cli.headless && !cli.no_ui && have_display();
    Plan::new(cli.no_rt, cli.cpu, cli.rt_priority, !studio)
}

/// Every flag checked before anything starts: one line with the accepted range.
fn validate(cli: &Cli) -> Result<(), String> {
    // --grid and --rt-priority are checked as they are parsed (`whole_in`).
    if let Some(c) = cli.cpu
        && !shared::cpus::allowed().contains(&c)
    {
        return Err(format!(
            "--cpu {c} is not a CPU this process may use ({})",
            shared::cpus::format_list(&shared::cpus::allowed())
        ));
    }
    if let Some(s) = cli.seconds
        && !(s > 0.0 && s <= 1.0e7)
    {
        return Err(format!("--seconds must be between 0 and 10000000, got {s}"));
    }
    Ok(())
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
    match cpu_plan(cli) {
        _ if cli.no_rt => a.push("--no-rt".into()),
        Some(plan) => a.extend([
            "--rt-priority".into(),
            cli.rt_priority.to_string(),
            "--cpu".into(),
            plan.haptic.to_string(),
        ]),
        None => a.extend(["--rt-priority".into(), cli.rt_priority.to_string()]),
    }
    a
}

/// `--cpus LIST` for cloth-ui: off the haptic loop's CPU.
fn other_cpus(cli: &Cli) -> Vec<String> {
    cpu_plan(cli).map_or_else(Vec::new, |p| {
        vec!["--cpus".into(), shared::cpus::format_list(&p.others)]
    })
}

fn sim_args(cli: &Cli, domain: &Domain, autosave: Option<&PathBuf>) -> Vec<String> {
    let mut a = vec![
        "run".to_string(),
        "--domain".into(),
        domain.name().into(),
        "--grid".into(),
        cli.grid.to_string(),
    ];
    if let Some(b) = &cli.body {
        a.extend(["--body".into(), b.clone()]);
    }
    if let Some(m) = &cli.model {
        a.extend(["--model".into(), m.clone()]);
    }
    if cli.guard {
        a.push("--guard".into());
    }
    if cli.no_guard {
        a.push("--no-guard".into());
    }
    if let Some(f) = &cli.fabric {
        a.extend(["--fabric".into(), f.clone()]);
    }
    if let Some(l) = cli.strain_limit {
        a.extend(["--strain-limit".into(), l.to_string()]);
    }
    if let Some(p) = &cli.pattern {
        a.extend(["--pattern".into(), p.display().to_string()]);
    }
    if let Some(p) = autosave {
        a.extend(["--autosave".into(), p.display().to_string()]);
    }
    if let Some(plan) = cpu_plan(cli) {
        a.extend(["--cpus".into(), shared::cpus::format_list(&plan.sim)]);
        if plan.sim_threads() > 1 {
            a.extend(["--threads".into(), plan.sim_threads().to_string()]);
        }
    }
    a
}

/// What the lab tells the user about real time, in one line.
fn real_time_line(cli: &Cli) -> String {
    match cpu_plan(cli) {
        _ if cli.no_rt => "real-time off (--no-rt): haptic ticks may be late under load".into(),
        Some(plan) => plan.line(cli.rt_priority),
        None => format!(
            "asking real-time for haptic-loop (SCHED_FIFO {}); one CPU, shared by all",
            cli.rt_priority
        ),
    }
}

fn run_lab(cli: &Cli) -> Result<(), String> {
    validate(cli)?;
    let domain = domain_of(cli.domain.as_deref())?;
    eprintln!("cloth-lab: {}", real_time_line(cli));
    let mut sup = Supervisor::new(domain.clone())?;
    sup.add(Role::Haptic, haptic_args(cli, &domain, cli.script.as_ref()));
    // --fresh on the first start only: a restarted cloth-sim resumes what it was doing.
    let fresh = if cli.fresh {
        vec!["--fresh".into()]
    } else {
        Vec::new()
    };
    sup.add_first(Role::Sim, sim_args(cli, &domain, None), fresh);
    if !cli.no_ui {
        if sibling("cloth-ui")?.is_file() {
            let mut ui = vec!["--domain".into(), domain.name().into()];
            ui.extend(other_cpus(cli));
            sup.add(Role::Ui, ui);
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

/// The headless scenarios: the paper's fit-cube, and the dress on the mannequin.
#[derive(Clone, Copy, PartialEq)]
enum Headless {
    FitCube,
    DressMannequin,
}

impl Headless {
    /// The scenario `cli` asks for, if its flags fit it.
    fn of(cli: &Cli) -> Result<Self, String> {
        let s = match cli.scenario.as_str() {
            "fit-cube" => Self::FitCube,
            "dress-mannequin" => Self::DressMannequin,
            other => {
                return Err(format!(
                    "unknown headless scenario '{other}' (fit-cube, dress-mannequin)"
                ));
            }
        };
        let body = cli.body.as_deref().unwrap_or("cube");
        match s {
            Self::FitCube if body != "cube" => {
                return Err("the fit-cube scenario drapes over the cube (--body cube)".into());
            }
            Self::DressMannequin if !matches!(body, "cube" | "mannequin") => {
                return Err(
                    "the dress-mannequin scenario dresses the mannequin (--body mannequin)".into(),
                );
            }
            _ => {}
        }
        if cli.pattern.is_some() {
            return Err(
                "--pattern starts the studio's design from a pattern; the headless \
                 scenarios use their own (without a display, `cloth-sim scenario \
                 drape-pattern FILE` drapes a pattern)"
                    .into(),
            );
        }
        Ok(s)
    }

    fn name(self) -> &'static str {
        match self {
            Self::FitCube => "fit-cube",
            Self::DressMannequin => "dress-mannequin",
        }
    }

    /// cloth-sim's arguments: the dress starts on the mannequin from the shipped pattern,
    /// written into `out`.
    fn sim_args(
        self,
        cli: &Cli,
        domain: &Domain,
        autosave: &PathBuf,
    ) -> Result<Vec<String>, String> {
        let mut a = sim_args(cli, domain, Some(autosave));
        if self == Self::DressMannequin {
            let svg = cli.out.join("dress.svg");
            std::fs::write(&svg, tools::headless::DRESS_SVG)
                .map_err(|e| format!("{}: {e}", svg.display()))?;
            if let Some(i) = a.iter().position(|s| s == "--body") {
                a.drain(i..i + 2);
            }
            a.extend(["--body".into(), "mannequin".into()]);
            a.extend(["--pattern".into(), svg.display().to_string()]);
        }
        Ok(a)
    }
}

/// The scripted designer's part of a headless scenario: what it did, as JSON.
fn stand_in(
    which: Headless,
    domain: &Domain,
    out: &std::path::Path,
    abort: &AtomicBool,
) -> Result<serde_json::Value, String> {
    let mut progress = |m: &str| eprintln!("cloth-lab: {m}");
    let json = |e: serde_json::Error| e.to_string();
    match which {
        Headless::FitCube => tools::headless::fit_cube(domain, out, abort, &mut progress)
            .and_then(|r| serde_json::to_value(&r).map_err(json)),
        Headless::DressMannequin => {
            tools::headless::dress_mannequin(domain, out, abort, &mut progress)
                .and_then(|r| serde_json::to_value(&r).map_err(json))
        }
    }
}

fn run_headless(cli: &Cli) -> Result<(), String> {
    validate(cli)?;
    let which = Headless::of(cli)?;
    std::fs::create_dir_all(&cli.out).map_err(|e| format!("{}: {e}", cli.out.display()))?;
    // A private domain unless one is given, so a running lab is never disturbed.
    let domain = match &cli.domain {
        Some(d) => domain_of(Some(d))?,
        None => domain_of(Some(&format!("lab{}", std::process::id())))?,
    };
    let started = Instant::now();
    eprintln!("cloth-lab: {}", real_time_line(cli));
    let autosave = cli.out.join("autosave.saiho");
    let mut sup = Supervisor::new(domain.clone())?;
    sup.add(Role::Haptic, haptic_args(cli, &domain, cli.script.as_ref()));
    sup.add_first(
        Role::Sim,
        which.sim_args(cli, &domain, &autosave)?,
        vec!["--fresh".into()],
    );
    sup.start_all()?;
    eprintln!(
        "cloth-lab: headless {} in domain '{}': haptic-loop ({}), cloth-sim (grid {}, {} model), a scripted designer in place of cloth-ui",
        which.name(),
        domain.name(),
        cli.device,
        cli.grid,
        cli.model.as_deref().unwrap_or("xpbd")
    );
    let done = Arc::new(AtomicBool::new(false));
    // Set when the lab stops (Ctrl-C, or a process failed): the designer gives up at once.
    let abort = Arc::new(AtomicBool::new(false));
    let stop = shared::signals::termination_flag();
    let worker = {
        let (domain, out, done) = (domain.clone(), cli.out.clone(), done.clone());
        let abort = abort.clone();
        std::thread::spawn(move || {
            let r = stand_in(which, &domain, &out, &abort).and_then(|standin| {
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
    abort.store(true, Ordering::Relaxed);
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
    report.insert("scenario".into(), which.name().into());
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
    report.insert("stand_in".into(), standin);
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
    let cli: Cli = shared::cli::parse();
    // `cloth-lab --domain D stop` and `cloth-lab stop --domain D` name the same lab.
    fn of<'a>(d: &'a Option<String>, lab: &'a Option<String>) -> Option<&'a str> {
        d.as_deref().or(lab.as_deref())
    }
    let lab = &cli.domain;
    let r = match &cli.command {
        Some(Cmd::Restart { role, domain }) => Role::parse(role)
            .and_then(|r| control(&format!("restart {}", r.name()), of(domain, lab))),
        Some(Cmd::Status { domain }) => control("status", of(domain, lab)),
        Some(Cmd::Stop { domain }) => control("stop", of(domain, lab)),
        Some(Cmd::Soak(a)) => run_soak(a),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The model and fabric asked of the lab reach cloth-sim; without them cloth-sim's
    /// own defaults hold (no flag passed).
    #[test]
    fn model_and_fabric_go_to_cloth_sim() {
        let domain = Domain::new("labargs").unwrap();
        let cli = Cli::try_parse_from([
            "cloth-lab",
            "--model",
            "vbd",
            "--fabric",
            "denim",
            "--strain-limit",
            "0.25",
            "--pattern",
            "dress.svg",
        ])
        .unwrap();
        let a = sim_args(&cli, &domain, None);
        let at = |flag: &str| a.iter().position(|s| s == flag).map(|i| a[i + 1].as_str());
        assert_eq!(at("--model"), Some("vbd"), "{a:?}");
        assert_eq!(at("--fabric"), Some("denim"), "{a:?}");
        assert_eq!(at("--strain-limit"), Some("0.25"), "{a:?}");
        assert_eq!(at("--pattern"), Some("dress.svg"), "{a:?}");
        assert!(!a.iter().any(|s| s == "--guard"), "{a:?}");
        let guarded = sim_args(
            &Cli::try_parse_from(["cloth-lab", "--guard"]).unwrap(),
            &domain,
            None,
        );
        assert!(guarded.iter().any(|s| s == "--guard"), "{guarded:?}");
        let unguarded = sim_args(
            &Cli::try_parse_from(["cloth-lab", "--no-guard"]).unwrap(),
            &domain,
            None,
        );
        assert!(unguarded.iter().any(|s| s == "--no-guard"), "{unguarded:?}");
        assert!(Cli::try_parse_from(["cloth-lab", "--guard", "--no-guard"]).is_err());
        let plain = sim_args(&Cli::try_parse_from(["cloth-lab"]).unwrap(), &domain, None);
        assert!(
            !plain.iter().any(|s| s == "--model"
                || s == "--fabric"
                || s == "--strain-limit"
                || s == "--pattern"
                || s == "--body"),
            "{plain:?}"
        );
        let human = sim_args(
            &Cli::try_parse_from(["cloth-lab", "--body", "human"]).unwrap(),
            &domain,
            None,
        );
        assert_eq!(
            human
                .iter()
                .position(|s| s == "--body")
                .map(|i| human[i + 1].as_str()),
            Some("human"),
            "{human:?}"
        );
        assert!(Cli::try_parse_from(["cloth-lab", "--model", "blender"]).is_err());
    }

    /// cloth-sim's `--cpus` and `--threads` are the plan's (`tools::cpu_plan`), and
    /// cloth-ui's CPUs are off the loop's; no CPU list and one thread with real time off.
    #[test]
    fn cloth_sim_and_cloth_ui_get_the_plans_cpus() {
        let domain = Domain::new("labthreads").unwrap();
        let value =
            |a: &[String], flag: &str| a.iter().position(|s| s == flag).map(|i| a[i + 1].clone());
        let cli = Cli::try_parse_from(["cloth-lab", "--no-rt"]).unwrap();
        let a = sim_args(&cli, &domain, None);
        assert_eq!((value(&a, "--threads"), value(&a, "--cpus")), (None, None));
        let cli = Cli::try_parse_from(["cloth-lab"]).unwrap();
        let a = sim_args(&cli, &domain, None);
        let Some(plan) = cpu_plan(&cli) else { return };
        let threads = value(&a, "--threads").map_or(1, |t| t.parse().unwrap());
        assert_eq!(threads, plan.sim_threads());
        assert_eq!(
            value(&a, "--cpus"),
            Some(shared::cpus::format_list(&plan.sim))
        );
        let ui = other_cpus(&cli);
        let ui = shared::cpus::parse_list(&ui[1]).unwrap();
        assert!(!ui.contains(&plan.haptic), "{ui:?}");
    }
}
