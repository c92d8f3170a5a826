//! The cloth's dynamic state.

use glam::Vec3;

use super::material::Material;
use super::zones::MaterialZones;
use crate::error::GeometryError;
use crate::mesh::{ClothMesh, LiveMesh, Topology};

#[derive(Clone, Debug)]
pub struct Cloth {
    /// The rest pattern as loaded (positions define rest lengths and angles; UVs the
    /// warp/weft axes). Edits do not change it; see `live`.
    pub rest: ClothMesh,
    /// The pattern's topology (used by models that do not support edits).
    pub topology: Topology,
    /// The triangles as they are now, after cuts, tears and sews.
    pub live: LiveMesh,
    /// Vertices held in place by the user (inverse mass 0).
    pub pinned: Vec<bool>,
    pub x: Vec<Vec3>,
    pub v: Vec<Vec3>,
    /// Lumped masses from triangle areas and their densities.
    pub mass: Vec<f32>,
    /// Inverse masses, 0 for pinned vertices.
    pub inv_mass: Vec<f32>,
    /// Materials by region of the rest plane (pieces of other fabrics); none for a
    /// cloth of one material. Set with [`Simulation::set_zones`](super::Simulation::set_zones).
    pub zones: MaterialZones,
}

impl Cloth {
    pub fn new(rest: ClothMesh, material: &Material) -> Result<Self, GeometryError> {
        rest.validate()?;
        let topology = Topology::build(&rest.triangles)?;
        let mass = rest.lumped_masses(material.density);
        let inv_mass = mass
            .iter()
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        Ok(Self {
            live: LiveMesh::from_mesh(&rest),
            pinned: vec![false; rest.positions.len()],
            x: rest.positions.clone(),
            v: vec![Vec3::ZERO; rest.positions.len()],
            topology,
            mass,
            inv_mass,
            rest,
            zones: MaterialZones::default(),
        })
    }

    /// A cloth from an edited design: the live triangles, positions and velocities, and a
    /// pattern mesh for the models that do not edit (same vertices, live triangles).
    /// `live` must already be validated against `x`.
    pub fn from_parts(
        rest: ClothMesh,
        live: LiveMesh,
        x: Vec<Vec3>,
        v: Vec<Vec3>,
        material: &Material,
    ) -> Result<Self, GeometryError> {
        let n = x.len();
        if rest.positions.len() != n || v.len() != n || live.vertex_count() != n {
            return Err(GeometryError::IndexOutOfRange {
                triangle: 0,
                vertices: n,
            });
        }
        let topology = Topology::build(&rest.triangles)?;
        let mut c = Self {
            rest,
            topology,
            live,
            pinned: vec![false; n],
            x,
            v,
            mass: vec![0.0; n],
            inv_mass: vec![0.0; n],
            zones: MaterialZones::default(),
        };
        for i in 0..n {
            c.update_mass(i, material.density);
        }
        Ok(c)
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    pub fn pin(&mut self, i: usize) {
        self.set_pinned(i, true);
    }

    /// Pins or frees vertex `i` (out of range: nothing).
    pub fn set_pinned(&mut self, i: usize, pinned: bool) {
        if let Some(p) = self.pinned.get_mut(i) {
            *p = pinned;
            self.v[i] = Vec3::ZERO;
            self.update_inv_mass(i);
        }
    }

    pub fn is_pinned(&self, i: usize) -> bool {
        self.pinned.get(i).copied().unwrap_or(false)
    }

    /// Gives the cloth's regions their own materials and recomputes the masses
    /// (`density` outside every zone). The models must be rebuilt after: see
    /// [`Simulation::set_zones`](super::Simulation::set_zones).
    pub fn set_zones(&mut self, zones: MaterialZones, density: f32) {
        self.zones = zones;
        self.set_density(density);
    }

    /// Recomputes every lumped mass for a new areal density (of the triangles outside
    /// every zone).
    pub fn set_density(&mut self, density: f32) {
        for i in 0..self.len() {
            self.update_mass(i, density);
        }
    }

    /// The live vertex nearest to `p` within `radius`.
    pub fn nearest_vertex(&self, p: Vec3, radius: f32) -> Option<u32> {
        let r2 = radius * radius;
        let mut best = None;
        let mut best_d = f32::INFINITY;
        for (i, x) in self.x.iter().enumerate() {
            let d = (*x - p).length_squared();
            if d <= r2 && d < best_d && self.live.vertex_alive(i as u32) {
                best_d = d;
                best = Some(i as u32);
            }
        }
        best
    }

    /// Area-weighted normal of the triangles around `v` in the current shape.
    pub fn vertex_normal(&self, v: u32) -> Vec3 {
        let x = &self.x;
        self.live
            .tris_of(v)
            .iter()
            .filter_map(|&t| self.live.tri(t))
            .map(|t| {
                let [a, b, c] = t.v.map(|i| x[i as usize]);
                (b - a).cross(c - a)
            })
            .sum::<Vec3>()
            .normalize_or_zero()
    }

    /// Recomputes vertex `i`'s lumped mass from its live triangles, each with its zone's
    /// density (`density` outside every zone).
    pub fn update_mass(&mut self, i: usize, density: f32) {
        let m: f32 = self
            .live
            .tris_of(i as u32)
            .iter()
            .filter_map(|&t| self.live.tri(t))
            .map(|t| self.zones.density_at(&t.rest, density) * t.rest_area() / 3.0)
            .sum();
        self.mass[i] = m;
        self.update_inv_mass(i);
    }

    fn update_inv_mass(&mut self, i: usize) {
        let m = self.mass[i];
        self.inv_mass[i] = if self.pinned[i] || m <= 0.0 {
            0.0
        } else {
            1.0 / m
        };
    }

    /// Each live triangle's sides with their stretch, `length / rest length - 1` (an
    /// interior edge once per triangle; sides of no rest length left out).
    fn side_strains(&self) -> impl Iterator<Item = (u32, u32, f64)> + '_ {
        self.live.iter().flat_map(move |(_, t)| {
            (0..3).filter_map(move |k| {
                let (a, b) = (t.v[k], t.v[(k + 1) % 3]);
                let rest = (t.rest[k] - t.rest[(k + 1) % 3]).length();
                (rest > 0.0).then(|| {
                    let len = (self.x[a as usize] - self.x[b as usize]).length();
                    (a, b, (len / rest - 1.0) as f64)
                })
            })
        })
    }

