//! A garment held while it settles (a waistband at the waist, as GarmentCode's simulator
//! holds it): what holds it and at how many substeps, and, once let go, whether it slid
//! down the body and why (docs/garments.md).

use crate::design::Design;
use crate::design::garment::{PatternSpec, Waist, cloth_top};
use crate::solver::ModelKind;

/// How far a garment's highest point may drop after its holds let go before the run
/// says it slid down the body, m.
const SLID: f32 = 0.15;

/// Watches a garment held while it settles ([`Design::hold_while_draping`]): where its
/// highest point was when the holds let go, and its waist against the body's hips then,
/// to say at the end whether it slid down the body and why (GarmentCode's skirts can
/// slide off the hips: docs/garments.md).
pub(super) struct Release {
    /// The vertices held at the last frame they were.
    held: Vec<u32>,
    /// The frame the holds let go after, the cloth's top then (m), and its waist.
    at: Option<(u64, f32, Option<Waist>)>,
}

impl Release {
    pub(super) fn watching(design: &Design) -> Self {
        Self {
            held: design.held().0.iter().map(|h| h.vertex).collect(),
            at: None,
        }
    }

    pub(super) fn after_frame(&mut self, design: &Design, frame: u64) {
        if self.held.is_empty() || self.at.is_some() {
            return;
        }
        let holds = design.held().0;
        if holds.is_empty() {
            let waist = Waist::of(design, &self.held);
            self.at = Some((frame, cloth_top(design), waist));
        } else {
            self.held.clear();
            self.held.extend(holds.iter().map(|h| h.vertex));
        }
    }

    /// Says (and records in the design's notices) how far the garment slid, if it did,
    /// and why.
    pub(super) fn finish(self, design: &mut Design) {
        let Some((frame, top, waist)) = self.at else {
            return;
        };
        let drop = top - cloth_top(design);
        if drop > SLID {
            let why = slid_because(waist, design.sim.model, design.sim.substeps);
            let n = format!(
                "the garment slid {drop:.2} m down the body after its holds let go at frame {frame}: {why}"
            );
            eprintln!("note: {n}");
            design.sim.notices.push(n);
        }
    }
}

/// Why a garment held by its waist slid down once let go: a waist longer than the hips,
/// or cloth that stretched over them (with what holds it under `model` at `substeps`).
fn slid_because(waist: Option<Waist>, model: ModelKind, substeps: usize) -> String {
    let Some(w) = waist.filter(|w| w.hangs) else {
        return "its cloth stretched or slid over the body (docs/garments.md)".into();
    };
    let (round, hips) = (w.round, w.hips);
    if w.falls_off() {
        return format!(
            "its waist is {round:.2} m round at rest, longer than the body's {hips:.2} m round the hips below it, so only friction could keep it up (a real body's too)"
        );
    }
    let stretch = 100.0 * (hips / round - 1.0);
    let remedy = match model {
        ModelKind::Xpbd if substeps < FIRM_SUBSTEPS => format!(
            "; the xpbd model's cloth gives that much under a garment's weight at {substeps} substeps: --model vbd holds it, and --substeps {FIRM_SUBSTEPS} may"
        ),
        ModelKind::Xpbd => {
            "; the xpbd model's cloth gives that much under a garment's weight: --model vbd holds it".into()
        }
        _ => String::new(),
    };
    format!(
        "its waist ({round:.2} m round at rest) stretched {stretch:.0}% to pass the body's {hips:.2} m round the hips{remedy} (docs/garments.md)"
    )
}

/// The substeps at which the xpbd model held two of GarmentCode's random skirts on the
/// hips that slid off at 5 (a third slid at 20 too; vbd held all three), and the shipped
/// circle skirt (docs/garments.md): a garment hanging from its waist runs at these.
pub const FIRM_SUBSTEPS: usize = 20;

