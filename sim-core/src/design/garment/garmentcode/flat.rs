//! A GarmentCode panel kept flat where its file puts it: a full circle skirt's half ring.

use glam::{Mat3, Vec2, Vec3};

use super::super::place::{Landmarks, Placement};

/// How much wider than half the way round the torso's cylinder a panel's top must be to
/// be kept flat ([`kept_flat`]).
const FLAT_TOP: f32 = 0.95;

/// How far below a panel's top its top is measured, m.
const TOP_BAND: f32 = 0.02;

/// How tall a panel kept flat must be, m: a waistband as wide goes round the torso.
const FLAT_TALL: f32 = 0.15;

/// How far apart a panel's two runs along its top must be, m, for the top to be two
/// sides with a waist dipping between them ([`kept_flat`]).
const WAIST_GAP: f32 = 0.05;

/// Their transform (unlifted, as [`super::placement`] keeps it) for a full circle skirt's half
/// ring: a panel [`FLAT_TALL`] or taller whose top is two runs of its outline (the side
/// seams) with its waist dipping between them, wider from end to end than [`FLAT_TOP`]
/// of half the way round our torso. Bent round the torso's cylinder such a panel starts
/// wrapped past the body's sides, over the panel it is sewn to there, and its seams
/// cannot close through it (seed 13's design 11 left 15 of its 48 pairs open and never
/// settled); flat where GarmentCode puts it, it is sewn in the air as GarmentCode sews
/// it (docs/garments.md). A gathered skirt's panel, as wide but whose top is its waist
/// seam, one run, goes round the torso. None for others.
pub(crate) fn kept_flat(
    outline: &[Vec2],
    rot: Mat3,
    trans: Vec3,
    marks: &Landmarks,
) -> Option<Placement> {
    let height = |p: Vec2| (rot * p.extend(0.0)).y;
    let top = outline.iter().map(|&p| height(p)).fold(f32::MIN, f32::max);
    let low = outline.iter().map(|&p| height(p)).fold(f32::MAX, f32::min);
    let near = |p: Vec2| height(p) > top - TOP_BAND;
    // The stretches of x that the outline's sides along the top cover.
    let mut runs: Vec<(f32, f32)> = (0..outline.len())
        .map(|i| (outline[i], outline[(i + 1) % outline.len()]))
        .filter(|&(a, b)| near(a) && near(b))
        .map(|(a, b)| (a.x.min(b.x), a.x.max(b.x)))
        .collect();
    runs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (Some(first), Some(last)) = (runs.first(), runs.iter().map(|r| r.1).reduce(f32::max))
    else {
        return None;
    };
    let (mut reach, mut gap) = (first.1, 0.0f32);
    for &(lo, hi) in &runs[1..] {
        gap = gap.max(lo - reach);
        reach = reach.max(hi);
    }
    let wide = last - first.0 > FLAT_TOP * 0.5 * marks.girth();
    (wide && gap > WAIST_GAP && top - low >= FLAT_TALL).then(|| Placement::Transform {
        rotation: rot,
        translation: trans + marks.garmentcode,
    })
}

/// How many layers ([`super::super::LAYER`]) further from the body than its file puts it a
/// panel kept flat may start, where nearer it would start through the body or another
/// piece, before it falls back on the torso's cylinder: GarmentCode puts a skirt's back
/// 12.5 cm behind the axis, against `human`'s seat (its simulator lets a start touch the
/// body), its front 17.5 cm ahead.
pub(crate) const FLAT_OUT_TRIES: usize = 4;

/// `placement` (a panel kept flat, whose outline's bounds are `bounds`) moved `by` m
/// along its normal away from the body's axis; any other placement as it is.
pub(crate) fn moved_out(
    placement: Placement,
    bounds: (Vec2, Vec2),
    marks: &Landmarks,
    by: f32,
) -> Placement {
    let Placement::Transform {
        rotation,
        translation,
    } = placement
    else {
        return placement;
    };
    let centre = rotation * ((bounds.0 + bounds.1) * 0.5).extend(0.0) + translation;
    let radial = Vec2::new(centre.x - marks.axis.x, centre.z - marks.axis.y);
    let n = rotation * Vec3::Z;
    let away = if Vec2::new(n.x, n.z).dot(radial) < 0.0 {
        -n
    } else {
        n
    };
    Placement::Transform {
        rotation,
        translation: translation + away * by,
    }
}
