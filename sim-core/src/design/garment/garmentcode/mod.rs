//! GarmentCode's pattern specification (the JSON of ETH's GarmentCode and its data set):
//! `pattern.panels` by name, each with `vertices` (2D, in `properties.units_in_meter`,
//! centimetres by default), `edges` (`endpoints`, and a `curvature`: quadratic or cubic
//! Bézier control points relative to the edge, or a circular arc as SVG gives it:
//! radius, large-arc and sweep flags), `rotation` (XYZ Euler degrees, applied z·y·x)
//! and `translation`; `pattern.stitches`, pairs of `{panel, edge}`.
//!
//! Their 3D placement is for their own body in a T-pose. We keep what it says of where a
//! panel goes (front or back, how far round, how high, which arm) and bend the panel
//! round our body's torso or arm from there, so it starts close without touching; a panel
//! that cannot be bent (lying flat, upside down, wider than the limb) keeps their
//! transform.

mod flat;

use glam::{Mat3, Vec2, Vec3};
use serde_json::Value;

use super::cone::{self, Fan};
#[cfg(test)]
use super::place::GC_RAISE;
use super::place::{Landmarks, Placement};
use super::spec::{
    DEFAULT_FABRIC, EdgeRef, HoldSpec, PatternSpec, PieceSpec, SeamSpec, shift_angle,
};
use crate::mesh::mesher::{MeshError, Outline, signed_area2};
use flat::kept_flat;
pub(crate) use flat::{FLAT_OUT_TRIES, moved_out};

/// The waist of GarmentCode's average body (`assets/bodies/mean_all.yaml`: `height -
/// head_l - waist_line` = 108.77 cm), m, in that body's coordinates
/// ([`Landmarks::garmentcode`] puts it on ours). GarmentCode's data-set simulations keep
/// every waistband (`lower_interface`) from falling below it for their first 400 frames
/// (`pygarment/meshgen/datasim_utils.py`: `attachment_label_names`, only that label).
const GC_WAIST: f32 = 1.0877;

/// The half-space (normal, level) GarmentCode keeps an edge labelled `label` in, on our
/// body, if it keeps such edges. Its interactive settings also keep a strapless top above
/// the armpits and a neckline's (`left_collar`, `right_collar`) sides within half the
/// neck's width; its data-set simulations do not, nor do we (a neckline wider than the
/// neck would be pinched in).
fn hold_plane(label: &str, marks: &Landmarks) -> Option<(Vec3, f32)> {
    (label == "lower_interface").then_some((Vec3::Y, GC_WAIST + marks.garmentcode.y))
}

/// The holds of a panel (piece `piece`) whose `edges` run `ends` on its outline: one for
/// each edge with a label GarmentCode holds.
fn holds<'a>(
    edges: &'a [Value],
    ends: &'a [(Vec2, Vec2)],
    piece: usize,
    marks: &'a Landmarks,
) -> impl Iterator<Item = HoldSpec> + 'a {
    edges.iter().zip(ends).filter_map(move |(e, &(from, to))| {
        let label = e.get("label").and_then(Value::as_str)?;
        let (normal, level) = hold_plane(label, marks)?;
        Some(HoldSpec {
            label: label.into(),
            edge: EdgeRef { piece, from, to },
            normal,
            level,
            measured: false,
        })
    })
}

/// Most points one curved edge is flattened into.
const CURVE_POINTS: usize = 64;

fn bad(s: impl Into<String>) -> String {
    s.into()
}

fn num(v: &Value) -> Option<f32> {
    v.as_f64().map(|x| x as f32).filter(|x| x.is_finite())
}

fn vec2(v: &Value) -> Option<Vec2> {
    let a = v.as_array()?;
    Some(Vec2::new(num(a.first()?)?, num(a.get(1)?)?))
}

fn vec3(v: Option<&Value>) -> Option<Vec3> {
    let a = v?.as_array()?;
    Some(Vec3::new(
        num(a.first()?)?,
        num(a.get(1)?)?,
        num(a.get(2)?)?,
    ))
}

/// A point given relative to edge `p -> q` (along it, and to its left, in edge lengths).
fn rel(p: Vec2, q: Vec2, r: Vec2) -> Vec2 {
    let e = q - p;
    p + e * r.x + Vec2::new(-e.y, e.x) * r.y
}

