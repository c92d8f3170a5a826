//! The scene panel: the running design's model and whether its cloth may cross (the
//! guard's switch), body, model and grid of a new scene (with the material panel's
//! values), and the reset that builds it.

use std::time::{Duration, Instant};

use shared::command::{BodyChoice, Command};
use shared::telemetry::{SimTelemetry, scene_body, scene_model};

use super::material::MaterialChoice;
use crate::action::Action;

/// What a reset builds: body, grid and cloth model (the default is cloth-sim's cloth on
/// the cube, under cloth-sim's own model).
pub struct ScenePanel {
    pub body: BodyChoice,
    pub grid: u32,
    /// A pattern file whose pieces a new scene is, placed and sewn (empty: a square
    /// cloth of `grid` cells).
    pub pattern: String,
    /// A [`scene_model`] code; `None` until cloth-sim reports one (then its own).
    pub model: Option<u32>,
    /// A reset waits for a second click within a few seconds.
    reset_armed: Option<Instant>,
    /// The running design's body, grid and model, as cloth-sim last reported them.
    running: Option<(u32, u32, u32)>,
    /// The pattern file the running design was made from, as cloth-sim last listed it.
    running_source: Option<String>,
    /// The guard last asked for, shown until cloth-sim's telemetry (once a second)
    /// reports it or a few seconds pass.
    guard_asked: Option<(bool, Instant)>,
    /// Likewise the strain limit last asked for (0: none).
    limit_asked: Option<(f32, Instant)>,
    /// The most a triangle may stretch, as a ratio of its rest length, that the switch
    /// asks for: the running limit's when cloth-sim reports a new one, else as edited.
    limit_ratio: f32,
    /// The strain limit cloth-sim last reported.
    limit_seen: Option<f32>,
}

impl Default for ScenePanel {
    fn default() -> Self {
        Self {
            body: BodyChoice::Cube,
            grid: 64,
            pattern: String::new(),
            model: None,
            reset_armed: None,
            running: None,
            running_source: None,
            guard_asked: None,
            limit_asked: None,
            limit_ratio: 1.2,
            limit_seen: None,
        }
    }
}

/// A model's name as `--model` spells it.
fn model_name(code: u32) -> &'static str {
    scene_model::NAMES
        .get(code as usize)
        .copied()
        .unwrap_or("?")
}

/// What each model is for, as the Scene panel's chooser says.
const MODEL_HINTS: [&str; 4] = [
    "xpbd: the one to design with; fast, and with its guard (on unless switched off) it never crosses",
    "vbd: never crosses and holds the fabric's stiffness; several times slower",
    "seed: the 2005 paper's mass-spring model, as it was",
    "implicit: the reference (backward Euler); slow, for checking a drape's rest shape",
];

/// A body's name as the Scene panel shows it.
fn body_name(code: u32) -> &'static str {
    match code {
        scene_body::CUBE => "cube",
        scene_body::SPHERE => "sphere",
        scene_body::MANNEQUIN => "mannequin",
        scene_body::MANNEQUIN_APOSE => "mannequin, arms out (A-pose)",
        scene_body::HUMAN => "human body",
        scene_body::FILE => "a body from a file",
        _ => "no body",
    }
}

impl ScenePanel {
    /// Follows the pattern file the running design was made from: when cloth-sim lists
    /// another (a lab started with `--pattern`, a new scene, a load), the next scene is
    /// made from it (New scene makes the same garment again, not a square); a path being
    /// typed stays until then.
    pub fn follow_source(&mut self, source: &str) {
        if self.running_source.as_deref() != Some(source) {
            self.running_source = Some(source.to_string());
            self.pattern = source.to_string();
        }
    }

    /// Follows the running design: when cloth-sim reports another body or grid (a reset,
    /// a load, a restart), the next scene starts from it.
    fn follow(&mut self, tel: Option<&SimTelemetry>) {
        let Some(t) = tel else { return };
        if self.running == Some((t.body, t.grid, t.model)) {
            return;
        }
        self.running = Some((t.body, t.grid, t.model));
        self.model = Some(t.model);
        match t.body {
            scene_body::CUBE => self.body = BodyChoice::Cube,
            scene_body::SPHERE => self.body = BodyChoice::Sphere,
            scene_body::MANNEQUIN => self.body = BodyChoice::Mannequin,
            scene_body::MANNEQUIN_APOSE => self.body = BodyChoice::MannequinAPose,
            scene_body::HUMAN => self.body = BodyChoice::Human,
            _ => {}
        }
        if t.grid > 0 {
            self.grid = t.grid;
        }
    }

