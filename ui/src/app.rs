//! The design studio: tools on the left, the 3D view in the middle, processes and latency
//! on the right, a status bar below. Each frame: take in what the system sent, lay out
//! the panels (each returns the user's [`Action`]s; input is read apart from drawing),
//! then apply the actions: commands for cloth-sim and the pointer for the simulated pen
//! go out through the `Link` when there is one, and land in [`App::emitted`] for tests.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::Vec3;
use shared::command::Command;
use shared::domain::Domain;
use shared::sim_to_ui::tool;
use shared::ui_to_sim::TEXT_LEN;

use crate::action::{Action, Emitted, PathOp};
use crate::camera::{Camera, Hit};
use crate::input;
use crate::link::Link;
use crate::mapper::Mapper;
use crate::panels::{MaterialPanel, PiecesPanel, ScenePanel, StatusPanel, ToolsPanel, ViewPanel};
use crate::store::Store;
use crate::stretch::StretchView;
use crate::tools::{tool_name, tool_sentence};
use crate::view3d::Overlay;

/// Options from the command line.
#[derive(Clone, Debug, Default)]
pub struct Options {
    pub domain: Option<Domain>,
    /// Save a screenshot here after `exit_after` and quit.
    pub screenshot: Option<PathBuf>,
    pub exit_after: Option<Duration>,
    /// Print the frame rate every few seconds.
    pub log_fps: bool,
    /// Resolution of the 3D view relative to the window's pixels (None: 1 on a GPU, 0.5
    /// on a software rasteriser such as llvmpipe).
    pub render_scale: Option<f32>,
    /// Most frames per second (None: 30 on a software renderer, the display's rate on a
    /// GPU).
    pub max_fps: Option<f32>,
    /// Paint the panels' background with the window's clear colour instead of egui
    /// fills. The look is the same and a software rasteriser saves a full shading pass
    /// over the panels; off for test harnesses that clear to transparent.
    pub clear_panels: bool,
    /// When the process started (for the "whole design arrived" time; default: when the
    /// app was made).
    pub launched: Option<Instant>,
}

/// The status while the pinch drags a paused cloth.
pub const PAUSED_PINCH: &str =
    "Paused: the cloth holds still under the pen; Simulate (Space) to let it move";

/// The frame rate the UI keeps to on a software renderer.
pub const SOFTWARE_FPS: f32 = 30.0;

pub struct App {
    /// What the system sent (the UI holds no design state of its own).
    pub store: Store,
    pub link: Option<Link>,
    link_error: Option<String>,
    link_retry: Instant,
    domain: Option<Domain>,
    /// Every action that went out (the last 1,000), in order.
    pub emitted: Vec<Emitted>,
    pub camera: Camera,
    /// The tool chosen here (cloth-sim's tool state wins once it arrives).
    pub tool: u32,
    pub sew_first: Option<u32>,
    /// Shift-clicks of a seam: start and end of path A, then of path B.
    pub seam_picks: Vec<u32>,
    pub tools: ToolsPanel,
    pub material: MaterialPanel,
    pub scene: ScenePanel,
    pub pieces: PiecesPanel,
    pub status_panel: StatusPanel,
    pub view: ViewPanel,
    /// Whether the view shows the stretch or ease map, and at what scale.
    pub stretch: StretchView,
    /// Keeps the map the view shows current.
    mapper: Mapper,
    /// How long after start everything of the design had arrived.
    pub design_arrived: Option<Duration>,
    pub status: String,
    /// The body version and whether a cloth was there when the camera last framed them.
    framed: (u64, bool),
    opts: Options,
    started: Instant,
    screenshot_asked: bool,
    /// The pause last asked for (true: paused), shown until cloth-sim's telemetry reports
    /// it or a few seconds pass.
    pause_asked: Option<(bool, Instant)>,
    screenshot_rx: Option<std::sync::mpsc::Receiver<std::sync::Arc<egui::ColorImage>>>,
}

