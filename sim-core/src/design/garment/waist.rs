//! Whether a garment held up by its waist while it settled can stay up once let go: its
//! waist's length round at rest against the way round the body below it.
//!
//! A ring of cloth longer than the hips' girth passes over them without stretching:
//! only friction keeps such a skirt up, on a real body too. One shorter stays up only if
//! the cloth does not stretch over the hips; if it slides off all the same, the solver let
//! it stretch (docs/garments.md: at 5 substeps the xpbd model's strain limit gives way
//! under a circle skirt's weight, at 20 it holds).

use super::place::Landmarks;
use crate::design::Design;
use crate::mesh::live::NONE;

/// How far below a waist the hips' girth is looked for, m: a standing body's widest
/// girth under its waist is within 25 cm of it; farther down, the legs part.
pub const HIPS_BELOW: f32 = 0.35;

/// How far above a waist cloth must reach for something else to hold the garment up, m
/// (a skirt's waistband is 3-10 cm tall; a top reaches its shoulders 30-50 cm higher).
pub const ABOVE: f32 = 0.15;

/// The least share of the held vertices that must have a border edge to another for the
/// waist to be measured: an open chain of `n` vertices on each of a skirt's `k` panels has
/// `n - k` border edges between them.
const BORDER_SHARE: f32 = 0.8;

/// A held waist and the body below it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waist {
    /// The waist's length round at rest: the cloth's border edges between held vertices, m.
    pub round: f32,
    /// Its height when measured (the held vertices' mean), m.
    pub height: f32,
    /// The longest way round the body within [`HIPS_BELOW`] under it, m.
    pub hips: f32,
    /// Whether the garment hangs from this waist: none of its cloth is more than
    /// [`ABOVE`] higher (a skirt, trousers; a top's waistband hangs from its shoulders).
    pub hangs: bool,
}

impl Waist {
    /// Of the vertices `held` in `design` as they are now; None when they share no
    /// border edge or there is no body under them.
    pub fn of(design: &Design, held: &[u32]) -> Option<Self> {
        let live = &design.sim.cloth.live;
        let x = &design.sim.cloth.x;
        let n = x.len();
        let mut is_held = vec![false; n];
        for &v in held {
            if let Some(h) = is_held.get_mut(v as usize) {
                *h = live.vertex_alive(v);
            }
        }
        let on = |v: u32| is_held.get(v as usize).copied().unwrap_or(false);
        let (mut round, mut edges) = (0.0f32, 0usize);
        for (_, t) in live.iter() {
            for (k, (a, b, _)) in t.edges().into_iter().enumerate() {
                if on(a) && on(b) && live.edge(a, b)[1] == NONE {
                    round += (t.rest[(k + 1) % 3] - t.rest[k]).length();
                    edges += 1;
                }
            }
        }
        let alive: Vec<f32> = (held.iter())
            .filter(|&&v| on(v))
            .map(|&v| x[v as usize].y)
            .collect();
        // A waist sewn to a bodice, wholly or in part, is no border there: its length
        // round is not known from the border (a few vertices short of one edge each are
        // the open chains' ends, one per piece).
        if round <= 0.0 || (edges as f32) < BORDER_SHARE * alive.len() as f32 {
            return None;
        }
        let height = alive.iter().sum::<f32>() / alive.len() as f32;
        let top = cloth_top(design);
        let profile = Landmarks::of(design.sim.body.as_ref()).profile;
        let hips = profile.widest_girth(height - HIPS_BELOW, height);
        (hips > 0.0).then_some(Self {
            round,
            height,
            hips,
            hangs: top - height <= ABOVE,
        })
    }

    /// Whether the garment hangs from a waist longer round than the hips: it falls past
    /// them unstretched.
    pub fn falls_off(&self) -> bool {
        self.hangs && self.round > self.hips
    }
}

/// The highest point of the cloth's live triangles, m.
pub fn cloth_top(design: &Design) -> f32 {
    let x = &design.sim.cloth.x;
    (design.sim.cloth.live.iter())
        .flat_map(|(_, t)| t.v)
        .map(|v| x[v as usize].y)
        .fold(f32::NEG_INFINITY, f32::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::ModelKind;

    #[test]
    fn a_held_border_is_measured_round_at_rest_against_the_body_below_it() {
        // A 1 m cloth of 4 x 4 cells at 1.2 m over a 0.4 m cube (its top at 0.6 m).
        let mesh = ClothMesh::grid(1.0, 1.0, 4, 4, 1.2).unwrap();
        let mut design = crate::design::floating(mesh, ModelKind::Xpbd);
        design.sim.body = Some(crate::collision::body::cube(glam::Vec3::Y * 0.4, 0.2, 2).unwrap());
        // Stretch the cloth: the waist is its length at rest, not as it lies.
        for x in &mut design.sim.cloth.x {
            *x *= 1.5;
        }
        // And stand it up, the first row at the top.
        let up = design.sim.cloth.x[0].z.signum();
        for x in &mut design.sim.cloth.x {
            (x.y, x.z) = (2.0 + up * x.z, 0.0);
        }
        // The grid's first row: 4 border edges, the cloth's side.
        let row: Vec<u32> = (0..5).collect();
        let w = Waist::of(&design, &row).unwrap();
        assert!((w.round - 1.0).abs() < 1e-5, "{w:?}");
        // Known only by its bounds, the cube is as wide round as the circle through its
        // corners: 2 pi x 0.2 sqrt 2.
        let round = std::f32::consts::TAU * 0.2 * std::f32::consts::SQRT_2;
        assert!((w.hips - round).abs() < 1e-4, "{w:?}");
        assert!(w.hangs && !w.falls_off(), "{w:?}");
        // Round a cube half as wide (0.89 m) the metre falls.
        design.sim.body = Some(crate::collision::body::cube(glam::Vec3::Y * 0.4, 0.1, 2).unwrap());
        assert!(Waist::of(&design, &row).unwrap().falls_off());
        // Held by its bottom row it hangs from what is above (the cloth's 1.5 m).
        let bottom: Vec<u32> = (20..25).collect();
        let w = Waist::of(&design, &bottom).unwrap();
        assert!(!w.hangs && !w.falls_off(), "{w:?}");
        // Vertices that share no border edge measure nothing, nor do a few that share
        // one (a waist sewn to a bodice but for a pair), nor does no body.
        assert_eq!(Waist::of(&design, &[0, 12]), None);
        assert_eq!(Waist::of(&design, &[0, 1, 12, 13, 23]), None);
        assert_eq!(Waist::of(&design, &[]), None);
        design.sim.body = None;
        assert_eq!(Waist::of(&design, &row), None);
    }
}