/// Holds what `spec` holds while the garment settles (a waistband at the waist), and says
/// what (`None`: it holds nothing); a waist too wide to stay up once let go is a notice
/// of the design's. A garment that hangs from its waist under xpbd runs at
/// [`FIRM_SUBSTEPS`] unless `asked` names the substeps: at 5, skirts whose waists fit the
/// body slid over its hips once let go (docs/garments.md).
pub fn hold_pattern(
    design: &mut Design,
    spec: &PatternSpec,
    asked: Option<usize>,
) -> Option<String> {
    let holds = crate::design::garment::holds(design, spec);
    if holds.is_empty() {
        return None;
    }
    let mut what: Vec<&str> = spec.holds.iter().map(|h| h.label.as_str()).collect();
    what.dedup();
    let mut said = format!(
        "{} vertices ({}) held for the first {} frames",
        holds.len(),
        what.join(", "),
        crate::design::HOLD_FRAMES
    );
    let held: Vec<u32> = holds.iter().map(|h| h.vertex).collect();
    design.hold_while_draping(holds);
    let waist = Waist::of(design, &held);
    if let Some(w) = waist.filter(Waist::falls_off) {
        design.sim.notices.push(format!(
            "its waist is {:.2} m round at rest, longer than the body's {:.2} m round the hips below it: it will slide down once the holds let go",
            w.round, w.hips
        ));
    } else if let Some(w) = waist.filter(|w| w.hangs)
        && design.sim.model == ModelKind::Xpbd
        && asked.is_none()
        && design.sim.substeps < FIRM_SUBSTEPS
    {
        said += &format!(
            "; it hangs from its waist ({:.2} m round, the hips {:.2} m): xpbd at {FIRM_SUBSTEPS} substeps instead of {}, so its cloth holds it up (--substeps to choose)",
            w.round, w.hips, design.sim.substeps
        );
        design.sim.substeps = FIRM_SUBSTEPS;
    }
    Some(said)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scenario::{ScenarioConfig, ScenarioName};

    /// A small cloth over the cube, held at two corners, the holds let go, then moved
    /// down by `drop` m: what the run says.
    fn said_after_dropping(drop: f32) -> Vec<String> {
        let mut cfg = ScenarioConfig::new(ScenarioName::DrapeCube);
        cfg.grid = 4;
        let mut design = crate::scenario::build_design(&cfg).unwrap();
        let hold = |vertex| crate::solver::Hold {
            vertex,
            normal: Vec3::Y,
            level: 0.0,
            max_force: 0.05,
        };
        design.hold_while_draping(vec![hold(0), hold(24)]);
        let mut release = Release::watching(&design);
        release.after_frame(&design, 1);
        assert_eq!(release.at, None, "still held");
        design.hold_while_draping(Vec::new());
        release.after_frame(&design, 2);
        assert_eq!(release.at.map(|(f, _, _)| f), Some(2));
        for x in &mut design.sim.cloth.x {
            x.y -= drop;
        }
        let before = design.sim.notices.len();
        release.finish(&mut design);
        design.sim.notices[before..].to_vec()
    }

    #[test]
    fn a_garment_that_slides_down_after_its_holds_let_go_is_said_to() {
        let said = said_after_dropping(0.4);
        assert_eq!(said.len(), 1, "{said:?}");
        assert!(
            said[0].contains("slid 0.40 m") && said[0].contains("frame 2"),
            "{said:?}"
        );
        // Settling a few centimetres is not sliding off.
        assert!(said_after_dropping(0.05).is_empty());
    }

    #[test]
    fn why_a_garment_slid_names_its_waist_against_the_hips() {
        let waist = |round| {
            Some(Waist {
                round,
                height: 1.09,
                hips: 1.04,
                hangs: true,
            })
        };
        let wide = slid_because(waist(1.11), ModelKind::Xpbd, 5);
        assert!(
            wide.contains("1.11 m round") && wide.contains("longer than the body's 1.04 m"),
            "{wide}"
        );
        let stretched = slid_because(waist(0.85), ModelKind::Xpbd, 5);
        assert!(stretched.contains("stretched 22%"), "{stretched}");
        assert!(stretched.contains("--model vbd") && stretched.contains("--substeps 20"));
        // At 20 substeps only vbd is left to offer; under vbd, nothing.
        let firm = slid_because(waist(0.85), ModelKind::Xpbd, 20);
        assert!(
            firm.contains("--model vbd") && !firm.contains("--substeps"),
            "{firm}"
        );
        let vbd = slid_because(waist(0.85), ModelKind::Vbd, 2);
        assert!(
            vbd.contains("stretched 22%") && !vbd.contains("--"),
            "{vbd}"
        );
        // A top's waistband hangs from the shoulders: its waist says nothing.
        let top = waist(1.34).map(|w| Waist { hangs: false, ..w });
        for w in [None, top] {
            let s = slid_because(w, ModelKind::Xpbd, 5);
            assert!(
                !s.contains("waist") && s.contains("docs/garments.md"),
                "{s}"
            );
        }
    }
}
