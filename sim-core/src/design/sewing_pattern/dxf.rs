//! The pattern as DXF in the AAMA/ASTM D6673 layout pattern tools exchange (Seamly2D,
//! Valentina, CLO, Gerber): ASCII DXF R12, millimetres, one block per piece holding its
//! boundary (layer 1, the cut line), its sewing line (layer 14, with an allowance), the
//! turn points of both (layer 2: points where the outline turns by more than
//! [`TURN_DEGREES`]), its notches (layer 4, slits as lines, as Seamly2D writes them),
//! its drill holes (layer 13, points: a sewn dart's point),
//! its grain line (layer 7), its seams (layer 8, labelled) and its annotation (layer 15:
//! "Piece Name: ...", "Material: ...", "Quantity: 1"), and an INSERT of each block where
//! the layout put it.

use std::fmt::Write as _;

use glam::DVec2;

use super::Piece;

/// Group code and value pairs, one per line each.
struct Dxf(String);

impl Dxf {
    fn pair(&mut self, code: i32, value: impl std::fmt::Display) {
        let _ = write!(self.0, "{code:>3}\n{value}\n");
    }

    fn point(&mut self, p: DVec2, k: i32) {
        self.pair(10 + k, format!("{:.4}", p.x));
        self.pair(20 + k, format!("{:.4}", p.y));
        self.pair(30 + k, "0.0");
    }

    fn polyline(&mut self, layer: &str, l: &[DVec2]) {
        self.pair(0, "POLYLINE");
        self.pair(8, layer);
        self.pair(66, 1);
        self.point(DVec2::ZERO, 0);
        self.pair(70, 1);
        for &p in l {
            self.pair(0, "VERTEX");
            self.pair(8, layer);
            self.point(p, 0);
        }
        self.pair(0, "SEQEND");
        self.pair(8, layer);
    }

    fn dot(&mut self, layer: &str, p: DVec2) {
        self.pair(0, "POINT");
        self.pair(8, layer);
        self.point(p, 0);
    }

    fn line(&mut self, layer: &str, a: DVec2, b: DVec2) {
        self.pair(0, "LINE");
        self.pair(8, layer);
        self.point(a, 0);
        self.point(b, 1);
    }

    fn text(&mut self, layer: &str, at: DVec2, height: f64, s: &str) {
        self.pair(0, "TEXT");
        self.pair(8, layer);
        self.point(at, 0);
        self.pair(40, format!("{height:.1}"));
        // DXF text is one line of printable ASCII.
        let clean: String = s
            .chars()
            .map(|c| if c.is_ascii_graphic() { c } else { ' ' })
            .collect();
        self.pair(1, clean);
    }
}

/// An outline's corner turns by more than this to be a turn point, degrees.
pub const TURN_DEGREES: f64 = 30.0;

/// The points where closed loop `l` turns by more than [`TURN_DEGREES`].
fn turn_points(l: &[DVec2]) -> impl Iterator<Item = DVec2> + '_ {
    let n = l.len();
    let cos_max = TURN_DEGREES.to_radians().cos();
    (0..n).filter_map(move |i| {
        let a = (l[i] - l[(i + n - 1) % n]).normalize_or_zero();
        let b = (l[(i + 1) % n] - l[i]).normalize_or_zero();
        (a != DVec2::ZERO && b != DVec2::ZERO && a.dot(b) < cos_max).then_some(l[i])
    })
}

/// The block name of piece `i`.
fn block(i: usize) -> String {
    format!("PIECE{}", i + 1)
}

