//! The material panel: the current design's material and substeps as cloth-sim reports
//! them (its telemetry), edited here and applied in place, or a measured fabric chosen by
//! name from the fabric library.

use shared::command::{Command, MaterialChange};
use shared::telemetry::SimTelemetry;

use crate::action::Action;

/// The chooser's name for the design's default material.
const DEFAULT_SHOWN: &str = "cotton (default)";

/// Whether two material values agree to a thousandth of the larger.
fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-3 * a.abs().max(b.abs())
}

/// A material and substep count as the panel shows them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialChoice {
    /// density, stretch, shear, bending, friction, damping, shear damping, bending
    /// damping.
    pub values: [f32; 8],
    pub substeps: u32,
}

impl Default for MaterialChoice {
    /// cloth-sim's defaults: cotton, 5 substeps.
    fn default() -> Self {
        Self {
            values: [0.15, 2000.0, 40.0, 1.0e-5, 0.4, 0.6, 0.005, 0.002],
            substeps: 5,
        }
    }
}

impl MaterialChoice {
    /// Every value as a change (on the wire a 0 keeps cloth-sim's value).
    pub fn change(&self) -> MaterialChange {
        let [
            density,
            stretch,
            shear,
            bending,
            friction,
            damping,
            shear_damping,
            bend_damping,
        ] = self.values.map(Some);
        MaterialChange {
            density,
            stretch,
            shear,
            bending,
            friction,
            damping,
            shear_damping,
            bend_damping,
        }
    }
}

/// The material and solver settings shown: cloth-sim's (from its telemetry) until the
/// user edits them; Apply sends them for the current design, New scene builds with them.
pub struct MaterialPanel {
    /// density, stretch, shear, bending, friction, damping, shear damping, bending
    /// damping, as shown.
    pub values: [f32; 8],
    pub substeps: u32,
    /// The material last read from cloth-sim's telemetry: a different one (a reset, a
    /// load, another UI's change) replaces what is shown.
    seen: Option<MaterialChoice>,
    /// The library's fabrics: name, what the chooser's hover says, and the values the
    /// telemetry shows when the design has that fabric.
    fabrics: Vec<FabricEntry>,
}

/// A fabric as the chooser offers it.
struct FabricEntry {
    name: String,
    about: String,
    /// density, stretch, shear, bending, friction (the telemetry's first five).
    values: [f32; 5],
}

/// What a fabric chooser's hover says of `f`: weight, bending, source.
pub fn fabric_about(f: &sim_core::fabric::Fabric) -> String {
    let m = f.material();
    format!(
        "{}: {:.0} g/m², bending {:.1e} N m (weft {:.1e}); {}",
        f.name,
        m.density * 1e3,
        m.bending,
        m.bending * m.bending_weft,
        f.source
    )
}

/// The built-in fabric library as the chooser lists it.
fn fabric_entries() -> Vec<FabricEntry> {
    sim_core::fabric::Library::builtin()
        .fabrics
        .iter()
        .map(|f| {
            let m = f.material();
            FabricEntry {
                name: f.name.clone(),
                about: fabric_about(f),
                values: [m.density, m.stretch, m.shear, m.bending, m.friction],
            }
        })
        .collect()
}

impl Default for MaterialPanel {
    /// cloth-sim's defaults until it tells otherwise.
    fn default() -> Self {
        let d = MaterialChoice::default();
        Self {
            values: d.values,
            substeps: d.substeps,
            seen: None,
            fabrics: fabric_entries(),
        }
    }
}

impl MaterialPanel {
    /// What is shown.
    pub fn choice(&self) -> MaterialChoice {
        MaterialChoice {
            values: self.values,
            substeps: self.substeps,
        }
    }

    /// Follows cloth-sim's telemetry: a material it has not shown yet replaces what is
    /// shown.
    fn follow(&mut self, tel: Option<&SimTelemetry>) {
        if let Some(t) = tel {
            let seen = MaterialChoice {
                values: t.material,
                substeps: t.substeps,
            };
            if t.substeps > 0 && self.seen != Some(seen) {
                self.seen = Some(seen);
                self.values = seen.values;
                self.substeps = seen.substeps;
            }
        }
    }

    /// The library's fabric whose measured values the design has now, if one does.
    pub fn current_fabric(&self) -> Option<&str> {
        let seen = self.seen?;
        self.fabrics
            .iter()
            .find(|f| {
                f.values
                    .iter()
                    .zip(&seen.values)
                    .all(|(a, b)| close(*a, *b))
            })
            .map(|f| f.name.as_str())
    }

