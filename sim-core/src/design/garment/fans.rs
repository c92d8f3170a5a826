//! Fans drawn in a pattern file (SVG, DXF): a circle skirt's panels, whose arcs reach us
//! as polylines. Found again ([`fan_in`]), such a panel starts at the body's waist on a
//! cone ([`super::cone`]), as GarmentCode's circle skirts do; where no cone there clears
//! the body (a full circle skirt's half rings, whose waist is a half circle of the
//! waist's own length), it starts flat in front of or behind the body, its top at the
//! waist, and is sewn in the air, as GarmentCode's full circle skirts are. Bent round the
//! torso's cylinder from the shoulders, as other pieces are, a circle skirt started
//! through the body or was refused as too wide (docs/garments.md).

use std::f32::consts::{FRAC_PI_2, PI};

use glam::{Mat3, Vec2, Vec3};

use super::cone::{self, Fan};
use super::place::{Landmarks, Place, Placement};

/// The fewest outline points an arc is found on.
const ARC_POINTS: usize = 5;

/// How far from its circle a point of an arc may lie: this many metres, or this share of
/// the radius if more. The SVG reader flattens curves to a tenth of a millimetre, and a
/// circle drawn as Bézier curves strays 0.03% of its radius from the circle.
const ARC_TOL: f32 = 5e-4;
const ARC_TOL_SHARE: f32 = 2e-3;

/// The largest radius of an arc, m: a run of points on a wider circle is a straight side.
const ARC_MAX_R: f32 = 5.0;

/// The least turn of an arc, radians (10 degrees): a gentle curve of a few points is a
/// side, not a fan's arc.
const ARC_MIN_TURN: f32 = 0.17;

/// Arcs round one centre: centres this share of the smaller radius apart, or 2 mm.
const SAME_CENTRE: f32 = 0.02;

/// The least difference of radius between a fan's top and its hem, m (as
/// [`cone::fan_of`]).
const FAN_DEPTH: f32 = 0.05;

/// The most points of an outline looked at for arcs: the search is quadratic in an
/// arc's points (a circle of 4,000 takes 8 million distances; a file's arcs flattened to
/// 0.1 mm give a few hundred).
const MOST_POINTS: usize = 4_000;

/// How far from the body's widest reach a fan started flat stands, m.
const FLAT_CLEARANCE: f32 = 0.03;

/// The circle through `a`, `b` and `c` (centre, radius); None when they are in line.
fn circle3(a: Vec2, b: Vec2, c: Vec2) -> Option<(Vec2, f32)> {
    let (ab, ac) = (b - a, c - a);
    let d = 2.0 * ab.perp_dot(ac);
    if d.abs() < 1e-12 {
        return None;
    }
    let (l1, l2) = (ab.length_squared(), ac.length_squared());
    let centre = a + Vec2::new(ac.y * l1 - ab.y * l2, ab.x * l2 - ac.x * l1) / d;
    let r = (a - centre).length();
    (r.is_finite() && r < ARC_MAX_R).then_some((centre, r))
}

/// The circle the points `pts` lie on (centre, radius, how far they turn round it), if
/// they do, going round it one way.
fn arc_over(pts: &[Vec2]) -> Option<(Vec2, f32, f32)> {
    let (a, b, c) = (pts[0], pts[pts.len() / 2], pts[pts.len() - 1]);
    let (centre, r) = circle3(a, b, c)?;
    let tol = ARC_TOL.max(ARC_TOL_SHARE * r);
    if pts.iter().any(|p| ((*p - centre).length() - r).abs() > tol) {
        return None;
    }
    let mut turn = 0.0f32;
    let mut sign = 0.0f32;
    for w in pts.windows(2) {
        let step = (w[0] - centre)
            .perp_dot(w[1] - centre)
            .atan2((w[0] - centre).dot(w[1] - centre));
        if step * sign < 0.0 {
            return None;
        }
        sign = if step != 0.0 { step.signum() } else { sign };
        turn += step;
    }
    Some((centre, r, turn.abs()))
}

/// An arc of an outline: its circle's centre and radius, its length, and its ends in
/// the outline's order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    pub centre: Vec2,
    pub r: f32,
    pub length: f32,
    pub ends: (Vec2, Vec2),
}