/// The points of an edge from `p` to `q` (m) after `p`, up to but not including `q`.
/// Absolute control points and radii are in the file's units, `scale` m each.
fn curve(
    p: Vec2,
    q: Vec2,
    c: Option<&Value>,
    absolute: bool,
    scale: f32,
) -> Result<Vec<Vec2>, String> {
    let Some(c) = c else {
        return Ok(Vec::new());
    };
    let ctrl = |v: &Value| -> Result<Vec2, String> {
        let r = vec2(v).ok_or_else(|| bad("a curvature control point is not [x, y]"))?;
        Ok(if absolute { r * scale } else { rel(p, q, r) })
    };
    let n = CURVE_POINTS;
    let sample = |f: &dyn Fn(f32) -> Vec2| (1..n).map(|k| f(k as f32 / n as f32)).collect();
    // The older format: a bare [x, y] is a quadratic control point.
    if c.is_array() {
        let m = ctrl(c)?;
        return Ok(sample(&|t| {
            p * (1.0 - t).powi(2) + m * 2.0 * t * (1.0 - t) + q * t * t
        }));
    }
    let kind = c.get("type").and_then(Value::as_str).unwrap_or("quadratic");
    let params = c
        .get("params")
        .and_then(Value::as_array)
        .ok_or_else(|| bad("a curvature has no params"))?;
    match kind {
        "quadratic" => {
            let m = ctrl(
                params
                    .first()
                    .ok_or_else(|| bad("quadratic without a control point"))?,
            )?;
            Ok(sample(&|t| {
                p * (1.0 - t).powi(2) + m * 2.0 * t * (1.0 - t) + q * t * t
            }))
        }
        "cubic" => {
            let a = ctrl(
                params
                    .first()
                    .ok_or_else(|| bad("cubic without control points"))?,
            )?;
            let b = ctrl(
                params
                    .get(1)
                    .ok_or_else(|| bad("cubic needs two control points"))?,
            )?;
            Ok(sample(&|t| {
                let u = 1.0 - t;
                p * u * u * u + a * 3.0 * u * u * t + b * 3.0 * u * t * t + q * t * t * t
            }))
        }
        "circle" => {
            let (r, large, right) =
                circle_params(params).ok_or_else(|| bad("circle without a radius"))?;
            Ok(arc(p, q, r * scale, large, right, n))
        }
        other => Err(format!("unknown curvature type {other:?}")),
    }
}

/// The circle of a circular arc from `p` to `q` of radius `r` (grown to half the chord if
/// smaller), bulging to the right of `p -> q` when `right`, the long way round when
/// `large`: its centre and radius. None for a chord of no length.
fn circle(p: Vec2, q: Vec2, r: f32, large: bool, right: bool) -> Option<(Vec2, f32)> {
    let chord = (q - p).length();
    if chord < 1e-9 {
        return None;
    }
    let r = r.abs().max(0.5 * chord);
    let h = (r * r - 0.25 * chord * chord).max(0.0).sqrt();
    let left = Vec2::new(-(q - p).y, (q - p).x) / chord;
    // The arc's middle is on the bulge side; the centre is h from the chord's middle,
    // on the bulge side for a large arc, across for a small one.
    let bulge = if right { -left } else { left };
    Some(((p + q) * 0.5 + bulge * if large { h } else { -h }, r))
}

/// The points of the circular arc from `p` to `q` (see [`circle`]) after `p`, up to but
/// not including `q`.
fn arc(p: Vec2, q: Vec2, r: f32, large: bool, right: bool, n: usize) -> Vec<Vec2> {
    let Some((centre, r)) = circle(p, q, r, large, right) else {
        return Vec::new();
    };
    let left = Vec2::new(-(q - p).y, (q - p).x).normalize_or_zero();
    let bulge = if right { -left } else { left };
    let a0 = (p - centre).to_angle();
    let a1 = (q - centre).to_angle();
    let mid = centre + bulge * r;
    let mut sweep = (a1 - a0).rem_euclid(std::f32::consts::TAU);
    // Go the way that passes through the middle.
    let am = (mid - centre).to_angle();
    if (am - a0).rem_euclid(std::f32::consts::TAU) > sweep {
        sweep -= std::f32::consts::TAU;
    }
    (1..n)
        .map(|k| centre + Vec2::from_angle(a0 + sweep * k as f32 / n as f32) * r)
        .collect()
}

