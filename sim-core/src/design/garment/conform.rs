//! Both sides of every seam meshed with their border vertices at the same places along
//! them, so that sewing pairs each vertex with one at its own place on the other side.
//!
//! Meshed on their own, two sides get their border vertices wherever each outline's
//! corners and the mesher's refinement put them: a shoulder of 14 cm split in five on one
//! piece, on the other in five plus a point the refinement added beside the neck (to keep
//! that corner's triangles' angles over 20 degrees). Sewing pairs each vertex with the
//! nearest by share of the length, and the weld then held a 6.6 mm side of the small
//! triangle at the neck at 11.8 mm: the dress's most stretched triangle (90%) sat there
//! whatever the solver, as the weld, not the cloth, set it.
//!
//! So the pieces are meshed twice. Before the first, each seam's two stretches are
//! resampled at the same shares of their lengths (the corners along either side, each gap
//! between them in equal parts no longer than the mesh's edge). The first meshing adds
//! border points where its refinement needs them; every piece's outline takes them, each
//! seam's two sides take each other's (merged where closer than a fifth of an edge), and
//! the second meshing keeps the border exactly as given. Which ends of a seam meet is
//! decided before meshing, from where the placements put them, as sewing decides it.

use glam::Vec2;

use super::spec::EdgeRef;
use crate::mesh::mesher::Outline;
use crate::mesh::{ClothMesh, MAX_VERTICES};

/// Arc length of each point of closed loop `l` from its first.
pub(crate) fn arc(l: &[Vec2]) -> Vec<f32> {
    let mut out = Vec::with_capacity(l.len() + 1);
    out.push(0.0);
    for i in 0..l.len() {
        let d = (l[(i + 1) % l.len()] - l[i]).length();
        out.push(out[i] + d);
    }
    out
}

/// Where `p` projects on closed loop `l` (arc lengths `cum`): its arc length and its
/// distance from the loop.
pub(crate) fn project(l: &[Vec2], cum: &[f32], p: Vec2) -> (f32, f32) {
    let mut best = (0.0, f32::INFINITY);
    for i in 0..l.len() {
        let (a, b) = (l[i], l[(i + 1) % l.len()]);
        let ab = b - a;
        let t = ((p - a).dot(ab) / ab.length_squared().max(1e-20)).clamp(0.0, 1.0);
        let d = (a + ab * t - p).length();
        if d < best.1 {
            best = (cum[i] + t * (cum[i + 1] - cum[i]), d);
        }
    }
    best
}

/// A turn of the outline that is a corner, kept where it is (as `mesher::simplify` does).
const CORNER_DEG: f32 = 30.0;

/// Shares closer than this many edge lengths apart (over the longer side) are one.
const MERGE: f32 = 0.2;

/// One side of a seam on a piece's outer loop: where along the loop it starts, and how
/// far it runs (m, along the loop's direction).
#[derive(Clone, Copy, Debug)]
struct Side {
    piece: usize,
    start: f32,
    span: f32,
}

impl Side {
    fn of(edge: &EdgeRef, loops: &[Outline]) -> Option<Self> {
        let l = &loops.get(edge.piece)?.loops[0];
        let cum = arc(l);
        let per = cum[l.len()];
        let (t0, d0) = project(l, &cum, edge.from);
        let (t1, d1) = project(l, &cum, edge.to);
        let span = (t1 - t0).rem_euclid(per);
        (d0 < 1e-4 && d1 < 1e-4 && span > 1e-6).then_some(Self {
            piece: edge.piece,
            start: t0,
            span,
        })
    }

    /// Where arc length `t` (from the loop's first point) is along this side, as a share
    /// of its length; None off it.
    fn share(&self, t: f32, per: f32) -> Option<f32> {
        let s = (t - self.start).rem_euclid(per);
        let s = if s > per - 1e-6 { 0.0 } else { s };
        (s <= self.span + 1e-6).then(|| (s / self.span).clamp(0.0, 1.0))
    }

    /// The shares along this side of the points of its loop strictly inside it that
    /// `keep` picks (by index).
    fn inner(&self, l: &[Vec2], keep: impl Fn(usize) -> bool) -> Vec<f32> {
        let cum = arc(l);
        let per = cum[l.len()];
        (0..l.len())
            .filter(|&i| keep(i))
            .filter_map(|i| self.share(cum[i], per))
            .filter(|&f| f > 1e-4 && f < 1.0 - 1e-4)
            .collect()
    }
}

/// A seam as the meshing sees it: its two sides, and whether the first's start meets the
/// second's end.
#[derive(Clone, Copy, Debug)]
pub(super) struct SeamSides {
    pub a: EdgeRef,
    pub b: EdgeRef,
    pub reversed: bool,
}

