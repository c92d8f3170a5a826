//! A cloth piece: a triangle mesh with UVs, made from a rectangular pattern or loaded.

use glam::{Vec2, Vec3};

use super::topology::Topology;
use crate::error::GeometryError;

/// Upper bound on vertices (indices are u32; this also keeps a typo in `--grid` from asking
/// for tens of GB).
pub const MAX_VERTICES: usize = 4_000_000;

#[derive(Clone, Debug, PartialEq)]
pub struct ClothMesh {
    /// Rest (and initial) positions, metres.
    pub positions: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
}

impl ClothMesh {
    /// A horizontal `width` x `depth` sheet in the XZ plane at height `y`, centred on the Y
    /// axis, with `nx` x `nz` cells. Diagonals alternate so the sheet has no preferred
    /// shear direction. UV (0,0) is the -X,-Z corner.
    pub fn grid(
        width: f32,
        depth: f32,
        nx: usize,
        nz: usize,
        y: f32,
    ) -> Result<Self, GeometryError> {
        if nx == 0
            || nz == 0
            || !(width > 0.0 && depth > 0.0 && width.is_finite() && depth.is_finite())
        {
            return Err(GeometryError::Empty);
        }
        let nv = (nx + 1).saturating_mul(nz + 1);
        if nv > MAX_VERTICES {
            return Err(GeometryError::TooLarge {
                vertices: nv,
                max: MAX_VERTICES,
            });
        }
        let mut positions = Vec::with_capacity(nv);
        let mut uvs = Vec::with_capacity(nv);
        for j in 0..=nz {
            for i in 0..=nx {
                let u = i as f32 / nx as f32;
                let v = j as f32 / nz as f32;
                positions.push(Vec3::new((u - 0.5) * width, y, (v - 0.5) * depth));
                uvs.push(Vec2::new(u, v));
            }
        }
        let mut triangles = Vec::with_capacity(2 * nx * nz);
        let row = (nx + 1) as u32;
        for j in 0..nz as u32 {
            for i in 0..nx as u32 {
                let a = j * row + i;
                let (b, c, d) = (a + 1, a + row, a + row + 1);
                // Wound so the normal points +Y (up) for the flat sheet.
                if (i + j) % 2 == 0 {
                    triangles.push([a, c, b]);
                    triangles.push([b, c, d]);
                } else {
                    triangles.push([a, c, d]);
                    triangles.push([a, d, b]);
                }
            }
        }
        Ok(Self {
            positions,
            uvs,
            triangles,
        })
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The smallest angle of the triangles, degrees (180 for none).
    pub fn min_angle_deg(&self) -> f32 {
        let mut worst = 180.0f32;
        for t in &self.triangles {
            let p = t.map(|i| self.positions[i as usize]);
            for k in 0..3 {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                worst = worst.min((b - a).angle_between(c - a).to_degrees());
            }
        }
        worst
    }

    /// Checks everything a solver relies on: finite coordinates, indices in range, no
    /// degenerate triangle, every edge in at most two triangles.
    pub fn validate(&self) -> Result<(), GeometryError> {
        if self.triangles.is_empty() {
            return Err(GeometryError::Empty);
        }
        if self.positions.len() > MAX_VERTICES {
            return Err(GeometryError::TooLarge {
                vertices: self.positions.len(),
                max: MAX_VERTICES,
            });
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NonFinite { vertex: i });
        }
        if let Some(i) = self
            .positions
            .iter()
            .position(|p| p.abs().max_element() > super::MAX_COORD)
        {
            return Err(GeometryError::TooFar {
                vertex: i,
                at: self.positions[i].abs().max_element(),
                max: super::MAX_COORD,
            });
        }
        if self.uvs.len() != self.positions.len() {
            return Err(GeometryError::BadUv {
                vertex: self.uvs.len().min(self.positions.len()),
            });
        }
        if let Some(i) = self.uvs.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::BadUv { vertex: i });
        }
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if tri.iter().any(|&i| i as usize >= n) {
                return Err(GeometryError::IndexOutOfRange {
                    triangle: t,
                    vertices: n,
                });
            }
            let [a, b, c] = tri.map(|i| self.positions[i as usize]);
            let scale = (b - a)
                .length_squared()
                .max((c - a).length_squared())
                .max(1e-30);
            if tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
                || (b - a).cross(c - a).length_squared() <= 1e-12 * scale * scale
            {
                return Err(GeometryError::Degenerate { triangle: t });
            }
        }
        Topology::build(&self.triangles).map(|_| ())
    }

    /// Lumped vertex masses: a third of each adjacent triangle's rest area times `density`.
    pub fn lumped_masses(&self, density: f32) -> Vec<f32> {
        let mut m = vec![0.0f32; self.positions.len()];
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|i| self.positions[i as usize]);
            let area = 0.5 * (b - a).cross(c - a).length();
            for &i in tri {
                m[i as usize] += density * area / 3.0;
            }
        }
        m
    }

    /// Total rest area, m^2.
    pub fn area(&self) -> f32 {
        self.triangles
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|i| self.positions[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_counts_mass_and_validity() {
        let m = ClothMesh::grid(1.0, 1.0, 128, 128, 0.5).unwrap();
        assert_eq!(m.vertex_count(), 16_641);
        assert_eq!(m.triangles.len(), 2 * 128 * 128);
        m.validate().unwrap();
        let total: f32 = m.lumped_masses(0.15).iter().sum();
        assert!((total - 0.15).abs() < 1e-4, "{total}");
        // Normals point up.
        let [a, b, c] = m.triangles[0].map(|i| m.positions[i as usize]);
        assert!((b - a).cross(c - a).y > 0.0);
    }

    #[test]
    fn bad_grids_are_rejected() {
        assert_eq!(
            ClothMesh::grid(1.0, 1.0, 0, 4, 0.0),
            Err(GeometryError::Empty)
        );
        assert_eq!(
            ClothMesh::grid(-1.0, 1.0, 4, 4, 0.0),
            Err(GeometryError::Empty)
        );
        assert!(matches!(
            ClothMesh::grid(1.0, 1.0, 100_000, 100_000, 0.0),
            Err(GeometryError::TooLarge { .. })
        ));
    }

    #[test]
    fn validation_catches_each_defect() {
        let good = ClothMesh::grid(1.0, 1.0, 2, 2, 0.0).unwrap();
        let mut m = good.clone();
        m.positions[0].x = f32::NAN;
        assert_eq!(m.validate(), Err(GeometryError::NonFinite { vertex: 0 }));
        let mut m = good.clone();
        m.triangles[1][2] = 99;
        assert!(matches!(
            m.validate(),
            Err(GeometryError::IndexOutOfRange { triangle: 1, .. })
        ));
        let mut m = good.clone();
        m.triangles[0] = [0, 0, 1];
        assert_eq!(m.validate(), Err(GeometryError::Degenerate { triangle: 0 }));
        let mut m = good.clone();
        let t = m.triangles[0];
        m.positions.push(Vec3::new(0.0, 1.0, 0.0));
        m.uvs.push(Vec2::ZERO);
        // Edge t[1]-t[2] is the interior diagonal: already in two triangles.
        m.triangles.push([t[1], t[2], 9]);
        assert!(matches!(
            m.validate(),
            Err(GeometryError::NonManifoldEdge { count: 3, .. })
        ));
    }
}