/// The circle (centre, radius; m) of an edge from `p` to `q` whose curvature `c` is a
/// circular arc, in the file's units of `scale` m each.
fn arc_circle(p: Vec2, q: Vec2, c: Option<&Value>, scale: f32) -> Option<(Vec2, f32)> {
    let c = c?;
    if c.get("type").and_then(Value::as_str) != Some("circle") {
        return None;
    }
    let (r, large, right) = circle_params(c.get("params").and_then(Value::as_array)?)?;
    circle(p, q, r * scale, large, right)
}

/// A circular arc's `params` as GarmentCode writes them: its radius (in the file's
/// units), whether it goes the long way round, whether it bulges to the right.
fn circle_params(params: &[Value]) -> Option<(f32, bool, bool)> {
    let r = params.first().and_then(num)?;
    let large = params.get(1).and_then(Value::as_f64).unwrap_or(0.0) != 0.0;
    let right = params.get(2).and_then(Value::as_f64).unwrap_or(1.0) != 0.0;
    Some((r, large, right))
}

/// Rotation from XYZ Euler degrees, as GarmentCode applies them (z · y · x).
fn euler(d: Vec3) -> Mat3 {
    Mat3::from_rotation_z(d.z.to_radians())
        * Mat3::from_rotation_y(d.y.to_radians())
        * Mat3::from_rotation_x(d.x.to_radians())
}

/// Where a panel starts on our body, from where GarmentCode put it on theirs, and for a
/// panel round an arm how far down their arm it starts, m.
fn placement(
    outline: &[Vec2],
    rot: Mat3,
    trans: Vec3,
    marks: &Landmarks,
    fan: Option<Fan>,
) -> (Placement, Option<f32>) {
    let (lo, hi) = crate::mesh::bounds2(outline);
    let to_ours = marks.garmentcode + Vec3::Y * marks.lift;
    let world = |p: Vec2| rot * p.extend(0.0) + trans + to_ours;
    let centre = world((lo + hi) * 0.5);
    let top = outline.iter().map(|&p| world(p).y).fold(f32::MIN, f32::max);
    // A panel kept in their transform is not lifted: nothing bends it clear of our body,
    // and lifted, a shirt's sleeves held out at 50 degrees started through our shoulders.
    let fixed = Placement::Transform {
        rotation: rot,
        translation: trans + to_ours - Vec3::Y * marks.lift,
    };
    let (xdir, up, normal) = (rot * Vec3::X, rot * Vec3::Y, rot * Vec3::Z);
    let radial = Vec2::new(centre.x - marks.axis.x, centre.z - marks.axis.y);
    // Beside the torso: its middle well out. Or, near the torso's side and reaching far
    // past it, a short sleeve if it runs down the arm (a trouser leg, which reaches as
    // far, does not, and goes round the body as before).
    let reach = (outline.iter())
        .map(|&p| (world(p).x - marks.axis.x).abs())
        .fold(0.0, f32::max);
    let beside = radial.x.abs() > marks.torso.x + 0.05;
    let short = radial.x.abs() > marks.torso.x - 0.05 && reach > marks.torso.x + SHORT_SLEEVE_REACH;
    if let Some(arms) = marks.arms
        && (beside || short)
        && normal.y.abs() < 0.7
    {
        // Their panel, where their body has it (unlifted).
        let theirs: Vec<Vec3> = (outline.iter())
            .map(|&p| world(p) - Vec3::Y * marks.lift)
            .collect();
        match sleeve(radial, top, rot, arms, (lo, hi), &theirs) {
            Some((p, start)) => return (p, Some(start)),
            None if beside => return (fixed, None),
            None => {}
        }
    }
    if up.y < 0.7 {
        return (fixed, None);
    }
    let mut out = Vec2::new(normal.x, normal.z);
    if out.dot(radial) < 0.0 {
        out = -out;
    }
    if out.length() < 0.3 {
        out = radial;
    }
    let phi = out.x.atan2(out.y);
    let tangent = Vec2::new(phi.cos(), -phi.sin());
    let lateral = radial.dot(tangent);
    let mirrored = Vec2::new(xdir.x, xdir.z).dot(tangent) < 0.0;
    let on_cone = fan.and_then(|f| {
        let facing = Facing {
            phi,
            tangent,
            mirrored,
        };
        cone_for(f, outline, (lo, hi), rot, &world, marks, facing)
    });
    if let Some(cone) = on_cone {
        return (cone, None);
    }
    let around = Placement::Around {
        angle: shift_angle(marks, phi, lateral),
        top,
        mirrored,
        out: 0.0,
    };
    (around, None)
}

