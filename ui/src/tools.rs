//! The tools the pen and the mouse work with: their labels, shortcuts and help.

use shared::sim_to_ui::tool;

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
        "Click the cloth to pin it in place there (a pink pin head shows each pin); shift-click a pin to free it",
    ),
];

pub fn tool_name(t: u32) -> &'static str {
    TOOLS.iter().find(|x| x.0 == t).map_or("unknown", |x| x.1)
}

/// The status line for a tool just chosen: its name and what the mouse does with it.
pub fn tool_sentence(t: u32) -> String {
    match TOOLS.iter().find(|x| x.0 == t) {
        Some((_, name, _, help)) => {
            let mut h = help.chars();
            let first = h
                .next()
                .map_or(String::new(), |c| c.to_lowercase().collect());
            format!("{name} tool: {first}{}", h.as_str())
        }
        None => "An unknown tool".into(),
    }
}