impl App {
    /// An app connected to `opts.domain` (or not connected at all, for tests: then every
    /// action only lands in `emitted`).
    pub fn new(opts: Options) -> Self {
        let mut app = Self {
            store: Store::default(),
            link: None,
            link_error: None,
            link_retry: Instant::now(),
            domain: opts.domain.clone(),
            emitted: Vec::new(),
            camera: Camera::default(),
            tool: tool::PINCH,
            sew_first: None,
            seam_picks: Vec::new(),
            tools: ToolsPanel::default(),
            material: MaterialPanel::default(),
            scene: ScenePanel::default(),
            pieces: PiecesPanel::default(),
            status_panel: StatusPanel::default(),
            view: ViewPanel::default(),
            stretch: StretchView::default(),
            mapper: Mapper::default(),
            design_arrived: None,
            status: String::new(),
            framed: (0, false),
            opts,
            started: Instant::now(),
            screenshot_asked: false,
            pause_asked: None,
            screenshot_rx: None,
        };
        app.connect();
        app
    }

    fn connect(&mut self) {
        let Some(d) = &self.domain else { return };
        match Link::open(d) {
            Ok(l) => {
                self.link = Some(l);
                self.link_error = None;
            }
            Err(e) => self.link_error = Some(e),
        }
        self.link_retry = Instant::now() + Duration::from_secs(2);
    }

    fn emit(&mut self, e: Emitted) {
        if let Some(l) = &mut self.link {
            match &e {
                Emitted::Command(c) => {
                    if let Err(m) = l.send(c) {
                        self.status = m;
                    }
                }
                Emitted::Pointer(p, b) => l.point(*p, *b),
            }
        }
        self.emitted.push(e);
        if self.emitted.len() > 1000 {
            self.emitted.drain(..500);
        }
    }

    fn command(&mut self, c: Command) {
        self.emit(Emitted::Command(c));
    }

    /// Whether the simulation is paused: as last asked for, until cloth-sim's telemetry
    /// says so or a few seconds pass; then as it says.
    pub fn paused(&self) -> bool {
        let told = self.store.sim_tel.as_ref().map(|t| t.paused == 1);
        match self.pause_asked {
            Some((asked, at)) if told != Some(asked) && at.elapsed() < Duration::from_secs(3) => {
                asked
            }
            _ => told.unwrap_or(false),
        }
    }

    /// The current tool: cloth-sim's when it has told us.
    pub fn current_tool(&self) -> u32 {
        self.store.tool.map_or(self.tool, |t| t.tool)
    }

    /// Carries out what the panels and the input asked for this frame, in order.
    pub fn apply(&mut self, actions: Vec<Action>) {
        for a in actions {
            match a {
                Action::Command(c) => self.command(c),
                Action::Path(op, path) => self.path_command(op, path),
                Action::SetTool(t) => self.set_tool(t),
                Action::Pointer(p, b) => {
                    // The pen grips the cloth, but nothing moves while paused: say why.
                    if b != 0 && self.paused() && self.current_tool() == tool::PINCH {
                        self.status = PAUSED_PINCH.to_string();
                    }
                    self.emit(Emitted::Pointer(p, b));
                }
                Action::Click {
                    tool,
                    hit,
                    shift,
                    view_dir,
                } => self.click(tool, hit, shift, view_dir),
                Action::ResetCamera => self.camera = Camera::default(),
                Action::FrameScene => self.frame_scene(),
                Action::ToggleStretchMap => self.stretch.on = !self.stretch.on,
                Action::ToggleSimulating => {
                    let paused = self.paused();
                    self.pause_asked = Some((!paused, Instant::now()));
                    self.command(Command::SetSimulating { on: paused });
                }
                Action::Status(s) => self.status = s,
            }
        }
    }

    pub fn set_tool(&mut self, t: u32) {
        self.tool = t;
        self.sew_first = None;
        self.seam_picks.clear();
        self.command(Command::SetTool {
            tool: t,
            rgba: self.tools.rgba(),
            brush_m: self.tools.brush_m,
        });
        // Show it at once; cloth-sim's tool state confirms it.
        if let Some(s) = &mut self.store.tool {
            s.tool = t;
        }
        self.status = tool_sentence(t);
    }

