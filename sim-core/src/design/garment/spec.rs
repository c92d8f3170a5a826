//! A pattern as read from a file or made by hand, before it becomes cloth: named pieces
//! with their outlines, fabric, grain and (maybe) placement, and seams between stretches
//! of their outlines.

use glam::Vec2;

use super::fans::{FanStart, fan_start};
use super::place::{Landmarks, Place, Placement};
use crate::mesh::mesher::{Outline, signed_area2};

/// A piece of a pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct PieceSpec {
    pub name: String,
    /// Metres, the piece's own coordinates, y up; the outer loop first.
    pub outline: Outline,
    pub fabric: String,
    /// The warp's direction, radians from the pattern's x.
    pub grain: f32,
    /// `None`: arranged by [`PatternSpec::arrange`].
    pub placement: Option<Placement>,
    /// Where a pattern file of ours says the piece started: [`load_pattern`](super::load_pattern)
    /// makes it the placement, measured from its bounds (carried over to another body:
    /// [`PatternSpec::start_where_saved`]).
    pub start: Option<super::start::PieceStart>,
    /// Where the piece starts instead if `placement` would start it through the body or
    /// another piece: a GarmentCode panel kept flat where its file puts it falls back on
    /// the torso's cylinder (`garmentcode::kept_flat`).
    pub fallback: Option<Placement>,
}

/// A stretch of a piece's outer loop: from the outline point nearest `from` to the one
/// nearest `to`, going counter-clockwise (the way the outer loop runs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeRef {
    pub piece: usize,
    pub from: Vec2,
    pub to: Vec2,
}

/// A seam between two stretches. Which ends meet is the file's where it says
/// (`reversed`), otherwise decided by where the pieces start: the pairing whose ends lie
/// closer together.
#[derive(Clone, Debug, PartialEq)]
pub struct SeamSpec {
    pub label: String,
    pub a: EdgeRef,
    pub b: EdgeRef,
    /// Whether `a.from` meets `b.to` (and `a.to` meets `b.from`), or `a.from` meets
    /// `b.from`; `None`: the file does not say.
    pub reversed: Option<bool>,
}

/// A stretch kept on one side of a plane of the body's while the garment settles (see
/// [`Design::hold_while_draping`](crate::design::Design::hold_while_draping)): where
/// `normal . x >= level`, in the body's coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct HoldSpec {
    /// What is held, as the file names it (GarmentCode's `lower_interface`, a skirt's or
    /// trousers' waistband).
    pub label: String,
    pub edge: EdgeRef,
    pub normal: glam::Vec3,
    pub level: f32,
    /// Whether `level` was measured on the body the pattern is placed on (a fan's or a
    /// skirt's waist, [`super::fans`]); GarmentCode's are its own body's, and on another
    /// body move to that body's waist (`assemble::holds`).
    pub measured: bool,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct PatternSpec {
    pub pieces: Vec<PieceSpec>,
    pub seams: Vec<SeamSpec>,
    pub holds: Vec<HoldSpec>,
}

/// Why a pattern cannot be made into cloth.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SpecError {
    #[error("the pattern has no pieces")]
    NoPieces,
    #[error("seam {label}: it names piece {piece}, and the pattern has {count}")]
    NoPiece {
        label: String,
        piece: usize,
        count: usize,
    },
    #[error("seam {label}: a side has no length (it starts where it ends)")]
    EmptySide { label: String },
    #[error("seam {label}: both sides are the same stretch of piece {piece}")]
    SameSide { label: String, piece: String },
}

/// The default fabric of pieces a pattern does not give one.
pub const DEFAULT_FABRIC: &str = "cotton";