impl SeamSides {
    /// Share `f` along one side as a share along the other.
    fn across(&self, f: f32) -> f32 {
        if self.reversed { 1.0 - f } else { f }
    }

    fn sides(&self, loops: &[Outline]) -> Option<[Side; 2]> {
        Some([Side::of(&self.a, loops)?, Side::of(&self.b, loops)?])
    }

    /// Both sides resampled at `shares` (along the first; the second's mirrored when
    /// reversed).
    /// A side on the piece the first is on (a dart's legs) is found again after the
    /// first is resampled: the first's points moved, and with them where along the loop
    /// the second starts (found from the old loop, a dart's point came out twice, 0.01
    /// mm apart: a sliver triangle that a weld stretched 98x).
    fn apply(&self, loops: &mut [Outline], [a, b]: [Side; 2], shares: &[f32]) {
        let l = &mut loops[a.piece].loops[0];
        *l = resampled(l, &a, shares);
        let b = if b.piece == a.piece {
            match Side::of(&self.b, loops) {
                Some(b) => b,
                None => return,
            }
        } else {
            b
        };
        let other: Vec<f32> = shares.iter().map(|&f| self.across(f)).collect();
        let l = &mut loops[b.piece].loops[0];
        *l = resampled(l, &b, &other);
    }
}

/// The loop's point at arc length `t` (wrapping).
pub(crate) fn point_at(l: &[Vec2], cum: &[f32], t: f32) -> Vec2 {
    let per = cum[l.len()];
    let t = t.rem_euclid(per);
    let i = cum.partition_point(|&c| c <= t).clamp(1, l.len()) - 1;
    let len = (cum[i + 1] - cum[i]).max(1e-12);
    l[i].lerp(l[(i + 1) % l.len()], ((t - cum[i]) / len).clamp(0.0, 1.0))
}

/// Whether point `i` of loop `l` is a corner.
fn corner(l: &[Vec2], i: usize) -> bool {
    let n = l.len();
    let (a, p, b) = (l[(i + n - 1) % n], l[i], l[(i + 1) % n]);
    (p - a).normalize_or_zero().dot((b - p).normalize_or_zero()) < CORNER_DEG.to_radians().cos()
}

/// `shares` sorted, those closer than `gap` (or to an end) merged.
fn tidy(mut shares: Vec<f32>, gap: f32) -> Vec<f32> {
    shares.retain(|f| *f > gap && *f < 1.0 - gap);
    shares.sort_by(f32::total_cmp);
    let mut out: Vec<f32> = Vec::with_capacity(shares.len());
    for f in shares {
        if out.last().is_none_or(|&q| f - q > gap) {
            out.push(f);
        }
    }
    out
}

/// `fixed` shares with each gap between them (and the ends) split into equal parts of at
/// most `edge` over a side `len` long.
fn filled(fixed: &[f32], len: f32, edge: f32) -> Vec<f32> {
    let mut out = Vec::new();
    let mut bounds = vec![0.0];
    bounds.extend_from_slice(fixed);
    bounds.push(1.0);
    for w in bounds.windows(2) {
        // `assemble` has bounded the pieces' size over the edge; the clamp keeps a
        // count from a non-finite length from asking for all memory all the same.
        let parts = (((w[1] - w[0]) * len / edge).ceil() as usize).clamp(1, MAX_VERTICES);
        out.extend((1..parts).map(|k| w[0] + (w[1] - w[0]) * k as f32 / parts as f32));
        if w[1] < 1.0 {
            out.push(w[1]);
        }
    }
    out
}

/// Loop `l` with the points inside `side` replaced by ones at `shares` of its length.
fn resampled(l: &[Vec2], side: &Side, shares: &[f32]) -> Vec<Vec2> {
    let cum = arc(l);
    let per = cum[l.len()];
    // Every point with its arc length; the side's inner points give way to the shares.
    let mut at: Vec<(f32, Vec2)> = (0..l.len())
        .filter(|&i| {
            side.share(cum[i], per)
                .is_none_or(|f| f <= 1e-4 || f >= 1.0 - 1e-4)
        })
        .map(|i| (cum[i], l[i]))
        .collect();
    for t in [side.start, side.start + side.span] {
        let t = t.rem_euclid(per);
        let near = |s: f32| (s - t).abs().min(per - (s - t).abs()) < 1e-5;
        if !at.iter().any(|(s, _)| near(*s)) {
            at.push((t, point_at(l, &cum, t)));
        }
    }
    for &f in shares {
        let t = (side.start + f * side.span).rem_euclid(per);
        at.push((t, point_at(l, &cum, t)));
    }
    at.sort_by(|a, b| a.0.total_cmp(&b.0));
    at.into_iter().map(|(_, p)| p).collect()
}