/// Which way a standing panel faces on our body: the angle round it its front faces
/// (see `place`), the way round there, and whether its pattern's x runs against it.
#[derive(Clone, Copy)]
struct Facing {
    phi: f32,
    tangent: Vec2,
    mirrored: bool,
}

/// A standing fan (a circle skirt's panel) that opens downward on their body, on the
/// narrowest cone that clears ours ([`cone`]), its top arc level at the height of the
/// top arc's ends on their body. None if the fan is narrower than [`cone::FAN_MIN`],
/// does not open downward, or no cone clears our body (its top tighter than our waist).
fn cone_for(
    fan: Fan,
    outline: &[Vec2],
    bounds: (Vec2, Vec2),
    rot: Mat3,
    world: &dyn Fn(Vec2) -> Vec3,
    marks: &Landmarks,
    facing: Facing,
) -> Option<Placement> {
    let m = cone::middle(fan.centre, bounds);
    if (rot * m.extend(0.0)).y > -0.9 {
        return None;
    }
    let (angle, outer) = cone::extent(outline, fan.centre, m);
    if angle < cone::FAN_MIN {
        return None;
    }
    let top = (outline.iter())
        .filter(|&&p| ((p - fan.centre).length() - fan.inner).abs() < 1e-3)
        .map(|&p| world(p).y)
        .fold(f32::NEG_INFINITY, f32::max);
    let sine = cone::cone_sine(angle, fan.inner, outer, top, &marks.profile)?;
    // The fan's middle stands this far round from `phi` on their body.
    let c = world(fan.centre);
    let lateral = Vec2::new(c.x - marks.axis.x, c.z - marks.axis.y).dot(facing.tangent);
    Some(Placement::Cone {
        angle: facing.phi + lateral / (fan.inner * sine),
        top,
        mirrored: facing.mirrored,
        centre: fan.centre,
        inner: fan.inner,
        sine,
    })
}

/// How far (degrees) our arm may run from a sleeve's way down its pattern for the sleeve
/// to be bent round it: their sleeves held out 50 degrees below the horizontal go round
/// the A-posed mannequin's arms, but not round arms that hang, where they would start
/// through the torso's panels.
const SLEEVE_ALIGN_DEG: f32 = 20.0;

