//! Arrangement: where a piece starts in 3D. A piece is bent round the body's torso
//! cylinder (an ellipse round its vertical axis) or round an arm, by arc length so no side
//! starts stretched, close to the body without touching it; or put at an explicit rigid
//! transform. Its rest shape stays the flat pattern: only its start positions are bent.
//!
//! Angles go round the body as a designer walks round a dress form: 0 in front (+Z),
//! a quarter turn to the body's left (+X), a half turn at the back. A piece's pattern x
//! runs the way a viewer facing it reads (to the viewer's right), so its front face, the
//! one the pattern is drawn from, faces out.

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use glam::{Mat3, Vec2, Vec3};

pub use super::cone::Profile;
use super::fit::waist_height;
use crate::collision::Body;
use crate::collision::body::{ARM_RADIUS, HUMAN, Pose};

/// The named places of a dress form, as a designer says them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    Front,
    Back,
    LeftSide,
    RightSide,
    LeftArm,
    RightArm,
}

impl Place {
    pub const ALL: &'static str = "front, back, left-side, right-side, left-arm, right-arm";

    pub fn parse(s: &str) -> Option<Self> {
        Some(
            match s
                .trim()
                .to_ascii_lowercase()
                .replace(['_', ' '], "-")
                .as_str()
            {
                "front" => Self::Front,
                "back" => Self::Back,
                "left-side" | "left" => Self::LeftSide,
                "right-side" | "right" => Self::RightSide,
                "left-arm" => Self::LeftArm,
                "right-arm" => Self::RightArm,
                _ => return None,
            },
        )
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Front => "front",
            Self::Back => "back",
            Self::LeftSide => "left-side",
            Self::RightSide => "right-side",
            Self::LeftArm => "left-arm",
            Self::RightArm => "right-arm",
        }
    }

    /// The placement at this place with the piece's top at height `top` m (for an arm:
    /// `top` m down the arm from the shoulder).
    pub fn at(self, top: f32) -> Placement {
        let around = |angle| Placement::Around {
            angle,
            top,
            mirrored: false,
            out: 0.0,
        };
        let arm = |left, angle| Placement::Arm {
            left,
            angle,
            down: top,
            mirrored: false,
            turn: 0,
            room: 0.0,
        };
        match self {
            Self::Front => around(0.0),
            Self::LeftSide => around(FRAC_PI_2),
            Self::Back => around(PI),
            Self::RightSide => around(3.0 * FRAC_PI_2),
            // The piece's middle faces out from the body, its sides meet under the arm:
            // a sleeve's cap on the shoulder, its underarm seam at the armpit, where the
            // armhole's two halves put them (with its middle to the front, its sides met
            // at the back of the arm, a quarter turn from the armpit).
            Self::LeftArm => arm(true, FRAC_PI_2),
            Self::RightArm => arm(false, -FRAC_PI_2),
        }
    }
}

/// Where a new or moved piece starts: a named place and how far, m, below that place's
/// own start its top goes (the shoulders round the torso; for an arm, down the arm from
/// the shoulder). A skirt's top at the mannequin's waist is about 0.42 m down.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    pub place: Place,
    pub drop: f32,
}

impl From<Place> for Start {
    fn from(place: Place) -> Self {
        Self { place, drop: 0.0 }
    }
}

/// The farthest a piece's top may start below its place's own start, m: from the
/// mannequin's shoulders to its knees.
pub const MAX_DROP: f32 = 1.0;