    /// The running model and its contact: a switch for xpbd's guard, a note for the
    /// others.
    fn contact(
        &mut self,
        ui: &mut egui::Ui,
        tel: Option<&SimTelemetry>,
        actions: &mut Vec<Action>,
    ) {
        let Some(t) = tel else { return };
        let reported = t.never_crosses == 1;
        if let Some((asked, at)) = self.guard_asked
            && (asked == reported || at.elapsed() > Duration::from_secs(4))
        {
            self.guard_asked = None;
        }
        let model = model_name(t.model);
        match t.model {
            scene_model::XPBD => {
                let mut on = self.guard_asked.map_or(reported, |(asked, _)| asked);
                let hint = "On: the cloth never passes through itself or the body's edges \
                     (contact checked between every pair of nearby triangles; frames cost \
                     several times more); on for a new design. Off: faster, and the cloth \
                     may cross. Crossings already there stay.";
                if ui
                    .checkbox(&mut on, "Never cross (guard)")
                    .on_hover_text(hint)
                    .changed()
                {
                    self.guard_asked = Some((on, Instant::now()));
                    actions.push(Action::Command(Command::SetGuard { on }));
                }
                self.strain_limit(ui, t, actions);
            }
            scene_model::VBD => {
                ui.label("Contact: never crossed (the vbd model)")
                    .on_hover_text("The vbd model's contact cannot be crossed; it has no switch");
            }
            _ => {
                ui.label(format!("Contact: the body only ({model} model)"))
                    .on_hover_text(
                        "This model has no guard against crossing; choose xpbd or vbd below \
                         for a new scene that has one",
                    );
            }
        }
    }

