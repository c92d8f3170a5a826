//! The cloth's dynamic state.

use glam::Vec3;

use super::material::Material;
use crate::error::GeometryError;
use crate::mesh::{ClothMesh, Topology};

#[derive(Clone, Debug)]
pub struct Cloth {
    /// The rest pattern (positions define rest lengths and angles; UVs the warp/weft axes).
    pub rest: ClothMesh,
    pub topology: Topology,
    pub x: Vec<Vec3>,
    pub v: Vec<Vec3>,
    /// Lumped masses from triangle areas and the density.
    pub mass: Vec<f32>,
    /// Inverse masses, 0 for pinned vertices.
    pub inv_mass: Vec<f32>,
}

impl Cloth {
    pub fn new(rest: ClothMesh, material: &Material) -> Result<Self, GeometryError> {
        rest.validate()?;
        let topology = Topology::build(&rest)?;
        let mass = rest.lumped_masses(material.density);
        let inv_mass = mass
            .iter()
            .map(|&m| if m > 0.0 { 1.0 / m } else { 0.0 })
            .collect();
        Ok(Self {
            x: rest.positions.clone(),
            v: vec![Vec3::ZERO; rest.positions.len()],
            topology,
            mass,
            inv_mass,
            rest,
        })
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    pub fn pin(&mut self, i: usize) {
        if let Some(w) = self.inv_mass.get_mut(i) {
            *w = 0.0;
            self.v[i] = Vec3::ZERO;
        }
    }

    pub fn is_pinned(&self, i: usize) -> bool {
        self.inv_mass.get(i).is_some_and(|&w| w == 0.0)
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
}