    fn path_command(&mut self, op: PathOp, path: String) {
        // cloth-sim resolves the path itself: hand it an absolute one.
        let abs = std::path::absolute(&path).unwrap_or_else(|_| PathBuf::from(&path));
        let abs = abs.display().to_string();
        if abs.len() > TEXT_LEN {
            self.status =
                format!("The path {path} is too long for a command (at most {TEXT_LEN} bytes)");
            return;
        }
        self.command(match op {
            PathOp::Save => Command::Save { path: abs },
            PathOp::Load => Command::Load { path: abs },
            PathOp::Export => Command::Export {
                dir: abs,
                allowance_mm: self.tools.allowance_mm,
            },
        });
    }

    /// A click with the tool on `hit`.
    fn click(&mut self, t: u32, hit: Option<Hit>, shift: bool, view_dir: Vec3) {
        let Some(h) = hit else {
            self.status = format!("{}: nothing under the mouse", tool_name(t));
            return;
        };
        match t {
            tool::CUT => {
                // Split across the view: the cut plane holds the view direction.
                let dirn = view_dir.cross(Vec3::Y).normalize_or(Vec3::X);
                self.command(Command::CutVertex {
                    vertex: h.vertex,
                    direction: dirn.to_array(),
                });
            }
            tool::SEW if shift => self.seam_pick(h.vertex),
            tool::SEW => match self.sew_first.take() {
                None => {
                    self.sew_first = Some(h.vertex);
                    self.status =
                        format!("Sew: vertex {} picked; click the second vertex", h.vertex);
                }
                Some(a) if a == h.vertex => {
                    self.status = "Sew: that is the same vertex; pick another".into();
                    self.sew_first = Some(a);
                }
                Some(a) => self.command(Command::Sew { a, b: h.vertex }),
            },
            tool::PIN => self.command(Command::Pin {
                vertex: h.vertex,
                pinned: !shift,
            }),
            tool::PAINT => self.command(Command::Paint {
                point: h.point.to_array(),
                radius_m: self.tools.brush_m,
                rgba: self.tools.rgba(),
            }),
            // Pinch and tear act by dragging.
            _ => {
                self.status = format!("{}: drag to pull the cloth", tool_name(t));
            }
        }
    }

    /// One shift-click of a seam; the fourth sends it.
    fn seam_pick(&mut self, vertex: u32) {
        self.seam_picks.push(vertex);
        if self.seam_picks.len() < 4 {
            self.status = format!(
                "Seam: {} of 4 vertices picked (the start and end of one border path, then of the other)",
                self.seam_picks.len()
            );
            return;
        }
        let picks = std::mem::take(&mut self.seam_picks);
        match self.seam_command(&picks) {
            Some(c) => self.command(c),
            None => self.status = "Seam: the picked vertices have no place on the pattern".into(),
        }
    }

