//! Where a garment scenario's pattern starts round the body: at the full lift above the
//! shoulders, or lower where that would start it crossed; each piece kept flat where its
//! file puts it that starts crossing put on its fallback round the torso; pieces round
//! the torso moved layers out where nothing else helps; refused, naming what crosses,
//! where nothing does.

use crate::collision::{Body, crossings};
use crate::design::garment::{self, Landmarks, PatternSpec};

use super::error::ScenarioError;

/// The pattern a garment scenario starts: its file (the shipped dress without one) and
/// its triangles' edge length, m.
pub(super) struct Source<'a> {
    pub file: Option<&'a std::path::Path>,
    pub edge: f32,
}

/// How many lifts a pattern is tried at, highest first, before it starts unlifted.
const LIFT_TRIES: usize = 4;

/// How many layers ([`garment::LAYER`]) out a piece round the torso may start, where
/// nearer it would start through the body at every lift.
const OUT_TRIES: usize = 3;

/// The garment scenarios' pattern (the file, or the shipped dress), its pieces placed
/// round the body. A GarmentCode pattern starts `Landmarks::lift` above where its file
/// puts it, so that its tops start above the shoulders as ours do; where that would
/// start a piece through the body or another piece, it starts lower, a quarter of the
/// lift at a time (a shirt lifted 8 cm met our arms at its armpits). Where no lift
/// starts it clear, each piece round the torso that starts through the body at the full
/// lift starts a layer further out, up to [`OUT_TRIES`] layers (the sleeved dress's back,
/// cut for the mannequin's broad shoulders, reached round into `human`'s arms).
pub(super) fn placed_garment(
    cfg: &Source<'_>,
    body: Option<&Body>,
    notices: &mut Vec<String>,
) -> Result<(PatternSpec, garment::Assembled), ScenarioError> {
    let full = Landmarks::of(body);
    let start_at = |lift: f32, out: &[f32], flat: &mut Vec<usize>| {
        settle(cfg, body, &Landmarks { lift, ..full }, out, flat)
    };
    // Each piece's step away from where its file puts it, if it is kept flat (`settle`).
    let mut flat = Vec::new();
    let around = |spec: &PatternSpec, i: usize| {
        matches!(
            spec.pieces[i].placement,
            Some(garment::Placement::Around { .. })
        )
    };
    // The full lift, lower by a quarter of it each time, and last none.
    let tries = if full.lift > 0.0 { LIFT_TRIES } else { 0 };
    let said_lift = |lift: f32| {
        format!(
            "the pattern starts {:.0} cm above the shoulders rather than {:.0}: higher, a piece would start through the body or another piece",
            100.0 * lift,
            100.0 * full.lift
        )
    };
    let refuse = |made: &garment::Assembled, said: &[String], crossed: &crossings::Crossings| {
        ScenarioError::StartsCrossed {
            self_pairs: crossed.self_pairs,
            body_pairs: crossed.body_pairs,
            which: match super::garment::crossed_pieces(made, body) {
                w if w.is_empty() => w,
                w => format!(" ({w})"),
            } + &(said.iter())
                .filter(|n| n.contains("placed for another body"))
                .map(|n| format!("; {n}"))
                .collect::<String>()
                + arms_hint(made, body),
        }
    };
    let (mut k, mut lifted) = (0, None);
    let refused = loop {
        let lift = full.lift * (tries - k) as f32 / tries.max(1) as f32;
        let (spec, said, made, crossed) = start_at(lift, &[], &mut flat)?;
        if crossed.self_pairs == 0 && crossed.body_pairs == 0 {
            notices.extend(said);
            notices.extend((k > 0).then(|| said_lift(lift)));
            notices.extend(kept_flat(&spec, &flat));
            notices.extend(arms_inside(&spec, &made, body));
            return Ok((spec, made));
        }
        let last = (k == tries).then(|| refuse(&made, &said, &crossed));
        if k == 0 {
            lifted = Some((spec, made, crossed));
        }
        if let Some(e) = last {
            break e;
        }
        k += 1;
    };
    // No lift starts it clear: at the full lift, each piece round the torso that starts
    // through the body a layer further out, up to `OUT_TRIES` layers; else refused as it
    // started unlifted.
    let Some((mut spec, mut made, mut crossed)) = lifted else {
        return Err(refused);
    };
    let mut out = vec![0.0; spec.pieces.len()];
    for _ in 0..OUT_TRIES {
        let through = super::garment::pieces_through_body(&made, body);
        let further: Vec<usize> = through.into_iter().filter(|&i| around(&spec, i)).collect();
        if further.is_empty() || crossed.self_pairs > 0 {
            break;
        }
        further.iter().for_each(|&i| out[i] += garment::LAYER);
        let said;
        (spec, said, made, crossed) = start_at(full.lift, &out, &mut flat)?;
        if crossed.self_pairs == 0 && crossed.body_pairs == 0 {
            notices.extend(said);
            notices.extend(further_out(&spec, &out));
            notices.extend(kept_flat(&spec, &flat));
            notices.extend(arms_inside(&spec, &made, body));
            return Ok((spec, made));
        }
    }
    Err(refused)
}

