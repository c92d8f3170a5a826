//! Small-steps XPBD (Macklin, Storey, Lu et al. 2019): many substeps, one Gauss-Seidel
//! pass each. Compliance is the inverse of a physical stiffness (membrane moduli times
//! area, bending rigidity times the hinge weight), and the time-scaled compliance
//! `alpha / h^2` is recomputed for the substep, so material stiffness does not depend on
//! the substep count. With one iteration per substep the Lagrange multipliers start at
//! zero every substep and need not be stored.

use glam::Vec3;

use super::cloth::Cloth;
use super::constraints::{BendConstraint, Membrane, build_bending, build_membranes};
use super::contact::{ContactCache, ContactParams};
use super::material::Material;
use super::sim::Environment;

#[derive(Clone, Debug)]
pub struct Xpbd {
    membranes: Vec<Membrane>,
    bends: Vec<BendConstraint>,
    prev: Vec<Vec3>,
    normals: Vec<Vec3>,
    area: Vec<f32>,
    material: Material,
}

impl Xpbd {
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        let mut membranes = build_membranes(&cloth.rest);
        let mut bends = build_bending(&cloth.rest, &cloth.topology);
        // Visit constraints in vertex order: neighbouring constraints share cache lines.
        membranes.sort_by_key(|m| m.v.iter().copied().min().unwrap_or(0));
        bends.sort_by_key(|b| b.v.iter().copied().min().unwrap_or(0));
        let mut area = vec![0.0f32; cloth.len()];
        for m in &membranes {
            for &i in &m.v {
                area[i as usize] += m.area / 3.0;
            }
        }
        Self {
            membranes,
            bends,
            prev: cloth.x.clone(),
            normals: vec![Vec3::Y; cloth.len()],
            area,
            material: *material,
        }
    }

    pub fn constraint_count(&self) -> usize {
        3 * self.membranes.len() + self.bends.len()
    }

    /// Advances one frame of `env.frame_dt` in `substeps` substeps.
    pub fn step(
        &mut self,
        cloth: &mut Cloth,
        contacts: &ContactCache,
        env: &Environment,
        substeps: usize,
    ) {
        let h = env.frame_dt / substeps as f32;
        let cp = ContactParams {
            thickness: self.material.thickness,
            friction: self.material.friction,
            floor: env.floor,
        };
        self.update_normals(cloth);
        let damp = (-self.material.damping * h).exp();
        let m = self.material;
        let inv_h2 = 1.0 / (h * h);
        let (a_stretch, a_shear, a_bend) = (
            inv_h2 / m.stretch,
            if m.shear > 0.0 {
                inv_h2 / m.shear
            } else {
                f32::INFINITY
            },
            if m.bending > 0.0 {
                inv_h2 / m.bending
            } else {
                f32::INFINITY
            },
        );
        for _ in 0..substeps {
            let g = env.gravity * h;
            for i in 0..cloth.len() {
                self.prev[i] = cloth.x[i];
                if cloth.inv_mass[i] > 0.0 {
                    cloth.v[i] += g;
                    cloth.x[i] += cloth.v[i] * h;
                }
            }
            solve_membranes(
                &self.membranes,
                &mut cloth.x,
                &cloth.inv_mass,
                a_stretch,
                a_shear,
            );
            if a_bend.is_finite() {
                solve_bending(&self.bends, &mut cloth.x, &cloth.inv_mass, a_bend);
            }
            contacts.project(&mut cloth.x, &self.prev, &cloth.inv_mass, &cp);
            let inv_h = 1.0 / h;
            for i in 0..cloth.len() {
                if cloth.inv_mass[i] == 0.0 {
                    cloth.v[i] = Vec3::ZERO;
                    continue;
                }
                let mut v = (cloth.x[i] - self.prev[i]) * inv_h * damp;
                // Air drag on the normal velocity, integrated implicitly (always stable).
                let n = self.normals[i];
                let vn = v.dot(n);
                let k = m.drag * self.area[i] * cloth.inv_mass[i] * h;
                v -= n * (vn * k / (1.0 + k));
                cloth.v[i] = v;
            }
        }
    }

    fn update_normals(&mut self, cloth: &Cloth) {
        self.normals.iter_mut().for_each(|n| *n = Vec3::ZERO);
        for m in &self.membranes {
            let [a, b, c] = m.v.map(|i| cloth.x[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in &m.v {
                self.normals[i as usize] += n;
            }
        }
        for n in &mut self.normals {
            *n = n.normalize_or(Vec3::Y);
        }
    }
}

/// One pass over every triangle: warp stretch, weft stretch, then shear.
fn solve_membranes(
    membranes: &[Membrane],
    x: &mut [Vec3],
    w: &[f32],
    a_stretch: f32,
    a_shear: f32,
) {
    for m in membranes {
        let [i0, i1, i2] = m.v.map(|i| i as usize);
        let wv = [w[i0], w[i1], w[i2]];
        if wv[0] + wv[1] + wv[2] == 0.0 {
            continue;
        }
        let mut p = [x[i0], x[i1], x[i2]];
        let at_stretch = a_stretch / m.area;
        // Warp (u) then weft (v): C = |F_col| - 1, grad_a = coeff_a * F_col / |F_col|.
        for coeff in [&m.c, &m.d] {
            let f = p[0] * coeff[0] + p[1] * coeff[1] + p[2] * coeff[2];
            let len = f.length();
            if len < 1e-9 {
                continue;
            }
            let dir = f / len;
            let c = len - 1.0;
            let denom = wv[0] * coeff[0] * coeff[0]
                + wv[1] * coeff[1] * coeff[1]
                + wv[2] * coeff[2] * coeff[2]
                + at_stretch;
            let dl = -c / denom;
            for a in 0..3 {
                p[a] += dir * (wv[a] * coeff[a] * dl);
            }
        }
        if a_shear.is_finite() {
            let fu = p[0] * m.c[0] + p[1] * m.c[1] + p[2] * m.c[2];
            let fv = p[0] * m.d[0] + p[1] * m.d[1] + p[2] * m.d[2];
            let c = fu.dot(fv);
            let g = [
                fv * m.c[0] + fu * m.d[0],
                fv * m.c[1] + fu * m.d[1],
                fv * m.c[2] + fu * m.d[2],
            ];
            let denom = wv[0] * g[0].length_squared()
                + wv[1] * g[1].length_squared()
                + wv[2] * g[2].length_squared()
                + a_shear / m.area;
            if denom > 0.0 {
                let dl = -c / denom;
                for a in 0..3 {
                    p[a] += g[a] * (wv[a] * dl);
                }
            }
        }
        x[i0] = p[0];
        x[i1] = p[1];
        x[i2] = p[2];
    }
}

/// One pass over every hinge. The constraint is linear, so its gradient is `K_a I`.
fn solve_bending(bends: &[BendConstraint], x: &mut [Vec3], w: &[f32], a_bend: f32) {
    for b in bends {
        let idx = b.v.map(|i| i as usize);
        let c = x[idx[0]] * b.k[0] + x[idx[1]] * b.k[1] + x[idx[2]] * b.k[2] + x[idx[3]] * b.k[3]
            - b.rest;
        let mut denom = a_bend / b.weight;
        for a in 0..4 {
            denom += w[idx[a]] * b.k[a] * b.k[a];
        }
        if denom <= 0.0 {
            continue;
        }
        let dl = -c / denom;
        for a in 0..4 {
            x[idx[a]] += dl * (w[idx[a]] * b.k[a]);
        }
    }
}
