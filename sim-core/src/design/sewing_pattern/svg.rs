//! The pattern as SVG, one unit a millimetre: a group per piece with its cut line, its
//! sewing line (dashed, when there is an allowance), its seams marked and labelled, its
//! balance notches, its grain line with arrow heads, its name and its fabric.

use std::fmt::Write as _;

use glam::DVec2;

use super::Piece;

/// A polyline's path data ("M x,y L x,y ..."), y flipped on a page `h` high.
fn line_d(points: &[DVec2], h: f64) -> String {
    let mut d = String::new();
    for (i, p) in points.iter().enumerate() {
        let _ = write!(
            d,
            "{}{:.3},{:.3} ",
            if i == 0 { "M" } else { "L" },
            p.x,
            h - p.y
        );
    }
    d.trim_end().to_string()
}

/// Closed loops' path data, each its polyline and "Z".
fn path_d(loops: &[Vec<DVec2>], h: f64) -> String {
    let loops: Vec<String> = loops.iter().map(|l| line_d(l, h) + " Z").collect();
    loops.join(" ")
}

/// Escapes text for XML.
fn xml(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The SVG document's start for laid-out pieces, and the height its y is flipped
/// about: the pieces' extent and a 10 mm margin all round (the layout's lowest and
/// leftmost points, a dart cap's, the first piece's side, lay on the page's edge with
/// their lines cut in half until 2026-12-05).
fn page(pieces: &[Piece]) -> (String, f64) {
    let (mut w, mut h) = (0.0f64, 0.0f64);
    for q in pieces.iter().flat_map(|p| p.cut.iter().flatten()) {
        w = w.max(q.x);
        h = h.max(q.y);
    }
    let h = h + 10.0;
    let (page_w, page_h) = (w + 20.0, h + 10.0);
    let head = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{page_w:.1}mm\" height=\"{page_h:.1}mm\" \
         viewBox=\"-10 0 {page_w:.3} {page_h:.3}\">\n\
         <title>Saiho sewing pattern (1 unit = 1 mm)</title>\n"
    );
    (head, h)
}

/// A piece's notches (lines) and drill holes (a 3 mm circle with a cross), its y
/// flipped about `h`.
fn marks(s: &mut String, p: &Piece, h: f64) {
    for (a, b) in &p.notches {
        let _ = writeln!(
            s,
            "<line class=\"notch\" x1=\"{:.3}\" y1=\"{:.3}\" x2=\"{:.3}\" y2=\"{:.3}\" stroke=\"black\" stroke-width=\"0.5\"/>",
            a.x,
            h - a.y,
            b.x,
            h - b.y
        );
    }
    for q in &p.drills {
        let (x, y) = (q.x, h - q.y);
        let _ = writeln!(
            s,
            "<circle class=\"drill\" cx=\"{x:.3}\" cy=\"{y:.3}\" r=\"1.5\" fill=\"none\" stroke=\"black\" stroke-width=\"0.3\"/>\n<path class=\"drill\" d=\"M{:.3},{y:.3} H{:.3} M{x:.3},{:.3} V{:.3}\" stroke=\"black\" stroke-width=\"0.3\"/>",
            x - 2.5,
            x + 2.5,
            y - 2.5,
            y + 2.5
        );
    }
}

/// What a piece's group carries for Saiho to read back (other readers ignore `data-`
/// attributes): its fabric, its grain's angle (radians from the pattern's x, y up), and,
/// where the design placed it, its start on the body (JSON) and where its own pattern
/// coordinates' origin lies in the group's units (mm, y flipped about `h`).
fn ours(p: &Piece, h: f64) -> String {
    let (a, b) = p.grain;
    let grain = (b.y - a.y).atan2(b.x - a.x);
    let mut s = format!(
        " data-fabric=\"{}\" data-grain=\"{grain:.6}\"",
        xml(&p.fabric)
    );
    if let Some((start, o)) = &p.start
        && let Ok(json) = serde_json::to_string(start)
    {
        let _ = write!(
            s,
            " data-start=\"{}\" data-origin=\"{:.3} {:.3}\"",
            xml(&json),
            o.x,
            h - o.y
        );
    }
    s
}

