//! The pattern view's drawing: the pattern plane fitted into the window, every piece's
//! outline (cloth-sim's pattern lines, or the mesh's own), seams in their colours, the
//! stitches still pulling, grain lines and a scale. What a drag there does is the
//! pieces panel's.

use shared::sim_to_ui::{OutlineSegment, outline};

use crate::store::Store;
use crate::view3d::HIGHLIGHT;

/// The scale bar's lengths, m, longest first: the first no longer than 30% of the view.
const SCALE_BARS: [(f32, &str); 6] = [
    (0.1, "10 cm"),
    (0.05, "5 cm"),
    (0.02, "2 cm"),
    (0.01, "1 cm"),
    (0.005, "5 mm"),
    (0.002, "2 mm"),
];

/// Seam `i`'s colour (the 3D view's, [`crate::view3d::seam_colour`]).
pub(super) fn seam_colour(i: usize) -> egui::Color32 {
    colour(crate::view3d::seam_colour(i))
}

/// What a drawn seam side looks like.
pub(super) const SIDE: egui::Color32 = egui::Color32::from_rgb(90, 220, 120);
/// A cut line drawn in the pattern view.
pub(super) const CUT_LINE: egui::Color32 = egui::Color32::from_rgb(240, 90, 80);

/// The pattern plane fitted into a rectangle of the screen.
#[derive(Clone, Copy)]
pub(super) struct PatternFrame {
    rect: egui::Rect,
    centre: [f32; 2],
    /// Pixels per metre.
    pub(super) scale: f32,
}

/// Whether the pattern view draws cloth-sim's pattern lines (the export's outlines, notches
/// and grain lines): when it sent them all; otherwise the mesh's own outline.
fn pattern_lines(store: &Store) -> Option<&[OutlineSegment]> {
    let all = !store.outline.is_empty() && store.outline.len() == store.outline_total as usize;
    all.then_some(&store.outline[..])
}

impl PatternFrame {
    pub(super) fn of(mesh: &crate::store::Mesh, store: &Store, rect: egui::Rect) -> Option<Self> {
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

    /// The frame zoomed by `zoom` (1: fitted) about its middle moved by `pan`, m.
    pub(super) fn viewed(mut self, zoom: f32, pan: [f32; 2]) -> Self {
        self.scale *= zoom;
        self.centre = [self.centre[0] + pan[0], self.centre[1] + pan[1]];
        self
    }

    /// A pattern place on the screen (pattern y is up, the screen's down).
    pub(super) fn at(&self, p: [f32; 2]) -> egui::Pos2 {
        self.rect.center()
            + egui::vec2(
                (p[0] - self.centre[0]) * self.scale,
                -(p[1] - self.centre[1]) * self.scale,
            )
    }

    /// The pattern place under a screen point.
    pub(super) fn to_plane(self, q: egui::Pos2) -> [f32; 2] {
        let d = q - self.rect.center();
        [
            self.centre[0] + d.x / self.scale,
            self.centre[1] - d.y / self.scale,
        ]
    }

    /// The outlines, each seam in its colour with its label, the stitches still pulling,
    /// the pins and the scale bar.
    pub(super) fn draw(
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
        // 10 cm, or less where the view is zoomed in so far that 10 cm would run across
        // most of it.
        let (m, label) = SCALE_BARS
            .iter()
            .copied()
            .find(|(m, _)| m * self.scale <= 0.3 * self.rect.width())
            .unwrap_or(SCALE_BARS[SCALE_BARS.len() - 1]);
        painter.line_segment(
            [bar, bar + egui::vec2(m * self.scale, 0.0)],
            egui::Stroke::new(2.0, grey),
        );
        painter.text(
            bar + egui::vec2(0.0, -4.0),
            egui::Align2::LEFT_BOTTOM,
            label,
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
        let mut drills: Vec<egui::Pos2> = Vec::new();
        let mut presses: Vec<(egui::Pos2, egui::Pos2)> = Vec::new();
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
                    if g.kind == outline::DRILL {
                        drills.push(a);
                        continue;
                    }
                    if g.kind == outline::PRESS {
                        presses.push((a, b));
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
                self.names(painter, lines, store, selected);
            }
            None => {
                // (The mesh's pieces are not numbered as the list's: no names here.)
                for (a, b, piece) in &mesh.outline {
                    let bright = store.highlight == Some(*piece);
                    painter.line_segment([self.at(*a), self.at(*b)], line(bright));
                }
            }
        }
        self.seams(painter, store);
        marks(painter, &notches, &presses, &drills);
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
        // A pin at its vertex's first place, in the 3D view's pin colour.
        for v in &store.pins {
            if let Some(p) = place_of.get(v) {
                let at = self.at(*p);
                painter.circle(
                    at,
                    3.5,
                    colour(crate::view3d::PIN_COLOUR),
                    egui::Stroke::new(1.0, egui::Color32::WHITE),
                );
            }
        }
    }
}

impl PatternFrame {
    /// Each seam's sides in its colour, its label where each run of its edges starts.
    fn seams(&self, painter: &egui::Painter, store: &Store) {
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
                h.seam == next.seam && h.stretch == next.stretch && h.b == next.a
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
                    g.label(s.label()),
                    egui::FontId::proportional(12.0),
                    c,
                );
            }
        }
    }

    /// Each listed piece's name over the middle of its outline (the grain line's), so
    /// that pieces cut alike can be told apart.
    fn names(
        &self,
        painter: &egui::Painter,
        lines: &[OutlineSegment],
        store: &Store,
        selected: Option<usize>,
    ) {
        for (piece, middle) in name_places(lines) {
            let Some(p) = store.pieces.get(piece as usize) else {
                continue;
            };
            let c = if selected == Some(piece as usize) {
                colour(HIGHLIGHT)
            } else {
                egui::Color32::from_gray(170)
            };
            painter.text(
                self.at(middle) + egui::vec2(0.0, -8.0),
                egui::Align2::CENTER_BOTTOM,
                &p.name,
                egui::FontId::proportional(12.0),
                c,
            );
        }
    }
}

