//! The maps the 3D view and the pattern view colour the cloth by. First the stretch map:
//! how far the cloth is stretched from its pattern (what a designer reads to see where a
//! garment pulls). Worked out
//! here from what cloth-sim already sends: each triangle's corners where they are now
//! and where they lie in the pattern, which is the cloth as cut.
//!
//! A triangle's stretch is that of its more stretched thread, warp or weft, less one:
//! how much longer than cut it now is (0.1: 10% longer). The threads run along the
//! texture's u and v, as in the solver's material frame (`sim_core`'s membranes). Shear,
//! which a woven takes easily (a draped garment is sheared everywhere), does not show;
//! a thread pulled longer does, which is where a garment pulls. Each vertex shows the mean
//! of its triangles' (weighted by their area in the pattern), so the map reads as a
//! smooth field across seams; the worst triangle is reported as it is.
//!
//! The same view can colour the cloth by its ease instead: each vertex's distance from
//! the body (red on it, blue at a chosen distance or more), measured against the body
//! mesh cloth-sim sent, through `sim_core`'s OBB tree. Stretched and on the body is tight;
//! stretched and off it is hanging from somewhere.

use glam::{Vec2, Vec3};
use shared::sim_to_ui::MeshCorner;

/// The stretch shown red unless the designer chooses another: 20%, what the default
/// strain limit holds a woven under (cloth-sim's `--strain-limit` 0.2).
pub const DEFAULT_FULL_SCALE: f32 = 0.2;

/// The full scales a designer may choose, as a stretch (1% to 200%).
pub const FULL_SCALE_RANGE: (f32, f32) = (0.01, 2.0);

/// The map's colours from no stretch (and compression) to the full scale: blue, green,
/// yellow, red, in linear RGB (the view lights them, then encodes sRGB).
const RAMP: [[f32; 3]; 4] = [
    [0.10, 0.28, 0.85],
    [0.10, 0.65, 0.25],
    [0.90, 0.80, 0.10],
    [0.90, 0.08, 0.05],
];

/// The ease shown blue unless the designer chooses another: 3 cm from the body, m.
pub const DEFAULT_EASE_SCALE: f32 = 0.03;

/// The ease scales a designer may choose, m (2 mm to 30 cm).
pub const EASE_SCALE_RANGE: (f32, f32) = (0.002, 0.3);

/// Cloth within this of the body counts as on it, m: three times the default contact
/// thickness (1 mm), where the cloth rests.
pub const ON_THE_BODY: f32 = 0.003;

/// What the map colours the cloth by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// How far the threads are stretched from the pattern.
    Stretch,
    /// How far the cloth is from the body.
    Ease,
}

/// Whether the map is shown, what it shows, the stretch shown red and the ease shown
/// blue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchView {
    pub on: bool,
    pub kind: MapKind,
    pub full: f32,
    pub ease_full: f32,
    /// Whether the tape measure is shown (`fit`): its girths, and its rings in the view;
    /// and a level of the designer's own to measure at too, m above the floor.
    pub fit: bool,
    pub fit_at: Option<f32>,
}

impl Default for StretchView {
    fn default() -> Self {
        Self {
            on: false,
            kind: MapKind::Stretch,
            full: DEFAULT_FULL_SCALE,
            ease_full: DEFAULT_EASE_SCALE,
            fit: false,
            fit_at: None,
        }
    }
}

impl StretchView {
    /// The scale of the map shown: the stretch shown red, or the ease shown blue.
    pub fn scale(&self) -> f32 {
        match self.kind {
            MapKind::Stretch => self.full,
            MapKind::Ease => self.ease_full,
        }
    }
}

/// How many times its length as cut each thread of a triangle now is, warp then weft
/// (`sim_core::solver::thread_stretch`, which the scenario reports use too): corners at
/// `x`, cut at `p` (pattern places, m), with texture coordinates `uv`.
pub fn thread_stretch(x: [Vec3; 3], p: [Vec2; 3], uv: [Vec2; 3]) -> Option<[f32; 2]> {
    sim_core::solver::thread_stretch(x, p.map(|q| q.extend(0.0)), uv)
}