/// Where a piece starts. Pattern points are taken from the top middle of the piece's
/// outline bounds: across (x) and down (y, negative).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Placement {
    /// Round the torso cylinder, the piece's middle at `angle` (radians, see the module
    /// doc), its top at height `top` m. `mirrored`: the pattern's x runs the other way
    /// round (its back face out).
    Around {
        angle: f32,
        top: f32,
        mirrored: bool,
        /// How far outside the cylinder, m: a piece that would start where another
        /// does goes a layer out (see `assemble`).
        #[serde(default)]
        out: f32,
    },
    /// Round an arm (the body's left or right), the piece's middle facing `angle` round
    /// it (0 to the front), its top `down` m below the shoulder along the arm. `turn`:
    /// quarter turns (counter-clockwise) the pattern is turned by first, for a sleeve
    /// drawn with the arm along its x (GarmentCode's are); 0: its y runs up the arm.
    Arm {
        left: bool,
        angle: f32,
        down: f32,
        mirrored: bool,
        #[serde(default)]
        turn: u8,
        /// How much further out than the body's sleeve radius the piece starts, m: one
        /// of two halves of a sleeve or cuff wider than half the way round the arm.
        #[serde(default)]
        room: f32,
    },
    /// The pattern plane (x, y, 0), in the piece's own coordinates, turned by `rotation`
    /// and moved by `translation` (m).
    Transform { rotation: Mat3, translation: Vec3 },
    /// A fan (a circle skirt's panel) rolled up on a cone round the body's axis
    /// ([`super::cone`]): its top arc, of radius `inner` round `centre` (the piece's own
    /// pattern coordinates, m), a level circle at height `top`; the fan's middle at
    /// `angle` round the body; `sine` of the cone's half angle (1: laid flat).
    Cone {
        angle: f32,
        top: f32,
        mirrored: bool,
        centre: Vec2,
        inner: f32,
        sine: f32,
    },
}

/// What arrangement needs of a body: its vertical axis, the elliptic cylinder round its
/// torso that pieces start on, and its arms, if it has them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landmarks {
    /// The body's vertical axis (x, z), m.
    pub axis: Vec2,
    /// The cylinder's semi-axes across (x) and front to back (z), m.
    pub torso: Vec2,
    /// Where a top's pieces start, m: above the shoulders.
    pub shoulders: f32,
    /// How far above the body's own shoulders that is, m: the mannequin's 8 cm; 0 for a
    /// body known only by its bounds (its top stands for its shoulders).
    pub lift: f32,
    /// Left then right: shoulder, wrist and the radius pieces start at.
    pub arms: Option<[(Vec3, Vec3, f32); 2]>,
    /// Where GarmentCode's average body stands on ours (its origin, between its feet):
    /// its patterns are placed for it. Zero on the `human` body, which is that body.
    pub garmentcode: Vec3,
    /// The torso's and legs' widest reach from the axis at each height, for fans
    /// started on cones.
    pub profile: Profile,
    /// The body's waist height, m, where it is a standing figure (`fit`'s waist: the
    /// torso's narrowest girth between 56% and 70% of its height): where a skirt drawn in
    /// a pattern file starts.
    pub waist: Option<f32>,
}

/// GarmentCode's average body (our `human`) stands lower than the mannequin (the tops of
/// its shoulders at 1.44 m against 1.50 m, and the mannequin's balls stand higher still at
/// their outer ends): on the mannequin, and on a body known only by its bounds, its
/// panels are raised by this much, m, and by the body's `Landmarks::lift` on top, so that
/// a top starts above the shoulders as ours do (a pencil dress's straps started level
/// with the mannequin's shoulders, slid off them while the stitches pulled, and the dress
/// fell to the floor; docs/garments.md).
pub const GC_RAISE: f32 = 0.10;

/// The top of the mannequin's shoulders, m.
pub const MANNEQUIN_SHOULDERS: f32 = 1.50;

/// Where a top's pieces start on the mannequin, m: 8 cm above its shoulders,
/// so that the stitches close a shoulder seam while the pieces fall onto it. From 3 cm
/// above (1.53) the dress's front and back landed on the shoulders 23-36 mm short of
/// each other and friction held them there (43-45 of its 61 pairs welded in three runs,
/// 51-54 from here; docs/garments.md).
pub const MANNEQUIN_TOPS: f32 = MANNEQUIN_SHOULDERS + 0.08;

/// The top of the `human` body's shoulders, m.
pub const HUMAN_SHOULDERS: f32 = 1.44;

/// How far above the `human` body's shoulders a top's pieces start, m (as on the
/// mannequin).
const HUMAN_LIFT: f32 = 0.08;

