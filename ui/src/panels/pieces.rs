//! The pieces panel: the design's pieces as cloth-sim lists them (name, vertices,
//! fabric), one selected (tinted in the 3D view and drawn bright in the pattern view);
//! new pieces (a rectangle, an ellipse, or every piece of an SVG, DXF or GarmentCode
//! file) at a place round the body; the selected piece placed elsewhere, deleted or
//! given a fabric of its own; and the pattern view: every piece flat as it is now, with
//! the stitches still pulling.

use shared::command::{Command, PieceShape};
use shared::ui_to_sim::{DART_WIDTH, PIECE_DROP, PIECE_EDGE, PIECE_SIZE, place, shape};

use super::pattern::{CUT_LINE, PatternFrame, SIDE, SNAP_PX, snap, snap_corners};
use super::seams::name_row;
use crate::action::Action;
use crate::store::Store;

/// What the panel holds between frames: the selection and the new piece's settings.
pub struct PiecesPanel {
    pub selected: Option<usize>,
    pub shape: u32,
    /// A new rectangle's or ellipse's size, m.
    pub size: [f32; 2],
    pub path: String,
    pub place: u32,
    /// How far below the place's start a piece's top goes, m.
    pub drop: f32,
    /// The new piece's mesh edge, m.
    pub edge: f32,
    pub pattern_open: bool,
    /// Seam sides drawn in the pattern view so far (pattern plane, m), and the drag
    /// under way.
    pub seam_sides: Vec<[[f32; 2]; 2]>,
    drag_from: Option<[f32; 2]>,
    /// Whether a drag in the pattern view makes a dart (from its point out across the
    /// edge) instead of a seam's side, and the dart's width at the edge, m.
    pub darting: bool,
    pub dart_width: f32,
    /// The pattern view's zoom (1: every piece fitted in) and how far its middle is
    /// moved from the fitted one, m.
    pub pattern_zoom: f32,
    pub pattern_pan: [f32; 2],
    /// What a piece can be made of: the design's own material, then the library's
    /// fabrics (name, what the chooser's hover says).
    fabrics: Vec<(String, String)>,
    /// The seam being named and the name typed so far.
    pub naming: Option<(usize, String)>,
    /// The piece being named and the name typed so far.
    pub piece_naming: Option<(usize, String)>,
    /// Whether Copy to turns the copy over (a mirror image).
    pub mirror: bool,
    /// The selected piece's name as last listed: when the list changes under the
    /// selection (a part given its own fabric moves to the end as a piece of its own),
    /// the selection follows the name.
    selected_name: Option<String>,
}

/// What the new piece's size row says: how big a piece must be to go round the body.
const SIZE_HELP: &str = "The new piece's width and height, metres. The mannequin is about 1.0 m \
     round at the chest and hips: a front and a back 0.6 m wide close round it with room to \
     spare (0.4 m ones cannot, and their side seams stop closing). 0.6 m high reaches from the \
     shoulders to the hips.";

/// What the place's drop says.
const DROP_HELP: &str = "How far below the place's usual start the piece's top goes, metres: \
     0 starts a piece with its top just above the shoulders (a sleeve at the shoulder). On \
     the mannequin the waist is about 0.42 m lower, the hips 0.55 m: a skirt starts there \
     (from 0.25 m lower the xpbd model runs 20 substeps, or the skirt slides off the hips). \
     For an arm, it is down the arm. Add piece, Place at and Copy to use it.";

/// What the Copy to button says.
const COPY_HELP: &str = "Add a copy of the selected piece as it is now (its cuts and tears \
     included, its fabric and grain) at the place chosen below, turned over if ticked, meshed \
     with the Edge below. Its seams, paint and pins are not copied; undo takes it away.";

/// The fabric chooser's entries.
fn fabric_entries() -> Vec<(String, String)> {
    let own = sim_core::design::garment::DEFAULT_FABRIC;
    let mut out = vec![(
        own.to_string(),
        "The design's own material (the Material panel's)".to_string(),
    )];
    for f in &sim_core::fabric::Library::builtin().fabrics {
        out.push((f.name.clone(), super::material::fabric_about(f)));
    }
    out
}

