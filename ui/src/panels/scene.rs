//! The scene panel: body and grid of a new scene (with the material panel's values), and
//! the reset that builds it.

use std::time::{Duration, Instant};

use shared::command::{BodyChoice, Command};

use super::material::MaterialChoice;
use crate::action::Action;

/// What a reset builds: body and grid (the default is cloth-sim's cloth on the cube).
pub struct ScenePanel {
    pub body: BodyChoice,
    pub grid: u32,
    /// A reset waits for a second click within a few seconds.
    reset_armed: Option<Instant>,
}

impl Default for ScenePanel {
    fn default() -> Self {
        Self {
            body: BodyChoice::Cube,
            grid: 64,
            reset_armed: None,
        }
    }
}

impl ScenePanel {
    pub fn ui(&mut self, ui: &mut egui::Ui, material: MaterialChoice, actions: &mut Vec<Action>) {
        ui.label("Scene");
        ui.horizontal(|ui| {
            ui.label("Body");
            egui::ComboBox::from_id_salt("body")
                .selected_text(match self.body {
                    BodyChoice::Sphere => "sphere",
                    BodyChoice::Mannequin => "mannequin",
                    BodyChoice::Cube => "cube",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut self.body, BodyChoice::Cube, "cube");
                    ui.selectable_value(&mut self.body, BodyChoice::Sphere, "sphere");
                    ui.selectable_value(&mut self.body, BodyChoice::Mannequin, "mannequin");
                })
                .response
                .on_hover_text("What the next scene drapes over");
        });
        ui.add(egui::Slider::new(&mut self.grid, 8..=128).text("Grid"))
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
                actions.push(Action::Command(Command::Reset {
                    body: self.body,
                    grid: Some(self.grid).filter(|&g| g != 0),
                    material: material.change(),
                    substeps: Some(material.substeps).filter(|&n| n != 0),
                }));
            } else {
                self.reset_armed = Some(Instant::now());
                actions.push(Action::Status(
                    "New scene: click again to replace the design (it is saved first)".into(),
                ));
            }
        }
    }
}
