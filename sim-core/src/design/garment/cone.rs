//! Fans on cones. A circle skirt's panel is a fan: its top an arc round a centre above
//! it, its hem a longer arc round the same centre. Bent round the torso's cylinder by its
//! width, a fan wider than the way round the body cannot start (GarmentCode's circle
//! skirts are 1.4-1.6 m wide against 1.29 m round the human body's cylinder). But a fan
//! is a cone unrolled: rolled up again round the body's axis, its top a level circle at
//! the waist and every ruling a straight line down and out, it starts with no side
//! stretched and clear of the hips.
//!
//! The cone's half angle `alpha` decides both how far round the fan goes (an arc of radius
//! `R` round the fan's centre becomes a circle of radius `R sin(alpha)`: the fan's angle
//! grows by `1 / sin(alpha)`) and how steeply it falls. The narrowest cone whose every
//! height clears the body's widest reach there (arms left out) is taken, going at most
//! half way round, so that a front and a back fan do not meet.

use glam::{Vec2, Vec3};

/// The height of one band of a body's [`Profile`], m.
pub const BAND: f32 = 0.05;

/// Bands in a [`Profile`]: 2.4 m, a standing body's height and more.
pub const BANDS: usize = 48;

/// How far a cone stays outside the body's widest reach at each height, m.
pub const CLEARANCE: f32 = 0.015;

/// The longest fan, and the highest top above the feet, a cone is sought for, m.
const MOST: f32 = 10.0;

/// How far round the body a fan may go, as a share of the way allotted to it (half of
/// it for each of a circle skirt's front and back): a gap is left at either side.
const HALF_ROUND: f32 = 0.95;

/// The least angle of a fan (radians) for it to start on a cone: 45 degrees. A narrower
/// one (a waistband cut as a gentle arc, GarmentCode's 10-35 degrees) is nearly straight
/// and goes round the torso's cylinder with the pieces it is sewn to.
pub const FAN_MIN: f32 = std::f32::consts::FRAC_PI_4;

/// A body's widest reach from its vertical axis in each band of heights up from its
/// lowest point, its arms left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Profile {
    /// The height of the lowest band's bottom (the body's feet), m.
    pub base: f32,
    pub radii: [f32; BANDS],
    /// The way round the body in each band, m: the perimeter of the convex hull of its
    /// vertices there seen from above, the shortest loop that goes round it (a waist
    /// shorter than the hips' cannot pass them without stretching).
    pub girths: [f32; BANDS],
}

impl Profile {
    /// Of `vertices` (the body's), measured from `axis` (x, z); vertices more than `half`
    /// across from the axis (the arms, held out or hanging beside the hips) are left out.
    pub fn of(vertices: &[Vec3], axis: Vec2, half: f32) -> Self {
        let base = vertices.iter().map(|v| v.y).fold(f32::INFINITY, f32::min);
        let base = if base.is_finite() { base } else { 0.0 };
        let mut radii = [0.0f32; BANDS];
        let mut bands: Vec<Vec<Vec2>> = vec![Vec::new(); BANDS];
        for v in vertices {
            if (v.x - axis.x).abs() > half || !v.is_finite() {
                continue;
            }
            let k = ((v.y - base) / BAND) as usize;
            if let (Some(r), Some(band)) = (radii.get_mut(k), bands.get_mut(k)) {
                let p = Vec2::new(v.x - axis.x, v.z - axis.y);
                *r = r.max(p.length());
                band.push(p);
            }
        }
        let mut girths = [0.0f32; BANDS];
        for (g, band) in girths.iter_mut().zip(&mut bands) {
            *g = hull_perimeter(band);
        }
        Self {
            base,
            radii,
            girths,
        }
    }

    /// The same reach `r` at every height from `base` up.
    pub fn uniform(base: f32, r: f32) -> Self {
        Self {
            base,
            radii: [r; BANDS],
            girths: [std::f32::consts::TAU * r; BANDS],
        }
    }