impl PatternSpec {
    /// Puts each outer loop counter-clockwise and each hole clockwise, gives duplicate
    /// names a number, and checks the seams.
    pub fn normalise(&mut self) -> Result<(), SpecError> {
        if self.pieces.is_empty() {
            return Err(SpecError::NoPieces);
        }
        for p in &mut self.pieces {
            for (i, l) in p.outline.loops.iter_mut().enumerate() {
                if (signed_area2(l) > 0.0) != (i == 0) {
                    l.reverse();
                }
            }
        }
        for i in 1..self.pieces.len() {
            let base = self.pieces[i].name.clone();
            let mut k = 1;
            while self.pieces[..i]
                .iter()
                .any(|p| p.name == self.pieces[i].name)
            {
                k += 1;
                self.pieces[i].name = format!("{base} ({k})");
            }
        }
        let count = self.pieces.len();
        for s in &self.seams {
            for side in [&s.a, &s.b] {
                if side.piece >= count {
                    return Err(SpecError::NoPiece {
                        label: s.label.clone(),
                        piece: side.piece,
                        count,
                    });
                }
                if (side.from - side.to).length() < 1e-6 {
                    return Err(SpecError::EmptySide {
                        label: s.label.clone(),
                    });
                }
            }
            let same = |p: Vec2, q: Vec2| (p - q).length() < 1e-4;
            if s.a.piece == s.b.piece
                && ((same(s.a.from, s.b.from) && same(s.a.to, s.b.to))
                    || (same(s.a.from, s.b.to) && same(s.a.to, s.b.from)))
            {
                return Err(SpecError::SameSide {
                    label: s.label.clone(),
                    piece: self.pieces[s.a.piece].name.clone(),
                });
            }
        }
        Ok(())
    }

    /// Starts every piece whose file saved its start (ours) where it started. On
    /// another body (landmarks more than 1 cm apart) the start is carried over: round
    /// the torso at the same angle, round the arm as it was, its height moved by as much
    /// as the shoulders differ (and a transform by as much as the axes do too); the
    /// notice returned says so. A skirt's piece among them is held at the waist as
    /// arranging would hold it ([`Self::hold_saved_skirt`]).
    pub fn start_where_saved(&mut self, marks: &Landmarks) -> Option<String> {
        let mut moved = (0, 0.0f32);
        let mut theirs: Option<String> = None;
        if let Some(waist) = marks.waist {
            for i in 0..self.pieces.len() {
                self.hold_saved_skirt(i, waist);
            }
        }
        for p in &mut self.pieces {
            let Some(s) = &p.start else { continue };
            if s.fits(marks) {
                p.placement = Some(s.placement);
            } else {
                let (placement, dy) = s.carried(marks);
                p.placement = Some(placement);
                moved = (moved.0 + 1, dy);
                theirs = theirs.or_else(|| s.body_name.clone());
            }
        }
        (moved.0 > 0).then(|| {
            format!(
                "{} of the pattern's pieces were placed for another body{}: they start as \
                 they did there, {:+.1} cm higher",
                moved.0,
                theirs.map_or(String::new(), |b| format!(" ({b})")),
                100.0 * moved.1
            )
        })
    }

    /// The bounds piece `i`'s placement measures from: its saved start's, or those of
    /// `outline` (the piece's outline as meshed).
    pub fn start_bounds(&self, i: usize, outline: &Outline) -> (Vec2, Vec2) {
        match self.pieces.get(i).and_then(|p| p.start.as_ref()) {
            Some(s) => s.bounds(),
            None => crate::mesh::bounds2(&outline.loops[0]),
        }
    }

