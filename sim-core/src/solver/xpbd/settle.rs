//! An edit's stretch taken up without becoming speed.
//!
//! A sew joins two border vertices halfway between them, and an undo puts vertices back
//! where they were while their neighbours have moved on: either can leave the sides
//! around them far past their rest length. XPBD takes a violation of a stiff constraint up
//! in a substep or two, and everything it moves a vertex by becomes velocity: a sew across
//! 25 cm sent the default cotton's vertices off at 16 m/s, a 9 cm one between two small
//! scraps at 56 m/s, and with the material's light damping the pieces flew 20 m (found by
//! the random-edits property test, `sim-core/tests/edit.rs`). Elastic energy a real
//! fabric never held, since nothing stretched it that far, came out as speed.
//!
//! So for [`SETTLE_FRAMES`] frames after an edit that left a side of the triangles it
//! touched more than [`SETTLE_STRETCH`] past its rest length, no vertex ends a substep
//! faster than it began the frame plus what gravity gave it since. The positions still
//! move wherever the constraints put them (the stretch is taken up), and the guard still
//! checks every move; only the speed those corrections would have added is dropped. A
//! falling cloth keeps falling at gravity's rate; a vertex the edit yanked does not fly.
//! The pen's pull is held to the same bound in those frames: for a sixth of a second
//! after such an edit a pinched cloth follows the pen in position without gaining speed.

use glam::Vec3;

use crate::solver::state::Cloth;

/// Frames after an edit during which no vertex may speed up beyond gravity's gain: a
/// sixth of a second at 60 Hz. After a 32 cm sew between two squares of 0.1 m cells (the
/// sew tests) the longest side is 0.167 m a frame later and at its rest length (0.1414 m,
/// a diagonal) after nine.
pub(super) const SETTLE_FRAMES: u32 = 10;

/// How far past its rest length (m) a side an edit left must be for the frames after it
/// to settle. The sewn dress's 122 seam welds left at most 12.5 mm (88 of them under 3
/// mm), and capping speeds through its drape left its neck 0.1x more stretched; the
/// random-edits test's sews reach 0.4 m.
pub(super) const SETTLE_STRETCH: f32 = 0.02;

/// The most any side of the live triangles in `tris` is longer than at rest, m.
fn stretch_beyond_rest(cloth: &Cloth, tris: &[u32]) -> f32 {
    let mut worst = 0.0f32;
    for t in tris.iter().filter_map(|&s| cloth.live.tri(s)) {
        for k in 0..3 {
            let (i, j) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
            let (Some(a), Some(b)) = (cloth.x.get(i), cloth.x.get(j)) else {
                continue;
            };
            let rest = (t.rest[k] - t.rest[(k + 1) % 3]).length();
            worst = worst.max((*a - *b).length() - rest);
        }
    }
    worst
}

/// The frames left to settle and each vertex's speed at the frame's start.
#[derive(Clone, Debug, Default)]
pub(super) struct Settle {
    frames_left: u32,
    start_speed: Vec<f32>,
}

impl Settle {
    /// An edit changed the triangles in slots `tris`: settle the next frames if it left
    /// one of their sides more than [`SETTLE_STRETCH`] past its rest length.
    pub(super) fn edited(&mut self, cloth: &Cloth, tris: &[u32]) {
        let worst = stretch_beyond_rest(cloth, tris);
        if worst > SETTLE_STRETCH {
            self.frames_left = SETTLE_FRAMES;
        }
    }

    /// At a frame's start: whether this frame settles, noting the speeds it starts with.
    pub(super) fn begin_frame(&mut self, v: &[Vec3]) -> bool {
        if self.frames_left == 0 {
            return false;
        }
        self.frames_left -= 1;
        self.start_speed.clear();
        self.start_speed.extend(v.iter().map(|v| v.length()));
        true
    }

    /// `v` slowed, keeping its direction, to at most vertex `i`'s speed at the frame's
    /// start plus `gain` (gravity's since then, m/s).
    pub(super) fn cap(&self, i: usize, v: Vec3, gain: f32) -> Vec3 {
        let most = self.start_speed.get(i).copied().unwrap_or(0.0) + gain;
        let s = v.length();
        if s > most { v * (most / s) } else { v }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::Material;

    /// A 0.2 m square of 2 x 2 cells, its centre vertex (4) pulled `by` metres along X.
    fn pulled(by: f32) -> (Cloth, Vec<u32>) {
        let mesh = ClothMesh::grid(0.2, 0.2, 2, 2, 1.0).unwrap();
        let mut cloth = Cloth::new(mesh, &Material::default()).unwrap();
        cloth.x[4].x += by;
        let tris = cloth.live.iter().map(|(s, _)| s).collect();
        (cloth, tris)
    }

    #[test]
    fn only_an_edit_that_stretched_a_side_settles_and_for_ten_frames() {
        let mut s = Settle::default();
        let v = vec![Vec3::new(0.0, -1.0, 0.0); 9];
        assert!(!s.begin_frame(&v), "no edit, no settling");
        let (cloth, tris) = pulled(0.01);
        s.edited(&cloth, &tris);
        assert!(!s.begin_frame(&v), "1 cm is not enough");
        let (cloth, tris) = pulled(0.05);
        assert!((stretch_beyond_rest(&cloth, &tris) - 0.05).abs() < 1e-4);
        s.edited(&cloth, &[]);
        assert!(!s.begin_frame(&v), "only the edited triangles count");
        s.edited(&cloth, &tris);
        for _ in 0..SETTLE_FRAMES {
            assert!(s.begin_frame(&v));
        }
        assert!(!s.begin_frame(&v), "settling ends");
    }

    #[test]
    fn the_cap_keeps_only_a_speed_up_to_the_start_plus_gravity() {
        let (cloth, tris) = pulled(0.05);
        let mut s = Settle::default();
        s.edited(&cloth, &tris);
        assert!(s.begin_frame(&[Vec3::new(0.0, -1.0, 0.0), Vec3::ZERO]));
        // Vertex 0 began at 1 m/s: it may reach 1.5 with a gain of 0.5, not 16.
        let fast = Vec3::new(16.0, 0.0, 0.0);
        assert!((s.cap(0, fast, 0.5) - Vec3::new(1.5, 0.0, 0.0)).length() < 1e-6);
        assert_eq!(
            s.cap(0, Vec3::new(0.0, -1.2, 0.0), 0.5),
            Vec3::new(0.0, -1.2, 0.0)
        );
        // Vertex 1 began at rest; a vertex past the frame's start (added since) too.
        assert!((s.cap(1, fast, 0.25).length() - 0.25).abs() < 1e-6);
        assert!((s.cap(7, fast, 0.25).length() - 0.25).abs() < 1e-6);
    }
}