    /// The longest way round the body in the bands between heights `lo` and `hi`, m.
    pub fn widest_girth(&self, lo: f32, hi: f32) -> f32 {
        let band = |y: f32| ((y - self.base) / BAND).clamp(0.0, (BANDS - 1) as f32) as usize;
        self.girths[band(lo)..=band(hi).max(band(lo))]
            .iter()
            .fold(0.0, |a, &b| a.max(b))
    }

    /// The widest reach in the bands between heights `lo` and `hi`.
    pub fn widest(&self, lo: f32, hi: f32) -> f32 {
        let band = |y: f32| ((y - self.base) / BAND).clamp(0.0, (BANDS - 1) as f32) as usize;
        self.radii[band(lo)..=band(hi).max(band(lo))]
            .iter()
            .fold(0.0, |a, &b| a.max(b))
    }
}

/// A fan: the centre its concentric circular arcs share, in the panel's own pattern
/// coordinates, and the radius of the innermost, its top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fan {
    pub centre: Vec2,
    pub inner: f32,
}

/// The fan among a panel's circular arcs (`(centre, radius)`, m): two or more round one
/// centre (within a millimetre) whose radii differ by more than 5 cm. None if there is
/// none.
pub fn fan_of(arcs: &[(Vec2, f32)]) -> Option<Fan> {
    arcs.iter().find_map(|&(c, r)| {
        let round: Vec<f32> = (arcs.iter())
            .filter(|(d, _)| (*d - c).length() < 1e-3)
            .map(|&(_, s)| s)
            .collect();
        let inner = round.iter().copied().fold(f32::INFINITY, f32::min);
        let outer = round.iter().copied().fold(0.0, f32::max);
        (outer - inner > 0.05 && inner > 0.0 && r == inner).then_some(Fan { centre: c, inner })
    })
}

/// The perimeter of the convex hull of `points` (sorted in place), m: 0 for fewer than
/// two. Andrew's monotone chain.
fn hull_perimeter(points: &mut [Vec2]) -> f32 {
    if points.len() < 2 {
        return 0.0;
    }
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let turns_left = |h: &[Vec2], p: Vec2| {
        let (o, a) = (h[h.len() - 2], h[h.len() - 1]);
        (a - o).perp_dot(p - o) > 0.0
    };
    let mut hull: Vec<Vec2> = Vec::with_capacity(points.len() + 1);
    for &p in points.iter() {
        while hull.len() >= 2 && !turns_left(&hull, p) {
            hull.pop();
        }
        hull.push(p);
    }
    let lower = hull.len() + 1;
    for &p in points.iter().rev().skip(1) {
        while hull.len() >= lower && !turns_left(&hull, p) {
            hull.pop();
        }
        hull.push(p);
    }
    // The last point pushed is the first again.
    hull.windows(2).map(|w| (w[1] - w[0]).length()).sum()
}

/// The unit direction from a fan's centre to the middle of the panel (its outline bounds
/// `lo`..`hi`): down the fan.
pub fn middle(centre: Vec2, (lo, hi): (Vec2, Vec2)) -> Vec2 {
    ((lo + hi) * 0.5 - centre).normalize_or(Vec2::NEG_Y)
}

/// The angle of pattern point `p` round the fan's centre from its middle direction `m`,
/// positive towards the pattern's +x.
fn angle_of(p: Vec2, centre: Vec2, m: Vec2) -> f32 {
    let d = p - centre;
    m.perp_dot(d).atan2(m.dot(d))
}

/// The fan's angle (radians) and its farthest point from the centre (m), from its outline.
pub fn extent(outline: &[Vec2], centre: Vec2, m: Vec2) -> (f32, f32) {
    let (mut lo, mut hi, mut far) = (0.0f32, 0.0f32, 0.0f32);
    for &p in outline {
        let a = angle_of(p, centre, m);
        lo = lo.min(a);
        hi = hi.max(a);
        far = far.max((p - centre).length());
    }
    (hi - lo, far)
}