    /// What the fabric chooser shows: the library's fabric the design has, the design's
    /// own default material (cloth-sim's cotton-like woven, which the Pieces panel lists
    /// as "cotton", a piece's fabric when none is given), or "custom" for values of neither.
    pub fn shown_fabric(&self) -> &str {
        let default = MaterialChoice::default().values;
        let is_default = |m: &MaterialChoice| {
            m.values[..5]
                .iter()
                .zip(&default)
                .all(|(a, b)| close(*a, *b))
        };
        match (self.current_fabric(), self.seen) {
            (Some(name), _) => name,
            (None, Some(m)) if is_default(&m) => DEFAULT_SHOWN,
            _ => "custom",
        }
    }

    /// The fabric chooser: a name picked sends it for the whole design.
    fn chooser(&self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        let shown = self.shown_fabric();
        egui::ComboBox::from_label("Fabric")
            .selected_text(shown)
            .show_ui(ui, |ui| {
                for f in &self.fabrics {
                    if ui
                        .add_enabled(
                            self.seen.is_some(),
                            egui::Button::selectable(shown == f.name, &f.name),
                        )
                        .on_hover_text(&f.about)
                        .clicked()
                    {
                        actions.push(Action::Command(Command::SetFabric {
                            name: f.name.clone(),
                        }));
                    }
                }
            })
            .response
            .on_hover_text(
                "A measured fabric for the whole design, in place: its weight, stretch, shear, \
                 bending (warp, weft, bias), friction and thickness (docs/fabrics.md lists the \
                 sources). 'cotton (default)' for the design's own default material, \
                 'custom' when the values are neither.",
            );
    }

    /// The material and substeps of the current design, applied in place.
    pub fn ui(&mut self, ui: &mut egui::Ui, tel: Option<&SimTelemetry>, actions: &mut Vec<Action>) {
        self.follow(tel);
        ui.label("Material and solver");
        self.chooser(ui, actions);
        self.sliders(ui);
        let changed = self.seen.is_some_and(|m| m != self.choice());
        ui.horizontal(|ui| {
            if ui
                .add_enabled(changed, egui::Button::new("Apply"))
                .on_hover_text("Change the current design's material and substeps in place (edits, seams and history stay)")
                .clicked()
            {
                actions.push(Action::Command(Command::SetMaterial {
                    material: self.choice().change(),
                    substeps: Some(self.substeps).filter(|&n| n != 0),
                }));
            }
            if ui
                .add_enabled(changed, egui::Button::new("Revert"))
                .on_hover_text("Back to the design's current values")
                .clicked()
                && let Some(m) = self.seen
            {
                self.values = m.values;
                self.substeps = m.substeps;
            }
        });
    }

    fn sliders(&mut self, ui: &mut egui::Ui) {
        // A design made with values beyond a slider's range (cloth-sim's flags) keeps
        // them until the user moves that slider.
        let keep = egui::SliderClamping::Edits;
        let [
            density,
            stretch,
            shear,
            bending,
            friction,
            damping,
            shear_damping,
            bend_damping,
        ] = &mut self.values;
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
        damping_ms(
            ui,
            shear_damping,
            "Int. damping, ms",
            "Damping of the weave in shear (CLO's internal damping): how long the \
             cloth's shearing takes to die out. Higher brings a fine garment to rest \
             (20 ms stops the 2 x 8k dress swinging); it costs small scenes a little \
             frame time. 5 ms by default",
        );
        damping_ms(
            ui,
            bend_damping,
            "Bend damping, ms",
            "The same internal damping on bending: how long a fold's swing takes to \
             die out. It stops a fine cloth's loose flaps swinging at rest (the \
             128 x 128 drape rests, and its frames cost less); it is left off while a \
             seam is being sewn or the pen holds the cloth. 2 ms by default",
        );
        ui.add(
            egui::Slider::new(&mut self.substeps, 1..=40)
                .clamping(keep)
                .text("Substeps"),
        )
        .on_hover_text(
            "XPBD substeps per 1/60 s frame: more is stiffer and stretches less where the \
                 cloth hangs, and costs frame time (watch 'sim frame' in the status panel)",
        );
    }
}

/// A damping time slider: shown in ms (the material holds seconds), 0.001 ms to 1 s,
/// cloth-sim's range; a value beyond it (cloth-sim's flags) is kept until moved.
fn damping_ms(ui: &mut egui::Ui, seconds: &mut f32, label: &str, hover: &str) {
    let mut ms = *seconds * 1e3;
    let r = ui
        .add(
            egui::Slider::new(&mut ms, 0.001..=1000.0)
                .clamping(egui::SliderClamping::Edits)
                .logarithmic(true)
                .text(label),
        )
        .on_hover_text(hover);
    if r.changed() {
        *seconds = ms * 1e-3;
    }
}