    /// Places every piece that has no placement, by its name: "front", "back", "left"
    /// or "right" (a side), "sleeve" or "arm" with "left" or "right" (an arm, when the
    /// body has them); otherwise front and back in turn. Pieces at one place stand side
    /// by side there, 2 cm apart, in the order a viewer facing them reads the body's
    /// right and left, in rows no wider than half the way round the torso, each row 2 cm
    /// below the one before. Tops start above the shoulders, sleeves as far up their arms
    /// past the shoulder; a row of skirts (pieces so named) no higher than the body's
    /// waist. A fan (a circle skirt's panel, [`super::fans`]) starts at the waist on a
    /// cone, or flat where no cone clears the body. Says which pieces start so.
    pub fn arrange(&mut self, marks: &Landmarks) -> Vec<String> {
        let mut at: Vec<Option<Place>> = Vec::with_capacity(self.pieces.len());
        let mut turn = 0;
        for p in &self.pieces {
            if p.placement.is_some() {
                at.push(None);
                continue;
            }
            let n = p.name.to_ascii_lowercase();
            let has = |w: &str| n.contains(w);
            let (left, right) = (has("left"), has("right"));
            let place = if (has("sleeve") || has("arm")) && marks.arms.is_some() {
                if right {
                    Place::RightArm
                } else {
                    Place::LeftArm
                }
            } else if has("front") {
                Place::Front
            } else if has("back") {
                Place::Back
            } else if left && !right {
                Place::LeftSide
            } else if right && !left {
                Place::RightSide
            } else {
                turn += 1;
                if turn % 2 == 1 {
                    Place::Front
                } else {
                    Place::Back
                }
            };
            at.push(Some(place));
        }
        let said = self.start_fans(&mut at, marks);
        for place in [
            Place::Front,
            Place::Back,
            Place::LeftSide,
            Place::RightSide,
            Place::LeftArm,
            Place::RightArm,
        ] {
            let mut group: Vec<usize> = (0..self.pieces.len())
                .filter(|&i| at[i] == Some(place))
                .collect();
            // A viewer facing the front sees the body's right on their left; facing the
            // back, its left.
            let first_word = if place == Place::Back {
                "left"
            } else {
                "right"
            };
            group.sort_by_key(|&i| {
                let n = self.pieces[i].name.to_ascii_lowercase();
                (!n.contains(first_word), i)
            });
            let arm = matches!(place, Place::LeftArm | Place::RightArm);
            let gap = 0.02;
            // Rows no wider than half the way round the torso, each below the last: side
            // by side further, they would reach round into the arms (a front cut in two
            // at the waist, exported and imported again, started through the body).
            let round = if arm {
                f32::INFINITY
            } else {
                half_round(marks.torso)
            };
            // A sleeve starts as far up its arm's line past the shoulder as a top starts
            // above the shoulders: its cap then has less to climb over the shoulder's
            // round. Started at the shoulder on the mannequin's hanging arms, a cap's top
            // stayed round the arm 5 cm below the dress's shoulder point and held a
            // shoulder seam open (157 and 177 of 188 pairs welded; 188 at all three
            // densities started so; docs/garments.md).
            let mut top = if arm { -marks.lift } else { marks.shoulders };
            for row in rows_within(&group, |i| size(&self.pieces[i].outline), gap, round) {
                let skirts = (row.iter()).all(|&(i, _)| is_skirt(&self.pieces[i].name));
                if let (Some(waist), true, false) = (marks.waist, skirts, arm) {
                    top = top.min(waist);
                    for &(i, _) in &row {
                        self.hold_top(i, top);
                    }
                }
                let total: f32 =
                    row.iter().map(|r| r.1.x).sum::<f32>() + gap * (row.len() - 1) as f32;
                let mut s = -0.5 * total;
                for &(i, size) in &row {
                    let centre = s + 0.5 * size.x;
                    s += size.x + gap;
                    self.pieces[i].placement = Some(around_at(marks, place.at(top), centre));
                }
                top -= row.iter().map(|r| r.1.y).fold(0.0, f32::max) + gap;
            }
        }
        said
    }

    /// Holds piece `i`'s top (the run of its outline within [`TOP_RUN`] of its highest
    /// point), starting at height `top`, [`HOLD_BELOW_WAIST`] under it while the garment
    /// settles: a skirt's waist.
    fn hold_top(&mut self, i: usize, top: f32) {
        let p = &self.pieces[i];
        if let Some(ends) = top_run(&p.outline.loops[0]) {
            let hold = waist_hold(&p.name, i, ends, top);
            self.holds.push(hold);
        }
    }

    /// Holds piece `i`, if its file saved its start and it is a skirt's (a fan that opens
    /// downward, by its top arc; or a piece so named, by its top), at `waist` while the
    /// garment settles, as the design it was exported from held it. `assemble::holds`
    /// keeps the hold no higher than where the top starts.
    fn hold_saved_skirt(&mut self, i: usize, waist: f32) {
        let p = &self.pieces[i];
        if p.start.is_none() {
            return;
        }
        let outline = &p.outline.loops[0];
        let top = super::fans::skirt_top(outline)
            .or_else(|| is_skirt(&p.name).then(|| top_run(outline)).flatten());
        if let Some(ends) = top {
            let hold = waist_hold(&p.name, i, ends, waist);
            self.holds.push(hold);
        }
    }