/// The `human` body's left arm (+X): where its axis leaves the torso, and the wrist, m.
const HUMAN_ARM: [Vec3; 2] = [Vec3::new(0.21, 1.33, -0.03), Vec3::new(0.52, 1.035, 0.02)];

/// The `human` body's upper arm radius, m, and the room round it a sleeve starts in.
const HUMAN_ARM_RADIUS: f32 = 0.05;
const HUMAN_ARM_ROOM: f32 = 0.035;

/// How far from the body a piece starts where the body's shape is known only by its
/// bounds, m.
const CLEARANCE: f32 = 0.03;

impl Landmarks {
    /// The mannequin's (its torso between its arms, its arms), or any body's from its
    /// bounds (an ellipse round its box, no arms), or the floor's (a 1 m wide axis).
    pub fn of(body: Option<&Body>) -> Self {
        match body.map(|b| (b, Pose::of_body(&b.name))) {
            Some((b, _)) if b.name == HUMAN => Self {
                waist: waist_height(&b.vertices, &b.triangles),
                ..Self::human(&b.vertices)
            },
            Some((b, Some(pose))) => {
                let (mn, mx) = b.bounds();
                let axis = Vec2::new(0.5 * (mn.x + mx.x), 0.5 * (mn.z + mx.z));
                let arms = pose.arm();
                // Room round the arm for a sleeve to start in. Held out, the arm is bent
                // forward at the elbow across the line a sleeve is bent round; 2.5 cm
                // started GarmentCode's back sleeves through it.
                let room = match pose {
                    Pose::Hanging => 0.025,
                    Pose::A => 0.035,
                };
                let arm = |s: f32| {
                    let m = Vec3::new(s, 1.0, 1.0);
                    (
                        arms[0] * m + Vec3::new(axis.x, 0.0, axis.y),
                        arms[2] * m + Vec3::new(axis.x, 0.0, axis.y),
                        ARM_RADIUS + room,
                    )
                };
                // Round the chest (0.18 x 0.11) with room for the shoulders, inside the
                // arms (see dress-mannequin).
                let torso = Vec2::new(0.215, 0.175);
                Self {
                    axis,
                    torso,
                    shoulders: MANNEQUIN_TOPS,
                    lift: MANNEQUIN_TOPS - MANNEQUIN_SHOULDERS,
                    arms: Some([arm(1.0), arm(-1.0)]),
                    garmentcode: Vec3::new(axis.x, GC_RAISE, axis.y),
                    profile: Profile::of(&b.vertices, axis, torso.x),
                    waist: waist_height(&b.vertices, &b.triangles),
                }
            }
            Some((b, None)) => {
                let (mn, mx) = b.bounds();
                let half = Vec2::new(0.5 * (mx.x - mn.x), 0.5 * (mx.z - mn.z));
                let axis = Vec2::new(0.5 * (mn.x + mx.x), 0.5 * (mn.z + mx.z));
                Self {
                    axis,
                    // The ellipse through the box's corners, and room.
                    torso: half * std::f32::consts::SQRT_2 + Vec2::splat(CLEARANCE),
                    shoulders: mx.y + CLEARANCE,
                    lift: 0.0,
                    arms: None,
                    garmentcode: Vec3::new(axis.x, GC_RAISE, axis.y),
                    profile: Profile::uniform(mn.y, half.length()),
                    waist: waist_height(&b.vertices, &b.triangles),
                }
            }
            None => Self {
                axis: Vec2::ZERO,
                torso: Vec2::new(0.2, 0.15),
                shoulders: 1.5,
                lift: 0.0,
                arms: None,
                garmentcode: Vec3::Y * GC_RAISE,
                profile: Profile::uniform(0.0, 0.0),
                waist: None,
            },
        }
    }

