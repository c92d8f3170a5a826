//! cloth-ui: the design studio window.

use std::panic::AssertUnwindSafe;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
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
    report_a_lost_display();
    watch_the_display();
    let run = std::panic::catch_unwind(AssertUnwindSafe(|| {
        eframe::run_native(
            "Saiho",
            native,
            Box::new(move |_cc| {
                OPENED.store(true, Ordering::SeqCst);
                Ok(Box::new(App::new(opts)))
            }),
        )
    }));
    match run {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) if OPENED.load(Ordering::SeqCst) => {
            eprintln!("error: cloth-ui's window failed: {e}; {SAFE}");
            ExitCode::FAILURE
        }
        Ok(Err(e)) => {
            eprintln!("error: cloth-ui could not open its window: {e}");
            ExitCode::FAILURE
        }
        // Reported by the hook; the app (and its iceoryx2 node) was dropped on the way.
        Err(_) if DISPLAY_LOST.load(Ordering::SeqCst) => ExitCode::FAILURE,
        Err(panic) => std::panic::resume_unwind(panic),
    }
}

/// The window opened (the app was made).
static OPENED: AtomicBool = AtomicBool::new(false);
/// A panic came from the window system: the display went away.
static DISPLAY_LOST: AtomicBool = AtomicBool::new(false);
const SAFE: &str = "the design is safe in cloth-sim: start cloth-ui again";

/// An X server that exits takes the window system down inside the event loop: winit
/// unwraps its connection's error there. That is not a bug of the studio's, so it is said
/// in one line (with winit's words) instead of a panic's backtrace, and cloth-ui exits 1
/// after its app and its node are dropped. Every other panic is reported as before.
fn report_a_lost_display() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let file = info.location().map_or("", |l| l.file());
        if !from_window_system(file) {
            return default(info);
        }
        DISPLAY_LOST.store(true, Ordering::SeqCst);
        let p = info.payload();
        let what = p
            .downcast_ref::<&str>()
            .copied()
            .or_else(|| p.downcast_ref::<String>().map(String::as_str))
            .unwrap_or("no message");
        eprintln!("error: cloth-ui lost its display (the window system failed: {what}); {SAFE}");
    }));
}

/// The local X display's socket (`DISPLAY` `:N`, `:N.S` or `unix:N`); `None` for any
/// other (a remote display, Wayland).
fn x_socket(display: &str) -> Option<PathBuf> {
    let n = display
        .strip_prefix("unix:")
        .or(display.strip_prefix(':'))?;
    let n = n.split('.').next()?;
    n.parse::<u32>().ok()?;
    Some(PathBuf::from(format!("/tmp/.X11-unix/X{n}")))
}

/// Watches the local X server cloth-ui draws on: once it no longer takes connections,
/// cloth-ui says so and exits 1 within 2 s if the window system has not ended it by
/// then. The software renderer can block in a put-image to the dead connection for
/// 30-60 s before winit sees it (seen under Xvfb, `gdb`: `xcb_put_image` from Mesa's
/// EGL), and a studio that hangs a minute is not one that reports a lost display.
fn watch_the_display() {
    let Some(socket) = std::env::var("DISPLAY").ok().as_deref().and_then(x_socket) else {
        return;
    };
    let watch = move || {
        let mut seen = false;
        loop {
            std::thread::sleep(Duration::from_millis(500));
            match std::os::unix::net::UnixStream::connect(&socket) {
                Ok(_) => seen = true,
                Err(_) if seen => break,
                Err(_) => {}
            }
        }
        std::thread::sleep(Duration::from_secs(2));
        if !DISPLAY_LOST.swap(true, Ordering::SeqCst) {
            let x = socket.display();
            eprintln!("error: cloth-ui lost its display (its X server at {x} is gone); {SAFE}");
        }
        std::process::exit(1);
    };
    let _ = std::thread::Builder::new()
        .name("display-watch".into())
        .spawn(watch);
}

/// Whether a panic at source `file` is the window system's (winit's) own.
fn from_window_system(file: &str) -> bool {
    file.replace('\\', "/")
        .split('/')
        .any(|part| part.starts_with("winit-"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_local_display_has_a_socket_to_watch() {
        let x = |d: &str| super::x_socket(d).map(|p| p.display().to_string());
        assert_eq!(x(":99").as_deref(), Some("/tmp/.X11-unix/X99"));
        assert_eq!(x(":0.1").as_deref(), Some("/tmp/.X11-unix/X0"));
        assert_eq!(x("unix:3").as_deref(), Some("/tmp/.X11-unix/X3"));
        assert_eq!(x("host:0"), None);
        assert_eq!(x(":x"), None);
    }

    #[test]
    fn a_panic_inside_winit_is_the_window_systems() {
        let x11 = "/root/.cargo/registry/src/index.crates.io-1949cf8c6b5b557f/winit-0.30.13/src/platform_impl/linux/x11/window.rs";
        assert!(super::from_window_system(x11));
        assert!(super::from_window_system(
            r"C:\cargo\registry\src\x\winit-0.30.13\src\lib.rs"
        ));
        assert!(!super::from_window_system("ui/src/app.rs"));
    }
}
