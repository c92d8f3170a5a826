//! The design studio: tools on the left, the 3D view in the middle, processes and latency
//! on the right, a status bar below. UI code turns input into `Emitted` actions (commands
//! for cloth-sim, the pointer for the simulated pen) that go out through the `Link` when
//! there is one; tests read them from `App::emitted`.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use shared::domain::Domain;
use shared::sim_to_ui::tool;
use shared::ui_to_sim::{ToolCommand, op};

use crate::camera::{Camera, Hit, pick};
use crate::link::Link;
use crate::store::Store;
use crate::view3d::{Overlay, View3d};

/// What the UI asked of the system.
// Commands are the common case here; boxing them would only add an allocation per action.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum Emitted {
    Command(ToolCommand),
    /// The simulated pen's target and buttons.
    Pointer([f32; 3], u32),
}

/// The tools, in the order of the tool panel, with their shortcut and help.
pub const TOOLS: [(u32, &str, egui::Key, &str); 6] = [
    (
        tool::PINCH,
        "Pinch",
        egui::Key::P,
        "Drag the cloth by the point under the mouse (the pen's button 1 does the same)",
    ),
    (
        tool::TEAR,
        "Tear",
        egui::Key::T,
        "Drag with tearing on: edges stretched past the threshold come apart",
    ),
    (
        tool::CUT,
        "Cut",
        egui::Key::C,
        "Click a vertex to split it across the view, or drag a stroke to cut along it",
    ),
    (
        tool::SEW,
        "Sew",
        egui::Key::S,
        "Click two border vertices: they are sewn together. Shift-click four border vertices \
         (start and end of one edge, then of the other) for a seam along two boundary paths",
    ),
    (
        tool::PAINT,
        "Paint",
        egui::Key::B,
        "Click or drag on the cloth to paint with the colour and brush below",
    ),
    (
        tool::PIN,
        "Pin",
        egui::Key::N,
        "Click a vertex to pin it in place; shift-click frees it",
    ),
];

pub fn tool_name(t: u32) -> &'static str {
    TOOLS.iter().find(|x| x.0 == t).map_or("unknown", |x| x.1)
}

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
    /// Paint the panels' background with the window's clear colour instead of egui
    /// fills. The look is the same and a software rasteriser saves a full shading pass
    /// over the panels; off for test harnesses that clear to transparent.
    pub clear_panels: bool,
    /// When the process started (for the "whole design arrived" time; default: when the
    /// app was made).
    pub launched: Option<Instant>,
}

/// What a reset builds: body and grid (the default is cloth-sim's cloth on the cube).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneChoice {
    pub body: u32,
    pub grid: u32,
}

impl Default for SceneChoice {
    fn default() -> Self {
        Self {
            body: shared::ui_to_sim::body::CUBE,
            grid: 64,
        }
    }
}

/// The material and solver settings shown: cloth-sim's (from its telemetry) until the
/// user edits them; Apply sends them for the current design, New scene builds with them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialChoice {
    /// density, stretch, shear, bending, friction, damping (a RESET's `uv` order).
    pub values: [f32; 6],
    pub substeps: u32,
}

impl Default for MaterialChoice {
    /// cloth-sim's defaults: cotton, 5 substeps.
    fn default() -> Self {
        Self {
            values: [0.15, 2000.0, 40.0, 1.0e-5, 0.4, 0.6],
            substeps: 5,
        }
    }
}

struct Drag {
    /// Depth of the grabbed point along the view, to keep it in its view plane.
    depth: f32,
    /// The pen is held (pointer button 1 down).
    pen: bool,
}

