//! The garment scenarios: dress-mannequin (the shipped pattern `assets/dress.svg`, a
//! front and a back panel with their seams marked, arranged in front of and behind the
//! mannequin, sewn at both shoulders and both sides, its neckline cut) and drape-pattern
//! (any pattern file, placed, sewn and draped the same way).

use glam::Vec2;

use crate::collision::{Body, crossings};
use crate::design::garment::{Assembled, Landmarks, PatternSpec, pattern_from_outlines};
use crate::design::{Design, EditError};
use crate::mesh::svg::{SvgError, read_svg};

/// The dress-mannequin scenario's pattern.
pub const DRESS_SVG: &str = include_str!("../../assets/dress.svg");

/// How hard a garment's seams pull, N per metre of seam: enough to close the 0.35 m over
/// the shoulders before the panels slide down the torso (a tailor pins the shoulders
/// first), fourteen times the interactive default. 0.5 N a pair on the dress's default
/// mesh (its pairs 11 mm apart), the force per pair it replaced.
pub const SEAM_PULL: f32 = 45.0;

/// The dress's pattern, arranged on a body with `marks`.
pub fn dress(marks: &Landmarks) -> Result<PatternSpec, SvgError> {
    let (mut spec, _) = pattern_from_outlines(read_svg(DRESS_SVG)?);
    // The shipped file is checked by the tests; nothing in it can fail here.
    let _ = spec.normalise();
    spec.arrange(marks);
    Ok(spec)
}

/// The front neckline: half its width and its depth below the shoulders' line, m (a
/// round neck between the shoulder seams).
const NECKLINE: Vec2 = Vec2::new(0.07, 0.08);

/// Cuts the front's neckline away along a half ellipse below the middle of its top edge
/// ([`NECKLINE`]), exactly: the new border follows the curve ([`Design::trim`]), not
/// the mesh's edges. Returns how many triangles went.
pub fn cut_neckline(design: &mut Design) -> Result<usize, EditError> {
    let Some(k) = design.pieces.iter().position(|r| r.name == "front") else {
        return Ok(0);
    };
    let rec = &design.pieces[k];
    let (lo, hi) = crate::mesh::bounds2(&rec.outline.loops[0]);
    let mid = 0.5 * (lo.x + hi.x);
    let steps = 48;
    let mut outline: Vec<Vec2> = (0..=steps)
        .map(|i| {
            let a = std::f32::consts::PI * i as f32 / steps as f32;
            Vec2::new(mid - NECKLINE.x * a.cos(), hi.y - NECKLINE.y * a.sin())
        })
        .collect();
    // Closed above the piece.
    outline.push(Vec2::new(mid + NECKLINE.x, hi.y + 0.05));
    outline.push(Vec2::new(mid - NECKLINE.x, hi.y + 0.05));
    let offset = rec.offset;
    let outline: Vec<Vec2> = outline.into_iter().map(|p| p + offset).collect();
    design.trim(&outline)
}

/// How the pieces of an assembled pattern start crossed: each piece's pairs of triangles
/// through the body and through itself, and each two pieces' pairs through each other.
struct StartCrossings {
    body: Vec<usize>,
    own: Vec<usize>,
    /// `(i, j, pairs)`, `i < j`, in order.
    between: Vec<(usize, usize, usize)>,
}

impl StartCrossings {
    fn of(made: &Assembled, body: Option<&Body>) -> Self {
        let x = &made.starts;
        let tris = piece_triangles(made);
        let boxes: Vec<(glam::Vec3, glam::Vec3)> = (made.ranges.iter())
            .map(|r| crate::mesh::bounds(&x[r.clone()]))
            .collect();
        let own: Vec<usize> = tris.iter().map(|t| crossings::count_self(x, t)).collect();
        let through = |t: &[[u32; 3]]| body.map_or(0, |b| crossings::count_against_body(x, t, b).1);
        let mut between = Vec::new();
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                let ((alo, ahi), (blo, bhi)) = (boxes[i], boxes[j]);
                if alo.cmpgt(bhi).any() || blo.cmpgt(ahi).any() {
                    continue;
                }
                let both: Vec<[u32; 3]> = tris[i].iter().chain(&tris[j]).copied().collect();
                let n = crossings::count_self(x, &both).saturating_sub(own[i] + own[j]);
                if n > 0 {
                    between.push((i, j, n));
                }
            }
        }
        Self {
            body: tris.iter().map(|t| through(t)).collect(),
            own,
            between,
        }
    }
}