/// Where each piece's name goes: the middle of the box round its outline (its sewing or
/// cut line), in the order the pieces first appear.
pub(super) fn name_places(lines: &[OutlineSegment]) -> Vec<(u32, [f32; 2])> {
    let mut boxes: Vec<(u32, [f32; 2], [f32; 2])> = Vec::new();
    for g in lines.iter().filter(|g| g.kind == outline::SEWING_LINE) {
        let k = match boxes.iter().position(|b| b.0 == g.piece) {
            Some(k) => k,
            None => {
                boxes.push((g.piece, [f32::MAX; 2], [f32::MIN; 2]));
                boxes.len() - 1
            }
        };
        for p in [g.a, g.b] {
            for d in 0..2 {
                boxes[k].1[d] = boxes[k].1[d].min(p[d]);
                boxes[k].2[d] = boxes[k].2[d].max(p[d]);
            }
        }
    }
    (boxes.into_iter())
        .map(|(piece, lo, hi)| (piece, [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]))
        .collect()
}

/// How far (pixels) a seam side's end snaps to a corner of the outlines.
pub(super) const SNAP_PX: f32 = 14.0;

/// The corners of the sewing and cut lines cloth-sim sent, each with how far the line
/// turns there (radians): where a run of joined segments (as the view draws it) turns
/// by more than 30 degrees, and where a run ends without closing (a seam's or a cut's
/// end on a line, pi). A curve meshed at the usual edges (a neckline of 6 cm radius at
/// 3 cm) turns less than that a segment.
pub(super) fn corners(lines: &[OutlineSegment]) -> Vec<Corner> {
    let sewing: Vec<&OutlineSegment> = (lines.iter())
        .filter(|g| g.kind == outline::SEWING_LINE && g.a != g.b)
        .collect();
    let mut out = Vec::new();
    let mut run: Vec<[f32; 2]> = Vec::new();
    for (k, g) in sewing.iter().enumerate() {
        if run.is_empty() {
            run.push(g.a);
        }
        run.push(g.b);
        let joined = (sewing.get(k + 1))
            .is_some_and(|n| n.a == g.b && n.piece == g.piece && n.kind == g.kind);
        if !joined {
            run_corners(&std::mem::take(&mut run), &mut out);
        }
    }
    out
}

/// A corner of the pattern's lines: where, and how far the line turns there (radians).
pub(super) type Corner = ([f32; 2], f32);

/// A run's corners (see [`corners`]).
fn run_corners(run: &[[f32; 2]], out: &mut Vec<Corner>) {
    let closed = run.len() > 3 && run.first() == run.last();
    let points = if closed { &run[..run.len() - 1] } else { run };
    let n = points.len();
    for i in 0..n {
        let turn = if !closed && (i == 0 || i + 1 == n) {
            std::f32::consts::PI
        } else {
            let p = glam::Vec2::from(points[i]);
            let before = p - glam::Vec2::from(points[(i + n - 1) % n]);
            let after = glam::Vec2::from(points[(i + 1) % n]) - p;
            before.angle_to(after).abs()
        };
        if turn > 30f32.to_radians() {
            out.push((points[i], turn));
        }
    }
}

