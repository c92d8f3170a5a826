//! `report.json`: what a scenario measured.

use serde::Serialize;

/// Percentiles and the mean of a sample, in the sample's unit (the mean is what a run
/// costs in all: a median hides the few dear frames of a cloth that rests).
#[derive(Clone, Copy, Debug, Default, Serialize, PartialEq)]
pub struct Percentiles {
    pub p50: f64,
    pub p99: f64,
    pub max: f64,
    pub mean: f64,
}

impl Percentiles {
    /// Nearest-rank percentiles; all zero for an empty sample.
    pub fn of(samples: &[f64]) -> Self {
        if samples.is_empty() {
            return Self::default();
        }
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let rank = |q: f64| s[((q * s.len() as f64).ceil() as usize).clamp(1, s.len()) - 1];
        Self {
            p50: rank(0.50),
            p99: rank(0.99),
            max: s[s.len() - 1],
            mean: s.iter().sum::<f64>() / s.len() as f64,
        }
    }
}

/// A stitched pair left open: its seam's label (the letter the pattern marks it by), its
/// place in the seam (0 at the seam's start), the gap between its two ends (m), where
/// its first end lies (m), and whether the open pairs had stopped closing (none a
/// millimetre nearer for `STALL_TOLD_AFTER` frames; `design::stalls`), and what lies
/// across the straight line between its ends: "cloth" (it is threaded round a fold),
/// "body" or "nothing" (`Design::between`).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct OpenPair {
    pub seam: String,
    pub pair: usize,
    pub gap_m: f32,
    pub at: [f32; 3],
    pub stalled: bool,
    pub between: &'static str,
}