/// What a refusal adds where a piece on a cone (a circle skirt's) starts through a body
/// whose arms hang beside its hips: a cone round the torso passes them.
fn arms_hint(made: &garment::Assembled, body: Option<&Body>) -> &'static str {
    if arms_hang(body) && on_cone(made) {
        "; a skirt on a cone round the body passes the mannequin's hanging arms: \
         `--body mannequin-apose` holds them clear"
    } else {
        ""
    }
}

/// Whether `body` is the mannequin whose arms hang beside its hips.
fn arms_hang(body: Option<&Body>) -> bool {
    body.is_some_and(|b| b.name == "mannequin")
}

/// Whether a piece of `made` starts on a cone (a circle skirt's).
fn on_cone(made: &garment::Assembled) -> bool {
    (made.records.iter()).any(|r| matches!(r.placement, Some(garment::Placement::Cone { .. })))
}

/// What a garment that hangs from the waist (a piece on a cone, or a skirt held at the
/// waist measured on this body) is told on the mannequin whose arms hang beside its hips:
/// a skirt flares out past them and its side seams close round them (GarmentCode's
/// circle skirt there: 0.40 m out at the hands' height, the hands 0.37 m; 12 of its 104
/// pairs left open, "the body between").
fn arms_inside(
    spec: &PatternSpec,
    made: &garment::Assembled,
    body: Option<&Body>,
) -> Option<String> {
    (arms_hang(body) && (on_cone(made) || spec.holds.iter().any(|h| h.measured))).then(|| {
        "the garment hangs from the waist beside the mannequin's hanging arms: a skirt's sides \
         close round them, the arms inside it (`--body mannequin-apose` holds them clear)"
            .into()
    })
}

/// A pattern placed and assembled: its spec, what its reading said, the cloth, and how
/// it starts crossed.
type Placed = (
    PatternSpec,
    Vec<String>,
    garment::Assembled,
    crossings::Crossings,
);

/// A piece kept flat that is this many steps away from where its file puts it is on its
/// fallback round the torso; fewer, it is that many layers further from the body.
const ROUND: usize = garment::FLAT_OUT_TRIES + 1;

/// The pattern placed for `marks` and assembled, each piece round the torso `out` m
/// further out than placed, each piece kept flat `flat` steps away ([`ROUND`]).
fn place(
    cfg: &Source<'_>,
    body: Option<&Body>,
    marks: &Landmarks,
    out: &[f32],
    flat: &[usize],
) -> Result<Placed, ScenarioError> {
    let (mut spec, said) = match cfg.file {
        Some(path) => garment::load_pattern(path, marks)?,
        None => {
            let spec = super::garment::dress(marks).map_err(|e| ScenarioError::PieceFile {
                path: "assets/dress.svg".into(),
                reason: e.to_string(),
            })?;
            (spec, Vec::new())
        }
    };
    for (p, &k) in spec.pieces.iter_mut().zip(flat) {
        match (p.fallback, p.placement) {
            (Some(f), _) if k >= ROUND => p.placement = Some(f),
            (Some(_), Some(pl)) if k > 0 => {
                let bounds = crate::mesh::bounds2(&p.outline.loops[0]);
                let by = k as f32 * garment::LAYER;
                p.placement = Some(garment::moved_out(pl, bounds, marks, by));
            }
            _ => {}
        }
    }
    for (p, &more) in spec.pieces.iter_mut().zip(out) {
        if let Some(garment::Placement::Around { out, .. }) = &mut p.placement {
            *out += more;
        }
    }
    let made = garment::assemble(&spec, marks, cfg.edge)?;
    let crossed = crossings::count(&made.starts, &made.mesh.triangles, body);
    Ok((spec, said, made, crossed))
}