impl Default for PiecesPanel {
    fn default() -> Self {
        Self {
            selected: None,
            shape: shape::RECTANGLE,
            size: [0.6, 0.6],
            path: String::new(),
            place: place::FRONT,
            drop: 0.0,
            edge: 0.03,
            pattern_open: false,
            seam_sides: Vec::new(),
            drag_from: None,
            darting: false,
            dart_width: 0.04,
            pattern_zoom: 1.0,
            pattern_pan: [0.0; 2],
            fabrics: fabric_entries(),
            naming: None,
            piece_naming: None,
            mirror: false,
            selected_name: None,
        }
    }
}

fn place_combo(ui: &mut egui::Ui, id: &str, value: &mut u32) {
    egui::ComboBox::from_id_salt(id)
        .selected_text(place::NAMES[(*value as usize).min(place::NAMES.len() - 1)])
        .show_ui(ui, |ui| {
            for (code, name) in place::NAMES.iter().enumerate() {
                ui.selectable_value(value, code as u32, *name);
            }
        })
        .response
        .on_hover_text("Where round the body the piece starts (a layer out if another is there)");
}

/// The selected piece's fabric: the design's own material or one of the library's
/// (`fabrics`); a name picked is sent for that piece alone (undoable).
fn fabric_combo(
    ui: &mut egui::Ui,
    piece: u32,
    current: &str,
    fabrics: &[(String, String)],
    actions: &mut Vec<Action>,
) {
    egui::ComboBox::from_label("Piece fabric")
        .selected_text(current)
        .show_ui(ui, |ui| {
            for (name, about) in fabrics {
                if ui
                    .selectable_label(current == name, name)
                    .on_hover_text(about)
                    .clicked()
                {
                    actions.push(Action::Command(Command::SetPieceFabric {
                        piece,
                        name: name.clone(),
                    }));
                }
            }
        })
        .response
        .on_hover_text(
            "What the selected piece is made of: its weight, stretch, shear and bending. \
             The other pieces keep theirs; damping, friction and the contact thickness are \
             the design's. Undo takes it back.",
        );
}

impl PiecesPanel {
    /// The selected piece's name being typed, and sent on OK or Enter.
    fn piece_name_row(&mut self, ui: &mut egui::Ui, selected: usize, actions: &mut Vec<Action>) {
        let Some((i, name)) = self.piece_naming.as_mut().filter(|(i, _)| *i == selected) else {
            self.piece_naming = None;
            return;
        };
        let piece = *i as u32;
        match name_row(
            ui,
            "Piece",
            name,
            "The piece's name, as the pattern will call it",
        ) {
            Some(true) => {
                // An empty name is sent too: cloth-sim's refusal says why.
                actions.push(Action::Command(Command::NamePiece {
                    piece,
                    name: name.trim().to_string(),
                }));
                self.piece_naming = None;
            }
            Some(false) => self.piece_naming = None,
            None => {}
        }
    }

    /// The selection kept on the piece it was, by name, when the list changed under it
    /// (renamed in place, it stays where it is); none once the list is shorter.
    fn follow_selection(&mut self, store: &Store) {
        let name_at = |i: usize| store.pieces.get(i).map(|p| p.name.clone());
        if let (Some(i), Some(was)) = (self.selected, &self.selected_name)
            && name_at(i).as_ref() != Some(was)
            && let Some(j) = store.pieces.iter().position(|p| &p.name == was)
        {
            self.selected = Some(j);
        }
        if self.selected.is_some_and(|i| i >= store.pieces.len()) {
            self.selected = None;
        }
        self.selected_name = self.selected.and_then(name_at);
    }