    /// How many live triangle sides are stretched past `by` (`length / rest length - 1`;
    /// an interior edge once per triangle).
    pub fn sides_stretched_past(&self, by: f64) -> usize {
        self.side_strains().filter(|s| s.2 > by).count()
    }

    /// Stretch of the live triangles' sides, `length / rest length - 1`: the mean and the
    /// largest (each interior edge counts once per triangle). Zero for no triangles.
    pub fn strain(&self) -> (f64, f64) {
        let (mut sum, mut max, mut n) = (0.0f64, f64::NEG_INFINITY, 0usize);
        for (_, _, e) in self.side_strains() {
            sum += e;
            max = max.max(e);
            n += 1;
        }
        if n == 0 {
            return (0.0, 0.0);
        }
        (sum / n as f64, max)
    }

    /// How far the live triangles' threads are stretched from the pattern
    /// (`solver::stretch`): each triangle's more stretched thread, warp or weft.
    pub fn thread_stretch(&self) -> super::ThreadStretch {
        let s = self
            .live
            .iter()
            .filter_map(|(_, t)| {
                let x = t.v.map(|v| self.x[v as usize]);
                let [warp, weft] = super::thread_stretch(x, t.rest, t.uv)?;
                Some(warp.max(weft) - 1.0)
            })
            .collect();
        super::ThreadStretch::of(s)
    }

    /// The most stretched live triangle side (where [`Self::strain`]'s largest is): its
    /// two vertices and its stretch. None for no triangles.
    pub fn worst_side(&self) -> Option<(u32, u32, f64)> {
        self.side_strains()
            .fold(None, |w: Option<(u32, u32, f64)>, s| match w {
                Some(w) if w.2 >= s.2 => Some(w),
                _ => Some(s),
            })
    }

    /// Kinetic energy with the lumped masses, J.
    pub fn kinetic_energy(&self) -> f64 {
        self.v
            .iter()
            .zip(&self.mass)
            .zip(&self.inv_mass)
            .filter(|(_, w)| **w > 0.0)
            .map(|((v, m), _)| 0.5 * *m as f64 * v.length_squared() as f64)
            .sum()
    }

    pub fn is_finite(&self) -> bool {
        self.x.iter().all(|p| p.is_finite()) && self.v.iter().all(|p| p.is_finite())
    }

    /// Finite, and every vertex within [`crate::mesh::MAX_COORD`] of the origin on each
    /// axis: what a design file may hold.
    pub fn in_scene(&self) -> bool {
        let max = crate::mesh::MAX_COORD;
        self.x.iter().all(|p| p.abs().max_element() <= max) && self.v.iter().all(|p| p.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cloth_pulled_along_its_warp_has_its_threads_stretched_and_not_its_bias() {
        let mesh = ClothMesh::grid(1.0, 1.0, 8, 8, 1.0).unwrap();
        let mut cloth = Cloth::new(mesh, &Material::default()).unwrap();
        assert_eq!(cloth.thread_stretch().max, 0.0);
        // 10% along x: every triangle's warp (the grid's u runs along x).
        for p in &mut cloth.x {
            p.x *= 1.1;
        }
        let t = cloth.thread_stretch();
        assert!(
            (t.p50 - 0.1).abs() < 1e-5 && (t.max - 0.1).abs() < 1e-5,
            "{t:?}"
        );
        // Sheared instead: the sides along the bias stretch, no thread by more than the
        // slant.
        let mut cloth = Cloth::new(
            ClothMesh::grid(1.0, 1.0, 8, 8, 1.0).unwrap(),
            &Material::default(),
        )
        .unwrap();
        for p in &mut cloth.x {
            p.x += 0.2 * p.z;
        }
        let t = cloth.thread_stretch();
        let slant = (1.0f64 + 0.04).sqrt() - 1.0;
        assert!((t.max - slant).abs() < 1e-5, "{t:?}");
        assert!(
            cloth.strain().1 > t.max,
            "a side across the shear stretches more"
        );
    }
}