    /// The xpbd model's strain limit: a switch and the ratio it holds triangles under.
    fn strain_limit(&mut self, ui: &mut egui::Ui, t: &SimTelemetry, actions: &mut Vec<Action>) {
        let reported = t.strain_limit;
        if let Some((asked, at)) = self.limit_asked
            && (asked == reported || at.elapsed() > Duration::from_secs(4))
        {
            self.limit_asked = None;
        }
        let limit = self.limit_asked.map_or(reported, |(asked, _)| asked);
        if self.limit_seen != Some(reported) {
            self.limit_seen = Some(reported);
            if reported > 0.0 {
                self.limit_ratio = 1.0 + reported;
            }
        }
        let mut on = limit > 0.0;
        let hint = "On, the default for woven fabrics: no triangle stretches past this \
             ratio of its rest length in any direction, held hard every substep (a woven \
             fabric's stiff end is about 1.2x; the mannequin drape's worst side falls from \
             1.43x to 1.24x). A fabric chosen brings its own (none for knits). Off: frames \
             cost 30-50% less, and the cloth stretches where it hangs.";
        ui.horizontal(|ui| {
            let toggled = ui
                .checkbox(&mut on, "Hold stretch under")
                .on_hover_text(hint)
                .changed();
            let ratio = ui
                .add(
                    egui::DragValue::new(&mut self.limit_ratio)
                        .range(1.05..=2.0)
                        .speed(0.005)
                        .fixed_decimals(2)
                        .suffix("x"),
                )
                .on_hover_text("The most a triangle may stretch, times its rest length");
            // A drag asks once, when it ends; a typed value when it is entered.
            let set = ratio.drag_stopped() || (ratio.changed() && !ratio.dragged());
            if toggled || (on && set) {
                let want = if on { self.limit_ratio - 1.0 } else { 0.0 };
                self.limit_asked = Some((want, Instant::now()));
                actions.push(Action::Command(Command::SetStrainLimit { limit: want }));
            }
        });
    }

    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        tel: Option<&SimTelemetry>,
        material: MaterialChoice,
        actions: &mut Vec<Action>,
    ) {
        self.follow(tel);
        ui.label("Scene");
        if let Some((body, grid, model)) = self.running {
            let cloth = if grid > 0 {
                format!("a {grid} x {grid} cloth")
            } else {
                "pieces of cloth".to_string()
            };
            ui.label(format!(
                "Now: {cloth} over {}, {} model",
                match body {
                    scene_body::CUBE
                    | scene_body::SPHERE
                    | scene_body::MANNEQUIN
                    | scene_body::MANNEQUIN_APOSE
                    | scene_body::HUMAN => {
                        format!("the {}", body_name(body))
                    }
                    other => body_name(other).to_string(),
                },
                model_name(model)
            ))
            .on_hover_text("The running design, as cloth-sim reports it");
        }
        self.contact(ui, tel, actions);
        ui.horizontal(|ui| {
            ui.label("Body");
            egui::ComboBox::from_id_salt("body")
                .selected_text(match self.body {
                    BodyChoice::Sphere => "sphere",
                    BodyChoice::Mannequin => "mannequin",
                    BodyChoice::Cube => "cube",
                    BodyChoice::MannequinAPose => "mannequin, A-pose",
                    BodyChoice::Human => "human body",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.body, BodyChoice::Cube, "cube");
                    ui.selectable_value(&mut self.body, BodyChoice::Sphere, "sphere");
                    ui.selectable_value(&mut self.body, BodyChoice::Mannequin, "mannequin");
                    ui.selectable_value(
                        &mut self.body,
                        BodyChoice::MannequinAPose,
                        "mannequin, A-pose",
                    )
                    .on_hover_text(
                        "Its arms held out 50 degrees below the horizontal, as GarmentCode's \
                         patterns place their sleeves: they go round its arms",
                    );
                    ui.selectable_value(&mut self.body, BodyChoice::Human, "human body")
                        .on_hover_text(
                            "An average adult figure, 1.72 m, arms held out 45 degrees \
                             (GarmentCode's body): its patterns are cut for it and fit it",
                        );
                })
                .response
                .on_hover_text("What the next scene drapes over");
        });
        if let Some(current) = self.model {
            let mut m = current;
            egui::ComboBox::from_label("Model")
                .selected_text(model_name(m))
                .show_ui(ui, |ui| {
                    for (code, hint) in MODEL_HINTS.iter().enumerate() {
                        ui.selectable_value(&mut m, code as u32, model_name(code as u32))
                            .on_hover_text(*hint);
                    }
                })
                .response
                .on_hover_text("The cloth model of the next scene");
            self.model = Some(m);
        }
        self.new_scene(ui, material, actions);
    }

    /// The grid or a pattern file, and the New scene button (two clicks) that builds it.
    fn new_scene(
        &mut self,
        ui: &mut egui::Ui,
        material: MaterialChoice,
        actions: &mut Vec<Action>,
    ) {
        let square = self.pattern.trim().is_empty();
        ui.add_enabled(
            square,
            egui::Slider::new(&mut self.grid, 8..=128).text("Grid"),
        )
        .on_hover_text("Cells per side of the next cloth ((N+1)^2 vertices)")
        .on_disabled_hover_text("The next scene is the pattern's pieces, not a square");
        ui.horizontal(|ui| {
            let label = ui.label("Pattern file");
            ui.add(
                egui::TextEdit::singleline(&mut self.pattern)
                    .hint_text("none: a square cloth")
                    .desired_width(140.0),
            )
            .on_hover_text(
                "A pattern file (.svg, .dxf or GarmentCode .json, as a path cloth-sim can \
                 read): the next scene is its pieces placed round the body, their tops above \
                 its shoulders, and sewn, with nothing else in the way (a garment added to a \
                 scene lands on its cloth). Empty: a square cloth of this grid",
            )
            .labelled_by(label.id);
        });
        // A GarmentCode specification (`own_body` also reads an SVG of ours for the body
        // it names: too slow for every frame, and the warning is GarmentCode's).
        let cut_for_human = std::path::Path::new(self.pattern.trim())
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        if !square && cut_for_human && self.body != BodyChoice::Human {
            self.garmentcode_off_its_body(ui);
        } else if !square && matches!(self.body, BodyChoice::Cube | BodyChoice::Sphere) {
            self.pattern_off_the_mannequin(ui);
        }
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
            .on_hover_text("Start a new design with this body and grid (or pattern) and the material above; cloth-sim saves the current one first")
            .clicked()
        {
            if armed {
                self.reset_armed = None;
                actions.push(Action::Command(Command::Reset {
                    body: self.body,
                    grid: Some(self.grid).filter(|&g| g != 0),
                    material: material.change(),
                    substeps: Some(material.substeps).filter(|&n| n != 0),
                    model: self.model,
                    pattern: Some(self.pattern.trim().to_string()).filter(|p| !p.is_empty()),
                }));
            } else {
                self.reset_armed = Some(Instant::now());
                actions.push(Action::Status(
                    "New scene: click again to replace the design (it is saved first)".into(),
                ));
            }
        }
    }

    /// A GarmentCode pattern is cut for GarmentCode's average body, ours as `human`: on
    /// the mannequin its shirt welded 249 of 346 stitched pairs and stretched a side 11x,
    /// on its own body all 346 and 1.4x (docs/garments.md).
    fn garmentcode_off_its_body(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "A GarmentCode pattern is cut for the human body: over another its seams \
                 close only by stretching, if at all.",
            );
            if ui
                .button("Use the human body")
                .on_hover_text("The next scene drapes over the human body")
                .clicked()
            {
                self.body = BodyChoice::Human;
            }
        });
    }

    /// A pattern is cut for a person; the body chooser starts at the running design's
    /// body, which in a new lab is the cube. Said before the designer builds it: on the
    /// cube the dress ran 0.3-0.8 s a frame and welded no seam (docs/garments.md).
    fn pattern_off_the_mannequin(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "A pattern is placed round a person: over this body its pieces go round a \
                 box, slowly, and its seams may not close.",
            );
            if ui
                .button("Use the mannequin")
                .on_hover_text("The next scene drapes over the mannequin")
                .clicked()
            {
                self.body = BodyChoice::Mannequin;
            }
        });
    }
}