pub struct App {
    pub store: Store,
    pub link: Option<Link>,
    link_error: Option<String>,
    link_retry: Instant,
    domain: Option<Domain>,
    /// Every action the UI took (the last 1,000), in order.
    pub emitted: Vec<Emitted>,
    view: Option<View3d>,
    view_error: Option<String>,
    pub camera: Camera,
    /// The tool chosen here (cloth-sim's tool state wins once it arrives).
    pub tool: u32,
    pub colour: egui::Color32,
    pub brush_m: f32,
    pub tear_on: bool,
    pub tear_threshold: f32,
    pub sew_first: Option<u32>,
    /// Shift-clicks of a seam: start and end of path A, then of path B.
    pub seam_picks: Vec<u32>,
    pub save_path: String,
    pub export_dir: String,
    /// The next scene (a reset): body, grid and material.
    pub scene: SceneChoice,
    pub material: MaterialChoice,
    /// The material last read from cloth-sim's telemetry: a different one (a reset, a
    /// load, another UI's change) replaces what is shown.
    material_seen: Option<MaterialChoice>,
    /// How long after start everything of the design had arrived.
    pub design_arrived: Option<Duration>,
    /// A reset waits for a second click within a few seconds.
    reset_armed: Option<Instant>,
    pub status: String,
    drag: Option<Drag>,
    last_hit: Option<Hit>,
    /// Where the 3D view was drawn last frame (points).
    pub view_rect: Option<egui::Rect>,
    /// The 3D view's resolution factor in use.
    pub render_scale: Option<f32>,
    opts: Options,
    started: Instant,
    frames: u64,
    fps: f32,
    fps_at: (Instant, u64),
    screenshot_asked: bool,
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
            view: None,
            view_error: None,
            camera: Camera::default(),
            tool: tool::PINCH,
            colour: egui::Color32::from_rgb(200, 30, 40),
            brush_m: 0.02,
            tear_on: false,
            tear_threshold: 1.6,
            sew_first: None,
            seam_picks: Vec::new(),
            save_path: "design.saiho".into(),
            export_dir: "out/export".into(),
            scene: SceneChoice::default(),
            material: MaterialChoice::default(),
            material_seen: None,
            design_arrived: None,
            reset_armed: None,
            status: String::new(),
            drag: None,
            last_hit: None,
            view_rect: None,
            render_scale: None,
            opts,
            started: Instant::now(),
            frames: 0,
            fps: 0.0,
            fps_at: (Instant::now(), 0),
            screenshot_asked: false,
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
                    if let Err(m) = l.send(*c) {
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

    fn command(&mut self, c: ToolCommand) {
        self.emit(Emitted::Command(c));
    }

    /// The current tool: cloth-sim's when it has told us.
    pub fn current_tool(&self) -> u32 {
        self.store.tool.map_or(self.tool, |t| t.tool)
    }

    pub fn set_tool(&mut self, t: u32) {
        self.tool = t;
        self.sew_first = None;
        self.seam_picks.clear();
        let [r, g, b, a] = self.colour.to_array();
        self.command(ToolCommand {
            op: op::SET_TOOL,
            a: t,
            rgba: [r, g, b, a],
            value: self.brush_m,
            ..Default::default()
        });
        // Show it at once; cloth-sim's tool state confirms it.
        if let Some(s) = &mut self.store.tool {
            s.tool = t;
        }
        self.status = format!("{} tool", tool_name(t));
    }

    fn undo(&mut self) {
        self.command(ToolCommand {
            op: op::UNDO,
            ..Default::default()
        });
    }

    fn redo(&mut self) {
        self.command(ToolCommand {
            op: op::REDO,
            ..Default::default()
        });
    }

    fn path_command(&mut self, o: u32, path: String) {
        let mut c = ToolCommand {
            op: o,
            ..Default::default()
        };
        // cloth-sim resolves the path itself: hand it an absolute one.
        let abs = std::path::absolute(&path).unwrap_or_else(|_| PathBuf::from(&path));
        if c.set_text(&abs.display().to_string()) {
            self.command(c);
        } else {
            self.status = format!("the path {path} is too long");
        }
    }

    fn tools_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Tools");
        let current = self.current_tool();
        for (t, name, key, help) in TOOLS {
            let label = format!("{name}  ({key:?})");
            if ui
                .selectable_label(current == t, label)
                .on_hover_text(help)
                .clicked()
            {
                self.set_tool(t);
            }
        }
        ui.separator();
        ui.label("Paint");
        ui.horizontal(|ui| {
            ui.label("Colour");
            if ui
                .color_edit_button_srgba(&mut self.colour)
                .on_hover_text("The paint tool's colour")
                .changed()
                && self.current_tool() == tool::PAINT
            {
                self.set_tool(tool::PAINT);
            }
        });
        let mut cm = self.brush_m * 100.0;
        if ui
            .add(egui::Slider::new(&mut cm, 0.2..=10.0).text("Brush radius, cm"))
            .on_hover_text("How far from the pointer the paint reaches")
            .changed()
        {
            self.brush_m = cm / 100.0;
            if self.current_tool() == tool::PAINT {
                self.set_tool(tool::PAINT);
            }
        }
        ui.separator();
        ui.label("Tearing");
        let mut changed = ui
            .checkbox(&mut self.tear_on, "Tear overstretched edges")
            .on_hover_text("Edges stretched past the threshold come apart during any drag")
            .changed();
        changed |= ui
            .add(egui::Slider::new(&mut self.tear_threshold, 1.05..=4.0).text("Threshold x rest"))
            .changed();
        if changed {
            self.command(ToolCommand {
                op: op::SET_TEAR,
                mode: u32::from(self.tear_on),
                value: self.tear_threshold,
                ..Default::default()
            });
        }
        ui.separator();
        ui.horizontal(|ui| {
            let (u, r) = self
                .store
                .tool
                .map_or((0, 0), |t| (t.undo_depth, t.redo_depth));
            if ui
                .add_enabled(u > 0 || self.link.is_none(), egui::Button::new("Undo"))
                .on_hover_text(format!(
                    "Undo the last operation (Ctrl+Z); {u} can be undone"
                ))
                .clicked()
            {
                self.undo();
            }
            if ui
                .add_enabled(r > 0 || self.link.is_none(), egui::Button::new("Redo"))
                .on_hover_text(format!("Redo (Ctrl+Y); {r} can be redone"))
                .clicked()
            {
                self.redo();
            }
        });
        ui.separator();
        ui.label("Design");
        ui.horizontal(|ui| {
            ui.label("File");
            ui.text_edit_singleline(&mut self.save_path)
                .on_hover_text("Where Save writes the design (.saiho)");
        });
        ui.horizontal(|ui| {
            if ui
                .button("Save")
                .on_hover_text("Save the design file (Ctrl+S)")
                .clicked()
            {
                let p = self.save_path.clone();
                self.path_command(op::SAVE, p);
            }
            if ui
                .button("Load")
                .on_hover_text("Load this design file in place of the current design (which cloth-sim saves first)")
                .clicked()
            {
                let p = self.save_path.clone();
                self.path_command(op::LOAD, p);
            }
        });
        ui.horizontal(|ui| {
            ui.label("Folder");
            ui.text_edit_singleline(&mut self.export_dir)
                .on_hover_text("Where Export writes OBJ+MTL+PNG, GLB and the design");
        });
        if ui
            .button("Export")
            .on_hover_text("Export the cloth and the body")
            .clicked()
        {
            let p = self.export_dir.clone();
            self.path_command(op::EXPORT, p);
        }
        ui.separator();
        self.material_section(ui);
        ui.separator();
        self.scene_section(ui);
        ui.separator();
        ui.label("View");
        if ui
            .button("Reset view")
            .on_hover_text("Back to the default camera (Home)")
            .clicked()
        {
            self.camera = Camera::default();
        }
        ui.small("Left: tool · Right drag: orbit · Shift+right or middle drag: pan · Wheel: zoom");
    }

