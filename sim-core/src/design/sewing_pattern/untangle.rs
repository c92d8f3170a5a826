//! A seam allowance's cut line without the loops its offset makes where the sewing line
//! folds back closer than twice the allowance: a notch's two sides, a slit, a dart whose
//! cap cannot be made (a sewn dart is bridged by its cap first: `dart.rs`). Offset as it
//! is, the two sides' offsets cross, and the cut line drawn as an X is no line a cutter
//! can follow; under a notch narrower than twice the allowance they pass each other, and
//! the hem's offsets either side of it lie along each other.

use glam::DVec2;

use super::area2;

/// Loop `cut` (an offset of a sewing line whose twice-signed area is `sign`'s sign)
/// with each loop its crossings close off removed: at each crossing, of the two loops
/// it splits the line into, the one turning the sewing line's way round and larger is
/// kept; where two sides run along each other, at the middle of the stretch they share.
/// A line that does not cross or overlap itself is returned as it is.
pub(super) fn untangle(mut cut: Vec<DVec2>, sign: f64) -> Vec<DVec2> {
    // Each removal takes at least one point away.
    for _ in 0..cut.len() {
        let Some((i, j, x)) = first_crossing(&cut) else {
            break;
        };
        let n = cut.len();
        let inner: Vec<DVec2> = std::iter::once(x)
            .chain(cut[i + 1..=j].iter().copied())
            .collect();
        let outer: Vec<DVec2> = (cut[j + 1..n].iter().chain(&cut[..=i]).copied())
            .chain(std::iter::once(x))
            .collect();
        let score = |l: &[DVec2]| {
            let a = area2(l);
            // The sewing line's way round first, then the larger.
            (a * sign > 0.0, a.abs())
        };
        let (si, so) = (score(&inner), score(&outer));
        cut = if si.0 && !so.0 || (si.0 == so.0 && si.1 > so.1) {
            inner
        } else {
            outer
        };
    }
    // A split at a side's end leaves that point twice.
    cut.dedup_by(|b, a| a.distance(*b) < EPS);
    while cut.len() > 1 && cut[0].distance(cut[cut.len() - 1]) < EPS {
        cut.pop();
    }
    cut
}

/// The first pair of non-adjacent sides of closed loop `l` that cross, `(i, j, where)`
/// with side `i` from `l[i]` to `l[i + 1]` and `i < j`.
fn first_crossing(l: &[DVec2]) -> Option<(usize, usize, DVec2)> {
    let n = l.len();
    if n < 4 {
        return None;
    }
    for i in 0..n - 2 {
        let (p, q) = (l[i], l[i + 1]);
        let (lo, hi) = (p.min(q), p.max(q));
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (a, b) = (l[j], l[(j + 1) % n]);
            if a.max(b).cmplt(lo - EPS).any() || a.min(b).cmpgt(hi + EPS).any() {
                continue;
            }
            if let Some(x) = crossing(p, q, a, b).or_else(|| overlap(p, q, a, b)) {
                return Some((i, j, x));
            }
        }
    }
    None
}

/// How near two sides must lie to run along each other, and how long a stretch they
/// must share, mm.
const EPS: f64 = 1e-3;