/// The sine of the half angle of the narrowest cone a fan (angle `angle`, top arc of
/// radius `inner`, its farthest point `outer` from the centre) can start on with its top
/// at height `top`: at every height it reaches at least [`CLEARANCE`] outside the body's
/// widest reach there, its lowest point above the body's feet, and it goes at most
/// [`HALF_ROUND`] of half the way round. None if no cone does (a fan whose top is tighter
/// than the body's waist: even laid flat, a ring at `top`, it would start inside it).
pub fn cone_sine(angle: f32, inner: f32, outer: f32, top: f32, profile: &Profile) -> Option<f32> {
    cone_sine_within(angle, inner, outer, top, profile, 0.5)
}

/// [`cone_sine`] for a fan that may go `share` of the way round (a half for one of a
/// front and a back; nearly all of it for a skirt of one fan sewn to itself), at most
/// [`HALF_ROUND`] of that.
pub fn cone_sine_within(
    angle: f32,
    inner: f32,
    outer: f32,
    top: f32,
    profile: &Profile,
    share: f32,
) -> Option<f32> {
    let clears = |s: f32| {
        let c = (1.0 - s * s).max(0.0).sqrt();
        let bottom = top - (outer - inner) * c;
        if bottom < profile.base + CLEARANCE {
            return false;
        }
        // Band by band down from the top; in each the cone is narrowest at its top.
        let mut y = top;
        loop {
            let lo = (y - BAND).max(bottom);
            let slant = if c > 1e-6 {
                inner + (top - y) / c
            } else {
                inner
            };
            if slant * s < profile.widest(lo, y) + CLEARANCE {
                return false;
            }
            if lo <= bottom {
                return true;
            }
            y = lo;
        }
    };
    let least = angle / (HALF_ROUND * std::f32::consts::TAU * share.clamp(0.0, 1.0));
    // A fan longer, or a top higher above the feet, than any garment's (a file's
    // nonsense) has no cone: and the bands walked down it stay few.
    let sane = inner > 0.0 && outer > inner && outer - inner < MOST && top - profile.base < MOST;
    if !sane || least > 1.0 || !clears(1.0) {
        return None;
    }
    // The clearance grows with the sine at every height: halve the interval.
    let (mut lo, mut hi) = (least.max(0.0), 1.0f32);
    if clears(lo) {
        return Some(lo.max(1e-3));
    }
    for _ in 0..24 {
        let mid = 0.5 * (lo + hi);
        if clears(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// The start positions of a fan's pattern points `pattern` (its outline bounds `lo`..`hi`)
/// on a cone round the vertical `axis` (x, z): the top arc (radius `inner` round `centre`)
/// a level circle at height `top`, the fan's middle at `angle` round the body (0 in front,
/// a quarter turn to the body's left), the pattern's +x going round to the body's left
/// unless `mirrored`. `sine`: of the cone's half angle, from [`cone_sine`].
#[allow(clippy::too_many_arguments)]
pub fn on_cone(
    pattern: &[Vec2],
    bounds: (Vec2, Vec2),
    centre: Vec2,
    inner: f32,
    sine: f32,
    angle: f32,
    top: f32,
    mirrored: bool,
    axis: Vec2,
) -> Vec<Vec3> {
    let s = if sine.is_finite() {
        sine.clamp(1e-3, 1.0)
    } else {
        1.0
    };
    let c = (1.0 - s * s).max(0.0).sqrt();
    let m = middle(centre, bounds);
    pattern
        .iter()
        .map(|&p| {
            let slant = (p - centre).length();
            let a = angle_of(p, centre, m);
            let a = if mirrored { -a } else { a };
            let phi = angle + a / s;
            let rho = slant * s;
            Vec3::new(
                axis.x + rho * phi.sin(),
                top - (slant - inner) * c,
                axis.y + rho * phi.cos(),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan round (0, 0.3) from radius 0.25 to 0.9, 100 degrees, as points on a grid of
    /// polar steps.
    fn fan_points() -> (Vec<Vec2>, Vec2) {
        let centre = Vec2::new(0.0, 0.3);
        let half = 50f32.to_radians();
        let mut pts = Vec::new();
        for i in 0..=20 {
            for j in 0..=20 {
                let r = 0.25 + 0.65 * i as f32 / 20.0;
                let a = -half + 2.0 * half * j as f32 / 20.0;
                pts.push(centre + Vec2::new(a.sin(), -a.cos()) * r);
            }
        }
        (pts, centre)
    }

    fn human_like() -> Profile {
        let mut p = Profile::uniform(0.0, 0.18);
        // A waist of 0.15 at 1.05-1.15 m, hips of 0.195 below.
        p.radii[21..23].fill(0.15);
        p.radii[14..21].fill(0.19);
        p
    }

    #[test]
    fn a_fan_rolls_up_on_a_cone_without_stretch_and_clear_of_the_body() {
        let (pts, centre) = fan_points();
        let bounds = crate::mesh::bounds2(&pts);
        let m = middle(centre, bounds);
        assert!((m - Vec2::NEG_Y).length() < 1e-3, "{m}");
        let (angle, outer) = extent(&pts, centre, m);
        assert!((angle.to_degrees() - 100.0).abs() < 0.1);
        let profile = human_like();
        let s = cone_sine(angle, 0.25, outer, 1.1, &profile).unwrap();
        // The narrowest that clears the waist: 0.15 + 0.015 over 0.25 (the hips below
        // clear by the cone's flare).
        assert!((s - 0.165 / 0.25).abs() < 2e-3, "{s}");
        let x = on_cone(&pts, bounds, centre, 0.25, s, 0.0, 1.1, false, Vec2::ZERO);
        // Every pair of pattern neighbours keeps its distance (to the chord).
        for i in 0..pts.len() {
            for j in i + 1..pts.len() {
                let d = (pts[i] - pts[j]).length();
                if d < 0.05 {
                    let e = (x[i] - x[j]).length();
                    assert!(e <= d + 1e-5 && e > d * 0.995, "{d} {e}");
                }
            }
        }
        for (p, q) in pts.iter().zip(&x) {
            // The top arc is level at 1.1 m, and nothing is above it.
            if ((*p - centre).length() - 0.25).abs() < 1e-5 {
                assert!((q.y - 1.1).abs() < 1e-5);
            }
            assert!(q.y <= 1.1 + 1e-5);
            // Outside the body's reach at its height, by the clearance.
            let k = (q.y / BAND) as usize;
            let r = Vec2::new(q.x, q.z).length();
            assert!(r >= profile.radii[k] + CLEARANCE - 1e-3, "{q}: {r}");
        }
        // Its middle in front, the pattern's +x round to the body's left (+X).
        let mid = x[pts.len() / 2];
        assert!(mid.z > 0.1 && mid.x.abs() < 1e-4, "{mid}");
        let right = x[20 * 21 + 20];
        assert!(right.x > 0.0, "{right}");
        // It goes round by its angle over the sine: 100 / 0.66 = 151.5 degrees.
        let round = |q: Vec3| q.x.atan2(q.z);
        let span = round(x[20 * 21 + 20]) - round(x[20 * 21]);
        assert!(
            (span.to_degrees() - 100.0 / s).abs() < 0.1,
            "{}",
            span.to_degrees()
        );
    }

    #[test]
    fn a_fan_tighter_than_the_waist_or_too_long_has_no_cone() {
        let p = human_like();
        // Its top arc, laid flat, 13 cm round the centre: inside the 15 cm waist.
        assert_eq!(cone_sine(1.0, 0.13, 0.8, 1.1, &p), None);
        // Three quarters of a circle: more than half way round on any cone.
        assert_eq!(cone_sine(4.7, 0.4, 0.8, 1.1, &p), None);
        // Longer than the fall to the floor on a steep cone: a flatter one, its hem
        // above the floor.
        let long = cone_sine(1.0, 0.25, 3.0, 1.1, &p).unwrap();
        let bottom = 1.1 - 2.75 * (1.0 - long * long).sqrt();
        assert!(
            long > 0.9 && (bottom - CLEARANCE).abs() < 1e-3,
            "{long} {bottom}"
        );
        // Longer than the fall to the floor on any cone.
        assert_eq!(cone_sine(1.0, 0.25, 3.0, 0.01, &p), None);
        // A file's nonsense: a fan a kilometre long, or its top 100 km up.
        assert_eq!(cone_sine(1.0, 0.25, 1000.0, 1.1, &p), None);
        assert_eq!(cone_sine(1.0, 0.25, 0.8, 1e5, &p), None);
        assert_eq!(cone_sine(1.0, 0.25, 0.8, f32::NAN, &p), None);
        // A wider top clears with a steeper cone.
        let a = cone_sine(1.0, 0.3, 0.8, 1.1, &p).unwrap();
        let b = cone_sine(1.0, 0.5, 0.8, 1.1, &p).unwrap();
        assert!(b < a, "{a} {b}");
    }

    #[test]
    fn fans_are_concentric_arcs_of_different_radii() {
        let c = Vec2::new(0.18, 0.16);
        let arcs = [
            (c, 1.033),
            (c + Vec2::splat(1e-4), 0.245),
            (Vec2::ZERO, 0.1),
        ];
        assert_eq!(
            fan_of(&arcs),
            Some(Fan {
                centre: c + Vec2::splat(1e-4),
                inner: 0.245
            })
        );
        // Two arcs round different centres, or of one radius (a waistband's two sides).
        assert_eq!(fan_of(&[(c, 1.0), (Vec2::ZERO, 0.3)]), None);
        assert_eq!(fan_of(&[(c, 0.626), (c, 0.626), (c, 0.66)]), None);
    }

    #[test]
    fn a_profile_leaves_the_arms_out() {
        let v = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.15, 1.07, 0.02),
            Vec3::new(0.45, 1.07, 0.0),
            Vec3::new(-0.1, 0.91, -0.05),
        ];
        let p = Profile::of(&v, Vec2::ZERO, 0.21);
        assert_eq!(p.base, 0.0);
        assert!((p.radii[21] - Vec2::new(0.15, 0.02).length()).abs() < 1e-6);
        assert!((p.radii[18] - Vec2::new(0.1, 0.05).length()).abs() < 1e-6);
        assert_eq!(p.radii[5], 0.0);
        assert!((p.widest(0.85, 1.1) - p.radii[21]).abs() < 1e-6);
    }

    #[test]
    fn a_girth_goes_round_the_outside_of_a_band() {
        // A 0.3 x 0.2 box with points inside and on its sides: 1.0 m round.
        let mut pts = vec![
            Vec2::new(0.1, 0.0),
            Vec2::new(-0.15, -0.1),
            Vec2::new(0.15, 0.1),
            Vec2::new(0.0, 0.1),
            Vec2::new(-0.15, 0.1),
            Vec2::new(0.15, -0.1),
            Vec2::new(0.0, 0.0),
            Vec2::new(-0.15, 0.0),
        ];
        assert!((hull_perimeter(&mut pts) - 1.0).abs() < 1e-5);
        assert_eq!(hull_perimeter(&mut [Vec2::ONE]), 0.0);
        // Round a circle of 0.15 m at the hips, a narrower one at the waist above.
        let ring = |r: f32, y: f32| {
            (0..64).map(move |k| {
                let a = k as f32 * std::f32::consts::TAU / 64.0;
                Vec3::new(r * a.cos(), y, r * a.sin())
            })
        };
        let v: Vec<Vec3> = ring(0.15, 0.87).chain(ring(0.12, 1.07)).collect();
        let p = Profile::of(&v, Vec2::ZERO, 0.21);
        let round = |r: f32| 128.0 * r * (std::f32::consts::PI / 64.0).sin();
        assert!((p.widest_girth(0.8, 1.1) - round(0.15)).abs() < 1e-4);
        assert!((p.widest_girth(1.0, 1.1) - round(0.12)).abs() < 1e-4);
        assert_eq!(p.widest_girth(1.5, 1.6), 0.0);
    }
}