/// The circular arcs along the closed outline `outline`: the
/// longest runs of its points on one circle that turn round it by at least
/// [`ARC_MIN_TURN`], found from its sharpest corner on.
pub fn arcs_of(outline: &[Vec2]) -> Vec<Arc> {
    let n = outline.len();
    if !(ARC_POINTS..=MOST_POINTS).contains(&n) {
        return Vec::new();
    }
    // The turn at each point, and the walk from the sharpest (so that no arc is cut at
    // the loop's start), once round and back to it.
    let turn = |i: usize| {
        let (a, b, c) = (outline[(i + n - 1) % n], outline[i], outline[(i + 1) % n]);
        let (u, v) = (b - a, c - b);
        u.perp_dot(v).atan2(u.dot(v)).abs()
    };
    let first = (0..n)
        .max_by(|&a, &b| turn(a).total_cmp(&turn(b)))
        .unwrap_or(0);
    let walk: Vec<Vec2> = (0..=n).map(|k| outline[(first + k) % n]).collect();
    let mut arcs = Vec::new();
    let mut i = 0;
    while i + ARC_POINTS <= walk.len() {
        let mut j = i + ARC_POINTS - 1;
        let Some(mut arc) = arc_over(&walk[i..=j]) else {
            i += 1;
            continue;
        };
        while let Some(longer) = walk.get(j + 1).and_then(|_| arc_over(&walk[i..=j + 1])) {
            arc = longer;
            j += 1;
        }
        if arc.2 >= ARC_MIN_TURN {
            arcs.push(Arc {
                centre: arc.0,
                r: arc.1,
                length: arc.1 * arc.2,
                ends: (walk[i], walk[j]),
            });
        }
        i = j;
    }
    arcs
}

/// The fan an outline drawn as a polyline is, if it is one: two or more of its arcs
/// ([`arcs_of`]) round one centre whose radii differ by more than [`FAN_DEPTH`] (the most
/// arc length round one centre, where several are). Its centre is the arcs', weighted by
/// their lengths; its inner radius the top arc's; and the top arc's ends, in the
/// outline's order.
pub fn fan_in(outline: &[Vec2]) -> Option<(Fan, (Vec2, Vec2))> {
    let arcs = arcs_of(outline);
    let near = |a: &Arc, b: &Arc| {
        (a.centre - b.centre).length() <= (SAME_CENTRE * a.r.min(b.r)).max(0.002)
    };
    (arcs.iter())
        .filter_map(|a| {
            let round: Vec<&Arc> = arcs.iter().filter(|b| near(a, b)).collect();
            let top = round.iter().min_by(|a, b| a.r.total_cmp(&b.r))?;
            let outer = round.iter().map(|b| b.r).fold(0.0, f32::max);
            let length: f32 = round.iter().map(|b| b.length).sum();
            let centre = round.iter().map(|b| b.centre * b.length).sum::<Vec2>() / length;
            let fan = Fan {
                centre,
                inner: top.r,
            };
            (outer - top.r > FAN_DEPTH).then_some((length, fan, top.ends))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, fan, ends)| (fan, ends))
}

/// How a fan drawn in a pattern file starts: on a cone or flat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FanStart {
    /// On the narrowest cone round the body that clears it, its top arc a level circle
    /// at the waist.
    Cone(Placement),
    /// Flat, square to the way `place` faces, its top at the waist and
    /// [`FLAT_CLEARANCE`] outside the body's widest reach over its height; and where that
    /// starts crossing, bent round the torso's cylinder at the waist (the second).
    Flat(Placement, Placement),
}

/// A fan drawn in a pattern file, and where it starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanAt {
    pub start: FanStart,
    /// Its angle, radians.
    pub angle: f32,
    /// Its top arc's ends, in the outline's order: the waist, held while the skirt
    /// settles.
    pub top: (Vec2, Vec2),
}

/// How near a seam's end must be to a fan's top arc and to its hem, m, for the seam to
/// join the fan's two sides ([`closes_itself`]).
const ON_ARC: f32 = 0.01;