/// The corners a seam side's ends snap to: those of cloth-sim's pattern lines, none
/// while the view draws the mesh's own outline (a design over the lines' limit).
pub(super) fn snap_corners(store: &Store) -> Vec<Corner> {
    pattern_lines(store).map(corners).unwrap_or_default()
}

/// The corner `p` snaps to: of those within `radius` (pattern units), where the line
/// turns most, the nearest of those alike (within 10 degrees). Where a cut meets a
/// border it can bend a few millimetres before it (a 30-degree kink 5 mm in, seen in
/// the studio), and the border's own corner is the end a designer means.
pub(super) fn snap(p: [f32; 2], corners: &[Corner], radius: f32) -> Option<[f32; 2]> {
    let d2 = |c: &[f32; 2]| (c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2);
    let near: Vec<&Corner> = (corners.iter())
        .filter(|c| d2(&c.0) <= radius * radius)
        .collect();
    let most = near.iter().map(|c| c.1).fold(0.0, f32::max);
    (near.into_iter())
        .filter(|c| c.1 >= most - 10f32.to_radians())
        .min_by(|x, y| d2(&x.0).total_cmp(&d2(&y.0)))
        .map(|c| c.0)
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

/// The marks drawn over the seams: balance notches (white, at least 7 pixels long), each
/// dart's press (an arrow across its mouth toward the leg its intake lies on) and drill
/// holes as the export marks them (a circle and a cross, a few pixels across).
fn marks(
    painter: &egui::Painter,
    notches: &[(egui::Pos2, egui::Pos2)],
    presses: &[(egui::Pos2, egui::Pos2)],
    drills: &[egui::Pos2],
) {
    for &(a, b) in notches {
        let d = (b - a).normalized() * (b - a).length().max(7.0);
        painter.line_segment([a, a + d], egui::Stroke::new(1.5, egui::Color32::WHITE));
    }
    for &(a, b) in presses {
        press_arrow(painter, a, b);
    }
    let pen = egui::Stroke::new(1.0, egui::Color32::WHITE);
    for &q in drills {
        painter.circle_stroke(q, 3.5, pen);
        painter.line_segment([q - egui::vec2(5.0, 0.0), q + egui::vec2(5.0, 0.0)], pen);
        painter.line_segment([q - egui::vec2(0.0, 5.0), q + egui::vec2(0.0, 5.0)], pen);
    }
}

/// A dart's press mark from `a` toward `b`, at least 10 pixels long, its head at `b`.
fn press_arrow(painter: &egui::Painter, a: egui::Pos2, b: egui::Pos2) {
    let stroke = egui::Stroke::new(1.5, egui::Color32::from_rgb(250, 220, 120));
    let b = a + (b - a).normalized() * (b - a).length().max(10.0);
    painter.line_segment([a, b], stroke);
    let d = (b - a).normalized() * 6.0;
    let side = egui::vec2(-d.y, d.x) * 0.6;
    painter.line_segment([b, b - d + side], stroke);
    painter.line_segment([b, b - d - side], stroke);
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

    /// A seam side's ends snap to a square's corners (its sides in several segments), to
    /// an open line's ends, never to a round outline's points, a notch or a grain line;
    /// within the radius the sharpest corner (the nearest of those alike), none beyond it.
    #[test]
    fn a_seam_sides_end_snaps_to_the_sharpest_corner_near_it() {
        let seg = |piece, kind, a: [f32; 2], b: [f32; 2]| OutlineSegment { piece, kind, a, b };
        let mut lines = Vec::new();
        // A 0.4 m square, each side in three segments, closed.
        let sq = [[0.0, 0.0], [0.4, 0.0], [0.4, 0.4], [0.0, 0.4]];
        for i in 0..4 {
            let (a, b) = (glam::Vec2::from(sq[i]), glam::Vec2::from(sq[(i + 1) % 4]));
            for k in 0..3 {
                let at = |t: f32| a.lerp(b, t).to_array();
                let (t0, t1) = (k as f32 / 3.0, (k + 1) as f32 / 3.0);
                let end = if k == 2 { sq[(i + 1) % 4] } else { at(t1) };
                let start = if k == 0 { sq[i] } else { at(t0) };
                lines.push(seg(0, outline::SEWING_LINE, start, end));
            }
        }
        // A 0.1 m circle in 16 segments (22.5 degrees a turn), closed.
        let ring = |k: usize| {
            let t = k as f32 * std::f32::consts::TAU / 16.0;
            [1.0 + 0.1 * t.cos(), 0.1 * t.sin()]
        };
        for k in 0..16 {
            lines.push(seg(1, outline::SEWING_LINE, ring(k), ring((k + 1) % 16)));
        }
        // An open line of two segments, a notch and a grain line.
        lines.push(seg(2, outline::SEWING_LINE, [2.0, 0.0], [2.1, 0.0]));
        lines.push(seg(2, outline::SEWING_LINE, [2.1, 0.0], [2.2, 0.01]));
        lines.push(seg(2, outline::NOTCH, [2.1, 0.0], [2.1, 0.05]));
        lines.push(seg(2, outline::GRAIN, [2.0, 0.2], [2.2, 0.2]));
        lines.push(seg(2, outline::DRILL, [2.15, 0.03], [2.15, 0.03]));
        let found = corners(&lines);
        let mut at: Vec<[f32; 2]> = found.iter().map(|c| c.0).collect();
        at.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
        let want = [
            [0.0, 0.0],
            [0.0, 0.4],
            [0.4, 0.0],
            [0.4, 0.4],
            [2.0, 0.0],
            [2.2, 0.01],
        ];
        assert_eq!(at, want);
        // The square's corners turn 90 degrees; the open line's ends count as turning back.
        let turn = |p: [f32; 2]| found.iter().find(|c| c.0 == p).unwrap().1;
        assert!((turn([0.4, 0.4]) - std::f32::consts::FRAC_PI_2).abs() < 1e-4);
        assert_eq!(turn([2.0, 0.0]), std::f32::consts::PI);
        assert_eq!(snap([0.39, 0.01], &found, 0.02), Some([0.4, 0.0]));
        assert_eq!(snap([0.37, 0.0], &found, 0.02), None);
        assert_eq!(snap([0.2, 0.0], &found, 0.02), None, "mid-side");
        assert_eq!(snap([1.1, 0.0], &found, 0.05), None, "on the circle");
        // The nearer of two alike within reach.
        let close = [([0.0, 0.0], 1.5), ([0.01, 0.0], 1.6)];
        assert_eq!(snap([0.008, 0.0], &close, 0.02), Some([0.01, 0.0]));
        // A cut's kink 5 mm before the border (30 degrees) nearer the pointer than the
        // border's corner (a right angle): the corner.
        let kink = [([0.0, 0.0], 1.57), ([0.005, 0.003], 0.6)];
        assert_eq!(snap([0.012, 0.0], &kink, 0.02), Some([0.0, 0.0]));
        assert_eq!(snap([0.03, 0.0], &kink, 0.026), Some([0.005, 0.003]));
    }

    /// A piece's name goes in the middle of its outline, whatever its grain line and
    /// notches and drill holes; each piece gets one place.
    #[test]
    fn each_pieces_name_goes_in_the_middle_of_its_outline() {
        let square = |piece: u32, x0: f32| {
            let c = [[x0, 0.0], [x0 + 0.4, 0.0], [x0 + 0.4, 0.5], [x0, 0.5]];
            (0..4).map(move |i| OutlineSegment {
                piece,
                kind: outline::SEWING_LINE,
                a: c[i],
                b: c[(i + 1) % 4],
            })
        };
        let mut lines: Vec<OutlineSegment> = square(0, 0.0).chain(square(1, 0.6)).collect();
        // A grain line, a notch and a drill hole outside the outline do not move the name.
        for (kind, a, b) in [
            (outline::GRAIN, [-1.0, 0.25], [1.0, 0.25]),
            (outline::NOTCH, [0.6, 0.5], [0.6, 0.9]),
            (outline::DRILL, [1.5, -0.5], [1.5, -0.5]),
        ] {
            lines.push(OutlineSegment {
                piece: 1,
                kind,
                a,
                b,
            });
        }
        let places = name_places(&lines);
        assert_eq!(places.len(), 2, "{places:?}");
        for ((piece, at), want) in places.iter().zip([(0, [0.2, 0.25]), (1, [0.8, 0.25])]) {
            assert_eq!(*piece, want.0);
            assert!(
                (at[0] - want.1[0]).abs() < 1e-6 && (at[1] - want.1[1]).abs() < 1e-6,
                "{at:?}"
            );
        }
    }
}