    /// A seam along the pattern segments between picks 0-1 and 2-3.
    fn seam_command(&self, picks: &[u32]) -> Option<Command> {
        let m = self.store.mesh.as_ref()?;
        let uv = |v: u32| m.corners.iter().find(|c| c.vertex == v).map(|c| [c.u, c.v]);
        let p: Vec<[f32; 2]> = picks.iter().map(|&v| uv(v)).collect::<Option<_>>()?;
        // A third of the pattern's smallest edge: the paths' vertices, not their neighbours.
        let mut edge = f32::INFINITY;
        for t in m.corners.chunks_exact(3).take(2000) {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let d = ((a.u - b.u).powi(2) + (a.v - b.v).powi(2)).sqrt();
                if d > 1e-6 {
                    edge = edge.min(d);
                }
            }
        }
        if !edge.is_finite() {
            return None;
        }
        // The start of each path is just before its first vertex, so that one is included.
        let back = |a: [f32; 2], b: [f32; 2]| {
            let d = [b[0] - a[0], b[1] - a[1]];
            let l = (d[0] * d[0] + d[1] * d[1]).sqrt().max(1e-6);
            [a[0] - d[0] / l * edge * 0.5, a[1] - d[1] / l * edge * 0.5]
        };
        Some(Command::Seam {
            a: [back(p[0], p[1]), p[1]],
            b: [back(p[2], p[3]), p[3]],
            tolerance: edge / 3.0,
        })
    }

    fn overlay(&self) -> Overlay {
        let pen = self.store.pen.map(|p| Vec3::from(p.position));
        let spring = match (pen, &self.store.model) {
            (Some(tip), Some(m)) if m.pinching == 1 => Some((tip, Vec3::from(m.vertex_position))),
            _ => None,
        };
        let marked = self
            .sew_first
            .and_then(|v| self.store.x.get(v as usize))
            .map(|p| Vec3::from(*p));
        Overlay {
            pen,
            spring,
            marked,
            dart: self
                .view
                .dart
                .map(|d| (Vec3::from(d.start), Vec3::from(d.now))),
            rings: crate::fit::rings(&self.store),
        }
    }

    /// The 3D view, the mouse in it, and a banner when something is wrong.
    fn view_panel(&mut self, ui: &mut egui::Ui, frame: &eframe::Frame, actions: &mut Vec<Action>) {
        let overlay = self.overlay();
        let resp = self.view.draw(
            ui,
            frame,
            &mut self.store,
            &self.camera,
            &overlay,
            self.opts.render_scale,
        );
        let current = self.current_tool();
        let stretch_at = |v: u32| self.store.stretch.as_ref()?.at_vertex(v);
        let resp = resp.on_hover_text_at_pointer(match &self.view.last_hit {
            Some(h) => format!(
                "{} · vertex {} at ({:.3}, {:.3}, {:.3}) m{}",
                tool_name(current),
                h.vertex,
                h.point.x,
                h.point.y,
                h.point.z,
                stretch_at(h.vertex).unwrap_or_default()
            ),
            None => tool_name(current).to_string(),
        });
        self.view.rect = Some(resp.rect);
        let ctx = ui.ctx().clone();
        // Dart ticked in the open pattern view (and no Cut, which cuts there too): a drag
        // on the cloth takes in a dart.
        let darting = (self.pieces.pattern_open && self.pieces.darting && current != tool::CUT)
            .then_some(self.pieces.dart_width);
        input::view_mouse(
            &mut self.view,
            &mut self.camera,
            &self.store,
            current,
            darting,
            &resp,
            &ctx,
            actions,
        );
        if let Some(b) = self.banner() {
            ViewPanel::banner(ui, resp.rect, b);
        }
    }

    /// What is wrong, if anything: a peer of another build, no connection, no renderer,
    /// or no cloth-sim.
    fn banner(&self) -> Option<String> {
        if let Some(m) = &self.store.mismatch {
            Some(format!("Cannot read a peer's messages: {m}"))
        } else if let Some(e) = &self.link_error {
            Some(format!("Cannot connect: {e}"))
        } else if let Some(e) = &self.view.error {
            Some(e.clone())
        } else if self.link.is_some()
            && self
                .store
                .heard
                .sim
                .is_none_or(|t| t.elapsed() > Duration::from_secs(2))
        {
            Some(format!(
                "Waiting for cloth-sim in domain '{}'…  (start it, or run cloth-lab)",
                self.domain.as_ref().map_or("?", |d| d.name())
            ))
        } else {
            None
        }
    }

    fn poll(&mut self) {
        if self.link.is_none() && self.domain.is_some() && Instant::now() > self.link_retry {
            self.connect();
        }
        if let Some(l) = &mut self.link {
            for a in l.poll(&mut self.store) {
                self.status = if a.ok {
                    a.message
                } else {
                    format!("Refused: {}", a.message)
                };
            }
        }
        if self.design_arrived.is_none()
            && self.store.mesh.is_some()
            && !self.store.x.is_empty()
            && self.store.tool.is_some()
            && self.store.sim_tel.is_some()
            && self.store.texture.complete()
        {
            let t = self.opts.launched.unwrap_or(self.started).elapsed();
            self.design_arrived = Some(t);
            eprintln!(
                "cloth-ui: the whole design (mesh, positions, seams, texture, tool, material) \
                 arrived {:.0} ms after start",
                t.as_secs_f64() * 1000.0
            );
        }
        if let Some(t) = &self.store.tool
            && t.sew_first != u32::MAX
            && self.current_tool() == tool::SEW
        {
            // The pen's first press of a sew shows too.
            self.sew_first.get_or_insert(t.sew_first);
        }
    }

    /// The frame rate, and the screenshot or exit asked for on the command line.
    fn timing(&mut self, ctx: &egui::Context) {
        if let Some(fps) = self.status_panel.count_frame()
            && self.opts.log_fps
        {
            eprintln!("cloth-ui: {fps:.1} fps");
        }
        if let Some(after) = self.opts.exit_after
            && self.started.elapsed() >= after
        {
            if self.opts.screenshot.is_some() {
                if !self.screenshot_asked {
                    let (tx, rx) = std::sync::mpsc::channel();
                    ctx.request_screenshot(move |img| {
                        let _ = tx.send(img);
                    });
                    self.screenshot_rx = Some(rx);
                    self.screenshot_asked = true;
                }
            } else {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
        let shot = self.screenshot_rx.as_ref().and_then(|r| r.try_recv().ok());
        if let (Some(img), Some(path)) = (shot, &self.opts.screenshot) {
            match save_png(path, &img) {
                Ok(()) => eprintln!("cloth-ui: wrote {}", path.display()),
                Err(e) => eprintln!("cloth-ui: {e}"),
            }
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    /// The most frames per second the UI draws, and why: `--max-fps`, or 30 on a software
    /// renderer (llvmpipe draws on the CPUs the simulation needs). None: as fast as the
    /// display allows.
    pub fn frame_cap(&self) -> Option<(f32, &'static str)> {
        match (self.opts.max_fps, self.view.software) {
            (Some(f), _) => Some((f, "--max-fps")),
            (None, Some(true)) => Some((SOFTWARE_FPS, "software renderer")),
            _ => None,
        }
    }

    /// Fits the camera to the body and the cloth (whichever the UI has).
    pub fn frame_scene(&mut self) {
        let body = self.store.body.as_ref().map(|(v, _)| &v[..]).unwrap_or(&[]);
        let points = body
            .iter()
            .chain(self.store.x.iter())
            .map(|p| Vec3::from(*p));
        let (mn, mx) = points.fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(a, b), p| (a.min(p), b.max(p)),
        );
        let aspect = self
            .view
            .rect
            .map_or(1.5, |r| r.width() / r.height().max(1.0));
        self.camera.fit(mn, mx, aspect);
    }

    /// Frames the scene when a body (a new scene's, or the first one heard) or the first
    /// cloth arrives; the user's camera is left alone otherwise.
    fn frame_new_scene(&mut self) {
        let version = self.store.body_version;
        let has_cloth = self.store.mesh.is_some() && !self.store.x.is_empty();
        let new_body = version > 0 && version != self.framed.0;
        let first_cloth = has_cloth && !self.framed.1;
        if new_body || first_cloth {
            self.frame_scene();
        }
        self.framed = (version, self.framed.1 || has_cloth);
    }

    /// The bar above the view: the tool, the cloth's size and frame, undo and redo.
    fn top_bar(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.strong("Saiho");
            ui.separator();
            ui.label(format!("tool: {}", tool_name(self.current_tool())));
            if let Some(m) = &self.store.mesh {
                ui.separator();
                ui.label(format!(
                    "{} vertices · {} triangles · frame {}",
                    m.used,
                    m.triangles(),
                    self.store.frame
                ));
            }
            if let Some(t) = &self.store.tool {
                ui.separator();
                ui.label(format!("undo {} · redo {}", t.undo_depth, t.redo_depth));
            }
            if self.paused() {
                ui.separator();
                ui.colored_label(egui::Color32::from_rgb(230, 160, 40), "paused")
                    .on_hover_text("Nothing moves until you simulate again (Space)");
            }
        });
    }

    /// The left column: tools, material, scene, view.
    fn left_column(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let depths = self
            .store
            .tool
            .map_or((0, 0), |t| (t.undo_depth, t.redo_depth));
        let current = self.current_tool();
        let linked = self.link.is_some();
        let paused = self.paused();
        let pins = self.store.pins_total;
        self.tools
            .ui(ui, current, (depths, paused, pins), linked, actions);
        ui.separator();
        self.material.ui(ui, self.store.sim_tel.as_deref(), actions);
        ui.separator();
        self.scene.follow_source(&self.store.source);
        self.scene.ui(
            ui,
            self.store.sim_tel.as_deref(),
            self.material.choice(),
            actions,
        );
        ui.separator();
        self.pieces.ui(ui, &self.store, actions);
        self.store.highlight = self.pieces.selected.and_then(|i| self.store.mesh_piece(i));
        ui.separator();
        ToolsPanel::view_section(ui, actions);
        crate::stretch::controls(ui, &mut self.stretch, self.store.stretch.as_ref());
        crate::fit::controls(ui, &mut self.stretch, self.store.fit.as_deref());
    }
}