/// The DXF document of laid-out pieces (`super::finish`).
pub fn dxf_string(pieces: &[Piece]) -> String {
    let mut d = Dxf(String::new());
    d.pair(0, "SECTION");
    d.pair(2, "HEADER");
    d.pair(9, "$ACADVER");
    d.pair(1, "AC1009");
    d.pair(9, "$INSBASE");
    d.point(DVec2::ZERO, 0);
    d.pair(0, "ENDSEC");
    d.pair(0, "SECTION");
    d.pair(2, "TABLES");
    d.pair(0, "TABLE");
    d.pair(2, "LTYPE");
    d.pair(70, 1);
    d.pair(0, "LTYPE");
    d.pair(2, "CONTINUOUS");
    d.pair(70, 0);
    d.pair(3, "Solid line");
    d.pair(72, 65);
    d.pair(73, 0);
    d.pair(40, "0.0");
    d.pair(0, "ENDTAB");
    let layers = ["0", "1", "2", "4", "7", "8", "13", "14", "15"];
    d.pair(0, "TABLE");
    d.pair(2, "LAYER");
    d.pair(70, layers.len());
    for l in layers {
        d.pair(0, "LAYER");
        d.pair(2, l);
        d.pair(70, 0);
        d.pair(62, 7);
        d.pair(6, "CONTINUOUS");
    }
    d.pair(0, "ENDTAB");
    d.pair(0, "ENDSEC");
    d.pair(0, "SECTION");
    d.pair(2, "BLOCKS");
    for (i, p) in pieces.iter().enumerate() {
        let name = block(i);
        d.pair(0, "BLOCK");
        d.pair(8, "0");
        d.pair(2, &name);
        d.pair(70, 0);
        d.point(DVec2::ZERO, 0);
        d.pair(3, &name);
        for l in &p.cut {
            d.polyline("1", l);
            for t in turn_points(l) {
                d.dot("2", t);
            }
        }
        if p.cut != p.loops {
            for l in &p.loops {
                d.polyline("14", l);
                for t in turn_points(l) {
                    d.dot("2", t);
                }
            }
        }
        for &(a, b) in &p.notches {
            d.line("4", a, b);
        }
        for &q in &p.drills {
            d.dot("13", q);
        }
        d.line("7", p.grain.0, p.grain.1);
        for (_, a, b) in &p.seams {
            d.line("8", *a, *b);
        }
        // A label on each stretch of a seam's marks (a side seam over a dart's mouth is
        // two on one piece): the reader labels the lines each text lies on, chained.
        let mut seen: Vec<&str> = Vec::new();
        let mut last: Option<(&str, DVec2)> = None;
        for (label, a, b) in &p.seams {
            let goes_on = last.is_some_and(|(l, end)| l == label && end.distance(*a) < 1e-6);
            last = Some((label, *b));
            if goes_on {
                continue;
            }
            let m = (*a + *b) * 0.5;
            d.text("15", m, 6.0, &format!("Seam: {label}"));
            if !seen.contains(&label.as_str()) {
                seen.push(label);
                // The designer's name beside the mark (our reader pairs by "Seam: X").
                if let Some((_, name)) = p.seam_names.iter().find(|(l, _)| l == label) {
                    d.text(
                        "15",
                        m - DVec2::new(0.0, 8.0),
                        5.0,
                        &format!("Seam {label} name: {name}"),
                    );
                }
            }
        }
        let m = (p.grain.0 + p.grain.1) * 0.5 + DVec2::new(0.0, 6.0);
        d.text("15", m, 8.0, &format!("Piece Name: {}", p.name));
        d.text("15", m - DVec2::new(0.0, 12.0), 6.0, "Quantity: 1");
        d.text(
            "15",
            m - DVec2::new(0.0, 20.0),
            6.0,
            &format!("Material: {}", p.fabric),
        );
        d.pair(0, "ENDBLK");
        d.pair(8, "0");
    }
    d.pair(0, "ENDSEC");
    d.pair(0, "SECTION");
    d.pair(2, "ENTITIES");
    for i in 0..pieces.len() {
        d.pair(0, "INSERT");
        d.pair(8, "0");
        d.pair(2, block(i));
        d.point(DVec2::ZERO, 0);
    }
    d.pair(0, "ENDSEC");
    d.pair(0, "EOF");
    d.0
}