    /// The material and substeps of the current design, applied in place.
    fn material_section(&mut self, ui: &mut egui::Ui) {
        if let Some(t) = &self.store.sim_tel {
            let seen = MaterialChoice {
                values: t.material,
                substeps: t.substeps,
            };
            if t.substeps > 0 && self.material_seen != Some(seen) {
                self.material_seen = Some(seen);
                self.material = seen;
            }
        }
        ui.label("Material and solver");
        // A design made with values beyond a slider's range (cloth-sim's flags) keeps
        // them until the user moves that slider.
        let keep = egui::SliderClamping::Edits;
        let [density, stretch, shear, bending, friction, damping] = &mut self.material.values;
        ui.add(
            egui::Slider::new(density, 0.03..=0.6)
                .clamping(keep)
                .text("Density, kg/m²"),
        )
        .on_hover_text("Areal density; cotton shirting is about 0.15");
        ui.add(
            egui::Slider::new(stretch, 100.0..=20000.0)
                .clamping(keep)
                .logarithmic(true)
                .text("Stretch, N/m"),
        )
        .on_hover_text("Stretch modulus along warp and weft");
        ui.add(
            egui::Slider::new(shear, 1.0..=1000.0)
                .clamping(keep)
                .logarithmic(true)
                .text("Shear, N/m"),
        )
        .on_hover_text("In-plane shear modulus; lower drapes into softer folds");
        ui.add(
            egui::Slider::new(bending, 1.0e-7..=1.0e-3)
                .clamping(keep)
                .logarithmic(true)
                .text("Bending, N m"),
        )
        .on_hover_text("Bending rigidity; cotton is about 1e-5");
        ui.add(
            egui::Slider::new(friction, 0.01..=1.5)
                .clamping(keep)
                .text("Friction"),
        )
        .on_hover_text("Coulomb friction against the body and the floor");
        ui.add(
            egui::Slider::new(damping, 0.0..=5.0)
                .clamping(keep)
                .text("Damping, 1/s"),
        )
        .on_hover_text("Velocity damping; higher settles faster and moves more sluggishly");
        ui.add(
            egui::Slider::new(&mut self.material.substeps, 1..=40)
                .clamping(keep)
                .text("Substeps"),
        )
        .on_hover_text(
            "XPBD substeps per 1/60 s frame: more is stiffer and stretches less where the \
                 cloth hangs, and costs frame time (watch 'sim frame' in the status panel)",
        );
        let changed = self.material_seen.is_some_and(|m| m != self.material);
        ui.horizontal(|ui| {
            if ui
                .add_enabled(changed, egui::Button::new("Apply"))
                .on_hover_text("Change the current design's material and substeps in place (edits, seams and history stay)")
                .clicked()
            {
                let mut c = ToolCommand {
                    op: op::SET_MATERIAL,
                    a: self.material.substeps,
                    ..Default::default()
                };
                c.uv[..6].copy_from_slice(&self.material.values);
                self.command(c);
            }
            if ui
                .add_enabled(changed, egui::Button::new("Revert"))
                .on_hover_text("Back to the design's current values")
                .clicked()
                && let Some(m) = self.material_seen
            {
                self.material = m;
            }
        });
    }