    /// The `human` body's, measured on its mesh (`sim-core/assets/human.obj`): the
    /// shoulders' top 1.44 m up at 10-15 cm from the middle, the arms' axis 45 degrees
    /// below the horizontal from where it leaves the torso to the wrist, the upper arm
    /// 4-5 cm in radius.
    fn human(vertices: &[Vec3]) -> Self {
        let axis = Vec2::new(0.0, -0.005);
        let torso = Vec2::new(0.21, 0.20);
        let arm = |s: f32| {
            let m = Vec3::new(s, 1.0, 1.0);
            (
                HUMAN_ARM[0] * m,
                HUMAN_ARM[1] * m,
                HUMAN_ARM_RADIUS + HUMAN_ARM_ROOM,
            )
        };
        Self {
            axis,
            // Round the torso from the hips to the shoulders (0.39 m across the hips, about
            // 0.27 m deep at the seat and at the bust), inside the arms at least 4% of the
            // way in from the ellipse; its sides pass in front of and behind the arms
            // where they leave the torso.
            torso,
            shoulders: HUMAN_SHOULDERS + HUMAN_LIFT,
            lift: HUMAN_LIFT,
            arms: Some([arm(1.0), arm(-1.0)]),
            garmentcode: Vec3::ZERO,
            profile: Profile::of(vertices, axis, torso.x),
            waist: None,
        }
    }

    /// The length round the torso cylinder, m.
    pub fn girth(&self) -> f32 {
        Ellipse::new(self.torso).perimeter()
    }
}

/// The arc length round the torso cylinder from the front to `angle`, m.
pub(super) fn arc_of_angle(marks: &Landmarks, angle: f32) -> f32 {
    Ellipse::new(marks.torso).arc_of(angle)
}

/// An ellipse walked by arc length: a table of the arc length at even steps of the
/// angle (x = a sin(phi), z = b cos(phi)).
struct Ellipse {
    semi: Vec2,
    arc: Vec<f32>,
}

const STEPS: usize = 4096;

impl Ellipse {
    fn new(semi: Vec2) -> Self {
        let at = |phi: f32| Vec2::new(semi.x * phi.sin(), semi.y * phi.cos());
        let mut arc = Vec::with_capacity(STEPS + 1);
        arc.push(0.0);
        let step = TAU / STEPS as f32;
        for k in 1..=STEPS {
            let d = (at(step * k as f32) - at(step * (k - 1) as f32)).length();
            arc.push(arc[k - 1] + d);
        }
        Self { semi, arc }
    }

    fn perimeter(&self) -> f32 {
        self.arc[STEPS]
    }

    /// The arc length from the front to angle `phi`.
    fn arc_of(&self, phi: f32) -> f32 {
        let t = phi.rem_euclid(TAU) / TAU * STEPS as f32;
        let k = (t as usize).min(STEPS - 1);
        let f = t - k as f32;
        self.arc[k] + (self.arc[k + 1] - self.arc[k]) * f
    }

    /// The point (x, z) at arc length `s` from the front.
    fn at_arc(&self, s: f32) -> Vec2 {
        let s = s.rem_euclid(self.perimeter());
        let k = self.arc.partition_point(|&a| a <= s).clamp(1, STEPS);
        let (a0, a1) = (self.arc[k - 1], self.arc[k]);
        let f = if a1 > a0 { (s - a0) / (a1 - a0) } else { 0.0 };
        let phi = TAU * ((k - 1) as f32 + f) / STEPS as f32;
        Vec2::new(self.semi.x * phi.sin(), self.semi.y * phi.cos())
    }
}

/// `p` turned by `turn` quarter turns counter-clockwise.
pub(super) fn quarter(p: Vec2, turn: u8) -> Vec2 {
    match turn % 4 {
        0 => p,
        1 => Vec2::new(-p.y, p.x),
        2 => -p,
        _ => Vec2::new(p.y, -p.x),
    }
}

/// At most this share of the way round an arm's cylinder a piece goes: a wider one
/// starts on a wider cylinder.
pub const ARM_WRAP: f32 = 0.9;

/// Why a piece cannot start where it was asked to.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PlaceError {
    #[error(
        "piece {piece} is {width:.2} m wide, more than the {girth:.2} m round the body it is placed on: it would start through itself"
    )]
    TooWide {
        piece: String,
        width: f32,
        girth: f32,
    },
    #[error("piece {piece} is placed on an arm, and this body has none")]
    NoArms { piece: String },
}