    pub fn ui(&mut self, ui: &mut egui::Ui, store: &Store, actions: &mut Vec<Action>) {
        ui.label("Pieces");
        self.follow_selection(store);
        if store.pieces.is_empty() {
            ui.label("No pieces heard from cloth-sim yet");
        }
        for (i, p) in store.pieces.iter().enumerate() {
            let text = format!("{} · {} vertices · {}", p.name, p.vertices, p.fabric);
            if ui
                .selectable_label(self.selected == Some(i), text)
                .on_hover_text("Select: the piece is tinted in the view")
                .clicked()
            {
                self.selected = if self.selected == Some(i) {
                    None
                } else {
                    Some(i)
                };
            }
        }
        if store.pieces_total as usize > store.pieces.len() {
            ui.label(format!(
                "… and {} more",
                store.pieces_total as usize - store.pieces.len()
            ));
        }
        if let Some(i) = self.selected {
            ui.horizontal(|ui| {
                if ui
                    .button("Place at")
                    .on_hover_text("Move the selected piece to the place chosen below")
                    .clicked()
                {
                    actions.push(Action::Command(Command::PlacePiece {
                        piece: i as u32,
                        place: self.place,
                        drop_m: self.drop,
                    }));
                }
                if ui
                    .button("Delete")
                    .on_hover_text("Delete the selected piece (undo brings it back)")
                    .clicked()
                {
                    actions.push(Action::Command(Command::DeletePiece { piece: i as u32 }));
                    self.selected = None;
                }
                if ui.button("Copy to").on_hover_text(COPY_HELP).clicked() {
                    actions.push(Action::Command(Command::DuplicatePiece {
                        piece: i as u32,
                        place: self.place,
                        drop_m: self.drop,
                        mirrored: self.mirror,
                        edge_m: self.edge,
                    }));
                }
                if ui
                    .button("Name")
                    .on_hover_text(
                        "Give the selected piece a name of your own: the pattern view and \
                         the pattern out call it so (undo takes it back)",
                    )
                    .clicked()
                {
                    let now = store.pieces.get(i).map(|p| p.name.clone());
                    self.piece_naming = Some((i, now.unwrap_or_default()));
                }
            });
            ui.checkbox(&mut self.mirror, "Turned over")
                .on_hover_text("Copy to makes a mirror image: a left front from a right one");
            self.piece_name_row(ui, i, actions);
            if let Some(p) = store.pieces.get(i) {
                fabric_combo(ui, i as u32, &p.fabric, &self.fabrics, actions);
            }
        }
        ui.horizontal(|ui| {
            ui.label("Place");
            place_combo(ui, "piece-place", &mut self.place);
            ui.add(
                egui::DragValue::new(&mut self.drop)
                    .range(0.0..=PIECE_DROP)
                    .speed(0.01)
                    .prefix("lower ")
                    .suffix(" m"),
            )
            .on_hover_text(DROP_HELP);
        });
        super::seams::seams_section(ui, store, &mut self.naming, actions);
        self.add_section(ui, actions);
        ui.checkbox(&mut self.pattern_open, "Pattern view")
            .on_hover_text("The pieces flat, as they are now, with the stitches still pulling");
    }

    /// The new piece's shape, size or file, edge length, and the Add button.
    fn add_section(&mut self, ui: &mut egui::Ui, actions: &mut Vec<Action>) {
        ui.horizontal(|ui| {
            for (code, name) in [
                (shape::RECTANGLE, "Rectangle"),
                (shape::ELLIPSE, "Ellipse"),
                (shape::FILE, "From file"),
            ] {
                ui.selectable_value(&mut self.shape, code, name);
            }
        });
        if self.shape == shape::FILE {
            ui.add(
                egui::TextEdit::singleline(&mut self.path)
                    .hint_text("pattern.svg, .dxf or GarmentCode .json"),
            )
            .on_hover_text(
                "Every piece of the file is added, its seams stitched, round the cloth already \
                 there (a garment's pieces land on it). To start a garment on its own, give the \
                 file to the scene panel's Pattern file and press New scene",
            );
        } else {
            ui.horizontal(|ui| {
                for (k, label) in ["W", "H"].iter().enumerate() {
                    ui.label(*label);
                    ui.add(
                        egui::DragValue::new(&mut self.size[k])
                            .range(PIECE_SIZE.0..=PIECE_SIZE.1)
                            .speed(0.01)
                            .suffix(" m"),
                    )
                    .on_hover_text(SIZE_HELP);
                }
            });
        }
        ui.add(
            egui::Slider::new(&mut self.edge, PIECE_EDGE.0..=0.1)
                .text("Edge")
                .suffix(" m"),
        )
        .on_hover_text("The new piece's triangle side: shorter is finer and slower");
        if ui
            .button("Add piece")
            .on_hover_text("Add the piece at the chosen place")
            .clicked()
        {
            let [w, h] = self.size;
            let shape = match self.shape {
                shape::ELLIPSE => PieceShape::Ellipse { w, h },
                shape::FILE => {
                    if self.path.trim().is_empty() {
                        actions.push(Action::Status(
                            "Add piece: type a pattern file's path first".into(),
                        ));
                        return;
                    }
                    // cloth-sim resolves a relative path in its own directory: send ours.
                    let path = std::path::absolute(self.path.trim()).map_or_else(
                        |_| self.path.trim().to_string(),
                        |p| p.display().to_string(),
                    );
                    PieceShape::File { path }
                }
                _ => PieceShape::Rectangle { w, h },
            };
            actions.push(Action::Command(Command::AddPiece {
                shape,
                place: self.place,
                drop_m: self.drop,
                edge_m: self.edge,
            }));
        }
    }