/// Before the first meshing: every seam's two sides at the same shares (the corners
/// along either side, equal parts of at most `edge` between).
pub(super) fn conform(loops: &mut [Outline], seams: &[SeamSides], edge: f32) {
    for s in seams {
        let Some([a, b]) = s.sides(loops) else {
            continue;
        };
        let len = a.span.max(b.span);
        let (la, lb) = (&loops[a.piece].loops[0], &loops[b.piece].loops[0]);
        let mut fixed = a.inner(la, |i| corner(la, i));
        fixed.extend(
            b.inner(lb, |i| corner(lb, i))
                .into_iter()
                .map(|f| s.across(f)),
        );
        let shares = filled(&tidy(fixed, MERGE * edge / len), len, edge);
        s.apply(loops, [a, b], &shares);
    }
}

/// After the first meshing (`mesh`, each piece's vertices at `ranges`, its pattern moved
/// by `offsets` from `loops`): every loop of every piece with the border points the mesher
/// added, then each seam's two sides with each other's.
pub(super) fn agree(
    loops: &mut [Outline],
    seams: &[SeamSides],
    edge: f32,
    (mesh, ranges, offsets): (&ClothMesh, &[std::ops::Range<usize>], &[Vec2]),
) {
    for ((o, range), offset) in loops.iter_mut().zip(ranges).zip(offsets) {
        let own: Vec<Vec2> = mesh.positions[range.clone()]
            .iter()
            .map(|q| Vec2::new(q.x, -q.z) - *offset)
            .collect();
        for l in &mut o.loops {
            let cum = arc(l);
            let mut at: Vec<(f32, Vec2)> = own
                .iter()
                .filter_map(|&q| {
                    let (t, d) = project(l, &cum, q);
                    (d < 1e-5).then_some((t, q))
                })
                .collect();
            at.sort_by(|a, b| a.0.total_cmp(&b.0));
            if at.len() >= l.len() {
                *l = at.into_iter().map(|(_, q)| q).collect();
            }
        }
    }
    for s in seams {
        let Some([a, b]) = s.sides(loops) else {
            continue;
        };
        let mut all = a.inner(&loops[a.piece].loops[0], |_| true);
        all.extend(
            b.inner(&loops[b.piece].loops[0], |_| true)
                .into_iter()
                .map(|f| s.across(f)),
        );
        let gap = MERGE * edge / a.span.max(b.span);
        s.apply(loops, [a, b], &tidy(all, gap));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge_ref(piece: usize, from: [f32; 2], to: [f32; 2]) -> EdgeRef {
        EdgeRef {
            piece,
            from: Vec2::from(from),
            to: Vec2::from(to),
        }
    }

    fn shares(loops: &[Outline], side: &Side) -> Vec<f32> {
        let mut s = side.inner(&loops[side.piece].loops[0], |_| true);
        s.sort_by(f32::total_cmp);
        s
    }

    /// A square's top (with a bend in it) sewn, end to end reversed, to a longer
    /// rectangle's straight top.
    fn pair() -> (Vec<Outline>, SeamSides) {
        let loops = vec![
            Outline {
                loops: vec![vec![
                    Vec2::new(0.0, 0.0),
                    Vec2::new(0.3, 0.0),
                    Vec2::new(0.3, 0.3),
                    Vec2::new(0.15, 0.38),
                    Vec2::new(0.0, 0.3),
                ]],
            },
            Outline::rectangle(0.4, 0.3),
        ];
        let seam = SeamSides {
            a: edge_ref(0, [0.3, 0.3], [0.0, 0.3]),
            b: edge_ref(1, [0.4, 0.3], [0.0, 0.3]),
            reversed: true,
        };
        (loops, seam)
    }

    #[test]
    fn both_sides_get_points_at_the_same_shares() {
        let (mut loops, seam) = pair();
        conform(&mut loops, &[seam], 0.05);
        let [a, b] = seam.sides(&loops).unwrap();
        let fa = shares(&loops, &a);
        let mut fb: Vec<f32> = shares(&loops, &b).iter().map(|f| 1.0 - f).collect();
        fb.sort_by(f32::total_cmp);
        assert_eq!(fa.len(), fb.len(), "{fa:?} against {fb:?}");
        assert!(
            fa.iter().zip(&fb).all(|(x, y)| (x - y).abs() < 1e-4),
            "{fa:?} against {fb:?}"
        );
        // The bend stays where it was (halfway along), no part is longer than the edge,
        // and the rectangle's other corners are as they were.
        assert!(loops[0].loops[0].contains(&Vec2::new(0.15, 0.38)));
        let parts = fb.windows(2).map(|w| (w[1] - w[0]) * b.span);
        assert!(parts.clone().all(|p| p <= 0.05 + 1e-5), "{fb:?}");
        assert!(loops[1].loops[0].contains(&Vec2::new(0.4, 0.0)));
        assert_eq!(loops[1].loops[0].len(), 4 + fb.len());
    }

    /// A dart's legs on one piece, a V cut up from its bottom edge, each leg a little
    /// crooked (bends under the corner angle, which resampling straightens). Both legs
    /// are resampled alike, and the point is one point of the loop, not two a hundredth
    /// of a millimetre apart (as the second leg, found on the loop before the first was
    /// resampled, put it).
    #[test]
    fn a_darts_legs_on_one_piece_keep_one_point() {
        let apex = Vec2::new(0.2013, 0.2);
        let mut l = vec![Vec2::new(0.0, 0.0), Vec2::new(0.18, 0.0)];
        l.extend([0.04, 0.09, 0.13, 0.17].map(|y| Vec2::new(0.18 + 0.1 * y + 0.003, y)));
        l.push(apex);
        l.extend([0.16, 0.11, 0.07, 0.02].map(|y| Vec2::new(0.22 - 0.1 * y - 0.002, y)));
        l.extend([[0.22, 0.0], [0.4, 0.0], [0.4, 0.4], [0.0, 0.4]].map(Vec2::from));
        let mut loops = vec![Outline { loops: vec![l] }];
        let seam = SeamSides {
            a: edge_ref(0, [0.18, 0.0], apex.into()),
            b: edge_ref(0, apex.into(), [0.22, 0.0]),
            reversed: true,
        };
        conform(&mut loops, &[seam], 0.03);
        let l = &loops[0].loops[0];
        let n = l.len();
        let shortest = (0..n)
            .map(|i| (l[(i + 1) % n] - l[i]).length())
            .fold(f32::INFINITY, f32::min);
        assert!(shortest > 0.005, "a side {} mm long: {l:?}", shortest * 1e3);
        assert_eq!(l.iter().filter(|p| (**p - apex).length() < 1e-3).count(), 1);
        let [a, b] = seam.sides(&loops).unwrap();
        let fa = shares(&loops, &a);
        let mut fb: Vec<f32> = shares(&loops, &b).iter().map(|f| 1.0 - f).collect();
        fb.sort_by(f32::total_cmp);
        assert_eq!(fa.len(), fb.len(), "{fa:?} against {fb:?}");
        assert!(fa.iter().zip(&fb).all(|(x, y)| (x - y).abs() < 1e-3));
    }

    #[test]
    fn a_point_the_first_meshing_added_to_one_side_goes_to_the_other() {
        let (mut loops, seam) = pair();
        conform(&mut loops, &[seam], 0.05);
        // The first meshing split the square's top once more, a twentieth of the way
        // along it from its start (at 0.3, 0.3); the mesh is the outlines' points, laid
        // out at x + 1 and x + 3.
        let extra = Vec2::new(0.3, 0.3).lerp(Vec2::new(0.15, 0.38), 0.1);
        let mut first = loops.clone();
        first[0].loops[0].insert(3, extra);
        let offsets = [Vec2::new(1.0, 0.0), Vec2::new(3.0, 0.0)];
        let positions: Vec<glam::Vec3> = first
            .iter()
            .zip(&offsets)
            .flat_map(|(o, off)| {
                o.loops[0]
                    .iter()
                    .map(move |p| glam::Vec3::new(p.x + off.x, 0.0, -(p.y + off.y)))
            })
            .collect();
        let n0 = first[0].loops[0].len();
        let mesh = ClothMesh {
            positions,
            uvs: Vec::new(),
            triangles: Vec::new(),
        };
        let ranges = [0..n0, n0..mesh.positions.len()];
        agree(&mut loops, &[seam], 0.05, (&mesh, &ranges, &offsets));
        let l = &loops[0].loops[0];
        let i = l.iter().position(|p| (*p - extra).length() < 1e-6);
        let i = i.expect("the mesher's point kept");
        let [a, b] = seam.sides(&loops).unwrap();
        let fa = shares(&loops, &a);
        let fb = shares(&loops, &b);
        assert_eq!(fa.len(), fb.len(), "{fa:?} against {fb:?}");
        let cum = arc(l);
        let at = a.share(cum[i], cum[l.len()]).unwrap();
        assert!(
            fb.iter().any(|f| (1.0 - f - at).abs() < 1e-4),
            "{at} on the other side: {fb:?}"
        );
    }
}
