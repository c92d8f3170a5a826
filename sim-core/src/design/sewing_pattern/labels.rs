//! The seams' labels in the pattern out: "A", "B", ... by the seam's place in the design,
//! and "B1", "B2", ... for the stretches of a seam whose sides run over more than two
//! pieces.

use rustc_hash::FxHashMap as HashMap;

use crate::design::document::Design;

/// The seams' labels ("A", "B", ...) of each vertex in them. A seam whose sides run
/// over more than two of the pieces `parts` (a side cut across, say: the front cut at the
/// waist leaves the back's side seam joined to the front above and to the lower front
/// below) is labelled by its stretches between one pair of pieces, "B1", "B2", ..., in
/// the seam's order, so that each label marks exactly two stretches of outline, as a
/// pattern pairs its seams. A seam with one side left in every pair (the piece across it
/// deleted: the back's shoulders once the front is gone) is sewn to nothing and has no
/// label; a dart, a seam on one piece, keeps both its sides.
pub(super) fn seam_labels(design: &Design, parts: &[Vec<u32>]) -> HashMap<u32, Vec<String>> {
    let live = &design.sim.cloth.live;
    let mut parts_of: HashMap<u32, Vec<u32>> = HashMap::default();
    // Each vertex's places in the pattern (a welded pair's vertex has one on each side).
    let mut places: HashMap<u32, Vec<[u32; 3]>> = HashMap::default();
    for (p, part) in parts.iter().enumerate() {
        for t in part.iter().filter_map(|&slot| live.tri(slot)) {
            for (v, rest) in t.v.into_iter().zip(t.rest) {
                let e = parts_of.entry(v).or_default();
                if !e.contains(&(p as u32)) {
                    e.push(p as u32);
                }
                let e = places.entry(v).or_default();
                let bits = rest.to_array().map(f32::to_bits);
                if !e.contains(&bits) {
                    e.push(bits);
                }
            }
        }
    }
    let two_sided = |&(a, b): &(u32, u32)| {
        let at = |v| places.get(&v).map_or(&[][..], Vec::as_slice);
        let (pa, pb) = (at(a), at(b));
        pa.len() + pb.iter().filter(|q| !pa.contains(q)).count() >= 2
    };
    let mut m: HashMap<u32, Vec<String>> = HashMap::default();
    for (i, s) in design.seams.iter().enumerate() {
        if !s.pairs.iter().any(two_sided) {
            continue;
        }
        let runs = stretch_runs(&s.pairs, &parts_of);
        let split = runs.iter().flatten().any(|&r| r > 0);
        let any = runs.iter().any(|r| !r.is_empty());
        for (&(a, b), runs) in s.pairs.iter().zip(&runs) {
            // Split, each stretch its own label; whole, the seam's; a pair in no stretch
            // (a side whose other side was cut away) none, unless no pair is in one.
            let labels: Vec<String> = if split {
                runs.iter()
                    .map(|r| format!("{}{}", label(i), r + 1))
                    .collect()
            } else if runs.is_empty() && any {
                Vec::new()
            } else {
                vec![label(i)]
            };
            for label in labels {
                for v in [a, b] {
                    let e = m.entry(v).or_default();
                    if !e.contains(&label) {
                        e.push(label.clone());
                    }
                }
            }
        }
    }
    m
}