/// The middle of the stretch where segments `p`-`q` and `a`-`b` lie along each other
/// (within [`EPS`]) for longer than [`EPS`], if they do: under a dart narrower than
/// twice the allowance the hem's offsets either side of it overlap so, never crossing.
fn overlap(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> Option<DVec2> {
    let len = p.distance(q);
    if len < EPS {
        return None;
    }
    let t = (q - p) / len;
    let off = |x: DVec2| (x - p).perp_dot(t).abs();
    if off(a) > EPS || off(b) > EPS {
        return None;
    }
    let (sa, sb) = ((a - p).dot(t), (b - p).dot(t));
    let (lo, hi) = (sa.min(sb).max(0.0), sa.max(sb).min(len));
    (hi - lo > EPS).then(|| p + t * (0.5 * (lo + hi)))
}

/// Where segments `p`-`q` and `a`-`b` cross (within both, not at an end), if they do.
fn crossing(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> Option<DVec2> {
    let (r, s) = (q - p, b - a);
    let den = r.perp_dot(s);
    if den.abs() < 1e-12 {
        return None;
    }
    let t = (a - p).perp_dot(s) / den;
    let u = (a - p).perp_dot(r) / den;
    let inside = |v: f64| v > 1e-9 && v < 1.0 - 1e-9;
    (inside(t) && inside(u)).then(|| p + r * t)
}

#[cfg(test)]
mod tests {
    use super::super::offset;
    use super::*;

    /// Whether point `p` is inside closed loop `l` (crossing count).
    fn inside(l: &[DVec2], p: DVec2) -> bool {
        let n = l.len();
        (0..n).fold(false, |odd, i| {
            let (a, b) = (l[i], l[(i + 1) % n]);
            let straddles = (a.y > p.y) != (b.y > p.y);
            odd ^ (straddles && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x))
        })
    }

    /// A 500 x 300 mm piece's sewing line (counter-clockwise, mm) with a dart `wide` mm
    /// at the hem and 200 mm long in its middle.
    fn dart_at_hem(wide: f64) -> Vec<DVec2> {
        let v = |x: f64, y: f64| DVec2::new(x, y);
        let h = 0.5 * wide;
        vec![
            v(0.0, 0.0),
            v(250.0 - h, 0.0),
            v(250.0, 200.0),
            v(250.0 + h, 0.0),
            v(500.0, 0.0),
            v(500.0, 300.0),
            v(0.0, 300.0),
        ]
    }

    /// A dart from the hem of a 500 x 300 mm piece, 50 mm wide and 200 mm long (the
    /// studio's, cut in the dress's front), under a 10 mm allowance: offset alone, its
    /// legs' offsets cross where the dart is narrower than 20 mm; untangled, the cut
    /// line crosses nowhere, runs the sewing line's way round and holds all of it. A
    /// square alone is left as it is.
    #[test]
    fn a_darts_allowance_is_one_line_round_it() {
        let v = |x: f64, y: f64| DVec2::new(x, y);
        let dart = dart_at_hem(50.0);
        let raw = offset(&dart, 10.0);
        assert!(first_crossing(&raw).is_some(), "the raw offset crosses");
        let cut = untangle(raw.clone(), area2(&dart));
        assert!(first_crossing(&cut).is_none(), "{cut:?}");
        assert!(area2(&cut) > 0.0);
        assert!(cut.len() < raw.len());
        for &p in &dart {
            assert!(inside(&cut, p), "{p} outside {cut:?}");
        }
        // The hem under the dart is cut 10 mm below it, as beside it.
        assert!(cut.iter().all(|p| p.y > -10.0 - 1e-9), "{cut:?}");
        let square = vec![v(0.0, 0.0), v(100.0, 0.0), v(100.0, 100.0), v(0.0, 100.0)];
        let o = offset(&square, 10.0);
        assert_eq!(untangle(o.clone(), area2(&square)), o);
        // A hole (clockwise) keeps its way round too.
        let hole: Vec<DVec2> = dart.iter().rev().copied().collect();
        let cut = untangle(offset(&hole, 10.0), area2(&hole));
        assert!(
            first_crossing(&cut).is_none() && area2(&cut) < 0.0,
            "{cut:?}"
        );
    }

    /// A dart narrower at the hem (12 mm) than twice the allowance: its legs' offsets
    /// pass each other without crossing, and the hem's offsets on each side of it lie
    /// along each other under it. Untangled, the cut line is the hem's offset straight
    /// across (the allowance covers the whole dart there), not a flag running up into
    /// the piece to the dart's point and back, as it was until 2026-12-05.
    #[test]
    fn a_narrow_darts_allowance_runs_straight_under_it() {
        let dart = dart_at_hem(12.0);
        let raw = offset(&dart, 10.0);
        assert!(
            first_crossing(&raw).is_some(),
            "the raw offset overlaps itself"
        );
        let cut = untangle(raw, area2(&dart));
        assert!(first_crossing(&cut).is_none(), "{cut:?}");
        // Every point of it on the rectangle's offset, none up in the piece.
        let on_edge = |p: &DVec2| {
            (p.y + 10.0).abs() < 1e-6
                || (p.y - 310.0).abs() < 1e-6
                || (p.x + 10.0).abs() < 1e-6
                || (p.x - 510.0).abs() < 1e-6
        };
        assert!(cut.iter().all(on_edge), "{cut:?}");
        assert!((area2(&cut) - 2.0 * 520.0 * 320.0).abs() < 1e-3, "{cut:?}");
    }
}