    /// Body and grid of a new scene (with the material above), and the reset that builds it.
    fn scene_section(&mut self, ui: &mut egui::Ui) {
        use shared::ui_to_sim::body;
        ui.label("Scene");
        let sc = &mut self.scene;
        ui.horizontal(|ui| {
            ui.label("Body");
            egui::ComboBox::from_id_salt("body")
                .selected_text(match sc.body {
                    body::SPHERE => "sphere",
                    body::MANNEQUIN => "mannequin",
                    _ => "cube",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut sc.body, body::CUBE, "cube");
                    ui.selectable_value(&mut sc.body, body::SPHERE, "sphere");
                    ui.selectable_value(&mut sc.body, body::MANNEQUIN, "mannequin");
                })
                .response
                .on_hover_text("What the next scene drapes over");
        });
        ui.add(egui::Slider::new(&mut sc.grid, 8..=128).text("Grid"))
            .on_hover_text("Cells per side of the next cloth ((N+1)^2 vertices)");
        let armed = self
            .reset_armed
            .is_some_and(|t| t.elapsed() < Duration::from_secs(4));
        let label = if armed {
            "Click again to reset"
        } else {
            "New scene"
        };
        if ui
            .button(label)
            .on_hover_text("Start a new design with this body and grid and the material above; cloth-sim saves the current one first")
            .clicked()
        {
            if armed {
                self.reset_armed = None;
                let mut c = ToolCommand {
                    op: op::RESET,
                    a: self.scene.grid,
                    b: self.scene.body,
                    mode: self.material.substeps,
                    ..Default::default()
                };
                c.uv[..6].copy_from_slice(&self.material.values);
                self.command(c);
            } else {
                self.reset_armed = Some(Instant::now());
                self.status = "New scene: click again to replace the design (it is saved first)".into();
            }
        }
    }

    fn status_panel(&mut self, ui: &mut egui::Ui) {
        ui.heading("Processes");
        let fresh = |t: Option<Instant>| t.is_some_and(|t| t.elapsed() < Duration::from_secs(2));
        let dot = |ui: &mut egui::Ui, ok: bool, what: &str| {
            let c = if ok {
                egui::Color32::from_rgb(80, 200, 120)
            } else {
                egui::Color32::from_rgb(220, 80, 60)
            };
            let state = if ok { "connected" } else { "not connected" };
            ui.colored_label(c, format!("{what}: {state}"));
        };
        dot(ui, fresh(self.store.heard.sim), "cloth-sim");
        dot(ui, fresh(self.store.heard.haptic), "haptic-loop");
        dot(ui, self.link.is_some(), "iceoryx2");
        if let Some(l) = &self.store.loop_tel {
            let us = |ns: u64| ns as f64 / 1000.0;
            ui.label(format!(
                "haptic: {} ticks, {} missed\nperiod p50 {:.0} µs · p99.9 {:.0} µs\ncompute p99 {:.0} µs · force {:.2} N",
                l.ticks,
                l.missed,
                us(l.period.quantile_ns(0.5)),
                us(l.period.quantile_ns(0.999)),
                us(l.compute.quantile_ns(0.99)),
                l.force_n
            ));
        }
        if let Some(s) = &self.store.sim_tel {
            ui.label(format!(
                "sim: {} vertices · {:.0} Hz\nframe p50 {:.2} ms · p99 {:.2} ms",
                s.vertices,
                s.rate_hz,
                s.frame_time.quantile_ns(0.5) as f64 * 1e-6,
                s.frame_time.quantile_ns(0.99) as f64 * 1e-6
            ));
        }
        ui.label(format!("UI: {:.0} fps", self.fps));
        if let Some(t) = self.design_arrived {
            ui.label(format!(
                "design received {:.0} ms after start",
                t.as_secs_f64() * 1000.0
            ))
            .on_hover_text("Mesh, positions, seams, all texture tiles, tool and material");
        }
        if self.store.rejected > 0 {
            ui.colored_label(
                egui::Color32::from_rgb(230, 160, 40),
                format!(
                    "{} messages rejected (last: {})",
                    self.store.rejected,
                    self.store.last_rejection.as_deref().unwrap_or("?")
                ),
            );
        }
        ui.separator();
        ui.heading("Latency");
        let h = &self.store.history;
        let series = |f: fn(&crate::store::Sample) -> f64| -> egui_plot::PlotPoints<'static> {
            h.iter().map(|s| [s.t, f(s)]).collect()
        };
        egui_plot::Plot::new("haptic timing")
            .height(140.0)
            .legend(egui_plot::Legend::default())
            .y_axis_label("µs")
            .show(ui, |p| {
                p.line(egui_plot::Line::new(
                    "period p99.9",
                    series(|s| s.haptic_period_p999_us),
                ));
                p.line(egui_plot::Line::new(
                    "compute p99",
                    series(|s| s.haptic_compute_p99_us),
                ));
            });
        egui_plot::Plot::new("model age")
            .height(120.0)
            .legend(egui_plot::Legend::default())
            .y_axis_label("ms")
            .show(ui, |p| {
                p.line(egui_plot::Line::new(
                    "model age p99",
                    series(|s| s.model_age_p99_ms),
                ));
                p.line(egui_plot::Line::new(
                    "sim frame p50",
                    series(|s| s.sim_frame_ms),
                ));
            });
        if let Some(l) = &self.store.loop_tel {
            // The period histogram around 1 ms, bucketed by 10 µs.
            let mut bars = Vec::new();
            for b in (900..1100).step_by(10) {
                let c: u32 = l.period.counts[b..b + 10].iter().sum();
                if c > 0 {
                    bars.push(
                        egui_plot::Bar::new(b as f64 + 5.0, (c as f64).log10() + 1.0).width(9.0),
                    );
                }
            }
            egui_plot::Plot::new("period histogram")
                .height(110.0)
                .y_axis_label("log10 count + 1")
                .x_axis_label("period, µs")
                .show(ui, |p| {
                    p.bar_chart(egui_plot::BarChart::new("period", bars))
                });
        }
    }

    fn keyboard(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let (mut tool_key, mut undo, mut redo, mut save, mut home) =
            (None, false, false, false, false);
        ctx.input(|i| {
            for (t, _, key, _) in TOOLS {
                if i.key_pressed(key) && !i.modifiers.command {
                    tool_key = Some(t);
                }
            }
            undo = i.modifiers.command && i.key_pressed(egui::Key::Z) && !i.modifiers.shift;
            redo = i.modifiers.command
                && (i.key_pressed(egui::Key::Y)
                    || (i.modifiers.shift && i.key_pressed(egui::Key::Z)));
            save = i.modifiers.command && i.key_pressed(egui::Key::S);
            home = i.key_pressed(egui::Key::Home);
        });
        if save {
            let p = self.save_path.clone();
            self.path_command(op::SAVE, p);
        } else if let Some(t) = tool_key {
            self.set_tool(t);
        }
        if undo {
            self.undo();
        }
        if redo {
            self.redo();
        }
        if home {
            self.camera = Camera::default();
        }
    }

    /// Mouse in the 3D view: camera on the right and middle buttons, the tool on the left.
    fn view_input(&mut self, resp: &egui::Response, ctx: &egui::Context) {
        let rect = resp.rect;
        let size = Vec2::new(rect.width(), rect.height());
        let (shift, wheel) = ctx.input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y));
        if resp.hovered() && wheel != 0.0 {
            self.camera.zoom(wheel / 50.0);
        }
        let d = resp.drag_delta();
        let dv = Vec2::new(d.x, d.y);
        if resp.dragged_by(egui::PointerButton::Middle)
            || (resp.dragged_by(egui::PointerButton::Secondary) && shift)
        {
            self.camera.pan(dv, size.y);
        } else if resp.dragged_by(egui::PointerButton::Secondary) {
            self.camera.orbit(dv);
        }
        let Some(pos) = resp.interact_pointer_pos().or(resp.hover_pos()) else {
            return;
        };
        let local = Vec2::new(pos.x - rect.min.x, pos.y - rect.min.y);
        let (o, dir) = self.camera.ray(local, size);
        let hit = self
            .store
            .mesh
            .as_ref()
            .and_then(|m| pick(o, dir, &m.corners, &self.store.x));
        if resp.hovered() {
            self.last_hit = hit;
        }
        let t = self.current_tool();
        let primary_pressed = resp.drag_started_by(egui::PointerButton::Primary)
            || resp.clicked_by(egui::PointerButton::Primary);
        // A drag with pinch, tear or a cut stroke moves the simulated pen, button held.
        let pen_tool = matches!(t, tool::PINCH | tool::TEAR | tool::CUT | tool::PAINT);
        if resp.drag_started_by(egui::PointerButton::Primary) && pen_tool {
            if let Some(h) = hit {
                let depth = (h.point - o).dot(dir);
                self.drag = Some(Drag { depth, pen: true });
                self.emit(Emitted::Pointer(h.point.to_array(), 1));
            } else {
                self.status = "nothing under the mouse to grab".into();
            }
        } else if let Some(dr) = &self.drag {
            let target = o + dir * dr.depth;
            if resp.dragged_by(egui::PointerButton::Primary) {
                if dr.pen {
                    self.emit(Emitted::Pointer(target.to_array(), 1));
                }
            } else if resp.drag_stopped() || !ctx.input(|i| i.pointer.primary_down()) {
                self.emit(Emitted::Pointer(target.to_array(), 0));
                self.drag = None;
            }
        }
        if resp.clicked_by(egui::PointerButton::Primary) && primary_pressed {
            self.click(t, hit, shift, dir);
        }
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
                self.command(ToolCommand {
                    op: op::CUT_VERTEX,
                    a: h.vertex,
                    vec: dirn.to_array(),
                    ..Default::default()
                });
            }
            tool::SEW if shift => {
                self.seam_picks.push(h.vertex);
                if self.seam_picks.len() < 4 {
                    self.status = format!(
                        "seam: {} of 4 picked (start and end of path A, then of path B)",
                        self.seam_picks.len()
                    );
                    return;
                }
                let picks = std::mem::take(&mut self.seam_picks);
                match self.seam_command(&picks) {
                    Some(c) => self.command(c),
                    None => {
                        self.status =
                            "seam: the picked vertices have no place on the pattern".into()
                    }
                }
            }
            tool::SEW => match self.sew_first.take() {
                None => {
                    self.sew_first = Some(h.vertex);
                    self.status = format!("sew: vertex {} picked, click the other", h.vertex);
                }
                Some(a) if a == h.vertex => {
                    self.status = "sew: that is the same vertex; pick another".into();
                    self.sew_first = Some(a);
                }
                Some(a) => self.command(ToolCommand {
                    op: op::SEW,
                    a,
                    b: h.vertex,
                    ..Default::default()
                }),
            },
            tool::PIN => self.command(ToolCommand {
                op: op::PIN,
                a: h.vertex,
                mode: u32::from(!shift),
                ..Default::default()
            }),
            tool::PAINT => {
                let [r, g, b, a] = self.colour.to_array();
                self.command(ToolCommand {
                    op: op::PAINT,
                    vec: h.point.to_array(),
                    value: self.brush_m,
                    rgba: [r, g, b, a],
                    ..Default::default()
                });
            }
            // Pinch and tear act by dragging.
            _ => {
                self.status = format!("{}: drag to pull the cloth", tool_name(t));
            }
        }
    }

    /// A SEAM command along the pattern segments between picks 0-1 and 2-3.
    fn seam_command(&self, picks: &[u32]) -> Option<ToolCommand> {
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
        let (a0, b0) = (back(p[0], p[1]), back(p[2], p[3]));
        Some(ToolCommand {
            op: op::SEAM,
            value: edge / 3.0,
            uv: [
                a0[0], a0[1], p[1][0], p[1][1], b0[0], b0[1], p[3][0], p[3][1],
            ],
            ..Default::default()
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
        }
    }

    fn view_panel(&mut self, ui: &mut egui::Ui, frame: &eframe::Frame) {
        let size = ui.available_size();
        let overlay = self.overlay();
        let resp = ui.allocate_response(size, egui::Sense::click_and_drag());
        match frame.wgpu_render_state() {
            Some(rs) => {
                let scale = *self.render_scale.get_or_insert_with(|| {
                    self.opts.render_scale.unwrap_or(
                        if rs.adapter.get_info().device_type == egui_wgpu::wgpu::DeviceType::Cpu {
                            0.5
                        } else {
                            1.0
                        },
                    )
                });
                let ppp = ui.ctx().pixels_per_point() * scale.clamp(0.1, 2.0);
                let px = [
                    (size.x * ppp).round().max(16.0) as u32,
                    (size.y * ppp).round().max(16.0) as u32,
                ];
                let view = self.view.get_or_insert_with(|| View3d::new(&rs.device));
                view.render(
                    &rs.device,
                    &rs.queue,
                    &mut self.store,
                    &self.camera,
                    &overlay,
                    px,
                );
                if let Some(cb) = view.paint_callback(&rs.device, rs.target_format, resp.rect) {
                    ui.painter().add(cb);
                }
            }
            None => {
                self.view_error = Some("no wgpu renderer: the 3D view needs wgpu".into());
            }
        }
        let resp = resp.on_hover_text_at_pointer(match &self.last_hit {
            Some(h) => format!(
                "{} · vertex {} at ({:.3}, {:.3}, {:.3}) m",
                tool_name(self.current_tool()),
                h.vertex,
                h.point.x,
                h.point.y,
                h.point.z
            ),
            None => tool_name(self.current_tool()).to_string(),
        });
        self.view_rect = Some(resp.rect);
        self.view_input(&resp, ui.ctx());
        // Banners over the view.
        let banner = if let Some(m) = &self.store.mismatch {
            Some(format!("Cannot read a peer's messages: {m}"))
        } else if let Some(e) = &self.link_error {
            Some(format!("Cannot connect: {e}"))
        } else if let Some(e) = &self.view_error {
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
        };
        if let Some(b) = banner {
            ui.put(
                egui::Rect::from_min_size(
                    resp.rect.min + egui::vec2(12.0, 12.0),
                    egui::vec2(resp.rect.width() - 24.0, 28.0),
                ),
                egui::Label::new(
                    egui::RichText::new(b)
                        .color(egui::Color32::from_rgb(255, 210, 120))
                        .size(15.0),
                ),
            );
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
                    format!("refused: {}", a.message)
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

    fn timing(&mut self, ctx: &egui::Context) {
        self.frames += 1;
        let el = self.fps_at.0.elapsed().as_secs_f32();
        if el >= 1.0 {
            self.fps = (self.frames - self.fps_at.1) as f32 / el;
            self.fps_at = (Instant::now(), self.frames);
            if self.opts.log_fps {
                eprintln!("cloth-ui: {:.1} fps", self.fps);
            }
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
        self.keyboard(&ctx);
        let mut panel = egui::Frame::side_top_panel(ui.style());
        if self.opts.clear_panels {
            panel = panel.fill(egui::Color32::TRANSPARENT);
        }
        egui::Panel::top("top").frame(panel).show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.strong("Saiho");
                ui.separator();
                ui.label(format!("tool: {}", tool_name(self.current_tool())));
                if let Some(m) = &self.store.mesh {
                    ui.separator();
                    ui.label(format!(
                        "{} vertices · {} triangles · frame {}",
                        self.store.x.len(),
                        m.triangles(),
                        self.store.frame
                    ));
                }
                if let Some(t) = &self.store.tool {
                    ui.separator();
                    ui.label(format!("undo {} · redo {}", t.undo_depth, t.redo_depth));
                }
            });
        });
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
                egui::ScrollArea::vertical().show(ui, |ui| self.tools_panel(ui));
            });
        egui::Panel::right("status panel")
            .frame(panel)
            .default_size(300.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.status_panel(ui));
            });
        // No fill: the 3D view covers the panel, and on a software rasteriser every pixel
        // egui shades costs (see blit.wgsl).
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.view_panel(ui, frame));
        self.timing(&ctx);
        ctx.request_repaint();
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        if self.opts.clear_panels {
            visuals.panel_fill.to_normalized_gamma_f32()
        } else {
            egui::Color32::from_rgb(12, 12, 12).to_normalized_gamma_f32()
        }
    }
}
