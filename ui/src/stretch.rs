//! The stretch map: how far the cloth is stretched from its pattern, as the 3D view
//! colours it (the fit map a designer reads to see where a garment pulls). Worked out
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

/// Whether the map is shown, and what stretch is red.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StretchView {
    pub on: bool,
    pub full: f32,
}

impl Default for StretchView {
    fn default() -> Self {
        Self {
            on: false,
            full: DEFAULT_FULL_SCALE,
        }
    }
}

/// How many times its length as cut each thread of a triangle now is, warp then weft
/// (`sim_core::mesh::thread_stretch`, which the scenario reports use too): corners at
/// `x`, cut at `p` (pattern places, m), with texture coordinates `uv`.
pub fn thread_stretch(x: [Vec3; 3], p: [Vec2; 3], uv: [Vec2; 3]) -> Option<[f32; 2]> {
    sim_core::mesh::thread_stretch(x, p.map(|q| q.extend(0.0)), uv)
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
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StretchMap {
    /// Per vertex: the mean stretch of its triangles, by their area in the pattern.
    pub vertex: Vec<f32>,
    /// The most stretched triangle's stretch and its middle now (m).
    pub worst: f32,
    pub worst_at: Option<Vec3>,
    /// The share of the cloth (by its area as cut) stretched past `full`.
    pub over: f32,
    /// The stretch shown red.
    pub full: f32,
    /// Which frame and mesh it is of (`Store::frame`, `Store::mesh_generation`).
    pub of: (u64, u64),
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
            vertex,
            worst,
            worst_at,
            over: if area > 0.0 { over / area } else { 0.0 },
            full,
            of: (0, 0),
        })
    }

    /// The colour of vertex `v`.
    pub fn colour_of(&self, v: u32) -> [f32; 4] {
        colour(
            self.vertex.get(v as usize).copied().unwrap_or(0.0),
            self.full,
        )
    }

    /// One line for the panel: the worst stretch and how much of the cloth is past red.
    pub fn summary(&self) -> String {
        format!(
            "Worst {:.0}% · {:.1}% of the cloth past {:.0}%",
            100.0 * self.worst,
            100.0 * self.over,
            100.0 * self.full
        )
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

/// The map's controls under the view's: the switch (M), the stretch shown red, the colour
/// bar and the summary of `map`.
pub fn controls(ui: &mut egui::Ui, view: &mut StretchView, map: Option<&StretchMap>) {
    ui.horizontal(|ui| {
        ui.checkbox(&mut view.on, "Stretch map (M)").on_hover_text(
            "Colour the cloth by how far its threads (warp or weft, whichever more) are \
             stretched from the pattern: blue as cut or eased, red at the stretch set \
             beside. Where a garment pulls, it is red; shear, which cloth takes easily, \
             does not show.",
        );
        let mut percent = 100.0 * view.full;
        let (lo, hi) = FULL_SCALE_RANGE;
        if ui
            .add(
                egui::DragValue::new(&mut percent)
                    .range(100.0 * lo..=100.0 * hi)
                    .speed(0.5)
                    .max_decimals(0)
                    .suffix(" %"),
            )
            .on_hover_text("The stretch shown red (and anything past it)")
            .changed()
        {
            view.full = (percent / 100.0).clamp(lo, hi);
        }
    });
    if !view.on {
        return;
    }
    colour_bar(ui, view.full);
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
        None => {
            ui.label("No cloth to map yet");
        }
    }
}

/// The colour bar from 0 to `full`, with its ends and middle marked.
fn colour_bar(ui: &mut egui::Ui, full: f32) {
    let width = ui.available_width().clamp(120.0, 220.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 12.0), egui::Sense::hover());
    let steps = 32;
    let painter = ui.painter();
    for k in 0..steps {
        let t0 = k as f32 / steps as f32;
        let t1 = (k + 1) as f32 / steps as f32;
        let [r, g, b, _] = colour(full * (t0 + t1) * 0.5, full);
        let c = egui::Rgba::from_rgb(r, g, b);
        let cell = egui::Rect::from_min_max(
            egui::pos2(rect.left() + t0 * rect.width(), rect.top()),
            egui::pos2(rect.left() + t1 * rect.width(), rect.bottom()),
        );
        painter.rect_filled(cell, 0.0, c);
    }
    ui.horizontal(|ui| {
        ui.set_width(width);
        ui.small("0%");
        let mid = format!("{:.0}%", 50.0 * full);
        let end = format!("{:.0}%+", 100.0 * full);
        ui.add_space((width * 0.5 - 30.0).max(0.0));
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