    /// The pattern view's window, when open.
    /// With `cutting` (the Cut tool), a drag is a cut along its line instead of a seam's
    /// side.
    pub fn pattern_window(
        &mut self,
        ctx: &egui::Context,
        store: &Store,
        cutting: bool,
        actions: &mut Vec<Action>,
    ) {
        let mut open = self.pattern_open;
        if cutting || self.darting {
            self.seam_sides.clear();
        }
        egui::Window::new("Pattern")
            .open(&mut open)
            .default_size([420.0, 440.0])
            .show(ctx, |ui| {
                if cutting {
                    ui.label("Cut tool: drag a line across a piece to cut it along the line")
                        .on_hover_text(
                            "From beside a piece to beside it cuts it in two; choose another \
                             tool to make seams here",
                        );
                } else if self.darting {
                    ui.label("Dart: drag from the dart's point out across the piece's edge")
                        .on_hover_text(
                            "The wedge between is cut away and its two legs seamed, as one \
                             step to undo; the dart closes as the cloth is simulated. Its \
                             width is at the edge. The same drag on the cloth in the 3D view \
                             (any tool but Cut) takes it in where the drag runs",
                        );
                } else {
                    ui.label("Drag along a border, then along another: a seam joins them")
                        .on_hover_text(
                            "Each side from its start to its end; an end within a few pixels \
                             of a corner (or a cut's end) goes to it, unless Alt is held; \
                             right-click forgets a first side; with the Cut tool a drag cuts \
                             instead",
                        );
                }
                if !cutting {
                    self.dart_row(ui);
                }
                self.zoom_row(ui);
                self.pattern_view(ui, store, cutting, actions);
            });
        self.pattern_open = open;
    }

