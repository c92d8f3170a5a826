//! Which ends of a seam's two sides meet, as the design sewed them. The pattern out
//! draws each side from the end that meets the other side's start and says so (SVG:
//! `data-seam-pairs="from-start"`), so that read back the seam is sewn the same way
//! round: paired by where the pieces start, GarmentCode's hood was sewn twisted onto
//! the back's neckline (docs/garments.md).

use glam::DVec2;
use rustc_hash::{FxHashMap as HashMap, FxHashSet};

use super::labels::seam_label;
use super::{Key, Piece};
use crate::design::document::Design;

/// A seam's side on one piece: its label and its two ends (vertex, pattern place) in the
/// order its segments run.
pub(super) struct Side {
    piece: usize,
    label: String,
    ends: [(u32, DVec2); 2],
}

/// The sides of piece `piece` (its seams' segments `segs`, each a label and two corner
/// keys, placed by `places`): one for each open chain of a label's segments (a tube's
/// seam has two on one piece).
pub(super) fn sides(
    piece: usize,
    segs: &[(String, Key, Key)],
    places: &HashMap<Key, DVec2>,
) -> Vec<Side> {
    let mut labels: Vec<&String> = segs.iter().map(|s| &s.0).collect();
    labels.sort_unstable();
    labels.dedup();
    let mut out = Vec::new();
    for label in labels {
        let next: HashMap<Key, Key> = (segs.iter())
            .filter(|s| &s.0 == label)
            .map(|s| (s.1, s.2))
            .collect();
        let tos: FxHashSet<Key> = next.values().copied().collect();
        for &a in next.keys().filter(|k| !tos.contains(k)) {
            let mut b = a;
            // (At most as many steps as segments: a chain cannot loop back into itself
            // past its start, which nothing leads to.)
            for _ in 0..next.len() {
                match next.get(&b) {
                    Some(&c) => b = c,
                    None => break,
                }
            }
            out.push(Side {
                piece,
                label: label.clone(),
                ends: [(a.0, places[&a]), (b.0, places[&b])],
            });
        }
    }
    out
}

/// For each label sewn between exactly two `sides` whose ends the design's stitched pairs
/// (or a weld: one vertex) tell apart, each side's end that meets the other's start,
/// given to its piece in `pieces`.
pub(super) fn seam_starts(design: &Design, sides: Vec<Side>, pieces: &mut [Piece]) {
    let index: HashMap<String, usize> = (0..design.seams.len())
        .map(|i| (seam_label(i), i))
        .collect();
    let mut by_label: HashMap<String, Vec<Side>> = HashMap::default();
    for s in sides {
        by_label.entry(s.label.clone()).or_default().push(s);
    }
    for (label, two) in by_label {
        let [s1, s2] = &two[..] else { continue };
        let base = label.trim_end_matches(|c: char| c.is_ascii_digit());
        let Some(seam) = index.get(base).map(|&i| &design.seams[i]) else {
            continue;
        };
        let pairs: FxHashSet<(u32, u32)> = (seam.pairs.iter())
            .flat_map(|&(a, b)| [(a, b), (b, a)])
            .collect();
        let meet = |x: u32, y: u32| x == y || pairs.contains(&(x, y));
        let (u, w) = (s1.ends, s2.ends);
        let straight = meet(u[0].0, w[0].0) && meet(u[1].0, w[1].0);
        let crossed = meet(u[0].0, w[1].0) && meet(u[1].0, w[0].0);
        let w_start = match (straight, crossed) {
            (true, false) => w[0].1,
            (false, true) => w[1].1,
            _ => continue,
        };
        if let (Some(_), Some(_)) = (pieces.get(s1.piece), pieces.get(s2.piece)) {
            pieces[s1.piece].seam_starts.push((label.clone(), u[0].1));
            pieces[s2.piece].seam_starts.push((label, w_start));
        }
    }
}
