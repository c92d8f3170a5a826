//! Slits the cloth has sewn shut, left out of the pattern: where a dart's two cuts leave
//! a slit past its point and the legs' welds close it, the fabric has no cut.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use super::{Corners, Key, SLIT_MM, area2, perimeter};

/// `key_loops` (a part's outline, `c` its corners) without the slits the cloth has sewn
/// shut: a hole under [`SLIT_MM`] wide whose every edge, in the cloth, is between two of
/// the part's triangles or is no edge, its ends welded into one vertex (its sides welded
/// to each other, as the legs' welds close the slit a dart's two cuts can leave past its
/// point). Such a cut is no cut in the fabric; left in, it touched the outline at the
/// dart's point, which no pattern reader takes (ours: "the outline crosses itself").
/// The largest loop always stays.
pub(super) fn sewn_shut_dropped(
    key_loops: Vec<Vec<Key>>,
    c: &Corners,
    places: &HashMap<Key, DVec2>,
) -> Vec<Vec<Key>> {
    // A loop through one corner twice (a slit touching the outline at a dart's point,
    // chained as one loop) as the loops either side of the corner.
    let key_loops: Vec<Vec<Key>> = key_loops.into_iter().flat_map(split_pinches).collect();
    let pts = |l: &[Key]| l.iter().map(|k| places[k]).collect::<Vec<DVec2>>();
    let areas: Vec<f64> = key_loops.iter().map(|l| area2(&pts(l)).abs()).collect();
    let Some(outer) = (0..areas.len()).max_by(|&a, &b| areas[a].total_cmp(&areas[b])) else {
        return key_loops;
    };
    let slits: Vec<usize> = (0..key_loops.len())
        .filter(|&i| i != outer && areas[i] < SLIT_MM * perimeter(&pts(&key_loops[i])))
        .collect();
    if slits.is_empty() {
        // Nearly every part: no slit, nothing to count (the piece list is made on every
        // cut and tear).
        return key_loops;
    }
    let undirected = |a: u32, b: u32| (a.min(b) as u64) << 32 | a.max(b) as u64;
    let mut in_tris: HashMap<u64, u8> = HashMap::default();
    for t in &c.tris {
        let v = t.map(|i| c.keys[i as usize].0);
        for k in 0..3 {
            let n = in_tris.entry(undirected(v[k], v[(k + 1) % 3])).or_default();
            *n = n.saturating_add(1);
        }
    }
    (key_loops.into_iter().enumerate())
        .filter(|(i, l)| {
            let n = l.len();
            // A slit whose every side is between two of the part's triangles, or is
            // welded to nothing (its two ends merged into one vertex), goes.
            let shut = || {
                (0..n).all(|k| {
                    let (a, b) = (l[k].0, l[(k + 1) % n].0);
                    a == b || in_tris.get(&undirected(a, b)) == Some(&2)
                })
            };
            !(slits.contains(i) && shut())
        })
        .map(|(_, l)| l)
        .collect()
}

/// Loop `l` split where it passes a corner it has passed before: each stretch between
/// the two passes a loop of its own.
fn split_pinches(l: Vec<Key>) -> Vec<Vec<Key>> {
    let mut out = Vec::new();
    let mut stack: Vec<Key> = Vec::with_capacity(l.len());
    let mut at: HashMap<Key, usize> = HashMap::default();
    for k in l {
        if let Some(&j) = at.get(&k) {
            for q in &stack[j + 1..] {
                at.remove(q);
            }
            out.push(stack.split_off(j));
        }
        at.insert(k, stack.len());
        stack.push(k);
    }
    out.push(stack);
    out
}
