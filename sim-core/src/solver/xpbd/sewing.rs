//! Whether a seam is still being sewn: its stitches still drawing their pairs together.
//!
//! While a seam is sewn its stitches pull the cloth across, and the stretch limits' links
//! take their edge paths, a few per cent longer than their straight rest distance
//! (`limits`): held at the straight distance, the cloth between the stitches would not
//! let them close. A pair that can no longer close (held apart by the body, or by what a
//! weld there would cross) kept every link of the garment loose for as long as it stayed
//! open, that is for good: the 2 x 8k dress's threads hung 8.6% longer than cut, where
//! a sewn dress's hang 1.5%. So a seam counts as sewn only while some pair is still
//! closing: within the last [`STALL_FRAMES`] frames a pair came a millimetre nearer than
//! it had ever been, or the set of open pairs changed (a weld, a new seam, an edit). When
//! no pair has closed further for that long, the links go back to their
//! straight distances over [`TIGHTEN_FRAMES`] (all at once, the garment shrank by the
//! paths' few per cent in a frame and had to come to rest again), while the stitches
//! keep pulling (and the designer is told, `design::stalls`). A pair closing again
//! loosens them at once (loosening adds no motion).
//!
//! The least distances only fall, by at least a millimetre each time (`ClosingWatch`),
//! so a pair can wake the links only finitely often: tightened links that draw a stalled
//! pair nearer do not set them swinging between the two lengths.

use glam::Vec3;

use crate::solver::stitch::{ClosingWatch, Stitch};

/// Frames without a pair closing after which a seam is no longer being sewn: one second
/// at 60 Hz.
pub(super) const STALL_FRAMES: u32 = 60;

/// Frames over which the links go from their paths to their straight distances after a
/// stall: one second at 60 Hz.
pub(super) const TIGHTEN_FRAMES: u32 = 60;

/// Whether the open stitches still close (`ClosingWatch`).
#[derive(Clone, Debug, Default)]
pub(super) struct SewingWatch {
    closing: ClosingWatch,
}

impl SewingWatch {
    /// Looks at this frame's open stitches (their pairs at `x`) and says how loose the
    /// links are to be: 1 while the seams are being sewn, then down to 0 over
    /// `TIGHTEN_FRAMES` once no pair closes; 0 with no stitches.
    pub(super) fn looseness(&mut self, stitches: &[Stitch], x: &[Vec3]) -> f32 {
        if stitches.is_empty() {
            self.closing.reset();
            return 0.0;
        }
        let quiet = self.closing.observe(stitches.iter().map(|s| (s.a, s.b)), x);
        let tightening = quiet.saturating_sub(STALL_FRAMES);
        1.0 - (tightening as f32 / TIGHTEN_FRAMES as f32).min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(a: u32, b: u32) -> Stitch {
        Stitch {
            a,
            b,
            max_force: 0.5,
        }
    }

    #[test]
    fn the_links_are_loose_while_a_pair_closes_and_tighten_once_they_stall() {
        let mut watch = SewingWatch::default();
        let mut x = vec![Vec3::ZERO, Vec3::X * 0.1, Vec3::Y, Vec3::Y + Vec3::X * 0.05];
        let st = [pair(0, 1), pair(2, 3)];
        // Closing 2 mm a frame: loose.
        while x[1].x > 0.02 {
            assert_eq!(watch.looseness(&st, &x), 1.0);
            x[1].x -= 0.002;
        }
        // Stalled at 2 cm (and wobbling under a millimetre): loose for STALL_FRAMES
        // frames more, then tightening, a step a frame, to 0.
        let mut seen = Vec::new();
        for f in 0..STALL_FRAMES + TIGHTEN_FRAMES + 10 {
            x[3].x = 0.05 + 0.0004 * (f % 2) as f32;
            seen.push(watch.looseness(&st, &x));
        }
        let loose = seen.iter().take_while(|&&l| l == 1.0).count();
        assert_eq!(loose as u32, STALL_FRAMES + 1, "{seen:?}");
        assert!(seen.windows(2).all(|w| w[1] <= w[0] && w[0] - w[1] < 0.02));
        let tight = seen.iter().filter(|&&l| l == 0.0).count();
        assert_eq!(tight, 10);
        // A pair drawn 1.5 mm nearer loosens them at once; a pair welded (gone) too.
        x[1].x -= 0.0015;
        assert_eq!(watch.looseness(&st, &x), 1.0);
        for _ in 0..STALL_FRAMES + TIGHTEN_FRAMES {
            watch.looseness(&st, &x);
        }
        assert_eq!(watch.looseness(&st, &x), 0.0);
        assert_eq!(watch.looseness(&st[..1], &x), 1.0, "a weld is progress");
        // No stitches: tight.
        assert_eq!(watch.looseness(&[], &x), 0.0);
    }

    /// A meshed piece hung by its top border in its own plane, the default cotton under
    /// xpbd for `frames`, with a stitch (when `stalled`) between two pinned corners that
    /// can never close: its threads' median stretch afterwards.
    fn hung(stalled: bool, frames: usize) -> f64 {
        use crate::mesh::mesher::{Outline, mesh_outline};
        use crate::solver::{Cloth, Environment, Material, ModelKind, Simulation};
        let material = Material::default();
        let mesh = mesh_outline(&Outline::rectangle(0.6, 0.6), 0.03).unwrap();
        let cloth = Cloth::new(mesh, &material).unwrap();
        let t = cloth.live.iter().next().unwrap().1;
        let warp = crate::mesh::live::warp_of(t.rest, t.uv);
        let env = Environment {
            gravity: -9.81 * warp,
            floor: None,
            ..Environment::default()
        };
        let top = cloth.x.iter().map(|p| p.dot(warp)).fold(f32::MIN, f32::max);
        let pins: Vec<usize> = (0..cloth.len())
            .filter(|&i| cloth.x[i].dot(warp) > top - 1e-4)
            .collect();
        let model = ModelKind::Xpbd;
        let mut sim = Simulation::new(cloth, None, model, material, env, None).unwrap();
        for &i in &pins {
            sim.pin(i);
        }
        if stalled {
            let (a, b) = (pins[0], pins[pins.len() - 1]);
            sim.stitches = vec![Stitch {
                a: a as u32,
                b: b as u32,
                max_force: 0.5,
            }];
        }
        for _ in 0..frames {
            sim.step().unwrap();
        }
        sim.cloth.thread_stretch().p50
    }

    /// The links go back to their straight distances once the seams stop closing: a
    /// piece with a stitch that cannot close hangs as one with none, not as while sewing.
    #[test]
    fn a_stitch_that_cannot_close_leaves_the_cloth_held_as_if_sewn() {
        let frames = (STALL_FRAMES + TIGHTEN_FRAMES) as usize + 60;
        let (free, stalled) = (hung(false, frames), hung(true, frames));
        assert!(
            (stalled - free).abs() < 0.1 * free.max(1e-3),
            "threads {stalled} with the stalled stitch, {free} without"
        );
    }
}
