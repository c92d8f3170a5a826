//! The material panel: the current design's material and substeps as cloth-sim reports
//! them (its telemetry), edited here and applied in place.

use shared::command::{Command, MaterialChange};
use shared::telemetry::SimTelemetry;

use crate::action::Action;

/// A material and substep count as the panel shows them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialChoice {
    /// density, stretch, shear, bending, friction, damping.
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

impl MaterialChoice {
    /// Every value as a change (on the wire a 0 keeps cloth-sim's value).
    pub fn change(&self) -> MaterialChange {
        let [density, stretch, shear, bending, friction, damping] = self.values.map(Some);
        MaterialChange {
            density,
            stretch,
            shear,
            bending,
            friction,
            damping,
        }
    }
}

/// The material and solver settings shown: cloth-sim's (from its telemetry) until the
/// user edits them; Apply sends them for the current design, New scene builds with them.
pub struct MaterialPanel {
    /// density, stretch, shear, bending, friction, damping, as shown.
    pub values: [f32; 6],
    pub substeps: u32,
    /// The material last read from cloth-sim's telemetry: a different one (a reset, a
    /// load, another UI's change) replaces what is shown.
    seen: Option<MaterialChoice>,
}

impl Default for MaterialPanel {
    /// cloth-sim's defaults until it tells otherwise.
    fn default() -> Self {
        let d = MaterialChoice::default();
        Self {
            values: d.values,
            substeps: d.substeps,
            seen: None,
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

    /// The material and substeps of the current design, applied in place.
    pub fn ui(&mut self, ui: &mut egui::Ui, tel: Option<&SimTelemetry>, actions: &mut Vec<Action>) {
        self.follow(tel);
        ui.label("Material and solver");
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
        let [density, stretch, shear, bending, friction, damping] = &mut self.values;
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