/// Which pieces of an assembled pattern start crossed, for the refusal's message: each
/// piece through the body, through itself, or through another, with its pairs of
/// triangles ("front through the body in 2 pairs; left_sleeve_f and right_ftorso in 51").
pub fn crossed_pieces(made: &Assembled, body: Option<&Body>) -> String {
    let c = StartCrossings::of(made, body);
    let name = |i: usize| made.records.get(i).map_or("?", |r| r.name.as_str());
    let mut said = Vec::new();
    for i in 0..c.own.len() {
        if c.body[i] > 0 {
            said.push(format!("{} through the body in {}", name(i), c.body[i]));
        }
        if c.own[i] > 0 {
            said.push(format!("{} through itself in {}", name(i), c.own[i]));
        }
        for &(_, j, n) in c.between.iter().filter(|b| b.0 == i) {
            said.push(format!("{} and {} in {n}", name(i), name(j)));
        }
    }
    said.join("; ")
}

/// The pieces of `made` that start crossing the body, themselves or another piece (both
/// of two that cross).
pub(super) fn pieces_crossing(made: &Assembled, body: Option<&Body>) -> Vec<usize> {
    let c = StartCrossings::of(made, body);
    let mut bad: Vec<bool> = (0..c.own.len()).map(|i| c.own[i] + c.body[i] > 0).collect();
    for &(i, j, _) in &c.between {
        (bad[i], bad[j]) = (true, true);
    }
    (0..bad.len()).filter(|&i| bad[i]).collect()
}

/// Each piece's triangles in `made`'s mesh.
fn piece_triangles(made: &Assembled) -> Vec<Vec<[u32; 3]>> {
    let tris = &made.mesh.triangles;
    (made.ranges.iter())
        .map(|r| {
            tris.iter()
                .copied()
                .filter(|t| r.contains(&(t[0] as usize)))
                .collect()
        })
        .collect()
}

/// The pieces of `made` that start through `body` (none without one).
pub(super) fn pieces_through_body(made: &Assembled, body: Option<&Body>) -> Vec<usize> {
    let Some(b) = body else {
        return Vec::new();
    };
    let x = &made.starts;
    (piece_triangles(made).iter().enumerate())
        .filter(|(_, t)| crossings::count_against_body(x, t, b).1 > 0)
        .map(|(i, _)| i)
        .collect()
}

/// Share of 36 directions round the torso at chest height (1.25-1.35 m) in which some
/// of the garment is found within 0.4 m of the body's axis (each triangle sampled at its
/// corners, edge middles and centre, so a coarse mesh is seen too).
pub fn torso_coverage(design: &Design, axis: Vec2) -> f64 {
    let mut seen = [false; 36];
    let x = &design.sim.cloth.x;
    for (_, t) in design.sim.cloth.live.iter() {
        let [a, b, c] = t.v.map(|v| x[v as usize]);
        for p in [
            a,
            b,
            c,
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c) / 3.0,
        ] {
            let d = Vec2::new(p.x - axis.x, p.z - axis.y);
            if (1.25..=1.35).contains(&p.y) && d.length() < 0.4 {
                let ang = d.y.atan2(d.x) + std::f32::consts::PI;
                let k = ((ang / std::f32::consts::TAU * 36.0) as usize).min(35);
                seen[k] = true;
            }
        }
    }
    seen.iter().filter(|&&s| s).count() as f64 / 36.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_dress_has_two_panels_and_four_seams() {
        let marks = Landmarks::of(None);
        let spec = dress(&marks).unwrap();
        let names: Vec<&str> = spec.pieces.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["front", "back"]);
        assert_eq!(spec.seams.len(), 4);
        for s in &spec.seams {
            assert_ne!(s.a.piece, s.b.piece, "{s:?}");
        }
    }
}
