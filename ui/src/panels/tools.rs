//! The tool panel: the tools, the paint colour and brush, tearing, undo and redo, the
//! design file and the export folder.

use shared::command::{Command, Tearing};
use shared::sim_to_ui::tool;

use crate::action::{Action, PathOp};
use crate::tools::TOOLS;

/// The settings of the tool panel.
pub struct ToolsPanel {
    pub colour: egui::Color32,
    pub brush_m: f32,
    pub tear_on: bool,
    pub tear_threshold: f32,
    pub save_path: String,
    pub export_dir: String,
    /// The seam allowance Export gives the sewing pattern, mm.
    pub allowance_mm: f32,
}

impl Default for ToolsPanel {
    fn default() -> Self {
        Self {
            colour: egui::Color32::from_rgb(200, 30, 40),
            brush_m: 0.02,
            tear_on: false,
            tear_threshold: 1.6,
            save_path: "design.saiho".into(),
            export_dir: "out/export".into(),
            allowance_mm: shared::command::DEFAULT_ALLOWANCE_MM,
        }
    }
}

impl ToolsPanel {
    /// The paint colour as RGBA bytes.
    pub fn rgba(&self) -> [u8; 4] {
        self.colour.to_array()
    }

    /// Draws the panel. `current` is the tool in use, `depths` the undo and redo depth,
    /// `pins` the design's pins, `linked` whether the UI is connected (without a link the
    /// buttons stay enabled).
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        current: u32,
        (depths, paused, pins): ((u32, u32), bool, u32),
        linked: bool,
        actions: &mut Vec<Action>,
    ) {
        ui.heading("Tools");
        for (t, name, key, help) in TOOLS {
            let label = format!("{name}  ({key:?})");
            if ui
                .selectable_label(current == t, label)
                .on_hover_text(help)
                .clicked()
            {
                actions.push(Action::SetTool(t));
            }
        }
        ui.separator();
        self.paint_section(ui, current, actions);
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
            actions.push(Action::Command(Command::SetTearing(if self.tear_on {
                Tearing::On {
                    threshold: self.tear_threshold,
                    split: false,
                }
            } else {
                Tearing::Off
            })));
        }
        ui.separator();
        Self::pins_section(ui, pins, linked, actions);
        ui.separator();
        ui.horizontal(|ui| {
            let (u, r) = depths;
            if ui
                .add_enabled(u > 0 || !linked, egui::Button::new("Undo"))
                .on_hover_text(format!(
                    "Undo your last operation (Ctrl+Z), with the welds of its seam; {u} can be undone"
                ))
                .clicked()
            {
                actions.push(Action::Command(Command::Undo));
            }
            if ui
                .add_enabled(r > 0 || !linked, egui::Button::new("Redo"))
                .on_hover_text(format!("Redo (Ctrl+Y); {r} can be redone"))
                .clicked()
            {
                actions.push(Action::Command(Command::Redo));
            }
            let (label, hint) = if paused {
                (
                    "Simulate",
                    "Run the simulation again (Space); seams made while paused pull their \
                     pieces together before they fall",
                )
            } else {
                (
                    "Pause",
                    "Pause the simulation (Space): the cloth stays where it is while you add, \
                     place, cut and sew pieces",
                )
            };
            if ui
                .add(egui::Button::new(label).selected(paused))
                .on_hover_text(hint)
                .clicked()
            {
                actions.push(Action::ToggleSimulating);
            }
        });
        ui.separator();
        self.design_section(ui, actions);
    }

    /// How many pins hold the cloth, and a button that frees them all (one undo).
    fn pins_section(ui: &mut egui::Ui, pins: u32, linked: bool, actions: &mut Vec<Action>) {
        ui.horizontal(|ui| {
            let label = match pins {
                0 => "No pins".to_string(),
                1 => "1 pin holds the cloth".to_string(),
                n => format!("{n} pins hold the cloth"),
            };
            ui.label(label).on_hover_text(
                "Pins (the Pin tool, N) hold a point of the cloth where it is; the views \
                 draw each as a pink pin head",
            );
            if ui
                .add_enabled(pins > 0 || !linked, egui::Button::new("Free pins"))
                .on_hover_text("Free every pin at once (one undo brings them back)")
                .clicked()
            {
                actions.push(Action::Command(Command::FreePins));
            }
        });
    }

    /// The paint colour and brush; a change is sent at once while painting.
    fn paint_section(&mut self, ui: &mut egui::Ui, current: u32, actions: &mut Vec<Action>) {
        ui.label("Paint");
        ui.horizontal(|ui| {
            ui.label("Colour");
            if ui
                .color_edit_button_srgba(&mut self.colour)
                .on_hover_text("The paint tool's colour")
                .changed()
                && current == tool::PAINT
            {
                actions.push(Action::SetTool(tool::PAINT));
            }
        });
        let mut cm = self.brush_m * 100.0;
        if ui
            .add(egui::Slider::new(&mut cm, 0.2..=10.0).text("Brush radius, cm"))
            .on_hover_text("How far from the pointer the paint reaches")
            .changed()
        {
            self.brush_m = cm / 100.0;
            if current == tool::PAINT {
                actions.push(Action::SetTool(tool::PAINT));
            }
        }
    }

    /// The design file (save, load) and the export folder.
    fn design_section(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
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
                actions.push(Action::Path(PathOp::Save, self.save_path.clone()));
            }
            if ui
                .button("Load")
                .on_hover_text("Load this design file in place of the current design (which cloth-sim saves first)")
                .clicked()
            {
                actions.push(Action::Path(PathOp::Load, self.save_path.clone()));
            }
        });
        ui.horizontal(|ui| {
            ui.label("Folder");
            ui.text_edit_singleline(&mut self.export_dir).on_hover_text(
                "Where Export writes OBJ+MTL+PNG, GLB, the sewing pattern (SVG, DXF) and the design",
            );
        });
        ui.horizontal(|ui| {
            ui.label("Seam allowance");
            ui.add(
                egui::DragValue::new(&mut self.allowance_mm)
                    .range(0.0..=100.0)
                    .speed(0.5)
                    .suffix(" mm"),
            )
            .on_hover_text(
                "The pattern's cut line, this far outside its sewing line (0: cut on it)",
            );
        });
        if ui
            .button("Export")
            .on_hover_text("Export the cloth, the body and the sewing pattern")
            .clicked()
        {
            actions.push(Action::Path(PathOp::Export, self.export_dir.clone()));
        }
    }

    /// The camera reset and the mouse's help.
    pub fn view_section(ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        ui.label("View");
        ui.horizontal(|ui| {
            if ui
                .button("Frame")
                .on_hover_text("Fit the body and the cloth in the view (F)")
                .clicked()
            {
                actions.push(Action::FrameScene);
            }
            if ui
                .button("Reset view")
                .on_hover_text("Back to the default camera (Home)")
                .clicked()
            {
                actions.push(Action::ResetCamera);
            }
        });
        ui.small("Left: tool · Right drag: orbit · Shift+right or middle drag: pan · Wheel: zoom");
    }
}
