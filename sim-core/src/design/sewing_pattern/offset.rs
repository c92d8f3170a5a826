//! A loop offset outward with mitred corners: the cut line round the sewing line.

use glam::DVec2;

/// Loop `l` offset by `d` to the right of its direction (away from the material, for
/// an outer loop counter-clockwise and a hole clockwise), with mitred corners; a corner
/// sharper than the mitre limit (4 d) is bevelled.
pub fn offset(l: &[DVec2], d: f64) -> Vec<DVec2> {
    offset_tagged(l, d).into_iter().map(|(_, p)| p).collect()
}

/// [`offset`], each point with the index of the corner of `l` it is offset from (two
/// points for a bevelled corner).
pub(super) fn offset_tagged(l: &[DVec2], d: f64) -> Vec<(usize, DVec2)> {
    let n = l.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let (p, c, q) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
        let right = |a: DVec2, b: DVec2| {
            let t = (b - a).normalize_or_zero();
            DVec2::new(t.y, -t.x)
        };
        let (n1, n2) = (right(p, c), right(c, q));
        let m = n1 + n2;
        let cos_half = (m.length() * 0.5).max(1e-9);
        let miter = d / cos_half;
        if miter <= 4.0 * d && m.length() > 1e-9 {
            out.push((i, c + m.normalize() * miter));
        } else {
            out.push((i, c + n1 * d));
            out.push((i, c + n2 * d));
        }
    }
    out
}
