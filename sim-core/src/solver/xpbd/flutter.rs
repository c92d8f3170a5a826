//! The cloth's flutter damped: once a frame, each vertex's velocity along its normal
//! moves toward the mean velocity of the triangles round it, at [`FLUTTER_DAMPING`] per
//! second. Motion the neighbours share (a garment falling, swinging, being carried by
//! the pen) is untouched; a vertex beating against its neighbours, out of the cloth's
//! plane, is damped, as the yarns' own friction in bending damps it in real cloth.
//!
//! Why: a garment resting on the body with a taut flap held by friction at its ends
//! could beat for good. Under the arm of the 5k dress sewn in the air, damped, about 30
//! vertices beat 3-4 mm along their normals at 15 Hz (0.15-0.3 m/s, 5-8e-6 J) frame
//! after frame, the garment never at rest (docs/garments.md, "Every pair of both
//! dresses welded, at rest"). The body's friction feeds it: with friction off after
//! frame 250 it died away within 100 frames, with the strain limit off it went on. The
//! material's own damping at 2 1/s or 10 substeps did not stop it; normal drag of
//! 2 kg/(m^2 s), four times the default, did. Damped here at 21.4 1/s (30% of the
//! relative velocity a frame at 60 Hz), it died within 120 frames of the saved design;
//! at 6 1/s it went on at a third of the speed.
//!
//! Border vertices are damped too, though their triangles lie on one side of them, so a
//! flap turning about the cloth inside is held back a little at its border: left alone,
//! the sewn dress went on moving at 6e-7 to 1.7e-6 J at frame 400, not 1e-9 to 3.5e-8.
//!
//! Not while a seam's stitch pulls (`Xpbd::frame`): the beat is a garment's at rest, its
//! seams closed, and sewing is left as it was. Damped while sewn, the shipped dress in
//! `drape-pattern` left 3 pairs open in one run of three, and tests built on how the 3 cm
//! dress sews came out otherwise.
//!
//! Velocities only: no vertex moves, so nothing can cross.

use glam::Vec3;

use crate::solver::state::Cloth;

/// How fast a vertex's velocity along its normal, relative to the mean velocity of the
/// triangles round it, dies away, 1/s (module doc).
pub const FLUTTER_DAMPING: f32 = 21.4;

/// Scratch for [`Flutter::damp`], kept so a frame allocates nothing once sized.
#[derive(Clone, Debug, Default)]
pub(super) struct Flutter {
    sum: Vec<Vec3>,
    count: Vec<f32>,
}

impl Flutter {
    /// Damps `cloth`'s flutter over a frame of `dt` seconds, with the vertices' unit
    /// `normals`.
    pub(super) fn damp(&mut self, cloth: &mut Cloth, normals: &[Vec3], dt: f32) {
        let share = 1.0 - (-FLUTTER_DAMPING * dt).exp();
        if share.is_nan() || share <= 0.0 {
            return;
        }
        let n = cloth.x.len();
        self.sum.clear();
        self.sum.resize(n, Vec3::ZERO);
        self.count.clear();
        self.count.resize(n, 0.0);
        for (_, t) in cloth.live.iter() {
            let [a, b, c] = t.v.map(|i| i as usize);
            let (Some(va), Some(vb), Some(vc)) = (cloth.v.get(a), cloth.v.get(b), cloth.v.get(c))
            else {
                continue;
            };
            let mean = (*va + *vb + *vc) / 3.0;
            for i in [a, b, c] {
                self.sum[i] += mean;
                self.count[i] += 1.0;
            }
        }
        for i in 0..n.min(normals.len()) {
            if self.count[i] == 0.0 || cloth.inv_mass[i] == 0.0 {
                continue;
            }
            let nrm = normals[i];
            let rel = (self.sum[i] / self.count[i] - cloth.v[i]).dot(nrm);
            if rel.is_finite() {
                cloth.v[i] += nrm * (share * rel);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;
    use crate::solver::material::Material;
    use crate::solver::state::Cloth;

    /// A flat 8 x 8 cloth in the xz plane (normals +y).
    fn flat() -> (Cloth, Vec<Vec3>) {
        let mesh = ClothMesh::grid(0.5, 0.5, 8, 8, 1.0).unwrap();
        let cloth = Cloth::new(mesh, &Material::default()).unwrap();
        let normals = vec![Vec3::Y; cloth.x.len()];
        (cloth, normals)
    }

    /// How much the vertices inside the cloth beat against the triangles round them: the
    /// sum of each one's normal (y) velocity less its triangles' mean.
    fn beating(cloth: &Cloth) -> f32 {
        let n = cloth.x.len();
        let (mut sum, mut count) = (vec![0.0f32; n], vec![0.0f32; n]);
        for (_, t) in cloth.live.iter() {
            let mean = t.v.iter().map(|&i| cloth.v[i as usize].y).sum::<f32>() / 3.0;
            for &i in &t.v {
                sum[i as usize] += mean;
                count[i as usize] += 1.0;
            }
        }
        (0..n)
            .filter(|&i| !cloth.live.is_boundary(i as u32))
            .map(|i| (sum[i] / count[i] - cloth.v[i].y).abs())
            .sum()
    }

    #[test]
    fn flutter_dies_away_and_shared_motion_is_kept() {
        let (mut cloth, normals) = flat();
        // The whole cloth falling and drifting: nothing is relative, nothing changes.
        let shared = Vec3::new(0.3, -1.0, 0.2);
        cloth.v.iter_mut().for_each(|v| *v = shared);
        let mut f = Flutter::default();
        f.damp(&mut cloth, &normals, 1.0 / 60.0);
        assert!(cloth.v.iter().all(|v| (*v - shared).length() < 1e-6));
        // Every other vertex beating up, the rest down (a flutter at the mesh's scale),
        // with a sideways drift they share: the beat dies, the drift stays.
        let beat = |i: usize| if i.is_multiple_of(2) { 0.2 } else { -0.2 };
        for (i, v) in cloth.v.iter_mut().enumerate() {
            *v = Vec3::new(0.1, beat(i), 0.0);
        }
        let before = beating(&cloth);
        for _ in 0..30 {
            f.damp(&mut cloth, &normals, 1.0 / 60.0);
        }
        let after = beating(&cloth);
        assert!(after < 0.05 * before, "{after} of {before}");
        assert!(
            cloth
                .v
                .iter()
                .all(|v| (v.x - 0.1).abs() < 1e-6 && v.z == 0.0)
        );
        // A pinned vertex keeps its velocity (none).
        cloth.inv_mass[0] = 0.0;
        cloth.v[0] = Vec3::ZERO;
        cloth.v[1] = Vec3::Y;
        f.damp(&mut cloth, &normals, 1.0 / 60.0);
        assert_eq!(cloth.v[0], Vec3::ZERO);
        // Half a second at 30 Hz frames damps as much as at 60 (a rate, not a share).
        let at = |dt: f32, frames: usize| {
            let (mut c, n) = flat();
            for (i, v) in c.v.iter_mut().enumerate() {
                *v = Vec3::new(0.0, beat(i), 0.0);
            }
            let mut g = Flutter::default();
            for _ in 0..frames {
                g.damp(&mut c, &n, dt);
            }
            beating(&c)
        };
        let (a, b) = (at(1.0 / 60.0, 30), at(1.0 / 30.0, 15));
        assert!((a - b).abs() <= 0.35 * a.max(b) + 1e-6, "{a} against {b}");
    }
}
