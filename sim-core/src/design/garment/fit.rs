//! How a garment fits: its length round at the bust, the waist and the hips beside the
//! body's own, as a designer reads a toile on the form with a tape measure. The
//! difference is the ease a pattern is drafted with (a fitted dress has a few centimetres
//! at the bust, a loose top ten or more; a negative ease is cloth stretched round the body).
//!
//! The levels are found on the body's own surface, so any standing figure of a human's
//! height has them (the mannequin in either pose, GarmentCode's human, an OBJ figure):
//! - the **waist** is the narrowest girth of the torso between 56% and 70% of the
//!   figure's height;
//! - the **bust** is the widest above it, up to where the arms join the torso (the
//!   lowest level above the waist where the section has no loop but the torso's, once it
//!   had arms beside it; on a figure without arms, 80% of its height);
//! - the **hips** are the widest within 30 cm below the waist, while the section still
//!   goes round the body's axis (above where the legs part).
//!
//! The body's girth is the tape's: the length of the convex hull of the torso's section,
//! which bridges every hollow. The garment's is the cloth's own length round: the loop
//! its section makes round the body's axis (the innermost, where layers lie over each
//! other), folds and gathers included, as a pattern's width is measured; a garment whose
//! cloth does not close round the body there (an open seam, a side left unsewn) has none.

use glam::{Vec2, Vec3};
use serde::Serialize;

use crate::mesh::bounds;
use crate::mesh::section::{Chain, hull, perimeter, section};

/// The shortest figure measured, m: bodies under it (the cube, the sphere) are no figure.
pub const MIN_HEIGHT_M: f32 = 1.0;

/// The step between the levels tried, m.
const STEP_M: f32 = 0.005;

/// The waist is looked for between these shares of the figure's height.
const WAIST_BAND: (f32, f32) = (0.56, 0.70);

/// The bust's top on a figure whose arms are not found, as a share of its height.
const BUST_TOP: f32 = 0.80;

/// The bust is looked for from this far above the waist, m, to this far under the arms.
const BUST_FROM_M: f32 = 0.05;
const UNDER_ARMS_M: f32 = 0.02;

/// The hips are looked for this far below the waist, m.
const HIPS_BAND_M: (f32, f32) = (0.05, 0.30);

/// The shortest loop beside the torso's that is taken for an arm, m.
const ARM_MIN_M: f32 = 0.05;

/// One level's girths.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Girth {
    /// "bust", "waist" or "hips".
    pub level: &'static str,
    /// Its height above the floor the body stands on, m.
    pub height_m: f32,
    /// The tape round the body there, m.
    pub body_m: f32,
    /// The cloth's length round the body there, m; none where it does not go round.
    pub garment_m: Option<f32>,
    /// `garment_m - body_m`, m.
    pub ease_m: Option<f32>,
    /// Where the cloth does not go round (an armhole, a side left open): how many runs
    /// of cloth the level crosses, and their length together, m (0 and none where it
    /// goes round, or where there is no cloth).
    pub open_runs: usize,
    pub open_cloth_m: Option<f32>,
    /// The body's hull and the garment's loop there, (x, z) at `height_m`: the studio
    /// draws them.
    #[serde(skip)]
    pub body_ring: Vec<Vec2>,
    #[serde(skip)]
    pub garment_ring: Vec<Vec2>,
}

/// A figure's levels, found once for its body.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The body's vertical axis (x, z), m: the middle of its bounds.
    pub axis: Vec2,
    /// Each level's name, height and the tape's hull there.
    pub levels: Vec<(&'static str, f32, Vec<Vec2>)>,
}

/// The torso's section at one level: the hull round it, and how many loops lie beside it.
struct Torso {
    hull: Vec<Vec2>,
    tape: f32,
    beside: usize,
}

fn torso(x: &[Vec3], tris: &[[u32; 3]], level: f32, axis: Vec2) -> Option<Torso> {
    let chains = section(x, tris, level);
    let round = chains
        .iter()
        .filter(|c| c.goes_round(axis))
        .max_by(|a, b| a.area().total_cmp(&b.area()))?;
    let beside = chains
        .iter()
        .filter(|c| c.closed && !c.goes_round(axis) && c.length() > ARM_MIN_M)
        .filter(|c| !c.points.iter().any(|&p| round.goes_round(p)))
        .count();
    let hull = hull(&round.points);
    Some(Torso {
        tape: perimeter(&hull),
        hull,
        beside,
    })
}