/// The colour of stretch `s` on a map whose red is `full`.
pub fn colour(s: f32, full: f32) -> [f32; 4] {
    let t = if full > 0.0 { s / full } else { 0.0 };
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        1.0
    };
    if t >= 1.0 {
        let [r, g, b] = RAMP[RAMP.len() - 1];
        return [r, g, b, 1.0];
    }
    let k = t * (RAMP.len() - 1) as f32;
    let i = (k.floor() as usize).min(RAMP.len() - 2);
    let f = k - i as f32;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    [
        a[0] + (b[0] - a[0]) * f,
        a[1] + (b[1] - a[1]) * f,
        a[2] + (b[2] - a[2]) * f,
        1.0,
    ]
}

/// The map of one frame of the cloth.
#[derive(Clone, Debug, PartialEq)]
pub struct StretchMap {
    pub kind: MapKind,
    /// Per vertex: the mean stretch of its triangles, by their area in the pattern; or
    /// its distance from the body (m, at most `full`).
    pub vertex: Vec<f32>,
    /// The most stretched triangle's stretch and its middle now (m); for the ease, the
    /// median vertex's distance.
    pub worst: f32,
    pub worst_at: Option<Vec3>,
    /// The share of the cloth (by its area as cut) stretched past `full`; for the ease,
    /// the share of its vertices on the body ([`ON_THE_BODY`]).
    pub over: f32,
    /// The stretch shown red, or the ease shown blue.
    pub full: f32,
    /// Which frame, mesh and body it is of (`Store::frame`, `Store::mesh_generation`,
    /// `Store::body_version`).
    pub of: (u64, u64, u64),
}

impl StretchMap {
    /// The map of the cloth at `x` over the mesh of `corners` (three a triangle) and
    /// `vertices`; None when the positions are another mesh's (a frame that has not
    /// caught up with an edit).
    pub fn of(corners: &[MeshCorner], vertices: usize, x: &[[f32; 3]], full: f32) -> Option<Self> {
        if x.len() != vertices {
            return None;
        }
        let mut sum = vec![0.0f32; x.len()];
        let mut weight = vec![0.0f32; x.len()];
        let (mut worst, mut worst_at) = (0.0f32, None);
        let (mut area, mut over) = (0.0f32, 0.0f32);
        for t in corners.chunks_exact(3) {
            let v = [t[0].vertex, t[1].vertex, t[2].vertex].map(|v| v as usize);
            if v.iter().any(|&i| i >= x.len()) {
                return None;
            }
            let pos = v.map(|i| Vec3::from(x[i]));
            let pat = [t[0].pattern, t[1].pattern, t[2].pattern].map(Vec2::from);
            let uv = [&t[0], &t[1], &t[2]].map(|c| Vec2::new(c.u, c.v));
            let Some([warp, weft]) = thread_stretch(pos, pat, uv) else {
                continue;
            };
            let s = warp.max(weft) - 1.0;
            let a = 0.5 * (pat[1] - pat[0]).perp_dot(pat[2] - pat[0]).abs();
            for &i in &v {
                sum[i] += a * s;
                weight[i] += a;
            }
            area += a;
            if s > full {
                over += a;
            }
            if worst_at.is_none() || s > worst {
                worst = s;
                worst_at = Some((pos[0] + pos[1] + pos[2]) / 3.0);
            }
        }
        let vertex = sum
            .iter()
            .zip(&weight)
            .map(|(&s, &w)| if w > 0.0 { s / w } else { 0.0 })
            .collect();
        Some(Self {
            kind: MapKind::Stretch,
            vertex,
            worst,
            worst_at,
            over: if area > 0.0 { over / area } else { 0.0 },
            full,
            of: (0, 0, 0),
        })
    }

    /// The ease map of the cloth at `x`: each vertex's distance from `body` (0 inside
    /// it), searched up to `full` and shown blue from there on.
    pub fn ease(body: &sim_core::collision::Body, x: &[[f32; 3]], full: f32) -> Self {
        let vertex: Vec<f32> = x
            .iter()
            .map(|&p| {
                let p = Vec3::from(p);
                // The body's clearance grid bounds the distance without a search: most of
                // a loose garment is known to be far enough at once.
                if body.outside_by(p).0 >= full {
                    return full;
                }
                match body.signed_distance(p, full) {
                    Some(d) => d.clamp(0.0, full),
                    // Farther than `full` from the surface: outside, or deep inside (cloth
                    // that crossed the body, which the guard does not let happen).
                    None if body.penetration(p) > 0.0 => 0.0,
                    None => full,
                }
            })
            .collect();
        let on = vertex.iter().filter(|&&d| d <= ON_THE_BODY).count();
        let mut sorted = vertex.clone();
        sorted.sort_by(f32::total_cmp);
        Self {
            kind: MapKind::Ease,
            worst: sorted.get(sorted.len() / 2).copied().unwrap_or(full),
            worst_at: None,
            over: if vertex.is_empty() {
                0.0
            } else {
                on as f32 / vertex.len() as f32
            },
            vertex,
            full,
            of: (0, 0, 0),
        }
    }