    /// Starts each piece of `at` (placed by its name) that is a fan at the body's waist
    /// ([`fan_start`]), its top arc held there while it settles, and takes it out of
    /// `at`; says which.
    fn start_fans(&mut self, at: &mut [Option<Place>], marks: &Landmarks) -> Vec<String> {
        let mut said = Vec::new();
        for (i, p) in self.pieces.iter_mut().enumerate() {
            let own: Vec<[(Vec2, Vec2); 2]> = (self.seams.iter())
                .filter(|s| s.a.piece == i && s.b.piece == i)
                .map(|s| [(s.a.from, s.a.to), (s.b.from, s.b.to)])
                .collect();
            let outline = &p.outline.loops[0];
            let Some(fan) = at[i].and_then(|place| fan_start(outline, place, marks, &own)) else {
                continue;
            };
            at[i] = None;
            let waist = marks.waist.unwrap_or_default();
            self.holds.push(waist_hold(&p.name, i, fan.top, waist));
            let deg = fan.angle.to_degrees();
            said.push(match fan.start {
                FanStart::Cone(on) => {
                    p.placement = Some(on);
                    format!(
                        "{} starts on a cone round the body, its top at the waist ({waist:.2} m up): a fan of {deg:.0} degrees",
                        p.name
                    )
                }
                FanStart::Flat(flat, round) => {
                    p.placement = Some(flat);
                    p.fallback = Some(round);
                    format!(
                        "{} starts flat at the waist ({waist:.2} m up): a fan of {deg:.0} degrees, which no cone round the body takes without crossing it",
                        p.name
                    )
                }
            });
        }
        said
    }
}

/// How far below the waist a skirt's waist is held while it settles, m: it starts
/// there, and settles onto the body.
pub(super) const HOLD_BELOW_WAIST: f32 = 0.03;

/// The hold of piece `piece` (named `name`) by its stretch from `ends.0` to `ends.1`,
/// its waist, started at height `top`: kept above [`HOLD_BELOW_WAIST`] under it.
fn waist_hold(name: &str, piece: usize, (from, to): (Vec2, Vec2), top: f32) -> HoldSpec {
    HoldSpec {
        label: format!("{name}'s waist"),
        edge: EdgeRef { piece, from, to },
        normal: glam::Vec3::Y,
        level: top - HOLD_BELOW_WAIST,
        measured: true,
    }
}

/// How far below a piece's highest point its top run reaches, m.
const TOP_RUN: f32 = 0.01;

/// The longest run of the closed outline `l`'s points (in its order) within [`TOP_RUN`]
/// of its highest point: its first and last point. None where it is one point (a
/// peak), or every point (no top to speak of).
fn top_run(l: &[Vec2]) -> Option<(Vec2, Vec2)> {
    let n = l.len();
    let high = l.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    let near = |k: usize| l[k % n].y >= high - TOP_RUN;
    // From a point below the band, so that no run is cut at the loop's start.
    let low = (0..n).find(|&k| !near(k))?;
    let (mut best, mut run): (Option<(usize, usize)>, Option<usize>) = (None, None);
    for k in low..=low + n {
        match (near(k), run) {
            (true, None) => run = Some(k),
            (false, Some(a)) => {
                if best.is_none_or(|(b0, b1)| k - a > b1 - b0) {
                    best = Some((a, k));
                }
                run = None;
            }
            _ => {}
        }
    }
    let (a, b) = best.filter(|(a, b)| b - a >= 2)?;
    Some((l[a % n], l[(b - 1) % n]))
}

/// Whether a piece's name says it is a skirt's.
fn is_skirt(name: &str) -> bool {
    name.to_ascii_lowercase().contains("skirt")
}

