//! The pieces panel: the design's pieces as cloth-sim lists them (name, vertices,
//! fabric), one selected (tinted in the 3D view and drawn bright in the pattern view);
//! new pieces (a rectangle, an ellipse, or every piece of an SVG, DXF or GarmentCode
//! file) at a place round the body; the selected piece placed elsewhere, deleted or
//! given a fabric of its own; and the pattern view: every piece flat as it is now, with
//! the stitches still pulling.

use shared::command::{Command, PieceShape};
use shared::sim_to_ui::{OutlineSegment, outline};
use shared::ui_to_sim::{PIECE_EDGE, PIECE_SIZE, place, shape};

use crate::action::Action;
use crate::store::Store;
use crate::view3d::HIGHLIGHT;

/// What the panel holds between frames: the selection and the new piece's settings.
pub struct PiecesPanel {
    pub selected: Option<usize>,
    pub shape: u32,
    /// A new rectangle's or ellipse's size, m.
    pub size: [f32; 2],
    pub path: String,
    pub place: u32,
    /// The new piece's mesh edge, m.
    pub edge: f32,
    pub pattern_open: bool,
    /// Seam sides drawn in the pattern view so far (pattern plane, m), and the drag
    /// under way.
    pub seam_sides: Vec<[[f32; 2]; 2]>,
    drag_from: Option<[f32; 2]>,
    /// What a piece can be made of: the design's own material, then the library's
    /// fabrics (name, what the chooser's hover says).
    fabrics: Vec<(String, String)>,
    /// The seam being named and the name typed so far.
    pub naming: Option<(usize, String)>,
}

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
            size: [0.4, 0.5],
            path: String::new(),
            place: place::FRONT,
            edge: 0.03,
            pattern_open: false,
            seam_sides: Vec::new(),
            drag_from: None,
            fabrics: fabric_entries(),
            naming: None,
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
    pub fn ui(&mut self, ui: &mut egui::Ui, store: &Store, actions: &mut Vec<Action>) {
        ui.label("Pieces");
        if self.selected.is_some_and(|i| i >= store.pieces.len()) {
            self.selected = None;
        }
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
            });
            if let Some(p) = store.pieces.get(i) {
                fabric_combo(ui, i as u32, &p.fabric, &self.fabrics, actions);
            }
        }
        ui.horizontal(|ui| {
            ui.label("Place");
            place_combo(ui, "piece-place", &mut self.place);
        });
        seams_section(ui, store, &mut self.naming, actions);
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
                    );
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
                edge_m: self.edge,
            }));
        }
    }

    /// The pattern view's window, when open.
    pub fn pattern_window(
        &mut self,
        ctx: &egui::Context,
        store: &Store,
        actions: &mut Vec<Action>,
    ) {
        let mut open = self.pattern_open;
        egui::Window::new("Pattern")
            .open(&mut open)
            .default_size([420.0, 440.0])
            .show(ctx, |ui| {
                ui.label("Drag along a border, then along another: a seam joins them")
                    .on_hover_text(
                        "Each side from its start to its end; right-click forgets a first side",
                    );
                self.pattern_view(ui, store, actions);
            });
        self.pattern_open = open;
    }

    /// Every piece's outline in the design's pattern plane, the highlighted piece bright, a
    /// line for each stitch still pulling between the places it joins, and a 10 cm scale;
    /// two drags make a seam between the borders they follow.
    fn pattern_view(&mut self, ui: &mut egui::Ui, store: &Store, actions: &mut Vec<Action>) {
        let Some(mesh) = &store.mesh else {
            ui.label("No cloth heard from cloth-sim yet");
            return;
        };
        let size = ui.available_size().max(egui::vec2(200.0, 200.0));
        let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click_and_drag());
        let Some(frame) = PatternFrame::of(mesh, store, rect) else {
            return;
        };
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, egui::Color32::from_gray(24));
        frame.draw(&painter, mesh, store, self.selected);
        // Two drags, each a side from its start to its end.
        // A drag starts once the pointer has moved; the side starts where it was pressed.
        if response.drag_started()
            && let Some(p) = ui.input(|i| i.pointer.press_origin())
        {
            self.drag_from = Some(frame.to_plane(p));
        }
        if let (Some(a), Some(p)) = (self.drag_from, response.interact_pointer_pos()) {
            let b = frame.to_plane(p);
            painter.line_segment([frame.at(a), frame.at(b)], egui::Stroke::new(2.0, SIDE));
            if response.drag_stopped() {
                self.drag_from = None;
                self.seam_sides.push([a, b]);
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

/// The seams: label, pairs (still pulling), the sides' lengths with a warning when they
/// differ by more than a fifth, and a Remove button each.
/// The seam list: each seam's colour, label and name, pairs, both sides' lengths (a
/// warning colour past a fifth apart), Name and Remove; and the name being typed.
fn seams_section(
    ui: &mut egui::Ui,
    store: &Store,
    naming: &mut Option<(usize, String)>,
    actions: &mut Vec<Action>,
) {
    if store.seams.is_empty() {
        *naming = None;
        return;
    }
    ui.label("Seams");
    for (i, s) in store.seams.iter().enumerate() {
        ui.horizontal(|ui| {
            seam_row(ui, i, s);
            if ui
                .small_button("Name")
                .on_hover_text("Give this seam a name of your own (the pattern keeps its letter)")
                .clicked()
            {
                *naming = Some((i, s.name().to_string()));
            }
            if ui
                .small_button("Remove")
                .on_hover_text("Remove this seam (undo brings it back)")
                .clicked()
            {
                actions.push(Action::Command(Command::RemoveSeam { seam: i as u32 }));
            }
        });
    }
    if store.seams_total as usize > store.seams.len() {
        ui.label(format!(
            "… and {} more",
            store.seams_total as usize - store.seams.len()
        ));
    }
    let Some((i, name)) = naming.as_mut().filter(|(i, _)| *i < store.seams.len()) else {
        *naming = None;
        return;
    };
    let seam = *i as u32;
    let mut done = false;
    ui.horizontal(|ui| {
        ui.label(format!("Seam {}", store.seams[*i].label()));
        ui.add(egui::TextEdit::singleline(name).desired_width(120.0))
            .on_hover_text("Empty: the seam goes by its letter again");
        if ui.button("OK").clicked() {
            actions.push(Action::Command(Command::NameSeam {
                seam,
                name: name.trim().to_string(),
            }));
            done = true;
        }
        if ui.button("Cancel").clicked() {
            done = true;
        }
    });
    if done {
        *naming = None;
    }
}

/// One seam's swatch and text.
fn seam_row(ui: &mut egui::Ui, i: usize, s: &shared::sim_to_ui::SeamEntry) {
    let [a, b] = s.lengths;
    let long = a.max(b);
    let warn = long > 0.0 && (a - b).abs() > 0.2 * long;
    // The seam's colour, as the views draw it.
    let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
    ui.painter().rect_filled(swatch, 2.0, seam_colour(i));
    let named = match s.name() {
        "" => String::new(),
        n => format!(" ({n})"),
    };
    let text = format!(
        "{}{named} · {} pairs, {} pulling · {:.0} / {:.0} mm",
        s.label(),
        s.pairs,
        s.open,
        1000.0 * a,
        1000.0 * b
    );
    let label = if warn {
        ui.colored_label(WARN, text)
            .on_hover_text("Its sides differ by more than a fifth: the longer will gather")
    } else {
        ui.label(text)
    };
    label.on_hover_text("Pairs already sewn stay sewn when the seam is removed");
    if s.stalled > 0 {
        let [lo, hi] = s.stalled_gap.map(|g| 1000.0 * g);
        let apart = match s.stalled {
            1 => format!("{hi:.0} mm"),
            _ => format!("{lo:.0}-{hi:.0} mm"),
        };
        ui.colored_label(
            WARN,
            format!("{} stopped closing, {apart} apart", s.stalled),
        )
        .on_hover_text(
            "These pairs have come no nearer for three seconds: the body or the cloth \
                 holds them apart. Their stitches still pull; a cut, a pin moved, or a \
                 pinch that carries the cloth over may let them close",
        );
    }
}

/// What a seam row that needs the designer's eye is written in.
const WARN: egui::Color32 = egui::Color32::from_rgb(240, 170, 60);

/// Seam `i`'s colour (the 3D view's, [`crate::view3d::seam_colour`]).
pub fn seam_colour(i: usize) -> egui::Color32 {
    colour(crate::view3d::seam_colour(i))
}

/// What a drawn seam side looks like.
const SIDE: egui::Color32 = egui::Color32::from_rgb(90, 220, 120);

/// The pattern plane fitted into a rectangle of the screen.
struct PatternFrame {
    rect: egui::Rect,
    centre: [f32; 2],
    /// Pixels per metre.
    scale: f32,
}

/// Whether the pattern view draws cloth-sim's pattern lines (the export's outlines, notches
/// and grain lines): when it sent them all; otherwise the mesh's own outline.
fn pattern_lines(store: &Store) -> Option<&[OutlineSegment]> {
    let all = !store.outline.is_empty() && store.outline.len() == store.outline_total as usize;
    all.then_some(&store.outline[..])
}

impl PatternFrame {
    fn of(mesh: &crate::store::Mesh, store: &Store, rect: egui::Rect) -> Option<Self> {
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        let ends: Vec<[f32; 2]> = match pattern_lines(store) {
            Some(lines) => lines.iter().flat_map(|g| [g.a, g.b]).collect(),
            None => mesh.outline.iter().flat_map(|(a, b, _)| [*a, *b]).collect(),
        };
        for p in ends {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            return None;
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-6);
        Some(Self {
            rect,
            centre: [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])],
            scale: 0.92 * rect.width().min(rect.height()) / span,
        })
    }

    /// A pattern place on the screen (pattern y is up, the screen's down).
    fn at(&self, p: [f32; 2]) -> egui::Pos2 {
        self.rect.center()
            + egui::vec2(
                (p[0] - self.centre[0]) * self.scale,
                -(p[1] - self.centre[1]) * self.scale,
            )
    }

    /// The pattern place under a screen point.
    fn to_plane(&self, q: egui::Pos2) -> [f32; 2] {
        let d = q - self.rect.center();
        [
            self.centre[0] + d.x / self.scale,
            self.centre[1] - d.y / self.scale,
        ]
    }

    /// The outlines, each seam in its colour with its label, the stitches still pulling
    /// and the scale bar.
    fn draw(
        &self,
        painter: &egui::Painter,
        mesh: &crate::store::Mesh,
        store: &Store,
        selected: Option<usize>,
    ) {
        if let Some(map) = &store.stretch {
            painter.add(crate::stretch::pattern_fill(&mesh.corners, map, |p| {
                self.at(p)
            }));
        }
        let bar = egui::pos2(self.rect.left() + 8.0, self.rect.bottom() - 10.0);
        let grey = egui::Color32::from_gray(140);
        painter.line_segment(
            [bar, bar + egui::vec2(0.1 * self.scale, 0.0)],
            egui::Stroke::new(2.0, grey),
        );
        painter.text(
            bar + egui::vec2(0.0, -4.0),
            egui::Align2::LEFT_BOTTOM,
            "10 cm",
            egui::FontId::proportional(11.0),
            grey,
        );
        let line = |bright: bool| {
            if bright {
                egui::Stroke::new(2.0, colour(HIGHLIGHT))
            } else {
                egui::Stroke::new(1.0, egui::Color32::from_gray(190))
            }
        };
        let mut notches: Vec<(egui::Pos2, egui::Pos2)> = Vec::new();
        match pattern_lines(store) {
            Some(lines) => {
                // Each run of joined segments as one path: drawn segment by segment, the
                // joins of a line at a fraction of a pixel look dashed.
                let mut run: Vec<egui::Pos2> = Vec::new();
                for (k, g) in lines.iter().enumerate() {
                    let bright = selected.is_some_and(|i| i as u32 == g.piece);
                    let (a, b) = (self.at(g.a), self.at(g.b));
                    if g.kind == outline::GRAIN {
                        grain_arrow(painter, a, b, bright);
                        continue;
                    }
                    if g.kind == outline::NOTCH {
                        // Drawn over the seams below, at least 7 pixels long.
                        notches.push((a, b));
                        continue;
                    }
                    if run.is_empty() {
                        run.push(a);
                    }
                    run.push(b);
                    let next = lines.get(k + 1);
                    let joined =
                        next.is_some_and(|n| n.a == g.b && n.piece == g.piece && n.kind == g.kind);
                    if !joined {
                        painter.add(egui::Shape::line(std::mem::take(&mut run), line(bright)));
                    }
                }
            }
            None => {
                for (a, b, piece) in &mesh.outline {
                    let bright = store.highlight == Some(*piece);
                    painter.line_segment([self.at(*a), self.at(*b)], line(bright));
                }
            }
        }
        // Each seam's sides in its colour, its label where each run of its edges starts.
        let segments = &store.seam_segments;
        let mut run: Vec<egui::Pos2> = Vec::new();
        for (k, g) in segments.iter().enumerate() {
            let (a, b) = (self.at(g.a), self.at(g.b));
            let c = seam_colour(g.seam as usize);
            if run.is_empty() {
                run.push(a);
            }
            run.push(b);
            let joined = |h: &shared::sim_to_ui::SeamSegment,
                          next: &shared::sim_to_ui::SeamSegment| {
                h.seam == next.seam && h.b == next.a
            };
            if !segments.get(k + 1).is_some_and(|n| joined(g, n)) {
                painter.add(egui::Shape::line(
                    std::mem::take(&mut run),
                    egui::Stroke::new(3.0, c),
                ));
            }
            // A run's label where it starts; a run a loop's start cut in two (the same
            // seam's segment ends where it starts) is labelled once.
            let starts_run =
                (k == 0 || !joined(&segments[k - 1], g)) && !segments.iter().any(|h| joined(h, g));
            if starts_run && let Some(s) = store.seams.get(g.seam as usize) {
                painter.text(
                    a + egui::vec2(4.0, -4.0),
                    egui::Align2::LEFT_BOTTOM,
                    s.label(),
                    egui::FontId::proportional(12.0),
                    c,
                );
            }
        }
        for (a, b) in notches {
            let d = (b - a).normalized() * (b - a).length().max(7.0);
            painter.line_segment([a, a + d], egui::Stroke::new(1.5, egui::Color32::WHITE));
        }
        // A stitch joins two vertices; each is drawn at its first place in the pattern.
        let mut place_of: std::collections::HashMap<u32, [f32; 2]> = Default::default();
        for c in &mesh.corners {
            place_of.entry(c.vertex).or_insert(c.pattern);
        }
        for [a, b, seam] in &store.stitches {
            if let (Some(pa), Some(pb)) = (place_of.get(a), place_of.get(b)) {
                let stitch =
                    egui::Stroke::new(1.0, seam_colour(*seam as usize).gamma_multiply(0.6));
                painter.line_segment([self.at(*pa), self.at(*pb)], stitch);
            }
        }
    }
}

