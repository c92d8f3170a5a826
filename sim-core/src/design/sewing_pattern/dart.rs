//! Darts in the pattern out: found on a piece's outline, their cut line closed with a
//! dart cap, and their legs notched where they meet the cut line.
//!
//! A dart here is a seam on one piece whose two sides run into the piece from its
//! outline and meet at a point: a V cut into the edge (the studio's dart, cut twice to one
//! point and sewn up its legs). Its sewing line keeps the V: the legs are what is
//! stitched. Its cut line does not follow the V in and out again, as a plain offset
//! does (the two legs' allowances overlap where the dart is narrower than twice the
//! allowance, and no one cuts fabric twice): pattern CAD bridges the dart's mouth with a
//! dart cap, the shape the edge's allowance takes when the dart is folded shut and its
//! intake pressed to one side, and then unfolded. Cut on it, the dart's cloth is kept as
//! its intake, and the edge's allowance lies in one line once it is sewn.
//!
//! The construction, with the tip `T` at the origin, leg A (the side the outline comes
//! from) at angle 0 and leg B at the dart's angle `theta` (the intake between them):
//! - closed, side B turned by `-theta` about `T` so that leg B lies on leg A, the edge
//!   crosses the dart's line in one line; its allowance there is the offset of the last
//!   side before the mouth on A and the first after it on B, mitred;
//! - pressed toward A, the intake's two halves lie over side A, in the wedge from the
//!   dart's middle folded (angle `-theta / 2`) to leg A (angle 0), and a cut along that
//!   allowance cuts all three layers;
//! - unfolded, the half next to leg A is that wedge's cut mirrored in leg A, the half
//!   next to leg B the same cut turned back by `theta`: the two meet on the dart's middle
//!   line in the cap's point.
//!
//! Pressed toward B instead (`Seam::press_second`), the construction is its mirror
//! image: the loop mirrored and turned round, so that leg B leads, capped, and the cap
//! mirrored back.

use glam::DVec2;
use rustc_hash::FxHashMap as HashMap;

use super::Piece;

/// The widest dart (radians) given a cap: 60 degrees. A seam that turns a wider corner
/// on one piece is not a dart.
pub(crate) const WIDEST: f64 = std::f64::consts::FRAC_PI_3;

/// How much longer one leg of a dart may be than the other.
pub(crate) const LEGS_RATIO: f64 = 1.25;

/// The most outline edges, unsewn, between a dart's sewn legs: its seam can stop short
/// of its point (the studio's left 6 mm there; a drag that ends short of it, more), and
/// a dart cut on a coarse mesh can end in a short flat.
const TIP_EDGES: usize = 8;

/// How far an unsewn vertex between a dart's legs may lie from their lines, as a share
/// of the shorter leg: the V goes on to its point, or a flat joins the legs' ends.
const TIP_SHARE: f64 = 0.1;

/// A dart on a piece's outline: the indices in loop `loop_index` of its mouth's two
/// ends (leg A from `a`, leg B to `b`; the outline runs `a` .. `b` round the V), and its
/// tip: where the legs meet, or, where their seam stops short of it, where their lines
/// do.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Dart {
    pub label: String,
    pub loop_index: usize,
    pub a: usize,
    pub b: usize,
    pub tip: DVec2,
    /// Its intake pressed toward leg B (the piece's `press_second` names its label);
    /// otherwise toward leg A.
    pub second: bool,
}

/// How far inside a dart's point its drill hole goes, mm (at most a quarter of the way
/// to its mouth): hidden in the dart once it is sewn.
pub const DRILL_IN_MM: f64 = 10.0;

impl Dart {
    /// The drill hole marking the dart's point on the fabric: [`DRILL_IN_MM`] in from the
    /// point along the dart's middle, toward its mouth (in loop `loops[loop_index]`).
    pub fn drill(&self, loops: &[Vec<DVec2>]) -> DVec2 {
        let l = &loops[self.loop_index];
        let mouth = (l[self.a] + l[self.b]) * 0.5;
        let way = mouth - self.tip;
        self.tip + way.normalize_or_zero() * DRILL_IN_MM.min(0.25 * way.length())
    }

    /// The dart's press mark, with its label: from the dart's middle, a fifth of the
    /// way in from its mouth, to halfway toward the leg its intake is pressed to (in
    /// loop `loops[loop_index]`).
    pub fn press_mark(&self, loops: &[Vec<DVec2>]) -> (String, DVec2, DVec2) {
        let l = &loops[self.loop_index];
        let leg = if self.second { l[self.b] } else { l[self.a] };
        let mouth = (l[self.a] + l[self.b]) * 0.5;
        let from = self.tip.lerp(mouth, 0.8);
        let to = from.lerp(self.tip.lerp(leg, 0.8), 0.5);
        (self.label.clone(), from, to)
    }
}

