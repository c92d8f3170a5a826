//! cloth-ui: the design studio window.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use shared::domain::Domain;
use ui::app::{App, Options};

#[derive(Parser)]
#[command(
    name = "cloth-ui",
    version,
    about = "Saiho's design studio: the cloth in 3D, the tools, and the system's status",
    long_about = "Saiho's design studio: the cloth in 3D, the cut/sew/paint/pinch/tear/pin tools, \
        and the processes' status and latency. It shows the design cloth-sim holds (it can be \
        closed and restarted at any time without losing anything) and drives the simulated pen \
        with the mouse."
)]
struct Cli {
    /// iceoryx2 domain of the running system (default: $SAIHO_DOMAIN, else "default").
    #[arg(long)]
    domain: Option<String>,
    /// Save a screenshot of the window as PNG after --exit-after seconds, then quit.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// Quit after this many seconds.
    #[arg(long)]
    exit_after: Option<f64>,
    /// Print the frame rate every second.
    #[arg(long)]
    log_fps: bool,
    /// 3D view resolution relative to the window (default: 1 on a GPU, 0.5 on a
    /// software rasteriser such as llvmpipe).
    #[arg(long)]
    render_scale: Option<f32>,
    /// Present frames as soon as they are drawn (for measuring the frame rate).
    #[arg(long)]
    no_vsync: bool,
    /// Window size, pixels.
    #[arg(long, default_value_t = 1280.0)]
    width: f32,
    #[arg(long, default_value_t = 800.0)]
    height: f32,
    /// Run only on these CPUs (such as 0 or 0-2); cloth-lab keeps cloth-ui off the haptic
    /// loop's CPU this way.
    #[arg(long)]
    cpus: Option<String>,
    /// Lower cloth-ui's scheduling priority to this niceness (0 to 19), so that where it
    /// shares a CPU with cloth-sim the simulation runs first: the pen's force fades when
    /// its model is 20 ms old, and a view can wait. 0 keeps the priority as it is.
    #[arg(long, default_value_t = 10, value_parser = shared::cli::whole_in::<i32>(0, 19, ""))]
    nice: i32,
    /// Most frames per second (default: 30 on a software renderer such as llvmpipe, so it
    /// leaves the CPUs to the simulation; the display's rate on a GPU).
    #[arg(long)]
    max_fps: Option<f32>,
}

fn main() -> ExitCode {
    let launched = std::time::Instant::now();
    let cli: Cli = shared::cli::parse();
    // First, before any thread starts: every thread takes the priority it is started with.
    if let Err(e) = shared::cpus::lower_priority(cli.nice) {
        eprintln!("error: --nice: {e}");
        return ExitCode::FAILURE;
    }
    let domain = match Domain::from_arg_or_env(cli.domain.as_deref()) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(s) = cli.exit_after
        && !(s.is_finite() && (0.0..=1.0e7).contains(&s))
    {
        eprintln!("error: --exit-after must be between 0 and 10000000 seconds, got {s}");
        return ExitCode::FAILURE;
    }
    if let Some(s) = cli.render_scale
        && !(s.is_finite() && (0.1..=2.0).contains(&s))
    {
        eprintln!("error: --render-scale must be between 0.1 and 2, got {s}");
        return ExitCode::FAILURE;
    }
    if let Some(f) = cli.max_fps
        && !(f.is_finite() && (1.0..=1000.0).contains(&f))
    {
        eprintln!("error: --max-fps must be between 1 and 1000, got {f}");
        return ExitCode::FAILURE;
    }
    let size = 200.0..=10_000.0;
    if !(size.contains(&cli.width) && size.contains(&cli.height)) {
        eprintln!(
            "error: --width and --height must be between 200 and 10000 pixels, got {} x {}",
            cli.width, cli.height
        );
        return ExitCode::FAILURE;
    }
    if let Some(c) = &cli.cpus
        && let Err(e) = shared::cpus::parse_list(c).and_then(|l| shared::cpus::keep_on(&l))
    {
        eprintln!("error: --cpus: {e}");
        return ExitCode::FAILURE;
    }
    let opts = Options {
        domain: Some(domain),
        screenshot: cli.screenshot,
        exit_after: cli.exit_after.map(Duration::from_secs_f64),
        log_fps: cli.log_fps,
        render_scale: cli.render_scale,
        max_fps: cli.max_fps,
        clear_panels: true,
        launched: Some(launched),
    };
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("Saiho")
            .with_inner_size([cli.width, cli.height]),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    let mut native = native;
    if cli.no_vsync {
        native.wgpu_options.surface.present_mode = egui_wgpu::wgpu::PresentMode::AutoNoVsync;
    }
    match eframe::run_native(
        "Saiho",
        native,
        Box::new(move |_cc| Ok(Box::new(App::new(opts)))),
    ) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: cloth-ui could not open its window: {e}");
            ExitCode::FAILURE
        }
    }
}