/// [`place`], each piece kept flat that starts crossing a layer further from the body,
/// and past [`garment::FLAT_OUT_TRIES`] layers on its fallback (its steps in `flat`),
/// until none that can starts crossing.
fn settle(
    cfg: &Source<'_>,
    body: Option<&Body>,
    marks: &Landmarks,
    out: &[f32],
    flat: &mut Vec<usize>,
) -> Result<Placed, ScenarioError> {
    loop {
        let (spec, said, made, crossed) = place(cfg, body, marks, out, flat)?;
        flat.resize(spec.pieces.len(), 0);
        let clear = crossed.self_pairs == 0 && crossed.body_pairs == 0;
        let step: Vec<usize> = if clear {
            Vec::new()
        } else {
            let can = |i: &usize| flat[*i] < ROUND && spec.pieces[*i].fallback.is_some();
            let crossing = super::garment::pieces_crossing(&made, body);
            crossing.into_iter().filter(can).collect()
        };
        if step.is_empty() {
            return Ok((spec, said, made, crossed));
        }
        step.into_iter().for_each(|i| flat[i] += 1);
    }
}

/// What a designer is told of the pieces kept flat where their file puts them (or
/// layers further from the body: their steps in `flat`), and of those that start round
/// the torso instead ([`ROUND`]): flat, they would start crossing.
fn kept_flat(spec: &PatternSpec, flat: &[usize]) -> Vec<String> {
    let (mut kept, mut out, mut fell) = (Vec::new(), Vec::new(), Vec::new());
    for (i, p) in (spec.pieces.iter().enumerate()).filter(|(_, p)| p.fallback.is_some()) {
        match flat.get(i).copied().unwrap_or(0) {
            0 => kept.push(p.name.as_str()),
            k if k >= ROUND => fell.push(p.name.as_str()),
            k => out.push((p.name.as_str(), k)),
        }
    }
    // One piece's words, or more than one's.
    let say = |names: &[&str], one: &str, more: &str| {
        let words = if names.len() == 1 { one } else { more };
        format!("{} {words}", names.join(", "))
    };
    let mut said = Vec::new();
    if !kept.is_empty() {
        said.push(say(
            &kept,
            "starts flat where it was placed: its top is wider than half the way round the body, and bent round it, it would start over the pieces sewn to its sides",
            "start flat where they were placed: their tops are wider than half the way round the body, and bent round it, they would start over the pieces sewn to their sides",
        ));
    }
    for (name, k) in out {
        said.push(format!(
            "{name} starts flat {:.1} cm further from the body than placed: its top is wider than half the way round the body, and nearer, it would start through the body or another piece",
            100.0 * k as f32 * garment::LAYER
        ));
    }
    if !fell.is_empty() {
        let cm = 100.0 * garment::FLAT_OUT_TRIES as f32 * garment::LAYER;
        said.push(say(
            &fell,
            &format!("starts bent round the body: flat, where it was placed or up to {cm:.1} cm further from the body, it would start through the body or another piece"),
            &format!("start bent round the body: flat, where they were placed or up to {cm:.1} cm further from the body, they would start through the body or another piece"),
        ));
    }
    said
}

/// What a designer is told of the pieces that start further out than placed (`out`, m
/// each), one line per distance.
fn further_out(spec: &PatternSpec, out: &[f32]) -> Vec<String> {
    let mut by: Vec<(i32, Vec<&str>)> = Vec::new();
    for (p, &o) in spec.pieces.iter().zip(out).filter(|(_, o)| **o > 0.0) {
        let mm = (1000.0 * o).round() as i32;
        match by.iter_mut().find(|(d, _)| *d == mm) {
            Some((_, names)) => names.push(&p.name),
            None => by.push((mm, vec![&p.name])),
        }
    }
    (by.into_iter())
        .map(|(mm, names)| {
            format!(
                "{} start{} {:.1} cm further out from the body than placed: nearer, {} would start through it",
                names.join(", "),
                if names.len() == 1 { "s" } else { "" },
                0.1 * mm as f32,
                if names.len() == 1 { "it" } else { "they" }
            )
        })
        .collect()
}
