//! What the design layer's tests share.

/// The dress scenario's design at `edge` m edges, its seams sewn at 45 N/m, draped
/// `frames` frames on the mannequin.
pub(crate) fn sewn_dress(edge: f32, frames: usize) -> super::Design {
    use crate::scenario::{ScenarioConfig, ScenarioName, build_scene};
    let mut cfg = ScenarioConfig::new(ScenarioName::DressMannequin);
    cfg.piece_edge = edge;
    let (mut d, spec) = build_scene(&cfg).unwrap();
    super::garment::sew(&mut d, &spec.unwrap(), 45.0).unwrap();
    for _ in 0..frames {
        d.step().unwrap();
    }
    d
}