/// A panel beside the torso, standing, as a sleeve round our arm on its side: turned so
/// that the arm runs down its pattern (their sleeves run along x, held out from a body
/// in an A-pose), in front of the arm or behind it. None (their transform is kept) if
/// our arm does not run the way the sleeve does, or the sleeve is too wide for it.
fn sleeve(
    radial: Vec2,
    top: f32,
    rot: Mat3,
    arms: [(Vec3, Vec3, f32); 2],
    (lo, hi): (Vec2, Vec2),
    theirs: &[Vec3],
) -> Option<(Placement, f32)> {
    let left = radial.x > 0.0;
    let (shoulder, wrist, r) = arms[usize::from(!left)];
    // The pattern's way down the arm: its axis (+-x, +-y) that runs most as our arm
    // does, from the shoulder to the wrist; `turn` quarter turns take it to -y.
    let along = (wrist - shoulder).normalize_or(Vec3::NEG_Y);
    let (turn, down_dir) = [Vec2::NEG_Y, Vec2::NEG_X, Vec2::Y, Vec2::X]
        .into_iter()
        .enumerate()
        .map(|(k, a)| (k as u8, rot * a.extend(0.0)))
        .max_by(|a, b| a.1.dot(along).total_cmp(&b.1.dot(along)))?;
    if down_dir.dot(along) < SLEEVE_ALIGN_DEG.to_radians().cos() {
        return None;
    }
    // Round the arm runs the turned pattern's x.
    let round = rot * super::place::quarter(Vec2::X, 4 - turn).extend(0.0);
    let width = if turn % 2 == 0 {
        hi.x - lo.x
    } else {
        hi.y - lo.y
    };
    if width >= std::f32::consts::TAU * r * 0.95 {
        return None;
    }
    let normal = rot * Vec3::Z;
    // In front of the arm or behind it, where the panel is. A panel level with the arm
    // goes as hanging sleeves always did, by which way it faces.
    let front = if turn == 0 && radial.y.abs() < SLEEVE_SIDE {
        normal.z * radial.y.signum() >= 0.0 || normal.z > 0.0
    } else {
        radial.y >= 0.0
    };
    // How far down the arm their panel starts.
    let start = (theirs.iter())
        .map(|&p| (p - shoulder).dot(along))
        .fold(f32::MAX, f32::min);
    let placed = Placement::Arm {
        left,
        angle: if front { 0.0 } else { std::f32::consts::PI },
        // A panel that starts well down their arm (a cuff at the end of its sleeve)
        // where it starts there; otherwise a hanging sleeve where it hangs on their body,
        // a turned one from just below the shoulder, clear of the shoulder's round.
        down: if start > CUFF_START {
            start
        } else if turn == 0 {
            (shoulder.y - top).max(0.0)
        } else {
            TURNED_SLEEVE_DOWN
        },
        // Each of a sleeve's two halves goes at most half way round the arm.
        room: (width / (std::f32::consts::PI * 0.95) - r).max(0.0),
        mirrored: round.x * if front { 1.0 } else { -1.0 } < 0.0,
        turn,
    };
    Some((placed, start))
}

