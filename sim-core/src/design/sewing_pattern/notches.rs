//! Balance notches: where each seam's two sides are matched, slits cut into the edge
//! (`Piece::notches`), and the seam sides as chains of outline points that they and the
//! SVG's seam labels are placed along.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use super::Piece;
use super::dart::{Dart, leg_on_cut};

/// A seam side longer than this gets notches at its quarters too, mm.
pub const QUARTER_NOTCHES_MM: f64 = 250.0;
/// How far a notch reaches into a piece without an allowance, mm.
const NOTCH_DEPTH_MM: f64 = 5.0;

/// Each seam side of `p` as a chain of outline points (its segments joined end to end),
/// with its seam's label.
pub(super) fn seam_sides(p: &Piece) -> Vec<(String, Vec<DVec2>)> {
    let mut labels: Vec<&str> = p.seams.iter().map(|(l, _, _)| l.as_str()).collect();
    labels.sort_unstable();
    labels.dedup();
    let mut sides = Vec::new();
    for label in labels {
        let mut segs: Vec<(DVec2, DVec2)> = (p.seams.iter())
            .filter(|(l, _, _)| l == label)
            .map(|&(_, a, b)| (a, b))
            .collect();
        let mut chains: Vec<Vec<DVec2>> = Vec::new();
        while let Some((a, b)) = segs.pop() {
            let mut c = vec![a, b];
            // Grow the chain at both ends while a segment continues it.
            loop {
                let end = c[c.len() - 1];
                let start = c[0];
                if let Some(k) = segs.iter().position(|s| s.0 == end) {
                    c.push(segs.swap_remove(k).1);
                } else if let Some(k) = segs.iter().position(|s| s.1 == start) {
                    c.insert(0, segs.swap_remove(k).0);
                } else {
                    break;
                }
            }
            chains.push(c);
        }
        sides.extend(chains.into_iter().map(|c| (label.to_string(), c)));
    }
    sides
}

/// Whether `q` lies in the piece's material (inside its outer loop and no hole; even-odd
/// over the loops).
pub(crate) fn in_material(loops: &[Vec<DVec2>], q: DVec2) -> bool {
    let mut inside = false;
    for l in loops {
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                inside = !inside;
            }
        }
    }
    inside
}

/// The point at `t` of the way along chain `c` by length, and the chain's direction there.
pub(super) fn along(c: &[DVec2], t: f64) -> (DVec2, DVec2) {
    let total: f64 = c.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    let mut left = t * total;
    for w in c.windows(2) {
        let len = (w[1] - w[0]).length();
        if len > 0.0 && (left <= len || w[1] == c[c.len() - 1]) {
            let d = (w[1] - w[0]) / len;
            return (w[0] + d * left.min(len), d);
        }
        left -= len;
    }
    (c[0], DVec2::X)
}

/// A chain's length.
fn length(c: &[DVec2]) -> f64 {
    c.windows(2).map(|w| (w[1] - w[0]).length()).sum()
}

/// The longest side of each seam over `pieces`, by label: both sides of a seam take their
/// notches by it, so that a side just under [`QUARTER_NOTCHES_MM`] and its partner just
/// over get the same notches.
pub(super) fn longest_sides(pieces: &[Piece]) -> HashMap<String, f64> {
    let mut longest: HashMap<String, f64> = HashMap::default();
    for (label, side) in pieces.iter().flat_map(seam_sides) {
        let l = longest.entry(label).or_default();
        *l = l.max(length(&side));
    }
    longest
}

/// The balance notches of piece `p` (see [`Piece::notches`]) for an allowance of
/// `allowance_mm`: each a slit square to its seam's side, from the cut line half way to
/// the sewing line (or [`NOTCH_DEPTH_MM`] into a piece cut on its sewing line); at the
/// quarters too where the seam's longest side (`longest`, by label) is long. A dart of
/// `darts` (its seam's two sides meet at its tip) is notched instead at its legs' ends:
/// each a slit along the leg's line, from where it meets the cut line toward the tip.
pub(super) fn notches(
    p: &Piece,
    allowance_mm: f64,
    longest: &HashMap<String, f64>,
    darts: &[Dart],
) -> Vec<(DVec2, DVec2)> {
    let mut out = Vec::new();
    for dart in darts {
        let l = &p.loops[dart.loop_index];
        let tip = dart.tip;
        for mouth in [l[dart.a], l[dart.b]] {
            let from = leg_on_cut(&p.cut, tip, mouth);
            let depth = if allowance_mm > 0.0 {
                0.5 * from.distance(mouth)
            } else {
                NOTCH_DEPTH_MM.min(0.25 * mouth.distance(tip))
            };
            out.push((from, from + (tip - from).normalize_or_zero() * depth));
        }
    }
    for (label, side) in seam_sides(p) {
        if darts.iter().any(|d| d.label == label) {
            continue;
        }
        let len = length(&side);
        if len <= 0.0 {
            continue;
        }
        let seam = longest.get(&label).copied().unwrap_or(len);
        let at: &[f64] = if seam > QUARTER_NOTCHES_MM {
            &[0.25, 0.5, 0.75]
        } else {
            &[0.5]
        };
        for &t in at {
            let (q, d) = along(&side, t);
            let mut n = DVec2::new(-d.y, d.x);
            if !in_material(&p.loops, q + n * 0.5) {
                n = -n;
            }
            let (from, depth) = if allowance_mm > 0.0 {
                (q - n * allowance_mm, 0.5 * allowance_mm)
            } else {
                (q, NOTCH_DEPTH_MM)
            };
            out.push((from, from + n * depth));
        }
    }
    out
}