    /// The colour of vertex `v`.
    pub fn colour_of(&self, v: u32) -> [f32; 4] {
        let s = self.vertex.get(v as usize).copied().unwrap_or(0.0);
        match self.kind {
            MapKind::Stretch => colour(s, self.full),
            // Red on the body, blue at `full` from it.
            MapKind::Ease => colour(self.full - s, self.full),
        }
    }

    /// One line for the panel: the worst stretch and how much of the cloth is past red;
    /// or how much of it is on the body and how far off the median vertex is.
    pub fn summary(&self) -> String {
        match self.kind {
            MapKind::Stretch => format!(
                "Worst {:.0}% · {:.1}% of the cloth past {:.0}%",
                100.0 * self.worst,
                100.0 * self.over,
                100.0 * self.full
            ),
            MapKind::Ease => format!(
                "{:.0}% of the cloth on the body · half of it within {:.1} cm{}",
                100.0 * self.over,
                100.0 * self.worst,
                if self.worst >= self.full { "+" } else { "" }
            ),
        }
    }

    /// What the tooltip adds for vertex `v`.
    pub fn at_vertex(&self, v: u32) -> Option<String> {
        let s = *self.vertex.get(v as usize)?;
        Some(match self.kind {
            MapKind::Stretch if s >= 0.0 => format!(" · stretched {:.1}%", 100.0 * s),
            MapKind::Stretch => format!(" · {:.1}% shorter than cut", -100.0 * s),
            MapKind::Ease if s <= ON_THE_BODY => " · on the body".to_string(),
            MapKind::Ease if s >= self.full => {
                format!(" · {:.1} cm or more from the body", 100.0 * s)
            }
            MapKind::Ease => format!(" · {:.1} cm from the body", 100.0 * s),
        })
    }
}

/// The map laid on the pattern: every triangle at its pattern places (`at` puts a place
/// on the screen), its corners in their vertices' colours, for the pattern view to draw
/// under its lines: where a piece pulls, and so where it wants more cloth.
pub fn pattern_fill(
    corners: &[MeshCorner],
    map: &StretchMap,
    at: impl Fn([f32; 2]) -> egui::Pos2,
) -> egui::Shape {
    let mut m = egui::Mesh::default();
    for c in corners {
        let [r, g, b, _] = map.colour_of(c.vertex);
        let i = m.vertices.len() as u32;
        m.colored_vertex(at(c.pattern), egui::Rgba::from_rgb(r, g, b).into());
        m.indices.push(i);
    }
    egui::Shape::mesh(m)
}

/// The map's controls under the view's: the switch (M), what it shows, its scale, the
/// colour bar and the summary of `map`.
pub fn controls(ui: &mut egui::Ui, view: &mut StretchView, map: Option<&StretchMap>) {
    ui.horizontal(|ui| {
        ui.checkbox(&mut view.on, "Map (M)").on_hover_text(
            "Colour the cloth by how far its threads are stretched from the pattern, or by \
             how far it is from the body",
        );
        ui.selectable_value(&mut view.kind, MapKind::Stretch, "Stretch")
            .on_hover_text(
                "How far the threads (warp or weft, whichever more) are stretched from the \
                 pattern: blue as cut or eased, red at the stretch set beside. Where a \
                 garment pulls, it is red; shear, which cloth takes easily, does not show.",
            );
        ui.selectable_value(&mut view.kind, MapKind::Ease, "Ease")
            .on_hover_text(
                "How far the cloth is from the body: red on it, blue at the distance set beside \
             or more. Stretched and on the body is tight.",
            );
        scale(ui, view);
    });
    if !view.on {
        return;
    }
    colour_bar(ui, view.kind, view.scale());
    match map {
        Some(m) => {
            let label = ui.label(m.summary());
            if let Some(p) = m.worst_at {
                label.on_hover_text(format!(
                    "The most stretched triangle is at ({:.3}, {:.3}, {:.3}) m",
                    p.x, p.y, p.z
                ));
            }
        }
        None if view.kind == MapKind::Ease => {
            ui.label("No cloth or no body to measure against yet");
        }
        None => {
            ui.label("No cloth to map yet");
        }
    }
}