/// Each pair's stretch of its seam: consecutive pairs between the same pieces (the parts
/// their two vertices lie on, `parts_of`) are one stretch. A pair on more pieces than
/// its neighbours (where a cut crosses the seam) belongs to the stretches either side; a
/// pair on none (its vertices gone), or on one piece where others join two (its other
/// side was cut away: a seam on one piece is a dart only if all of it is), to none. An
/// end pair counts on the pieces its neighbour is on (where it shares any).
fn stretch_runs(pairs: &[(u32, u32)], parts_of: &HashMap<u32, Vec<u32>>) -> Vec<Vec<usize>> {
    let on = |&(a, b): &(u32, u32)| {
        let mut k: Vec<u32> = [a, b]
            .iter()
            .flat_map(|v| parts_of.get(v).into_iter().flatten().copied())
            .collect();
        k.sort_unstable();
        k.dedup();
        k
    };
    let mut keys: Vec<Vec<u32>> = pairs.iter().map(on).collect();
    // An end pair's vertex can be welded into another seam too (a dart's end at the
    // waist, sewn to the bodice; a dart's mouth under a side seam sewn over it): it is on
    // a piece more, which its seam's stretch is not. It keeps the pieces its neighbour is
    // on, where that leaves any; the pairs at the end that share its vertex (the mouth's
    // vertex paired twice) go with it, their neighbour the first pair past them.
    let n = keys.len();
    let touch = |i: usize, j: usize| {
        let ((a, b), (c, d)) = (pairs[i], pairs[j]);
        a == c || a == d || b == c || b == d
    };
    for from_start in [true, false] {
        let at = |k: usize| if from_start { k } else { n - 1 - k };
        let Some(m) = (1..n).find(|&m| !touch(at(0), at(m))) else {
            continue;
        };
        for k in 0..m {
            let shared: Vec<u32> = (keys[at(k)].iter())
                .filter(|p| keys[at(m)].contains(p))
                .copied()
                .collect();
            if !shared.is_empty() {
                keys[at(k)] = shared;
            }
        }
    }
    let joins_two = keys.iter().any(|k| k.len() == 2);
    let common = |k: &[u32]| k.len() == 2 || (k.len() == 1 && !joins_two);
    let orphan = |k: &[u32]| k.len() == 1 && joins_two;
    let mut runs: Vec<Vec<usize>> = vec![Vec::new(); pairs.len()];
    let mut last: Option<(&[u32], usize)> = None;
    for (k, key) in keys.iter().enumerate() {
        if key.is_empty() || !common(key) {
            continue;
        }
        let r = match last {
            Some((l, r)) if l == &key[..] => r,
            Some((_, r)) => r + 1,
            None => 0,
        };
        runs[k].push(r);
        last = Some((key, r));
    }
    // A crossing: the stretches of the nearest pairs before and after it.
    for k in 0..pairs.len() {
        if keys[k].is_empty() || common(&keys[k]) || orphan(&keys[k]) {
            continue;
        }
        let before = (0..k).rev().find_map(|j| runs[j].first().copied());
        let after = (k + 1..pairs.len()).find_map(|j| runs[j].first().copied());
        runs[k] = before.into_iter().chain(after).collect();
        runs[k].dedup();
    }
    runs
}

/// Seam `i`'s label in the pattern out: "A".."Z", then "AA", "AB", ...
pub fn seam_label(i: usize) -> String {
    label(i)
}

/// "A".."Z", then "AA", "AB", ...
pub(crate) fn label(i: usize) -> String {
    let letter = |k: usize| char::from(b'A' + (k % 26) as u8);
    if i < 26 {
        letter(i).to_string()
    } else {
        format!("{}{}", letter(i / 26 - 1), letter(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dart on piece 0 whose end vertex (1) is also welded to piece 5 by another seam
    /// (a skirt's waist dart, its end sewn to the bodice): every pair is one stretch, so
    /// the dart keeps its label. Counted on pieces 0 and 5, that end made the pairs on
    /// piece 0 alone look like a seam whose other side was cut away (GarmentCode's pencil
    /// dress lost its four darts' marks). A seam whose side was cut away still drops them.
    #[test]
    fn a_darts_end_welded_to_another_piece_keeps_the_dart_one_stretch() {
        let parts_of: HashMap<u32, Vec<u32>> = [(1, vec![0, 5]), (2, vec![0]), (3, vec![0])]
            .into_iter()
            .collect();
        let pairs = [(1, 1), (2, 2), (3, 3)];
        assert_eq!(stretch_runs(&pairs, &parts_of), vec![vec![0]; 3]);
        // Pairs joining pieces 0 and 1, then two whose partner was cut away.
        let parts_of: HashMap<u32, Vec<u32>> = [
            (1, vec![0]),
            (2, vec![0]),
            (3, vec![0]),
            (11, vec![1]),
            (12, vec![1]),
        ]
        .into_iter()
        .collect();
        let pairs = [(1, 11), (2, 12), (3, 3)];
        assert_eq!(
            stretch_runs(&pairs, &parts_of),
            vec![vec![0], vec![0], vec![]]
        );
    }
}