/// `place` moved `centre` m round the torso (or its arm) from its middle.
fn around_at(marks: &Landmarks, mut placement: Placement, centre: f32) -> Placement {
    match &mut placement {
        Placement::Around { angle, .. } => {
            *angle = shift_angle(marks, *angle, centre);
        }
        Placement::Arm { angle, .. } => {
            let r = marks.arms.map_or(0.07, |a| a[0].2);
            *angle += centre / r;
        }
        Placement::Transform { .. } | Placement::Cone { .. } => {}
    }
    placement
}

/// Half the way round an ellipse of semi-axes `torso` (Ramanujan's perimeter), m.
fn half_round(torso: Vec2) -> f32 {
    let (a, b) = (torso.x, torso.y);
    let h = ((a - b) / (a + b)).powi(2);
    0.5 * std::f32::consts::PI * (a + b) * (1.0 + 3.0 * h / (10.0 + (4.0 - 3.0 * h).sqrt()))
}

/// The pieces `group` (each with its size, `size`) in rows, in order: a row takes pieces
/// while they fit side by side, `gap` apart, within `wide`; a piece wider than that has a
/// row of its own.
fn rows_within(
    group: &[usize],
    size: impl Fn(usize) -> Vec2,
    gap: f32,
    wide: f32,
) -> Vec<Vec<(usize, Vec2)>> {
    let mut rows: Vec<Vec<(usize, Vec2)>> = Vec::new();
    let mut used = 0.0;
    for &i in group {
        let s = size(i);
        match rows.last_mut() {
            Some(row) if used + gap + s.x <= wide => {
                row.push((i, s));
                used += gap + s.x;
            }
            _ => {
                rows.push(vec![(i, s)]);
                used = s.x;
            }
        }
    }
    rows
}

/// The size of an outline's outer loop (width, height), m.
fn size(o: &Outline) -> Vec2 {
    let (lo, hi) = crate::mesh::bounds2(o.loops.first().map_or(&[], |l| &l[..]));
    (hi - lo).max(Vec2::ZERO)
}

/// The angle `ds` m of arc round the torso cylinder on from `angle` (in small steps,
/// so a long shift follows the ellipse).
pub(super) fn shift_angle(marks: &Landmarks, angle: f32, ds: f32) -> f32 {
    let (a, b) = (marks.torso.x, marks.torso.y);
    let steps = 16;
    let mut phi = angle;
    for _ in 0..steps {
        // Arc length per radian at phi.
        let v = Vec2::new(a * phi.cos(), -b * phi.sin()).length().max(1e-3);
        phi += ds / steps as f32 / v;
    }
    phi
}

#[cfg(test)]
mod tests {
    use super::*;

    fn piece(name: &str, w: f32) -> PieceSpec {
        PieceSpec {
            name: name.into(),
            outline: Outline::rectangle(w, 0.5),
            fabric: DEFAULT_FABRIC.into(),
            grain: 0.0,
            placement: None,
            start: None,
            fallback: None,
        }
    }

    #[test]
    fn bad_seams_are_refused_and_names_made_unique() {
        let mut s = PatternSpec {
            pieces: vec![piece("a", 0.2), piece("a", 0.2)],
            ..Default::default()
        };
        s.normalise().unwrap();
        assert_eq!(s.pieces[1].name, "a (2)");
        let side = EdgeRef {
            piece: 0,
            from: Vec2::ZERO,
            to: Vec2::new(0.2, 0.0),
        };
        s.seams = vec![SeamSpec {
            reversed: None,
            label: "A".into(),
            a: side,
            b: EdgeRef {
                from: side.to,
                to: side.from,
                ..side
            },
        }];
        assert!(matches!(s.normalise(), Err(SpecError::SameSide { .. })));
        s.seams[0].b.piece = 7;
        assert!(matches!(s.normalise(), Err(SpecError::NoPiece { .. })));
        s.seams[0].b = EdgeRef {
            piece: 1,
            from: Vec2::ZERO,
            to: Vec2::ZERO,
        };
        assert!(matches!(s.normalise(), Err(SpecError::EmptySide { .. })));
        assert_eq!(PatternSpec::default().normalise(), Err(SpecError::NoPieces));
    }