/// The vertical extent and axis of the body with vertices `x`: its lowest point, its
/// height and its axis (x, z), m; None when it is no standing figure (under
/// [`MIN_HEIGHT_M`] tall).
fn standing(x: &[Vec3]) -> Option<(f32, f32, Vec2)> {
    if x.is_empty() {
        return None;
    }
    let (mn, mx) = bounds(x);
    let tall = mx.y - mn.y;
    if tall.is_nan() || tall < MIN_HEIGHT_M {
        return None;
    }
    Some((
        mn.y,
        tall,
        Vec2::new(0.5 * (mn.x + mx.x), 0.5 * (mn.z + mx.z)),
    ))
}

/// The waist of a standing body (`standing`'s `base`, `tall`, `axis`): the torso's
/// narrowest section within [`WAIST_BAND`] of its height (the last of equal girths), and
/// its height.
fn waist_of(
    x: &[Vec3],
    tris: &[[u32; 3]],
    (base, tall, axis): (f32, f32, Vec2),
) -> Option<(f32, Torso)> {
    let (lo, hi) = (base + WAIST_BAND.0 * tall, base + WAIST_BAND.1 * tall);
    let n = ((hi - lo) / STEP_M).floor().max(0.0) as usize;
    (0..=n)
        .map(|k| lo + k as f32 * STEP_M)
        .filter_map(|h| torso(x, tris, h, axis).map(|t| (h, t)))
        .max_by(|a, b| b.1.tape.total_cmp(&a.1.tape))
}

/// The waist's height of the body with vertices `x` and triangles `tris` ([`Figure::of`]'s
/// waist, found alone: where a skirt drawn in a pattern file starts), m; None when it is
/// no standing figure.
pub fn waist_height(x: &[Vec3], tris: &[[u32; 3]]) -> Option<f32> {
    waist_of(x, tris, standing(x)?).map(|(h, _)| h)
}

impl Figure {
    /// The levels of the body with vertices `x` and triangles `tris`; None when it is no
    /// standing figure (under [`MIN_HEIGHT_M`] tall, or no waist found round its axis).
    pub fn of(x: &[Vec3], tris: &[[u32; 3]]) -> Option<Self> {
        let (base, tall, axis) = standing(x)?;
        let at = |share: f32| base + share * tall;
        let steps = |lo: f32, hi: f32| {
            let n = ((hi - lo) / STEP_M).floor().max(0.0) as usize;
            (0..=n).map(move |k| lo + k as f32 * STEP_M)
        };
        let sample = |lo: f32, hi: f32| -> Vec<(f32, Torso)> {
            steps(lo, hi)
                .filter_map(|h| torso(x, tris, h, axis).map(|t| (h, t)))
                .collect()
        };
        let widest = |s: &[(f32, Torso)]| {
            s.iter()
                .max_by(|a, b| a.1.tape.total_cmp(&b.1.tape))
                .map(|(h, t)| (*h, t.hull.clone()))
        };
        let (waist, waist_torso) = waist_of(x, tris, (base, tall, axis))?;
        let waist_hull = waist_torso.hull;
        // Upward from the waist: the bust, under the arms.
        let above = sample(waist + BUST_FROM_M, at(BUST_TOP + 0.1));
        let armed = above.iter().position(|(_, t)| t.beside > 0);
        let top = match armed {
            Some(first) => (above[first..].iter())
                .find(|(_, t)| t.beside == 0)
                .map_or(at(BUST_TOP), |(h, _)| h - UNDER_ARMS_M),
            None => at(BUST_TOP),
        };
        let under: Vec<(f32, Torso)> = above.into_iter().filter(|(h, _)| *h <= top).collect();
        let bust = widest(&under);
        let hips = widest(&sample(waist - HIPS_BAND_M.1, waist - HIPS_BAND_M.0));
        let mut levels = Vec::new();
        if let Some((h, hull)) = bust {
            levels.push(("bust", h, hull));
        }
        levels.push(("waist", waist, waist_hull));
        if let Some((h, hull)) = hips {
            levels.push(("hips", h, hull));
        }
        Some(Self { axis, levels })
    }