/// Each cuff (a panel that starts more than [`CUFF_START`] down their arm) moved down our
/// arm by as much as the sleeve that starts highest on that arm was (a turned sleeve
/// starts 3 cm down ours wherever it starts on theirs), so that it stays at the
/// sleeve's end. `starts`: each piece's start down their arm, for those round an arm.
fn keep_cuffs_at_their_sleeves(pieces: &mut [PieceSpec], starts: &[Option<f32>]) {
    for side in [true, false] {
        let arm_down = |p: &PieceSpec| match p.placement {
            Some(Placement::Arm { left, down, .. }) if left == side => Some(down),
            _ => None,
        };
        // The shift of the sleeve that starts highest on this arm.
        let shift = (pieces.iter().zip(starts))
            .filter_map(|(p, s)| Some((s.filter(|&s| s <= CUFF_START)?, arm_down(p)?)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(start, down)| down - start);
        let Some(shift) = shift else { continue };
        for (p, s) in pieces.iter_mut().zip(starts) {
            if let Some(Placement::Arm { left, down, .. }) = &mut p.placement
                && *left == side
                && let Some(s) = s.filter(|&s| s > CUFF_START)
            {
                *down = s + shift;
            }
        }
    }
}

/// How far past the torso's side a panel whose middle is near it (within 5 cm) must reach
/// to be a short sleeve, m. GarmentCode's random designs' short sleeves have their
/// middles 2.8 cm inside the side to 2.7 cm past it and reach 15-20 cm past it; kept in
/// their transform, they started through our arm and shoulder (92-304 crossing pairs).
const SHORT_SLEEVE_REACH: f32 = 0.15;

/// How far in front of the body's axis (or behind it) a sleeve panel stands to be put in
/// front of the arm (or behind it), m. GarmentCode puts front and back sleeve panels 17.5
/// and 12.5 cm either side; its random designs' cuffs, whose way down the arm is their
/// pattern's own, both faced the front, and both went in front of the arm, one through
/// the other.
const SLEEVE_SIDE: f32 = 0.05;

/// How far down their arm a panel starts for it to start as far down ours, m: a cuff
/// (GarmentCode's random designs' cuffs start 23-48 cm down), not a sleeve (theirs start
/// at most 10 cm down, beside the shoulder).
const CUFF_START: f32 = 0.18;

/// How far down our arm a turned sleeve's top starts, m.
const TURNED_SLEEVE_DOWN: f32 = 0.03;

/// Whether a panel's `outline` (m; the side from point `i` part of edge `owner[i]` of
/// `edges`) keeps clear of itself; if not, which edges cross and where, in the file's
/// units (`per_m` to the metre), as a designer can find them. GarmentCode's random
/// designs cross most often where a deep neckline's arc runs through the armhole.
/// (GarmentCode's own check, `_is_panel_self_intersecting`, draws the curves mirrored,
/// as for a picture with y down, and misses these.)
fn uncrossed(outline: &[Vec2], owner: &[usize], edges: &[Value], per_m: f32) -> Result<(), String> {
    let whole = Outline {
        loops: vec![outline.to_vec()],
    };
    let Err(MeshError::SelfIntersecting { a, b, .. }) = crate::mesh::mesher::check(&whole) else {
        return Ok(());
    };
    let name = |i: usize| {
        let k = owner.get(i).copied().unwrap_or(0);
        match edges
            .get(k)
            .and_then(|e| e.get("label"))
            .and_then(Value::as_str)
        {
            Some(label) => format!("edge {k} ({label})"),
            None => format!("edge {k}"),
        }
    };
    let at = outline[a] * per_m;
    Err(format!(
        "its outline crosses itself: {} runs across {} near ({:.1}, {:.1}) in the file's units; a panel whose sides cross encloses no one piece of cloth: redraw it so that they do not",
        name(a),
        name(b),
        at.x,
        at.y
    ))
}

/// The seams of `pattern.stitches`, between the panels `edges_of` lists (name, edges as
/// (from, to) on the counter-clockwise outline, and whether that runs against the file).
fn seams(pattern: &Value, edges_of: &[(String, Ends, bool)]) -> Result<Vec<SeamSpec>, String> {
    let mut out = Vec::new();
    let stitches: &[Value] =
        (pattern.get("stitches").and_then(Value::as_array)).map_or(&[], Vec::as_slice);
    for (i, st) in stitches.iter().enumerate() {
        let label = super::super::sewing_pattern::label(i);
        let side = |k: usize| -> Result<(EdgeRef, bool), String> {
            let s = st
                .get(k)
                .ok_or_else(|| format!("stitch {i} does not have two sides"))?;
            let panel = s.get("panel").and_then(Value::as_str).unwrap_or("");
            let edge = s.get("edge").and_then(Value::as_u64).unwrap_or(u64::MAX) as usize;
            let piece = edges_of
                .iter()
                .position(|(n, _, _)| n == panel)
                .ok_or_else(|| format!("stitch {i} names panel {panel:?}, which is not there"))?;
            let (from, to) = *edges_of[piece].1.get(edge).ok_or_else(|| {
                format!("stitch {i} names edge {edge} of panel {panel}, which is not there")
            })?;
            Ok((EdgeRef { piece, from, to }, edges_of[piece].2))
        };
        let ((a, flip_a), (b, flip_b)) = (side(0)?, side(1)?);
        // GarmentCode sews the end of the first edge to the start of the second, in the
        // file's directions (the right sides of the fabric together), unless the stitch
        // says "right_wrong" (`pygarment/meshgen/boxmeshgen.py`, `Seam.swap`); an edge
        // whose panel runs the other way here has its ends swapped.
        let right_wrong = st.get(2).and_then(Value::as_str) == Some("right_wrong");
        out.push(SeamSpec {
            label,
            a,
            b,
            reversed: Some(!right_wrong ^ flip_a ^ flip_b),
        });
    }
    Ok(out)
}

/// A panel's edges as (from, to), m.
type Ends = Vec<(Vec2, Vec2)>;

/// A GarmentCode pattern specification as a pattern to drape on a body with `marks`.
pub fn read_garmentcode(text: &str, marks: &Landmarks) -> Result<PatternSpec, String> {
    let root: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let pattern = root
        .get("pattern")
        .ok_or_else(|| bad("no \"pattern\": not a GarmentCode specification"))?;
    let panels = pattern
        .get("panels")
        .and_then(Value::as_object)
        .ok_or_else(|| bad("no \"pattern.panels\" object"))?;
    let props = root.get("properties");
    let per_m = props
        .and_then(|p| p.get("units_in_meter"))
        .and_then(num)
        .unwrap_or(100.0);
    if per_m <= 0.0 {
        return Err(format!("units_in_meter must be positive, got {per_m}"));
    }
    let absolute = props
        .and_then(|p| p.get("curvature_coords"))
        .and_then(Value::as_str)
        == Some("absolute");
    let scale = 1.0 / per_m;
    let mut spec = PatternSpec::default();
    // Each panel's edges as (from, to) on its counter-clockwise outline, and whether that
    // runs against the file's order (the ends swapped).
    let mut edges_of: Vec<(String, Ends, bool)> = Vec::new();
    // Each panel's start down their arm, for those round an arm.
    let mut starts: Vec<Option<f32>> = Vec::new();
    for (name, panel) in panels {
        let err = |s: String| format!("panel {name}: {s}");
        let verts: Vec<Vec2> = panel
            .get("vertices")
            .and_then(Value::as_array)
            .ok_or_else(|| err("no vertices".into()))?
            .iter()
            .map(|v| vec2(v).map(|p| p * scale))
            .collect::<Option<_>>()
            .ok_or_else(|| err("a vertex is not [x, y]".into()))?;
        let edges = panel
            .get("edges")
            .and_then(Value::as_array)
            .ok_or_else(|| err("no edges".into()))?;
        let mut outline: Vec<Vec2> = Vec::new();
        let mut ends: Vec<(Vec2, Vec2)> = Vec::new();
        let mut circles: Vec<(Vec2, f32)> = Vec::new();
        // The edge each outline point starts a side of.
        let mut owner: Vec<usize> = Vec::new();
        for (k, e) in edges.iter().enumerate() {
            let ep = e
                .get("endpoints")
                .and_then(Value::as_array)
                .ok_or_else(|| err(format!("edge {k} has no endpoints")))?;
            let idx = |i: usize| {
                ep.get(i)
                    .and_then(Value::as_u64)
                    .and_then(|j| verts.get(j as usize).copied())
                    .ok_or_else(|| err(format!("edge {k} names a vertex that is not there")))
            };
            let (p, q) = (idx(0)?, idx(1)?);
            outline.push(p);
            let pts = curve(p, q, e.get("curvature"), absolute, scale)
                .map_err(|s| err(format!("edge {k}: {s}")))?;
            outline.extend(pts);
            owner.resize(outline.len(), k);
            ends.push((p, q));
            circles.extend(arc_circle(p, q, e.get("curvature"), scale));
        }
        if outline.len() < 3 {
            return Err(err("fewer than 3 points".into()));
        }
        uncrossed(&outline, &owner, edges, per_m).map_err(err)?;
        // Their loops may run either way; ours run counter-clockwise.
        let flipped = signed_area2(&outline) < 0.0;
        if flipped {
            outline.reverse();
            for e in &mut ends {
                *e = (e.1, e.0);
            }
        }
        let piece = spec.pieces.len();
        spec.holds.extend(holds(edges, &ends, piece, marks));
        let rot = euler(vec3(panel.get("rotation")).unwrap_or(Vec3::ZERO));
        let trans = vec3(panel.get("translation")).unwrap_or(Vec3::ZERO) * scale;
        let (placed, start) = placement(&outline, rot, trans, marks, cone::fan_of(&circles));
        starts.push(start);
        // Round the torso unless kept flat, and then round it if flat would cross.
        let (placed, fallback) = match kept_flat(&outline, rot, trans, marks) {
            Some(flat) if matches!(placed, Placement::Around { .. }) => (flat, Some(placed)),
            _ => (placed, None),
        };
        spec.pieces.push(PieceSpec {
            name: name.clone(),
            placement: Some(placed),
            outline: Outline {
                loops: vec![outline],
            },
            fabric: DEFAULT_FABRIC.into(),
            grain: 0.0,
            start: None,
            fallback,
        });
        edges_of.push((name.clone(), ends, flipped));
    }
    keep_cuffs_at_their_sleeves(&mut spec.pieces, &starts);
    spec.seams = seams(pattern, &edges_of)?;
    Ok(spec)
}

#[cfg(test)]
mod tests;