    /// A piece's top run: the longest run of its outline along its top, in the outline's
    /// order, wherever the loop starts; none for a peak.
    #[test]
    fn a_top_run_is_the_outline_along_the_top_in_its_order() {
        let v = Vec2::new;
        // A trapezoid whose top has a point in its middle, counter-clockwise.
        let mut l = vec![
            v(0.0, 0.0),
            v(0.6, 0.0),
            v(0.5, 0.5),
            v(0.3, 0.505),
            v(0.1, 0.5),
        ];
        for _ in 0..l.len() {
            assert_eq!(top_run(&l), Some((v(0.5, 0.5), v(0.1, 0.5))), "{l:?}");
            l.rotate_left(1);
        }
        // A triangle's apex is no run; a waist dipping 5 cm between two stretches of the
        // top leaves the longer.
        assert_eq!(top_run(&[v(0.0, 0.0), v(1.0, 0.0), v(0.5, 1.0)]), None);
        let dip = [
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 0.5),
            v(0.85, 0.5),
            v(0.7, 0.5),
            v(0.5, 0.45),
            v(0.4, 0.5),
            v(0.0, 0.5),
        ];
        assert_eq!(top_run(&dip), Some((v(1.0, 0.5), v(0.7, 0.5))));
    }

    #[test]
    fn pieces_are_arranged_by_name_side_by_side() {
        let marks = Landmarks {
            axis: Vec2::ZERO,
            torso: Vec2::new(0.2, 0.15),
            shoulders: 1.5,
            lift: 0.0,
            arms: None,
            garmentcode: glam::Vec3::ZERO,
            profile: super::super::cone::Profile::uniform(0.0, 0.1),
            waist: None,
        };
        let mut s = PatternSpec {
            pieces: vec![
                piece("left front", 0.2),
                piece("right front", 0.2),
                piece("back", 0.4),
                piece("left sleeve", 0.2),
            ],
            ..Default::default()
        };
        s.arrange(&marks);
        let angle = |i: usize| match s.pieces[i].placement {
            Some(Placement::Around { angle, .. }) => angle,
            ref p => panic!("{p:?}"),
        };
        // The body's right front is on the viewer's left: a smaller angle.
        assert!(
            angle(1) < 0.0 && angle(0) > 0.0,
            "{} {}",
            angle(0),
            angle(1)
        );
        assert!((angle(2) - std::f32::consts::PI).abs() < 1e-6);
        // No arms on this body: the sleeve goes to the body's left side.
        assert!((angle(3) - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    /// Two pieces at the front wider together than half the way round the torso (a front
    /// cut in two at the waist and imported again) go in two rows, the second below the
    /// first, each in the middle; side by side they reached round into the arms.
    #[test]
    fn a_row_too_wide_for_the_front_goes_on_below() {
        let marks = Landmarks {
            axis: Vec2::ZERO,
            torso: Vec2::new(0.17, 0.12),
            shoulders: 1.5,
            lift: 0.0,
            arms: None,
            garmentcode: glam::Vec3::ZERO,
            profile: super::super::cone::Profile::uniform(0.0, 0.1),
            waist: None,
        };
        assert!((half_round(Vec2::splat(0.1)) - 0.1 * std::f32::consts::PI).abs() < 1e-6);
        let mut s = PatternSpec {
            pieces: vec![
                piece("front", 0.4),
                piece("front 2", 0.4),
                piece("back", 0.4),
            ],
            ..Default::default()
        };
        s.arrange(&marks);
        let at = |i: usize| match s.pieces[i].placement {
            Some(Placement::Around { angle, top, .. }) => (angle, top),
            ref p => panic!("{p:?}"),
        };
        assert_eq!(at(0), (0.0, 1.5));
        let (angle, top) = at(1);
        assert!(
            angle.abs() < 1e-6 && (top - (1.5 - 0.5 - 0.02)).abs() < 1e-6,
            "{:?}",
            at(1)
        );
        assert_eq!(at(2).1, 1.5);
    }
}