/// The start positions of a piece's pattern points `pattern` (m, the piece's own
/// coordinates, whose outline bounds are `lo`..`hi`) under `placement`.
pub fn place(
    name: &str,
    pattern: &[Vec2],
    (lo, hi): (Vec2, Vec2),
    placement: &Placement,
    marks: &Landmarks,
) -> Result<Vec<Vec3>, PlaceError> {
    let top_mid = Vec2::new(0.5 * (lo.x + hi.x), hi.y);
    let width = hi.x - lo.x;
    let local = |p: Vec2, mirrored: bool| {
        let d = p - top_mid;
        Vec2::new(if mirrored { -d.x } else { d.x }, d.y)
    };
    match *placement {
        Placement::Around {
            angle,
            top,
            mirrored,
            out,
        } => {
            let e = Ellipse::new(marks.torso + Vec2::splat(out.max(0.0)));
            if width >= e.perimeter() {
                return Err(PlaceError::TooWide {
                    piece: name.into(),
                    width,
                    girth: e.perimeter(),
                });
            }
            let s0 = e.arc_of(angle);
            Ok(pattern
                .iter()
                .map(|&p| {
                    let q = local(p, mirrored);
                    let xz = e.at_arc(s0 + q.x);
                    Vec3::new(marks.axis.x + xz.x, top + q.y, marks.axis.y + xz.y)
                })
                .collect())
        }
        Placement::Arm {
            left,
            angle,
            down,
            mirrored,
            turn,
            room,
        } => {
            let Some(arms) = marks.arms else {
                return Err(PlaceError::NoArms { piece: name.into() });
            };
            let (shoulder, wrist, r) = arms[usize::from(!left)];
            // The pattern turned, and measured from its turned bounds' top middle.
            let (a, b) = (quarter(lo, turn), quarter(hi, turn));
            let (lo, hi) = (a.min(b), a.max(b));
            let top_mid = Vec2::new(0.5 * (lo.x + hi.x), hi.y);
            let width = hi.x - lo.x;
            let local = |p: Vec2, mirrored: bool| {
                let d = quarter(p, turn) - top_mid;
                Vec2::new(if mirrored { -d.x } else { d.x }, d.y)
            };
            // A piece about as wide as the way round (a sleeve cut to be sewn into a tube)
            // starts on a wider cylinder, its two long edges a gap of `1 - ARM_WRAP` of
            // the way round apart, for the Sew tool to close (a 0.44 m sleeve for the
            // dress's 0.44 m armhole was refused on the mannequin's 0.44 m cylinder).
            let r = r.max(width / (TAU * ARM_WRAP)) + room.max(0.0);
            // A frame on the arm: along it (down), to the front, and to a front viewer's
            // right; round it by arc length.
            let along = (wrist - shoulder).normalize_or(Vec3::NEG_Y);
            let front = (Vec3::Z - along * along.z).normalize_or(Vec3::Z);
            let right = along.cross(front).normalize_or(Vec3::X);
            let right = if right.x < 0.0 { -right } else { right };
            Ok(pattern
                .iter()
                .map(|&p| {
                    let q = local(p, mirrored);
                    let theta = angle + q.x / r;
                    shoulder
                        + along * (down - q.y)
                        + (front * theta.cos() + right * theta.sin()) * r
                })
                .collect())
        }
        Placement::Transform {
            rotation,
            translation,
        } => Ok(pattern
            .iter()
            .map(|p| rotation * Vec3::new(p.x, p.y, 0.0) + translation)
            .collect()),
        Placement::Cone {
            angle,
            top,
            mirrored,
            centre,
            inner,
            sine,
        } => Ok(super::cone::on_cone(
            pattern,
            (lo, hi),
            centre,
            inner,
            sine,
            angle,
            top,
            mirrored,
            marks.axis,
        )),
    }
}

#[cfg(test)]
mod tests;