    /// Adds a level named `name` at height `h` of the body with vertices `x` and
    /// triangles `tris` (the one [`Figure::of`] was found on): a hem, a high hip, a
    /// level a designer chooses. False, and nothing added, where the body has no torso
    /// round its axis at `h` (above the head, between the legs).
    pub fn add_level(&mut self, x: &[Vec3], tris: &[[u32; 3]], name: &'static str, h: f32) -> bool {
        match h
            .is_finite()
            .then(|| torso(x, tris, h, self.axis))
            .flatten()
        {
            Some(t) => {
                self.levels.push((name, h, t.hull));
                true
            }
            None => false,
        }
    }

    /// The garment with vertices `x` and triangles `tris` measured at each level.
    pub fn fit(&self, x: &[Vec3], tris: &[[u32; 3]]) -> Vec<Girth> {
        self.levels
            .iter()
            .map(|(level, h, hull)| {
                let body_m = perimeter(hull);
                let chains = section(x, tris, *h);
                let round: Option<Chain> = (chains.iter())
                    .filter(|c| c.goes_round(self.axis))
                    .min_by(|a, b| a.area().total_cmp(&b.area()))
                    .cloned();
                let garment_m = round.as_ref().map(Chain::length);
                let open: Vec<&Chain> = match round {
                    Some(_) => Vec::new(),
                    None => chains.iter().filter(|c| !c.closed).collect(),
                };
                Girth {
                    level,
                    height_m: *h,
                    body_m,
                    garment_m,
                    ease_m: garment_m.map(|g| g - body_m),
                    open_runs: open.len(),
                    open_cloth_m: (!open.is_empty()).then(|| open.iter().map(|c| c.length()).sum()),
                    body_ring: hull.clone(),
                    garment_ring: round.map(|c| c.points).unwrap_or_default(),
                }
            })
            .collect()
    }
}

/// The design's garment measured on its body; None without a body that is a figure.
pub fn of_design(design: &crate::design::Design) -> Option<Vec<Girth>> {
    let body = design.sim.body.as_ref()?;
    let figure = Figure::of(&body.vertices, &body.triangles)?;
    let tris: Vec<[u32; 3]> = design.sim.cloth.live.iter().map(|(_, t)| t.v).collect();
    Some(figure.fit(&design.sim.cloth.x, &tris))
}

