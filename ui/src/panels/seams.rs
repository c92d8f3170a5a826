//! The Pieces panel's seam list: each seam's colour, label and name, its pairs, its
//! sides' lengths and the pairs that stopped closing, with Name and Remove, and for a
//! dart which way it is pressed.

use shared::command::Command;
use shared::sim_to_ui::dart;

use super::pattern::seam_colour;
use crate::action::Action;
use crate::store::Store;

/// The seam list: each seam's colour, label and name with Name and Remove, then its
/// pairs and both sides' lengths (a warning colour past a fifth apart) and the pairs
/// that stopped closing, each on a line of its own so that the panel keeps its width;
/// and the name being typed.
pub(super) fn seams_section(
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
            // The seam's colour, as the views draw it.
            let (swatch, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
            ui.painter().rect_filled(swatch, 2.0, seam_colour(i));
            let named = match s.name() {
                "" => String::new(),
                n => format!(" ({n})"),
            };
            ui.label(format!("{}{named}", s.label()));
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
            if s.dart != dart::NONE
                && ui
                    .small_button("Press other way")
                    .on_hover_text(
                        "This seam closes a dart: press its intake toward the other leg. \
                         The arrow in the pattern view shows the way; the exported cut \
                         line's dart cap follows (undo takes it back)",
                    )
                    .clicked()
            {
                actions.push(Action::Command(Command::PressDart {
                    seam: i as u32,
                    second: s.dart == dart::FIRST,
                }));
            }
        });
        ui.indent(("seam", i), |ui| seam_lines(ui, s));
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
    let title = format!("Seam {}", store.seams[*i].label());
    match name_row(ui, &title, name, "Empty: the seam goes by its letter again") {
        Some(true) => {
            actions.push(Action::Command(Command::NameSeam {
                seam,
                name: name.trim().to_string(),
            }));
            *naming = None;
        }
        Some(false) => *naming = None,
        None => {}
    }
}

/// A name being typed for `title`: the field, OK (or Enter) and Cancel. `Some(true)`
/// once it is to be sent, `Some(false)` once cancelled.
pub(super) fn name_row(
    ui: &mut egui::Ui,
    title: &str,
    name: &mut String,
    hint: &str,
) -> Option<bool> {
    let mut out = None;
    ui.horizontal(|ui| {
        ui.label(title);
        let field = ui
            .add(egui::TextEdit::singleline(name).desired_width(120.0))
            .on_hover_text(hint);
        if ui.button("OK").clicked()
            || (field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)))
        {
            out = Some(true);
        }
        if ui.button("Cancel").clicked() {
            out = Some(false);
        }
    });
    out
}

/// One seam's pairs and sides' lengths, and the pairs that stopped closing.
fn seam_lines(ui: &mut egui::Ui, s: &shared::sim_to_ui::SeamEntry) {
    let [a, b] = s.lengths;
    let long = a.max(b);
    let warn = long > 0.0 && (a - b).abs() > 0.2 * long;
    let text = format!(
        "{} pairs, {} pulling · {:.0} / {:.0} mm",
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
    label.on_hover_text("Remove unpicks it: its sewn pairs come apart (undo sews them again)");
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
                 holds them apart (pieces too small to close round the body stop so). \
                 Their stitches still pull; a cut, a pin moved, or a pinch that carries \
                 the cloth over may let them close",
        );
    }
}

/// What a seam row that needs the designer's eye is written in.
const WARN: egui::Color32 = egui::Color32::from_rgb(240, 170, 60);
