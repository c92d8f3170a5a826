//! The cloth's elastic energy seen from one vertex: the force on it and the 3 x 3 block of
//! the Hessian at it, from the triangles and hinges around it. The energy is the one the
//! XPBD and implicit models share (`constraints.rs`: membrane in the warp/weft frame,
//! isometric bending), so the three agree on equilibrium. The block is made positive
//! semi-definite the way the implicit model makes its Hessian: stretch's transverse part
//! clamped at zero, shear by Gauss-Newton, bending exact (it is quadratic).

use glam::{Mat3, Vec3};

use crate::solver::constraints::{BendConstraint, Elements, Membrane, elements_of};
use crate::solver::material::Material;
use crate::solver::state::Cloth;

/// The elements of the live mesh and, per vertex, the ones around it.
#[derive(Clone, Debug, Default)]
pub struct Elastic {
    pub membranes: Vec<Membrane>,
    pub bends: Vec<BendConstraint>,
    /// Vertex `i`'s membranes are `mem_refs[mem_start[i]..mem_start[i + 1]]`, each
    /// `membrane * 4 + corner`; its hinges likewise.
    mem_start: Vec<u32>,
    mem_refs: Vec<u32>,
    bend_start: Vec<u32>,
    bend_refs: Vec<u32>,
}

/// The material's constants for one step of `h`.
#[derive(Clone, Copy, Debug)]
pub struct Stiffness {
    pub stretch: f32,
    pub shear: f32,
    pub bending: f32,
    /// Shear damping over the step, `shear_damping / h`.
    pub shear_rate: f32,
}

impl Stiffness {
    pub fn of(m: &Material, h: f32) -> Self {
        Self {
            stretch: m.stretch,
            shear: m.shear,
            bending: m.bending,
            shear_rate: m.shear_damping / h,
        }
    }
}

/// Counting sort of `(vertex, reference)` items into per-vertex lists.
fn lists(n: usize, items: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n + 1];
    for &(v, _) in items {
        start[v as usize + 1] += 1;
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut refs = vec![0u32; items.len()];
    let mut fill = start.clone();
    for &(v, r) in items {
        refs[fill[v as usize] as usize] = r;
        fill[v as usize] += 1;
    }
    (start, refs)
}

