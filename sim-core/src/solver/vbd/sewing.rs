//! Which vertices a seam is still pulling together: those joined by triangles to an end
//! of an open stitch.
//!
//! The global step's friction filter holds still every vertex whose contact's friction
//! can carry the force on it (`Vbd::contact_filter`). A stitch pulling two pieces
//! together round the body also presses them onto it (a seam's pull is a hoop tension:
//! the dress's open stitches pressed its panels onto the mannequin with about 100 N in
//! all, against 1 N of weight), and that pressure let friction hold the panels where the
//! stitches could not carry them: the dress's shoulder seams stayed 23-36 mm open. A
//! stitch is a way of bringing edges together, not a load a real garment carries, so
//! while its pieces are being sewn their vertices are not held by the filter; the
//! sweeps' own (IPC) friction still acts on them, and the filter holds them again once
//! every stitch on them has welded.

use crate::solver::Stitch;

/// Sets `out[v]` for every vertex of `n` that `tris` join to an end of an open stitch.
pub(super) fn mark(n: usize, tris: &[[u32; 3]], stitches: &[Stitch], out: &mut Vec<bool>) {
    out.clear();
    out.resize(n, false);
    if stitches.is_empty() {
        return;
    }
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    for t in tris {
        if t.iter().any(|&v| v as usize >= n) {
            continue;
        }
        let r0 = root(&mut parent, t[0]);
        for &v in &t[1..] {
            let r = root(&mut parent, v);
            parent[r as usize] = r0;
        }
    }
    let mut pulled = vec![false; n];
    for s in stitches {
        for v in [s.a, s.b] {
            if (v as usize) < n {
                let r = root(&mut parent, v);
                pulled[r as usize] = true;
            }
        }
    }
    for v in 0..n {
        out[v] = pulled[root(&mut parent, v as u32) as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles apart and a lone third: a stitch on the first marks only its
    /// triangle's vertices; no stitch marks none.
    #[test]
    fn only_the_pieces_a_stitch_pulls_are_marked() {
        let tris = [[0, 1, 2], [3, 4, 5], [2, 6, 7]];
        let stitch = Stitch {
            a: 1,
            b: 1,
            max_force: 0.5,
        };
        let mut out = Vec::new();
        mark(9, &tris, &[stitch], &mut out);
        let marked: Vec<usize> = (0..9).filter(|&v| out[v]).collect();
        assert_eq!(marked, [0, 1, 2, 6, 7]);
        mark(9, &tris, &[], &mut out);
        assert!(out.iter().all(|&m| !m));
    }
}