/// Writes an egui screenshot as an RGBA PNG.
pub fn save_png(path: &std::path::Path, img: &egui::ColorImage) -> Result<(), String> {
    let f = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut enc = png::Encoder::new(
        std::io::BufWriter::new(f),
        img.size[0] as u32,
        img.size[1] as u32,
    );
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    let bytes: Vec<u8> = img.pixels.iter().flat_map(|p| p.to_array()).collect();
    w.write_image_data(&bytes).map_err(|e| e.to_string())
}

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.poll();
        self.frame_new_scene();
        let mut actions = Vec::new();
        input::keyboard(&ctx, &self.tools.save_path, &mut actions);
        // Keys act before the panels are laid out, as a click on a panel would next frame.
        self.apply(std::mem::take(&mut actions));
        self.mapper.update(&mut self.store, self.stretch);
        let mut panel = egui::Frame::side_top_panel(ui.style());
        if self.opts.clear_panels {
            panel = panel.fill(egui::Color32::TRANSPARENT);
        }
        egui::Panel::top("top")
            .frame(panel)
            .show(ui, |ui| self.top_bar(ui));
        egui::Panel::bottom("status").frame(panel).show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label(if self.status.is_empty() {
                    "Ready"
                } else {
                    &self.status
                });
            });
        });
        egui::Panel::left("tools")
            .frame(panel)
            .resizable(false)
            .default_size(210.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.left_column(ui, &mut actions));
            });
        let cutting = self.current_tool() == tool::CUT;
        (self.pieces).pattern_window(&ctx, &self.store, cutting, &mut actions);
        egui::Panel::right("status panel")
            .frame(panel)
            .default_size(300.0)
            .show(ui, |ui| {
                let cap = self.frame_cap();
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.status_panel.ui(
                        ui,
                        &self.store,
                        self.link.is_some(),
                        self.design_arrived,
                        cap,
                    )
                });
            });
        // No fill: the 3D view covers the panel, and on a software rasteriser every pixel
        // egui shades costs (see blit.wgsl).
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.view_panel(ui, frame, &mut actions));
        self.apply(actions);
        self.timing(&ctx);
        match self.frame_cap() {
            Some((fps, _)) => ctx.request_repaint_after(Duration::from_secs_f32(1.0 / fps)),
            None => ctx.request_repaint(),
        }
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        if self.opts.clear_panels {
            visuals.panel_fill.to_normalized_gamma_f32()
        } else {
            egui::Color32::from_rgb(12, 12, 12).to_normalized_gamma_f32()
        }
    }
}