    /// Whether a drag makes a dart, and its width.
    fn dart_row(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.darting, "Dart").on_hover_text(
                "A drag from a point on a piece out across its edge takes in a dart there, \
                 here or on the cloth in the 3D view (off: drags make seams here, and the \
                 tool acts in 3D)",
            );
            let mut mm = self.dart_width * 1e3;
            let range = DART_WIDTH.0 * 1e3..=DART_WIDTH.1 * 1e3;
            ui.add_enabled(
                self.darting,
                egui::DragValue::new(&mut mm).range(range).suffix(" mm"),
            )
            .on_hover_text("The dart's width at the piece's edge");
            self.dart_width = mm * 1e-3;
        });
    }

    /// The pattern view's zoom, and Fit to see every piece again.
    fn zoom_row(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let fitted = self.pattern_zoom == 1.0 && self.pattern_pan == [0.0; 2];
            if ui
                .add_enabled(!fitted, egui::Button::new("Fit").small())
                .on_hover_text("Every piece in view again")
                .clicked()
            {
                (self.pattern_zoom, self.pattern_pan) = (1.0, [0.0; 2]);
            }
            ui.label(format!(
                "{:.0}% · wheel zooms, middle or shift+right drag pans",
                100.0 * self.pattern_zoom
            ));
        });
    }

    /// The wheel zooms the pattern view about the mouse (from half the fitted size to
    /// [`MAX_ZOOM`] times it), the place under the mouse staying there; a middle or
    /// shift+right drag pans it, as in the 3D view.
    fn navigate(&mut self, ui: &egui::Ui, response: &egui::Response, fitted: PatternFrame) {
        let (shift, wheel) = ui.input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y));
        if let Some(p) = response.hover_pos().filter(|_| wheel != 0.0) {
            let at = fitted
                .viewed(self.pattern_zoom, self.pattern_pan)
                .to_plane(p);
            self.pattern_zoom = (self.pattern_zoom * (wheel / 350.0).exp()).clamp(0.5, MAX_ZOOM);
            let now = fitted
                .viewed(self.pattern_zoom, self.pattern_pan)
                .to_plane(p);
            self.pattern_pan[0] += at[0] - now[0];
            self.pattern_pan[1] += at[1] - now[1];
        }
        if response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Secondary) && shift)
        {
            let (d, s) = (response.drag_delta(), fitted.scale * self.pattern_zoom);
            self.pattern_pan[0] -= d.x / s;
            self.pattern_pan[1] += d.y / s;
        }
    }

    /// Every piece's outline in the design's pattern plane, the highlighted piece bright, a
    /// line for each stitch still pulling between the places it joins, and a 10 cm scale;
    /// two drags make a seam between the borders they follow.
    fn pattern_view(
        &mut self,
        ui: &mut egui::Ui,
        store: &Store,
        cutting: bool,
        actions: &mut Vec<Action>,
    ) {
        let Some(mesh) = &store.mesh else {
            ui.label("No cloth heard from cloth-sim yet");
            return;
        };
        let size = ui.available_size().max(egui::vec2(200.0, 200.0));
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click_and_drag());
        let Some(fitted) = PatternFrame::of(mesh, store, rect) else {
            return;
        };
        self.navigate(ui, &response, fitted);
        let frame = fitted.viewed(self.pattern_zoom, self.pattern_pan);
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, egui::Color32::from_gray(24));
        frame.draw(&painter, mesh, store, self.selected);
        // Two drags, each a side from its start to its end.
        // A drag starts once the pointer has moved; the side starts where it was pressed.
        // A side's end near a corner (a seam's, a cut's end) goes to the corner, unless
        // Alt is held; a cut goes where it is drawn.
        let darting = self.darting && !cutting;
        let snapping = !cutting && !darting && !ui.input(|i| i.modifiers.alt);
        let primary = egui::PointerButton::Primary;
        let started = response.drag_started_by(primary);
        let corners = if snapping && (self.drag_from.is_some() || started) {
            snap_corners(store)
        } else {
            Vec::new()
        };
        let snapped = |p: [f32; 2]| {
            let at = snap(p, &corners, SNAP_PX / frame.scale);
            if let Some(c) = at {
                painter.circle_stroke(frame.at(c), 5.0, egui::Stroke::new(1.5, SIDE));
            }
            at.unwrap_or(p)
        };
        if started && let Some(p) = ui.input(|i| i.pointer.press_origin()) {
            self.drag_from = Some(snapped(frame.to_plane(p)));
        }
        if let (Some(a), Some(p)) = (self.drag_from, response.interact_pointer_pos()) {
            let b = snapped(frame.to_plane(p));
            let a = snapped(a);
            let colour = if cutting || darting { CUT_LINE } else { SIDE };
            painter.line_segment([frame.at(a), frame.at(b)], egui::Stroke::new(2.0, colour));
            if response.drag_stopped_by(primary) {
                self.drag_from = None;
                if cutting {
                    actions.push(Action::Command(Command::CutPlane { from: a, to: b }));
                } else if darting {
                    actions.push(Action::Command(Command::DartPlane {
                        point: a,
                        toward: b,
                        width_m: self.dart_width,
                    }));
                } else {
                    self.seam_sides.push([a, b]);
                }
            }
        }
        if response.secondary_clicked() {
            self.seam_sides.clear();
        }
        for s in &self.seam_sides {
            painter.line_segment(
                [frame.at(s[0]), frame.at(s[1])],
                egui::Stroke::new(2.0, SIDE),
            );
        }
        if let [a, b] = self.seam_sides[..] {
            self.seam_sides.clear();
            actions.push(Action::Command(Command::SeamPlane {
                a,
                b,
                // Eight pixels either side of the line, in metres.
                tolerance_m: (8.0 / frame.scale).clamp(0.002, 0.05),
            }));
        }
    }
}

/// How far the pattern view zooms in: a 1 m pattern fitted into 400 pixels shows a
/// millimetre as 13 pixels.
const MAX_ZOOM: f32 = 32.0;