/// A seam's side drawn from the end that meets the start of the seam's other side, and
/// whether that is known (`Piece::seam_starts`).
fn from_its_start(p: &Piece, label: &str, side: &[DVec2]) -> (Vec<DVec2>, bool) {
    // (A tube's seam has both its sides on one piece: a start each.)
    let at = |q: Option<&DVec2>| {
        q.is_some_and(|q| (p.seam_starts.iter()).any(|(l, s)| l == label && q.distance(*s) < 1e-6))
    };
    if at(side.first()) {
        (side.to_vec(), true)
    } else if at(side.last()) {
        (side.iter().rev().copied().collect(), true)
    } else {
        (side.to_vec(), false)
    }
}

/// The SVG document of laid-out pieces (`super::finish`).
pub fn svg_string(pieces: &[Piece]) -> String {
    let (mut s, h) = page(pieces);
    for (i, p) in pieces.iter().enumerate() {
        let _ = writeln!(
            s,
            "<g id=\"piece-{}\" class=\"piece\"{}>\n<title>{}</title>",
            i + 1,
            ours(p, h),
            xml(&p.name)
        );
        let _ = writeln!(
            s,
            "<path class=\"cut\" d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"0.5\" fill-rule=\"evenodd\"/>",
            path_d(&p.cut, h)
        );
        if p.cut != p.loops {
            let _ = writeln!(
                s,
                "<path class=\"sew\" d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"0.3\" stroke-dasharray=\"4 2\"/>",
                path_d(&p.loops, h)
            );
        }
        // Each side of a seam is one path (a designer selects it as one object; a
        // renderer draws a few paths, not hundreds of lines).
        let sides = super::notches::seam_sides(p);
        for (label, side) in &sides {
            let (side, paired) = from_its_start(p, label, side);
            let _ = writeln!(
                s,
                "<path class=\"seam\" data-seam=\"{}\"{} d=\"{}\" fill=\"none\" stroke=\"#c02030\" stroke-width=\"1\"/>",
                xml(label),
                if paired {
                    " data-seam-pairs=\"from-start\""
                } else {
                    ""
                },
                line_d(&side, h)
            );
        }
        marks(&mut s, p, h);
        // A label for each side of a seam, inside the piece beside its middle (where its
        // middle notch is), clear of the corners where sides meet.
        for (label, side) in sides {
            let (q, d) = super::notches::along(&side, 0.5);
            let mut n = DVec2::new(-d.y, d.x);
            if !super::notches::in_material(&p.loops, q + n * 0.5) {
                n = -n;
            }
            let m = q + n * 10.0;
            let _ = writeln!(
                s,
                "<text class=\"seam-label\" x=\"{:.3}\" y=\"{:.3}\" font-size=\"8\" text-anchor=\"middle\" fill=\"#c02030\">{}</text>",
                m.x,
                h - m.y,
                xml(&p.seam_text(&label))
            );
        }
        let (a, b) = p.grain;
        let t = (b - a).normalize_or_zero() * 6.0;
        let n = DVec2::new(-t.y, t.x) * 0.5;
        let _ = writeln!(
            s,
            "<path class=\"grain\" d=\"M{:.3},{:.3} L{:.3},{:.3} M{:.3},{:.3} L{:.3},{:.3} L{:.3},{:.3} M{:.3},{:.3} L{:.3},{:.3} L{:.3},{:.3}\" fill=\"none\" stroke=\"#2040a0\" stroke-width=\"0.5\"/>",
            a.x,
            h - a.y,
            b.x,
            h - b.y,
            (b - t + n).x,
            h - (b - t + n).y,
            b.x,
            h - b.y,
            (b - t - n).x,
            h - (b - t - n).y,
            (a + t + n).x,
            h - (a + t + n).y,
            a.x,
            h - a.y,
            (a + t - n).x,
            h - (a + t - n).y
        );
        let m = (a + b) * 0.5;
        let _ = writeln!(
            s,
            "<text class=\"name\" x=\"{:.3}\" y=\"{:.3}\" font-size=\"10\">{}</text>",
            m.x,
            h - m.y - 4.0,
            xml(&p.name)
        );
        let _ = writeln!(
            s,
            "<text class=\"fabric\" x=\"{:.3}\" y=\"{:.3}\" font-size=\"6\">fabric: {}</text>\n</g>",
            m.x,
            h - m.y + 6.0,
            xml(&p.fabric)
        );
    }
    s.push_str("</svg>\n");
    s
}