/// A point's bits, to key an outline edge by its two ends.
fn bits(p: DVec2) -> [u64; 2] {
    [p.x.to_bits(), p.y.to_bits()]
}

/// Where the line through `p0`, `p1` meets the one through `q0`, `q1`; None if they are
/// (nearly) parallel.
fn meet(p0: DVec2, p1: DVec2, q0: DVec2, q1: DVec2) -> Option<DVec2> {
    let (u, v) = (p1 - p0, q1 - q0);
    let den = u.perp_dot(v);
    (den.abs() > 1e-9 * u.length() * v.length()).then(|| p0 + u * ((q0 - p0).perp_dot(v) / den))
}

/// The darts of piece `p` (its sewing line and seam segments; not laid out).
pub(super) fn darts(p: &Piece) -> Vec<Dart> {
    let mut label_of: HashMap<[[u64; 2]; 2], &str> = HashMap::default();
    for (label, a, b) in &p.seams {
        label_of.insert([bits(*a), bits(*b)], label);
        label_of.insert([bits(*b), bits(*a)], label);
    }
    let mut out: Vec<Dart> = Vec::new();
    for (li, l) in p.loops.iter().enumerate() {
        let n = l.len();
        if n < 5 {
            continue;
        }
        let edge = |i: usize| {
            label_of
                .get(&[bits(l[i % n]), bits(l[(i + 1) % n])])
                .copied()
        };
        // Leg A ends at vertex `e`; leg B starts `g` unsewn edges on.
        for e in 0..n {
            let Some(x) = edge(e + n - 1) else {
                continue;
            };
            let Some(g) = (0..=TIP_EDGES)
                .find(|&g| edge(e + g) == Some(x) && (0..g).all(|k| edge(e + k).is_none()))
            else {
                continue;
            };
            let s = (e + g) % n;
            let mut a = (e + n - 1) % n;
            let mut steps = 1;
            while edge(a + n - 1) == Some(x) && steps < n / 2 {
                a = (a + n - 1) % n;
                steps += 1;
            }
            let mut b = (s + 1) % n;
            steps = 1;
            while edge(b) == Some(x) && steps < n / 2 {
                b = (b + 1) % n;
                steps += 1;
            }
            let tip = if g == 0 {
                // A seam that runs on round the V: its point is the run's vertex
                // farthest from the mouth (any vertex up a leg starts a run too).
                let (m0, m1) = (l[a], l[b]);
                let off = |q: DVec2| (m1 - m0).normalize_or_zero().perp_dot(q - m0).abs();
                let run = (b + n - a) % n;
                let far = (1..run)
                    .map(|k| (a + k) % n)
                    .max_by(|&i, &j| off(l[i]).total_cmp(&off(l[j])));
                if far != Some(e) {
                    continue;
                }
                l[e]
            } else {
                match meet(l[a], l[e], l[s], l[b]) {
                    Some(t) => t,
                    None => continue,
                }
            };
            let (ta, tb) = (l[a] - tip, l[b] - tip);
            let (la, lb) = (ta.length(), tb.length());
            let legs_alike = la > 0.0 && lb > 0.0 && la.max(lb) <= LEGS_RATIO * la.min(lb);
            let off_line = |q: DVec2| {
                let from = |u: DVec2| u.normalize_or_zero().perp_dot(q - tip).abs();
                from(ta).min(from(tb))
            };
            let on_the_v = (1..g).all(|k| off_line(l[(e + k) % n]) <= TIP_SHARE * la.min(lb));
            if !legs_alike || !on_the_v || a == b {
                continue;
            }
            // A V into the material (which lies left of the loop's way round): leg B is
            // counter-clockwise of leg A, the two within the widest dart.
            let theta = ta.perp_dot(tb).atan2(ta.dot(tb));
            if !(theta > 0.0 && theta <= WIDEST)
                || out.iter().any(|d| d.a == a && d.loop_index == li)
            {
                continue;
            }
            out.push(Dart {
                label: x.to_string(),
                loop_index: li,
                a,
                b,
                tip,
                second: p.press_second.iter().any(|l| l == x),
            });
        }
    }
    out
}

/// `p` turned by `angle` about `c`.
fn turn(p: DVec2, c: DVec2, angle: f64) -> DVec2 {
    c + DVec2::from_angle(angle).rotate(p - c)
}

/// The unit normal to the right of the way from `p` to `q` (away from the material).
fn right(p: DVec2, q: DVec2) -> DVec2 {
    let t = (q - p).normalize_or_zero();
    DVec2::new(t.y, -t.x)
}