/// The operation scenarios' part of the report.
#[derive(Clone, Debug, Default, Serialize)]
pub struct OpsReport {
    /// fit-cube: corner pieces cut away.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cuts: Option<usize>,
    /// fit-cube: seams added and stitched pairs in them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seams: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seam_pairs: Option<usize>,
    /// Welds made (each a sew of two vertices, or a zip of a seam's slit).
    #[serde(rename = "sews", skip_serializing_if = "Option::is_none")]
    pub welds: Option<usize>,
    /// Stitched pairs welded at the end (a weld that joins a vertex paired twice closes
    /// both its pairs, so this can exceed `sews`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seam_pairs_welded: Option<usize>,
    /// Stitched pairs still open at the end: where a seam did not close, and by how much.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seam_pairs_open: Option<Vec<OpenPair>>,
    /// drape-cube and fit-cube: distance from the side panels to the cube's side faces
    /// beyond the contact thickness, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit_gap_mean_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit_gap_max_m: Option<f64>,
    /// tear: edges torn, the frame of the first, and the largest pinch force.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tears: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_tear_frame: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pinch_force_max_n: Option<f64>,
    /// paint: strokes that landed and texels no longer the base colour.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paint_strokes: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texels_painted: Option<usize>,
    /// fold: folds made (of 2); layers over the lying triangles, the most common count
    /// and the most; the least height between two overlapping layers (pattern neighbours
    /// at a crease left out), m; the cloth's highest point, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub folds: Option<usize>,
    /// dress-mannequin: pattern pieces at the end, and the share of 36 directions round
    /// the torso at chest height in which the garment is found.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pieces: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torso_coverage: Option<f64>,
    /// dress-mannequin and drape-pattern on a figure: the garment's length round the
    /// bust, waist and hips beside the body's tape there, and the ease between
    /// (`design::garment::fit`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit: Option<Vec<crate::design::garment::fit::Girth>>,
    /// dress-mannequin: the largest difference between a seam's two sides' pattern
    /// lengths, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seam_length_mismatch_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layers: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layers_max: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub layer_gap_min_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub height_max_m: Option<f64>,
    /// drape-pattern: vertices the pattern holds to the body's planes while the garment
    /// settles (a waistband at the waist), for the first `HOLD_FRAMES` frames.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_vertices: Option<usize>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub scenario: String,
    pub model: String,
    /// Whether the xpbd model ran with its guard (contact that is never crossed).
    pub guard: bool,
    /// The xpbd model's strain limit (`--strain-limit`; 0: none): no side past `1 +`
    /// this times its rest length.
    pub strain_limit: f32,
    /// Garment scenarios: the damping while sewn in the air, 1/s (`--sew-damping`;
    /// dress-mannequin 30 by default, drape-pattern 0; 0: none, and dress-mannequin sews
    /// as it falls).
    pub sew_damping: f32,
    pub body: String,
    pub grid: usize,
    pub vertices: usize,
    pub triangles: usize,
    pub constraints: usize,
    pub frames: u64,
    pub frame_dt_s: f64,
    pub substeps: usize,
    /// Wall time of one whole frame (broad phase + all substeps), ms.
    pub step_ms: Percentiles,
    /// The frame's collision broad phase alone, ms.
    pub collision_ms: Percentiles,
    /// Whether the cloth could fall asleep once at rest (`--sleep`); the frames it slept
    /// through (each a check that nothing changed, a fraction of a millisecond), the
    /// first of them (1-based), and the frame time over the frames it was awake.
    pub sleep: bool,
    pub frames_asleep: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first_frame_asleep: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_ms_awake: Option<Percentiles>,
    /// Each frame's wall time in order, ms to 0.01: where a run spent its time (a drape's
    /// landing frames against its resting ones), which the percentiles do not say.
    pub frame_ms: Vec<f64>,
    pub threads: usize,
    pub max_penetration_m: f64,
    pub thickness_m: f64,
    pub kinetic_energy_final_j: f64,
    pub kinetic_energy_max_j: f64,
    pub mesh_valid: bool,
    /// Stretch of the cloth's triangle sides at the end, `length / rest - 1`: the mean
    /// and the largest. Cotton barely stretches; more is the solver's lag.
    pub strain_mean: f64,
    pub strain_max: f64,
    /// Where the most stretched side is (its midpoint, m), for a look at it.
    pub strain_max_at: Option<[f32; 3]>,
    /// How far the threads are stretched at the end (`solver::thread_stretch`: each triangle's
    /// more stretched thread, warp or weft, `length / cut - 1`): the median triangle's, the
    /// ninetieth percentile's and the most. Shear, which the sides' strain counts as
    /// stretch, is not in it, nor does compression cancel it; the studio's stretch map
    /// shows the same.
    pub thread_stretch_p50: f64,
    pub thread_stretch_p90: f64,
    pub thread_stretch_max: f64,
    /// Exact counts at the end (`collision::crossings`): pairs of cloth triangles that
    /// intersect (sharing no vertex); pairs of a cloth and a body triangle that
    /// intersect, and the cloth triangles among them.
    pub crossings_self: usize,
    pub crossings_body: usize,
    /// Pairs of cloth primitives in contact at the end (`Simulation::self_contacts`):
    /// closer than the thickness, and not neighbours in the pattern.
    pub self_contacts: usize,
    pub crossings_body_triangles: usize,
    /// With `--check-every N`: the most seen at any checked frame (the end included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crossings_self_max: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crossings_body_max: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub check_every: Option<u64>,
    /// Drape-cube only: the largest distance from the top-face part of the cloth to the
    /// plane it should rest on (top + thickness), m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub top_face_gap_max_m: Option<f64>,
    /// Seed model only: the stable step bound, s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stable_step_s: Option<f64>,
    pub settled: bool,
    /// At rest by the sleep rule (`SleepRule::default`): over the last second the cloth
    /// moved under 0.25 mm (root mean square), at most 1% of its vertices past 2 mm, and
    /// the pen did not hold it nor a stitch pull it. Stricter than `settled` (the root
    /// mean square speed under 1 cm/s at the last frame): a 128 x 128 drape was settled
    /// with a flap at the shoulder still swinging 3-4 cm (docs/models.md).
    pub at_rest: bool,
    /// What the operation scenarios did and measured (absent fields: not this scenario).
    #[serde(flatten)]
    pub ops: OpsReport,
    /// Files written besides report.json: the cloth as OBJ + MTL + PNG, and the design.
    pub exported: Vec<String>,
    pub wall_s: f64,
    pub notices: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_nearest_rank() {
        let s: Vec<f64> = (1..=100).map(f64::from).collect();
        assert_eq!(
            Percentiles::of(&s),
            Percentiles {
                p50: 50.0,
                p99: 99.0,
                max: 100.0,
                mean: 50.5,
            }
        );
        assert_eq!(
            Percentiles::of(&[3.0]),
            Percentiles {
                p50: 3.0,
                p99: 3.0,
                max: 3.0,
                mean: 3.0,
            }
        );
        assert_eq!(Percentiles::of(&[]), Percentiles::default());
    }
}
