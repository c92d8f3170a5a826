//! Where a piece started on the body, as the pattern out carries it (SVG's `data-start`):
//! a pattern exported and draped again starts every piece where the design started it,
//! whatever its name says, when it is draped on the same body. A GarmentCode garment's
//! panels ("left_ftorso", "left_sleeve_b") have names arrangement cannot read, and
//! before 2026-12-06 its exported pattern started through the body and was refused.

use glam::{Vec2, Vec3};

use super::place::{Landmarks, Placement};
use crate::design::MAX_NAME;

/// How far apart two bodies' landmarks may be and the bodies still be the same, m.
const SAME_BODY: f32 = 0.01;

/// A piece's start as a pattern file records it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PieceStart {
    pub placement: Placement,
    /// The bounds its placement is measured from ([`super::place`]'s top middle), the
    /// piece's outline as it was made, in its own coordinates, m: `[lo.x, lo.y, hi.x,
    /// hi.y]`. A piece cut in two since starts each part where it was.
    pub bounds: [f32; 4],
    /// The landmarks of the body it was placed for ([`signature`]).
    pub body: Vec<f32>,
    /// That body's name (`human`, `mannequin`, ...): the pattern's own body
    /// ([`own_body`](super::own_body)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_name: Option<String>,
}

impl PieceStart {
    /// Its bounds as (lo, hi).
    pub fn bounds(&self) -> (Vec2, Vec2) {
        let b = self.bounds;
        (Vec2::new(b[0], b[1]), Vec2::new(b[2], b[3]))
    }

    /// Reads a file's record: JSON, every number within 100 (m or radians), bounds a box,
    /// at most 64 landmarks.
    pub fn parse(text: &str) -> Result<Self, String> {
        let s: Self = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let (lo, hi) = s.bounds();
        let within = |v: &f32| v.abs() <= MAX_NUMBER;
        if !(s.bounds.iter().all(within) && lo.x <= hi.x && lo.y <= hi.y) {
            return Err(format!("bounds {:?} are not a box", s.bounds));
        }
        if s.body.len() > MAX_LANDMARKS || !s.body.iter().all(within) {
            return Err("its body's landmarks are not a body's".into());
        }
        if s.body_name.as_ref().is_some_and(|n| n.len() > MAX_NAME) {
            return Err("its body's name is too long".into());
        }
        if !placement_numbers(&s.placement)
            .iter()
            .all(|v| v.abs() <= MAX_NUMBER)
        {
            return Err(format!(
                "its placement has a number that is not finite or is beyond {MAX_NUMBER}"
            ));
        }
        Ok(s)
    }

    /// Whether it was placed for the body with `marks`.
    pub fn fits(&self, marks: &Landmarks) -> bool {
        let here = signature(marks);
        self.body.len() == here.len()
            && (self.body.iter().zip(&here)).all(|(a, b)| (a - b).abs() <= SAME_BODY)
    }
}

impl PieceStart {
    /// Its placement carried over to the body with `marks` (see
    /// [`PatternSpec::start_where_saved`](super::PatternSpec::start_where_saved)), and
    /// how much higher it starts there, m.
    pub fn carried(&self, marks: &Landmarks) -> (Placement, f32) {
        let theirs = |i: usize| self.body.get(i).copied().unwrap_or(0.0);
        let dy = marks.shoulders - theirs(4);
        let axis = marks.axis - Vec2::new(theirs(0), theirs(1));
        let mut p = self.placement;
        match &mut p {
            Placement::Around { top, .. } | Placement::Cone { top, .. } => *top += dy,
            Placement::Transform { translation, .. } => {
                *translation += Vec3::new(axis.x, dy, axis.y);
            }
            Placement::Arm { .. } => {}
        }
        (p, dy)
    }
}

/// A body's landmarks as the numbers a start records: its axis, its torso's cylinder,
/// where tops start, and each arm's shoulder and wrist (zeros without arms). The lift
/// is left out: it only says where arrangement starts pieces.
pub fn signature(marks: &Landmarks) -> Vec<f32> {
    let mut s = vec![
        marks.axis.x,
        marks.axis.y,
        marks.torso.x,
        marks.torso.y,
        marks.shoulders,
    ];
    let arms = marks.arms.map_or([(Vec3::ZERO, Vec3::ZERO, 0.0); 2], |a| a);
    for (shoulder, wrist, _) in arms {
        s.extend(shoulder.to_array());
        s.extend(wrist.to_array());
    }
    s
}

/// The most landmarks a start may give its body ([`signature`] gives 17).
const MAX_LANDMARKS: usize = 64;

/// The largest number a start's placement may hold (metres or radians): a body's
/// landmarks lie within a few metres, and a start far beyond them is no start.
const MAX_NUMBER: f32 = 100.0;

/// Every number of a placement.
fn placement_numbers(p: &Placement) -> Vec<f32> {
    match *p {
        Placement::Around {
            angle, top, out, ..
        } => vec![angle, top, out],
        Placement::Arm {
            angle, down, room, ..
        } => vec![angle, down, room],
        Placement::Transform {
            rotation,
            translation,
        } => (rotation.to_cols_array().into_iter())
            .chain(translation.to_array())
            .collect(),
        Placement::Cone {
            angle,
            top,
            centre,
            inner,
            sine,
            ..
        } => vec![angle, top, centre.x, centre.y, inner, sine],
    }
}

/// Piece `r` of `design`'s start, when it has a placement, for the body with `marks`;
/// with where its own coordinates' origin lies among the cloth's rest positions (at
/// height `rest_y`, the pattern plane's: x and -z are the design's pattern plane).
pub(crate) fn record_start(
    design: &crate::design::Design,
    r: usize,
    marks: &Landmarks,
    rest_y: f32,
) -> Option<(PieceStart, Vec3)> {
    let rec = design.pieces.get(r)?;
    let placement = rec.placement?;
    let (lo, hi) = crate::mesh::bounds2(rec.outline.loops.first()?);
    let start = PieceStart {
        placement,
        bounds: rec
            .frame
            .as_deref()
            .copied()
            .unwrap_or([lo.x, lo.y, hi.x, hi.y]),
        body: signature(marks),
        body_name: design.sim.body.as_ref().map(|b| b.name.clone()),
    };
    Some((start, Vec3::new(rec.offset.x, rest_y, -rec.offset.y)))
}