/// Whether a seam of a fan with itself, its two sides `sides` (each its ends), joins the
/// fan's two straight sides: each runs from the top arc (radius `fan.inner`) to the hem
/// (`outer`), as a circle skirt of one piece is sewn at its back. A dart's legs do not.
pub fn closes_itself(fan: &Fan, outer: f32, sides: [(Vec2, Vec2); 2]) -> bool {
    let at = |p: Vec2, r: f32| ((p - fan.centre).length() - r).abs() < ON_ARC;
    let spans = |(a, b): (Vec2, Vec2)| {
        (at(a, fan.inner) && at(b, outer)) || (at(b, fan.inner) && at(a, outer))
    };
    sides.into_iter().all(spans)
}

/// A fan that opens downward: a circle skirt's panel.
struct Downward {
    fan: Fan,
    /// Its top arc's ends, in the outline's order.
    top: (Vec2, Vec2),
    /// Its angle, radians.
    angle: f32,
    /// Its hem's radius, m.
    outer: f32,
}

/// The fan in `outline` ([`fan_in`]) if it opens downward and is at least
/// [`cone::FAN_MIN`] wide.
fn downward(outline: &[Vec2]) -> Option<Downward> {
    let (fan, top) = fan_in(outline)?;
    let m = cone::middle(fan.centre, crate::mesh::bounds2(outline));
    if m.y > -0.9 {
        return None;
    }
    let (angle, outer) = cone::extent(outline, fan.centre, m);
    (angle >= cone::FAN_MIN).then_some(Downward {
        fan,
        top,
        angle,
        outer,
    })
}

/// The top arc's ends (the waist, in the outline's order) of `outline` if it is a fan
/// that opens downward, wherever it starts: a circle skirt's panel whose file saved its
/// start ([`PatternSpec::start_where_saved`](super::PatternSpec::start_where_saved)).
pub fn skirt_top(outline: &[Vec2]) -> Option<(Vec2, Vec2)> {
    downward(outline).map(|d| d.top)
}

/// Where piece `outline` (its own coordinates, y up), placed by its name at `place`,
/// starts if it is a fan that opens downward (a circle skirt's panel) of at least
/// [`cone::FAN_MIN`] on a body whose waist is known. A fan sewn to itself (`seams`: the
/// piece's seams with itself, each side's ends; [`closes_itself`]) is a skirt of one
/// piece, and may go nearly all the way round; another, half of it. None for any other
/// piece, or at an arm.
pub fn fan_start(
    outline: &[Vec2],
    place: Place,
    marks: &Landmarks,
    seams: &[[(Vec2, Vec2); 2]],
) -> Option<FanAt> {
    let phi = match place {
        Place::Front => 0.0,
        Place::LeftSide => FRAC_PI_2,
        Place::Back => PI,
        Place::RightSide => 3.0 * FRAC_PI_2,
        Place::LeftArm | Place::RightArm => return None,
    };
    let waist = marks.waist?;
    let Downward {
        fan,
        top,
        angle,
        outer,
    } = downward(outline)?;
    let (lo, hi) = crate::mesh::bounds2(outline);
    let alone = seams.iter().any(|&s| closes_itself(&fan, outer, s));
    let share = if alone { 1.0 } else { 0.5 };
    if let Some(sine) =
        cone::cone_sine_within(angle, fan.inner, outer, waist, &marks.profile, share)
    {
        let on = Placement::Cone {
            angle: phi,
            top: waist,
            mirrored: false,
            centre: fan.centre,
            inner: fan.inner,
            sine,
        };
        let start = FanStart::Cone(on);
        return Some(FanAt { start, angle, top });
    }
    // Flat: the pattern's x round the body the way `place` faces (as bent round it), its
    // top middle at the waist, out from the axis past the body's widest reach.
    let rotation = Mat3::from_rotation_y(phi);
    let out = Vec3::new(phi.sin(), 0.0, phi.cos());
    let reach = marks.profile.widest(waist - (hi.y - lo.y), waist) + FLAT_CLEARANCE;
    let top_mid = Vec3::new(0.5 * (lo.x + hi.x), hi.y, 0.0);
    let at = Vec3::new(marks.axis.x, waist, marks.axis.y) + out * reach;
    let flat = Placement::Transform {
        rotation,
        translation: at - rotation * top_mid,
    };
    let start = FanStart::Flat(flat, place.at(waist));
    Some(FanAt { start, angle, top })
}

#[cfg(test)]
mod tests;