/// Where the line from `o` along `u` meets segment `a`-`b`: `(s, r)`, the point `o + u s`
/// at share `r` (clamped to 0..1) of the way from `a`; None if they are parallel or it
/// misses the segment. A hit at a segment's end counts to rounding (a symmetric dart at a
/// straight edge has its cap's mitre exactly on the legs' lines).
pub(crate) fn line_hit(o: DVec2, u: DVec2, a: DVec2, b: DVec2) -> Option<(f64, f64)> {
    let d = b - a;
    let den = u.perp_dot(d);
    if den.abs() < 1e-12 {
        return None;
    }
    let r = (a - o).perp_dot(u) / den;
    (-1e-7..=1.0 + 1e-7)
        .contains(&r)
        .then(|| ((a - o).perp_dot(d) / den, r.clamp(0.0, 1.0)))
}

/// Where the line from `o` along `u` (forwards only) meets polyline `q`, as an index along
/// it (segment `k` from `q[k]` to `q[k + 1]` spans `k..k + 1`): the first such place.
fn ray_hit(o: DVec2, u: DVec2, q: &[DVec2]) -> Option<f64> {
    (q.windows(2).enumerate()).find_map(|(k, w)| {
        let (s, r) = line_hit(o, u, w[0], w[1])?;
        (s > 0.0).then_some(k as f64 + r)
    })
}

/// The cut line across dart `dart` of loop `l` for an allowance `d` (see the module):
/// the points from where the edge's allowance before the mouth meets leg A's line,
/// over the cap's point, to where the allowance after it meets leg B's line. None when
/// the allowance does not cross the dart's lines as a cap's does (a dart at a corner,
/// its edge folding back).
pub(super) fn cap(l: &[DVec2], d: f64, dart: &Dart) -> Option<Vec<DVec2>> {
    if !dart.second {
        return cap_toward_a(l, d, dart);
    }
    // Pressed toward B: mirrored (x to -x) and turned round, the loop is still
    // counter-clockwise with the material on its left, and leg B leads.
    let n = l.len();
    let mirror = |p: DVec2| DVec2::new(-p.x, p.y);
    let turned: Vec<DVec2> = l.iter().rev().map(|&p| mirror(p)).collect();
    let led_by_b = Dart {
        a: n - 1 - dart.b,
        b: n - 1 - dart.a,
        tip: mirror(dart.tip),
        second: false,
        ..dart.clone()
    };
    let mut out: Vec<DVec2> = (cap_toward_a(&turned, d, &led_by_b)?.into_iter())
        .map(mirror)
        .collect();
    // From leg A's side to leg B's, as the loop runs.
    out.reverse();
    Some(out)
}

/// [`cap`] pressed toward leg A.
fn cap_toward_a(l: &[DVec2], d: f64, dart: &Dart) -> Option<Vec<DVec2>> {
    let n = l.len();
    let t = dart.tip;
    let (a, b) = (l[dart.a], l[dart.b]);
    let (a_prev, b_next) = (l[(dart.a + n - 1) % n], l[(dart.b + 1) % n]);
    let ua = (a - t).normalize_or_zero();
    let theta = ua.perp_dot(b - t).atan2(ua.dot(b - t));
    // Closed: side B turned onto side A.
    let (q0, q1) = (a_prev, a);
    let (q2, q3) = (turn(b, t, -theta), turn(b_next, t, -theta));
    let (d1, d2) = ((q1 - q0).normalize_or_zero(), (q3 - q2).normalize_or_zero());
    let (p1, p2) = (q1 + right(q0, q1) * d, q2 + right(q2, q3) * d);
    let den = d1.perp_dot(d2);
    let mitre = (den.abs() > 1e-9).then(|| p1 + d1 * ((p2 - p1).perp_dot(d2) / den));
    let far = 10.0 * (a.distance(t) + b.distance(t) + d);
    let m = match mitre {
        Some(m) if m.distance(q1) <= 4.0 * d => m,
        // No mitre near: the two lines run nearly parallel, apart by the step between
        // legs of different lengths.
        _ => return stepped(t, ua, theta, (p1, d1), (p2, d2), far),
    };
    // The closed allowance: the two offset lines, long enough to cross both rays.
    let q = [m - d1 * far, m, m + d2 * far];
    let at = |s: f64| {
        let k = (s.floor() as usize).min(1);
        q[k].lerp(q[k + 1], s - k as f64)
    };
    let middle = DVec2::from_angle(-0.5 * theta).rotate(ua);
    let (sc, s0) = (ray_hit(t, middle, &q)?, ray_hit(t, ua, &q)?);
    if sc >= s0 {
        return None;
    }
    let (c, pa) = (at(sc), at(s0));
    // The wedge's cut, from the dart's middle folded to leg A.
    let mut wedge = vec![c];
    if sc < 1.0 && 1.0 < s0 {
        wedge.push(m);
    }
    wedge.push(pa);
    let mirror = |p: DVec2| t + ua * (2.0 * (p - t).dot(ua)) - (p - t);
    let back = |p: DVec2| turn(p, t, theta);
    let mut out = Vec::new();
    if s0 > 1.0 {
        out.push(m);
    }
    out.push(pa);
    out.extend(wedge.iter().rev().skip(1).map(|&p| mirror(p)));
    out.extend(wedge.iter().skip(1).map(|&p| back(p)));
    if s0 < 1.0 {
        out.push(back(m));
    }
    Some(out)
}