/// The girths as a designer reads them, one level a line ("bust 0.92 m: the garment 1.01
/// m round, ease +8.6 cm").
pub fn describe(g: &Girth) -> String {
    match (g.garment_m, g.ease_m) {
        (Some(m), Some(e)) => format!(
            "{} at {:.2} m: body {:.1} cm, garment {:.1} cm, ease {:+.1} cm",
            g.level,
            g.height_m,
            100.0 * g.body_m,
            100.0 * m,
            100.0 * e
        ),
        _ => match g.open_cloth_m {
            Some(m) => format!(
                "{} at {:.2} m: body {:.1} cm, the garment is open there ({} run{} of cloth, \
                 {:.1} cm in all)",
                g.level,
                g.height_m,
                100.0 * g.body_m,
                g.open_runs,
                if g.open_runs == 1 { "" } else { "s" },
                100.0 * m
            ),
            None => format!(
                "{} at {:.2} m: body {:.1} cm, no garment round it there",
                g.level,
                g.height_m,
                100.0 * g.body_m
            ),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::body::{Pose, posed_mannequin};

    #[test]
    fn the_mannequins_levels_are_where_its_shape_puts_them() {
        for pose in [Pose::Hanging, Pose::A] {
            let b = posed_mannequin(pose).unwrap();
            let f = Figure::of(&b.vertices, &b.triangles).unwrap();
            let names: Vec<&str> = f.levels.iter().map(|l| l.0).collect();
            assert_eq!(names, ["bust", "waist", "hips"], "{pose:?}");
            let h = |k: usize| f.levels[k].1;
            // The chest's ellipsoid is widest at 1.30 m, the belly's at 1.03; the waist
            // lies where they meet.
            assert!((h(0) - 1.30).abs() < 0.04, "{pose:?} bust at {}", h(0));
            assert!((1.10..1.22).contains(&h(1)), "{pose:?} waist at {}", h(1));
            assert!((h(2) - 1.03).abs() < 0.04, "{pose:?} hips at {}", h(2));
            let tape: Vec<f32> = f.levels.iter().map(|l| perimeter(&l.2)).collect();
            // The chest's ellipse (0.18 x 0.11 m) is 0.92 m round; the arms left out.
            assert!((tape[0] - 0.92).abs() < 0.03, "{pose:?} bust {}", tape[0]);
            assert!(tape[1] < tape[0] && tape[1] < tape[2], "{pose:?} {tape:?}");
        }
    }

    #[test]
    fn a_level_is_added_where_the_torso_is_and_refused_elsewhere() {
        let b = posed_mannequin(Pose::Hanging).unwrap();
        let mut f = Figure::of(&b.vertices, &b.triangles).unwrap();
        // The chest's ellipsoid at 1.25 m: 0.174 x 0.107 m, 0.89 m round.
        assert!(f.add_level(&b.vertices, &b.triangles, "at", 1.25));
        let (name, h, hull) = f.levels.last().unwrap();
        assert_eq!((*name, *h), ("at", 1.25));
        assert!((perimeter(hull) - 0.89).abs() < 0.02, "{}", perimeter(hull));
        // Over the head, between the legs, and not a number: no level.
        for h in [1.9, 0.4, f32::NAN] {
            assert!(!f.add_level(&b.vertices, &b.triangles, "at", h), "{h}");
        }
        assert_eq!(f.levels.len(), 4);
    }

    #[test]
    fn no_figure_in_a_cube() {
        let c = crate::collision::body::cube(Vec3::new(0.0, 0.2, 0.0), 0.2, 8).unwrap();
        assert_eq!(Figure::of(&c.vertices, &c.triangles), None);
    }

    /// A cylinder of `n` sides round the y axis, radius `r`, from `y0` to `y1`, open.
    fn tube(n: u32, r: f32, y0: f32, y1: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut x = Vec::new();
        for k in 0..n {
            let a = std::f32::consts::TAU * k as f32 / n as f32;
            x.push(Vec3::new(r * a.cos(), y0, r * a.sin()));
            x.push(Vec3::new(r * a.cos(), y1, r * a.sin()));
        }
        let t = (0..n)
            .flat_map(|k| {
                let (a, b) = (2 * k, 2 * ((k + 1) % n));
                [[a, b, a + 1], [b, b + 1, a + 1]]
            })
            .collect();
        (x, t)
    }

    #[test]
    fn a_tube_round_the_mannequin_is_measured_round_and_an_open_one_is_not() {
        let b = posed_mannequin(Pose::Hanging).unwrap();
        let f = Figure::of(&b.vertices, &b.triangles).unwrap();
        // A 0.2 m tube round the torso (outside the arms too: 1.26 m round).
        let (x, mut t) = tube(64, 0.2, 0.8, 1.45);
        let g = f.fit(&x, &t);
        let round = 64.0 * 2.0 * 0.2 * (std::f32::consts::PI / 64.0).sin();
        for gi in &g {
            let m = gi.garment_m.unwrap();
            assert!((m - round).abs() < 1e-3, "{gi:?}");
            assert!((gi.ease_m.unwrap() - (m - gi.body_m)).abs() < 1e-6);
            assert!(describe(gi).contains("ease +"), "{}", describe(gi));
        }
        // Slit down one side: no level goes round; the cloth there is one open run.
        t.drain(0..2);
        for gi in f.fit(&x, &t) {
            assert_eq!(gi.garment_m, None, "{gi:?}");
            assert_eq!(gi.open_runs, 1, "{gi:?}");
            let open = gi.open_cloth_m.unwrap();
            assert!(open < round && open > 0.9 * round, "{gi:?}");
            assert!(
                describe(&gi).contains("open there (1 run of cloth"),
                "{}",
                describe(&gi)
            );
        }
        // No cloth at all.
        for gi in f.fit(&x, &[]) {
            assert_eq!(
                (gi.garment_m, gi.open_cloth_m, gi.open_runs),
                (None, None, 0)
            );
            assert!(describe(&gi).contains("no garment"));
        }
    }

    #[test]
    fn of_two_layers_the_one_next_to_the_body_is_measured() {
        let b = posed_mannequin(Pose::Hanging).unwrap();
        let f = Figure::of(&b.vertices, &b.triangles).unwrap();
        let (mut x, mut t) = tube(64, 0.2, 0.8, 1.45);
        let (x2, t2) = tube(64, 0.3, 0.8, 1.45);
        let n = x.len() as u32;
        x.extend(x2);
        t.extend(t2.iter().map(|t| t.map(|v| v + n)));
        let inner = 64.0 * 2.0 * 0.2 * (std::f32::consts::PI / 64.0).sin();
        for gi in f.fit(&x, &t) {
            assert!((gi.garment_m.unwrap() - inner).abs() < 1e-3, "{gi:?}");
        }
    }
}