impl Elastic {
    /// The elements of `cloth`'s live mesh.
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        let live = &cloth.live;
        let Elements {
            membranes, bends, ..
        } = elements_of(live, material, &cloth.zones);
        let n = cloth.len();
        let mem_items: Vec<(u32, u32)> = membranes
            .iter()
            .enumerate()
            .flat_map(|(m, t)| (0..3).map(move |a| (t.v[a], (m * 4 + a) as u32)))
            .collect();
        let bend_items: Vec<(u32, u32)> = bends
            .iter()
            .enumerate()
            .flat_map(|(b, c)| (0..4).map(move |a| (c.v[a], (b * 4 + a) as u32)))
            .collect();
        let (mem_start, mem_refs) = lists(n, &mem_items);
        let (bend_start, bend_refs) = lists(n, &bend_items);
        Self {
            membranes,
            bends,
            mem_start,
            mem_refs,
            bend_start,
            bend_refs,
        }
    }

    /// Adds to `f` and `hess` the elastic force on vertex `i` and its Hessian block, at
    /// positions `x` (with `xt` the step's start, for the shear damping).
    #[inline]
    pub fn add_vertex(
        &self,
        i: usize,
        x: &[Vec3],
        xt: &[Vec3],
        k: &Stiffness,
        f: &mut Vec3,
        hess: &mut Mat3,
    ) {
        let (a0, a1) = (self.mem_start[i] as usize, self.mem_start[i + 1] as usize);
        for &r in &self.mem_refs[a0..a1] {
            let m = &self.membranes[(r / 4) as usize];
            let a = (r % 4) as usize;
            let p = m.v.map(|v| x[v as usize]);
            let fu = p[0] * m.c[0] + p[1] * m.c[1] + p[2] * m.c[2];
            let fv = p[0] * m.d[0] + p[1] * m.d[1] + p[2] * m.d[2];
            let (ca, da) = (m.c[a], m.d[a]);
            // Stretch along warp and weft.
            for (fw, cw) in [(fu, ca), (fv, da)] {
                let len = fw.length();
                if len < 1e-12 {
                    continue;
                }
                let u = fw / len;
                let c = len - 1.0;
                let ks = k.stretch * m.area * m.ks;
                *f -= u * (ks * c * cw);
                let uu = Mat3::from_cols(u * u.x, u * u.y, u * u.z);
                let trans = if c > 0.0 {
                    (Mat3::IDENTITY - uu) * (c / len)
                } else {
                    Mat3::ZERO
                };
                *hess += (uu + trans) * (ks * cw * cw);
            }
            // Shear, with its damping: the rate of shearing over the step.
            if k.shear > 0.0 {
                let g = fv * ca + fu * da;
                let cs = fu.dot(fv);
                let q = m.v.map(|v| x[v as usize] - xt[v as usize]);
                let dcs: f32 = (0..3).map(|b| (fv * m.c[b] + fu * m.d[b]).dot(q[b])).sum();
                let ksh = k.shear * m.area * m.kg;
                *f -= g * (ksh * (cs + k.shear_rate * dcs));
                *hess += Mat3::from_cols(g * g.x, g * g.y, g * g.z) * (ksh * (1.0 + k.shear_rate));
            }
        }
        if k.bending > 0.0 {
            let (b0, b1) = (self.bend_start[i] as usize, self.bend_start[i + 1] as usize);
            for &r in &self.bend_refs[b0..b1] {
                let b = &self.bends[(r / 4) as usize];
                let a = (r % 4) as usize;
                let c = (0..4).map(|j| x[b.v[j] as usize] * b.k[j]).sum::<Vec3>() - b.rest;
                let kb = k.bending * b.weight;
                *f -= c * (kb * b.k[a]);
                *hess += Mat3::from_diagonal(Vec3::splat(kb * b.k[a] * b.k[a]));
            }
        }
    }

    /// Adds the elastic force on every vertex to `f`, one pass over the elements (the
    /// same forces as [`add_vertex`](Self::add_vertex), without the Hessian).
    pub fn add_forces(&self, x: &[Vec3], xt: &[Vec3], k: &Stiffness, f: &mut [Vec3]) {
        for m in &self.membranes {
            let p = m.v.map(|v| x[v as usize]);
            let fu = p[0] * m.c[0] + p[1] * m.c[1] + p[2] * m.c[2];
            let fv = p[0] * m.d[0] + p[1] * m.d[1] + p[2] * m.d[2];
            let ks = k.stretch * m.area * m.ks;
            let (lu, lv) = (fu.length(), fv.length());
            let gu = if lu > 1e-12 {
                fu * (ks * (lu - 1.0) / lu)
            } else {
                Vec3::ZERO
            };
            let gv = if lv > 1e-12 {
                fv * (ks * (lv - 1.0) / lv)
            } else {
                Vec3::ZERO
            };
            let mut shear = 0.0;
            if k.shear > 0.0 {
                let cs = fu.dot(fv);
                let dcs: f32 = (0..3)
                    .map(|b| {
                        (fv * m.c[b] + fu * m.d[b]).dot(x[m.v[b] as usize] - xt[m.v[b] as usize])
                    })
                    .sum();
                shear = k.shear * m.area * m.kg * (cs + k.shear_rate * dcs);
            }
            for a in 0..3 {
                let g = gu * m.c[a] + gv * m.d[a] + (fv * m.c[a] + fu * m.d[a]) * shear;
                f[m.v[a] as usize] -= g;
            }
        }
        if k.bending > 0.0 {
            for b in &self.bends {
                let c = (0..4).map(|j| x[b.v[j] as usize] * b.k[j]).sum::<Vec3>() - b.rest;
                let kb = k.bending * b.weight;
                for a in 0..4 {
                    f[b.v[a] as usize] -= c * (kb * b.k[a]);
                }
            }
        }
    }

    /// Total elastic energy at `x`, J.
    #[cfg(test)]
    pub fn energy(&self, x: &[Vec3], m: &Material) -> f64 {
        let mut e = 0.0f64;
        for t in &self.membranes {
            let p = t.v.map(|v| x[v as usize]);
            let fu = p[0] * t.c[0] + p[1] * t.c[1] + p[2] * t.c[2];
            let fv = p[0] * t.d[0] + p[1] * t.d[1] + p[2] * t.d[2];
            let (su, sv, sh) = (fu.length() - 1.0, fv.length() - 1.0, fu.dot(fv));
            e += 0.5
                * (t.area * (t.ks * m.stretch * (su * su + sv * sv) + t.kg * m.shear * sh * sh))
                    as f64;
        }
        e + crate::solver::constraints::bending_energy(&self.bends, x, m.bending)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;

    /// The force is minus the energy's gradient, checked by central differences.
    #[test]
    fn force_is_the_energy_gradient() {
        let mesh = ClothMesh::grid(0.1, 0.1, 4, 4, 0.0).expect("grid");
        let m = Material {
            shear_damping: 0.0,
            bending: 1e-3,
            ..Material::default()
        };
        let cloth = Cloth::new(mesh, &m).expect("cloth");
        let el = Elastic::new(&cloth, &m);
        // A stretched, sheared, bent state.
        let x: Vec<Vec3> = cloth
            .x
            .iter()
            .map(|p| {
                Vec3::new(
                    p.x * 1.05 + 0.02 * p.z,
                    0.3 * p.x * p.x + 0.01 * p.z,
                    p.z * 0.97,
                )
            })
            .collect();
        let k = Stiffness::of(&m, 1.0 / 60.0);
        for i in [0usize, 7, 12, 24] {
            let (mut f, mut hs) = (Vec3::ZERO, Mat3::ZERO);
            el.add_vertex(i, &x, &x, &k, &mut f, &mut hs);
            for axis in 0..3 {
                let eps = 1e-4f32;
                let mut xp = x.clone();
                xp[i][axis] += eps;
                let mut xm = x.clone();
                xm[i][axis] -= eps;
                let g = (el.energy(&xp, &m) - el.energy(&xm, &m)) / (2.0 * eps as f64);
                let tol = 2e-3 * g.abs().max(1e-2);
                assert!(
                    (f[axis] as f64 + g).abs() < tol,
                    "vertex {i} axis {axis}: force {} gradient {g}",
                    f[axis]
                );
            }
            // The one-pass forces agree.
            let mut all = vec![Vec3::ZERO; x.len()];
            el.add_forces(&x, &x, &k, &mut all);
            assert!(
                (all[i] - f).length() < 1e-4 * f.length().max(1e-3),
                "{} {f}",
                all[i]
            );
            // Positive semi-definite block.
            let e = (hs + hs.transpose()) * 0.5;
            for v in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE.normalize()] {
                assert!(v.dot(e * v) >= -1e-3, "{hs:?}");
            }
        }
    }
}