/// [`cap_toward_a`] where the dart's legs differ in length and closed, the edge steps
/// along the dart's line from the end of one leg to the end of the other (a leaning dart
/// at a straight edge: pattern CAD trues such legs by redrawing the edge, which here is
/// the cloth as it was simulated). The intake, pressed toward A, lies on side A, so its
/// cut is side A's allowance (`p1` along `d1`) from the dart's middle folded to the
/// dart's line; unfolded, it starts where side A's own allowance meets leg A and ends on
/// leg B's line, which it follows to where side B's own allowance (`p2` along `d2`,
/// turned onto A) meets it. Both sides' cut lines so run into the cap without a jog.
/// Points past `far` from the tip are no cap (None).
fn stepped(
    t: DVec2,
    ua: DVec2,
    theta: f64,
    (p1, d1): (DVec2, DVec2),
    (p2, d2): (DVec2, DVec2),
    far: f64,
) -> Option<Vec<DVec2>> {
    let on_ray = |p: DVec2, u: DVec2, dir: DVec2| {
        let h = meet(p, p + u, t, t + dir)?;
        ((h - t).dot(dir) > 0.0 && h.distance(t) < far).then_some(h)
    };
    let middle = DVec2::from_angle(-0.5 * theta).rotate(ua);
    let (c, ha, hb) = (
        on_ray(p1, d1, middle)?,
        on_ray(p1, d1, ua)?,
        on_ray(p2, d2, ua)?,
    );
    if (c - p1).dot(d1) >= (ha - p1).dot(d1) {
        return None;
    }
    let mirror = t + ua * (2.0 * (c - t).dot(ua)) - (c - t);
    Some(vec![ha, mirror, turn(ha, t, theta), turn(hb, t, theta)])
}

/// Loop `l`'s cut line for an allowance `d`: its offset (`super::offset`), with each
/// dart of `darts` (all on this loop) bridged by its cap instead of followed in and out.
pub(super) fn cut_line(l: &[DVec2], d: f64, darts: &[&Dart]) -> Vec<DVec2> {
    let tagged = super::offset_tagged(l, d);
    let n = l.len();
    // Each capped dart's vertices, mouth to mouth, and its cap.
    let caps: Vec<(Vec<usize>, Vec<DVec2>)> = darts
        .iter()
        .filter_map(|dart| {
            let cap = cap(l, d, dart)?;
            let span = (dart.b + n - dart.a) % n;
            Some(((0..=span).map(|k| (dart.a + k) % n).collect(), cap))
        })
        .collect();
    let mut out = Vec::with_capacity(tagged.len());
    let mut placed = vec![false; caps.len()];
    for (i, p) in tagged {
        match caps.iter().position(|(span, _)| span.contains(&i)) {
            Some(k) if !placed[k] => {
                placed[k] = true;
                out.extend_from_slice(&caps[k].1);
            }
            Some(_) => {}
            None => out.push(p),
        }
    }
    out
}

/// Where the cut line `cut` (its loops) meets the line of a dart's leg beyond its mouth:
/// from `mouth` away from `tip`; the nearest such place, or the mouth itself when none is
/// within a metre.
pub(super) fn leg_on_cut(cut: &[Vec<DVec2>], tip: DVec2, mouth: DVec2) -> DVec2 {
    let u = (mouth - tip).normalize_or_zero();
    let mut best: Option<DVec2> = None;
    for l in cut {
        let closed: Vec<DVec2> = l.iter().chain(l.first()).copied().collect();
        for w in closed.windows(2) {
            let Some((s, _)) = line_hit(mouth, u, w[0], w[1]) else {
                continue;
            };
            if (-1e-9..1000.0).contains(&s) {
                let p = mouth + u * s;
                if best.is_none_or(|b| b.distance(mouth) > p.distance(mouth)) {
                    best = Some(p);
                }
            }
        }
    }
    best.unwrap_or(mouth)
}

#[cfg(test)]
mod tests;