/// The map's scale: the stretch shown red (percent) or the ease shown blue (cm).
fn scale(ui: &mut egui::Ui, view: &mut StretchView) {
    // Percent in whole numbers, centimetres to a millimetre; both are hundredths.
    let k = 100.0;
    let (value, (lo, hi), suffix, decimals, speed, hint) = match view.kind {
        MapKind::Stretch => (
            &mut view.full,
            FULL_SCALE_RANGE,
            " %",
            0,
            0.5,
            "The stretch shown red (and anything past it)",
        ),
        MapKind::Ease => (
            &mut view.ease_full,
            EASE_SCALE_RANGE,
            " cm",
            1,
            0.05,
            "The distance from the body shown blue (and anything farther)",
        ),
    };
    let mut shown = k * *value;
    if ui
        .add(
            egui::DragValue::new(&mut shown)
                .range(k * lo..=k * hi)
                .speed(speed)
                .max_decimals(decimals)
                .suffix(suffix),
        )
        .on_hover_text(hint)
        .changed()
    {
        *value = (shown / k).clamp(lo, hi);
    }
}

/// The colour bar from 0 to `full`, with its ends and middle marked.
fn colour_bar(ui: &mut egui::Ui, kind: MapKind, full: f32) {
    let width = ui.available_width().clamp(120.0, 220.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 12.0), egui::Sense::hover());
    let steps = 32;
    let painter = ui.painter();
    for k in 0..steps {
        let t0 = k as f32 / steps as f32;
        let t1 = (k + 1) as f32 / steps as f32;
        let s = full * (t0 + t1) * 0.5;
        let [r, g, b, _] = match kind {
            MapKind::Stretch => colour(s, full),
            MapKind::Ease => colour(full - s, full),
        };
        let cell = egui::Rect::from_min_max(
            egui::pos2(rect.left() + t0 * rect.width(), rect.top()),
            egui::pos2(rect.left() + t1 * rect.width(), rect.bottom()),
        );
        painter.rect_filled(cell, 0.0, egui::Rgba::from_rgb(r, g, b));
    }
    let (start, mid, end) = match kind {
        MapKind::Stretch => (
            "0%".to_string(),
            format!("{:.0}%", 50.0 * full),
            format!("{:.0}%+", 100.0 * full),
        ),
        MapKind::Ease => (
            "on the body".to_string(),
            format!("{:.1} cm", 50.0 * full),
            format!("{:.1} cm+", 100.0 * full),
        ),
    };
    ui.horizontal(|ui| {
        ui.set_width(width);
        ui.small(start);
        ui.add_space((width * 0.5 - 60.0).max(0.0));
        ui.small(mid);
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.small(end);
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretched_triangle_is_measured_along_its_threads() {
        // 10% along the pattern's x (the warp: u along x), 3% along its y.
        let cut = [Vec2::ZERO, Vec2::new(0.1, 0.0), Vec2::new(0.0, 0.1)];
        let x = cut.map(|p| Vec3::new(1.1 * p.x, 1.03 * p.y, 0.2));
        let [warp, weft] = thread_stretch(x, cut, cut).unwrap();
        assert!((warp - 1.1).abs() < 1e-5 && (weft - 1.03).abs() < 1e-5);
        let flat = [Vec2::ZERO, Vec2::new(0.1, 0.0), Vec2::new(0.2, 0.0)];
        assert_eq!(thread_stretch(x, flat, cut), None);
    }

    #[test]
    fn the_colours_run_from_blue_to_red_and_stop_there() {
        let full = 0.2;
        assert_eq!(colour(0.0, full), [0.10, 0.28, 0.85, 1.0]);
        assert_eq!(colour(-0.3, full), colour(0.0, full));
        assert_eq!(colour(full, full), [0.90, 0.08, 0.05, 1.0]);
        assert_eq!(colour(5.0, full), colour(full, full));
        assert_eq!(colour(f32::NAN, full), colour(full, full));
        // Red rises and blue falls from one end to the other.
        let reds: Vec<[f32; 4]> = (0..=20).map(|k| colour(0.01 * k as f32, full)).collect();
        assert!(reds.windows(2).all(|w| w[1][0] >= w[0][0] - 1e-6));
        assert!(reds.windows(2).all(|w| w[1][2] <= w[0][2] + 1e-6));
    }

    /// A 1 m square of two triangles, the corner (1, 1) pulled out by `pull` m along x.
    fn square(pull: f32) -> (Vec<MeshCorner>, Vec<[f32; 3]>) {
        let corner = |vertex: u32, p: [f32; 2]| MeshCorner {
            vertex,
            u: p[0],
            v: p[1],
            pattern: p,
        };
        let corners = vec![
            corner(0, [0.0, 0.0]),
            corner(1, [1.0, 0.0]),
            corner(2, [0.0, 1.0]),
            corner(1, [1.0, 0.0]),
            corner(3, [1.0, 1.0]),
            corner(2, [0.0, 1.0]),
        ];
        let x = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0 + pull, 1.0, 0.0],
        ];
        (corners, x)
    }

    #[test]
    fn the_ease_map_measures_each_vertex_from_the_body() {
        // A 0.4 m cube round the origin (top at 0.2 m); vertices on it, above it, inside
        // it and far off.
        let body = sim_core::collision::body::cube(Vec3::ZERO, 0.2, 4).unwrap();
        let x = [
            [0.0, 0.2, 0.0],
            [0.05, 0.215, 0.0],
            [0.0, 0.1, 0.0],
            [0.0, 0.5, 0.0],
        ];
        let m = StretchMap::ease(&body, &x, 0.03);
        assert_eq!(m.kind, MapKind::Ease);
        assert!(
            m.vertex[0].abs() < 1e-5 && m.vertex[2] == 0.0,
            "{:?}",
            m.vertex
        );
        assert!((m.vertex[1] - 0.015).abs() < 1e-5 && m.vertex[3] == 0.03);
        // Two of four on the body; red there, blue at the scale or beyond.
        assert!((m.over - 0.5).abs() < 1e-6);
        assert_eq!(m.colour_of(0), colour(1.0, 1.0));
        assert_eq!(m.colour_of(3), colour(0.0, 1.0));
        assert_eq!(m.at_vertex(0).unwrap(), " · on the body");
        assert_eq!(m.at_vertex(1).unwrap(), " · 1.5 cm from the body");
        assert_eq!(m.at_vertex(3).unwrap(), " · 3.0 cm or more from the body");
        assert!(
            m.summary().starts_with("50% of the cloth on the body"),
            "{}",
            m.summary()
        );
    }

    #[test]
    fn the_map_finds_the_stretched_triangle_and_shares_it_out() {
        let (corners, x) = square(0.0);
        let m = StretchMap::of(&corners, 4, &x, 0.2).unwrap();
        assert!(m.worst.abs() < 1e-6 && m.over == 0.0);
        assert!(m.vertex.iter().all(|s| s.abs() < 1e-6));

        let (corners, x) = square(0.5);
        let m = StretchMap::of(&corners, 4, &x, 0.2).unwrap();
        // The warp of the pulled triangle (corners 1, 3, 2): its side from 2 to 3.
        assert!((m.worst - 0.5).abs() < 1e-6, "{}", m.worst);
        // The worst triangle is the one with the pulled corner: its middle.
        let at = m.worst_at.unwrap();
        assert!((at - Vec3::new(2.5 / 3.0, 2.0 / 3.0, 0.0)).length() < 1e-6);
        // Half the cloth is past red; vertex 0 is in the other triangle only.
        assert!((m.over - 0.5).abs() < 1e-6, "{}", m.over);
        assert!(m.vertex[0].abs() < 1e-6);
        assert!((m.vertex[3] - m.worst).abs() < 1e-6);
        assert!((m.vertex[1] - 0.5 * m.worst).abs() < 1e-6);
        assert_eq!(m.colour_of(3), colour(m.worst, 0.2));
        assert!(
            m.summary()
                .starts_with(&format!("Worst {:.0}%", 100.0 * m.worst))
        );
        // Positions of another mesh: no map.
        assert_eq!(StretchMap::of(&corners, 4, &x[..3], 0.2), None);
    }
}