/// A grain line: a thin line with an arrowhead at each end (the warp runs along it).
fn grain_arrow(painter: &egui::Painter, a: egui::Pos2, b: egui::Pos2, bright: bool) {
    let c = if bright {
        colour(HIGHLIGHT).gamma_multiply(0.7)
    } else {
        egui::Color32::from_gray(110)
    };
    let stroke = egui::Stroke::new(1.0, c);
    painter.line_segment([a, b], stroke);
    let d = (b - a).normalized() * 6.0;
    let side = egui::vec2(-d.y, d.x) * 0.5;
    for (tip, back) in [(a, d), (b, -d)] {
        painter.line_segment([tip, tip + back + side], stroke);
        painter.line_segment([tip, tip + back - side], stroke);
    }
}

fn colour(c: [f32; 4]) -> egui::Color32 {
    let b = |v: f32| (v.clamp(0.0, 1.0) * 255.0) as u8;
    egui::Color32::from_rgb(b(c[0]), b(c[1]), b(c[2]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The view fits and draws cloth-sim's pattern lines when it has them all, and the
    /// mesh's own outline when it has none or only some of them.
    #[test]
    fn the_pattern_view_draws_cloth_sims_lines_and_falls_back_to_the_mesh() {
        let (mesh, _) = Store::demo_cloth(4, 1.0);
        let mut store = Store::default();
        let rect = egui::Rect::from_min_size(egui::pos2(0.0, 0.0), egui::vec2(400.0, 400.0));
        let mesh_centre = PatternFrame::of(&mesh, &store, rect).unwrap().centre;
        // A square 1 m across round (5.5, 5.5), far from the demo cloth's pattern.
        let corners = [[5.0, 5.0], [6.0, 5.0], [6.0, 6.0], [5.0, 6.0]];
        store.outline = (0..4)
            .map(|i| OutlineSegment {
                piece: 0,
                kind: outline::SEWING_LINE,
                a: corners[i],
                b: corners[(i + 1) % 4],
            })
            .collect();
        store.outline_total = 4;
        let frame = PatternFrame::of(&mesh, &store, rect).unwrap();
        assert_eq!(frame.centre, [5.5, 5.5]);
        assert!((frame.scale - 0.92 * 400.0).abs() < 1e-3, "{}", frame.scale);
        // Cut short (more lines than sent): the mesh's outline.
        store.outline_total = 5;
        assert_eq!(
            PatternFrame::of(&mesh, &store, rect).unwrap().centre,
            mesh_centre
        );
        assert_ne!(mesh_centre, [5.5, 5.5]);
    }
}
