//! The implicit reference: backward Euler on the XPBD model's energy (membrane + bending,
//! see `constraints`), one minimisation of the incremental potential per step
//!
//! `Phi(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 + E(x)`, `y = x_n + h v_n + h^2 g`,
//!
//! by Newton's method with a positive semi-definite Hessian (stretch: the exact Hessian
//! with its transverse part clamped at zero; shear: Gauss-Newton; bending: exact, it is
//! quadratic), a backtracking line search, and sparse Cholesky in faer. The sparsity
//! pattern is fixed by the topology, so the symbolic factorisation is computed once.
//! Not real time; it validates XPBD.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat, Triplet};
use faer::{Mat, Side};
use glam::{DVec3, Vec3};

use super::constraints::{BendConstraint, Membrane, build_bending, build_membranes};
use super::material::{Material, ModelKind};
use super::model::{Drive, FrameInput, Solver, StepError};
use super::state::Cloth;

#[derive(Debug, thiserror::Error)]
pub enum ImplicitError {
    #[error("sparse factorisation failed: {0}")]
    Factorisation(String),
}

pub struct Implicit {
    membranes: Vec<Membrane>,
    bends: Vec<BendConstraint>,
    material: Material,
    /// Block index of each free vertex, `u32::MAX` for pinned ones.
    dof: Vec<u32>,
    nfree: usize,
    symbolic: Option<SymbolicLlt<usize>>,
    triplets: Vec<Triplet<usize, usize, f64>>,
    /// The Hessian's pattern and where each triplet's value goes in it, from the first
    /// assembly: the triplets come in the same order every time, so later assemblies
    /// only scatter their values (sorting them each time was 60% of a drape test).
    pattern: Option<(SymbolicSparseColMat<usize>, Argsort<usize>, usize)>,
    values: Vec<f64>,
    prev: Vec<Vec3>,
    /// Newton iterations per step (upper bound), and the tolerance: Newton stops when
    /// its step moves no vertex faster than this, m/s (the step over `h`).
    pub max_newton: usize,
    pub speed_tolerance: f64,
    /// Newton iterations used by the last step.
    pub last_iterations: usize,
}

impl std::fmt::Debug for Implicit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Implicit")
            .field("nfree", &self.nfree)
            .finish_non_exhaustive()
    }
}

/// Newton's default tolerance, m/s: a tenth of a millimetre a second, a hundredth of
/// what the drape test calls settled.
pub const SPEED_TOLERANCE: f64 = 1e-4;

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

impl Implicit {
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        let mut dof = vec![u32::MAX; cloth.len()];
        let mut nfree = 0;
        for (i, slot) in dof.iter_mut().enumerate() {
            if !cloth.is_pinned(i) {
                *slot = nfree as u32;
                nfree += 1;
            }
        }
        Self {
            membranes: build_membranes(&cloth.rest, &cloth.zones, material),
            bends: build_bending(&cloth.rest, &cloth.topology, material, &cloth.zones),
            material: *material,
            dof,
            nfree,
            symbolic: None,
            triplets: Vec::new(),
            pattern: None,
            values: Vec::new(),
            prev: cloth.x.clone(),
            max_newton: 20,
            speed_tolerance: SPEED_TOLERANCE,
            last_iterations: 0,
        }
    }

    /// Refreshes the free/pinned split after pins changed.
    pub fn repin(&mut self, cloth: &Cloth) {
        let material = self.material;
        *self = Self {
            max_newton: self.max_newton,
            speed_tolerance: self.speed_tolerance,
            ..Self::new(cloth, &material)
        };
    }

    fn energy(&self, x: &[DVec3]) -> f64 {
        let m = &self.material;
        let mut e = 0.0;
        for t in &self.membranes {
            let p = t.v.map(|i| x[i as usize]);
            let fu = p[0] * t.c[0] as f64 + p[1] * t.c[1] as f64 + p[2] * t.c[2] as f64;
            let fv = p[0] * t.d[0] as f64 + p[1] * t.d[1] as f64 + p[2] * t.d[2] as f64;
            let a = t.area as f64;
            let (su, sv, sh) = (fu.length() - 1.0, fv.length() - 1.0, fu.dot(fv));
            e += 0.5 * m.stretch as f64 * a * t.ks as f64 * (su * su + sv * sv)
                + 0.5 * m.shear as f64 * a * t.kg as f64 * sh * sh;
        }
        for b in &self.bends {
            let c = (0..4)
                .map(|k| x[b.v[k] as usize] * b.k[k] as f64)
                .sum::<DVec3>()
                - d(b.rest);
            e += 0.5 * (m.bending * b.weight) as f64 * c.length_squared();
        }
        e
    }

    /// Gradient of `E` into `g` (3 per vertex) and the Hessian's lower triangle into the
    /// triplet list, in a fixed order so the pattern never changes.
    fn assemble(&mut self, x: &[DVec3], g: &mut [DVec3], inertia: f64, mass: &[f32]) {
        let m = self.material;
        let dof = &self.dof;
        let trip = &mut self.triplets;
        trip.clear();
        for (i, &k) in dof.iter().enumerate() {
            if k != u32::MAX {
                for r in 0..3 {
                    trip.push(Triplet::new(
                        3 * k as usize + r,
                        3 * k as usize + r,
                        inertia * mass[i] as f64,
                    ));
                }
            }
        }
        let push_block =
            |a: u32, b: u32, blk: [[f64; 3]; 3], trip: &mut Vec<Triplet<usize, usize, f64>>| {
                let (da, db) = (dof[a as usize], dof[b as usize]);
                if da == u32::MAX || db == u32::MAX {
                    return;
                }
                for r in 0..3 {
                    for c in 0..3 {
                        let (row, col) = (3 * da as usize + r, 3 * db as usize + c);
                        if row >= col {
                            trip.push(Triplet::new(row, col, blk[r][c]));
                        }
                    }
                }
            };
        for t in &self.membranes {
            let p = t.v.map(|i| x[i as usize]);
            let (c, dd) = (t.c.map(|v| v as f64), t.d.map(|v| v as f64));
            let fu = p[0] * c[0] + p[1] * c[1] + p[2] * c[2];
            let fv = p[0] * dd[0] + p[1] * dd[1] + p[2] * dd[2];
            let area = t.area as f64;
            let (ks, kg) = (
                m.stretch as f64 * area * t.ks as f64,
                m.shear as f64 * area * t.kg as f64,
            );
            let (lu, lv) = (fu.length().max(1e-12), fv.length().max(1e-12));
            let (uu, vv) = (fu / lu, fv / lv);
            let sh = fu.dot(fv);
            let grad_sh = |a: usize| fv * c[a] + fu * dd[a];
            for a in 0..3 {
                g[t.v[a] as usize] += uu * (ks * (lu - 1.0) * c[a])
                    + vv * (ks * (lv - 1.0) * dd[a])
                    + grad_sh(a) * (kg * sh);
            }
            let tu = (1.0 - 1.0 / lu).max(0.0);
            let tv = (1.0 - 1.0 / lv).max(0.0);
            for a in 0..3 {
                for b in 0..3 {
                    let (ga, gb) = (grad_sh(a), grad_sh(b));
                    let blk: [[f64; 3]; 3] = std::array::from_fn(|r| {
                        std::array::from_fn(|s| {
                            let id = if r == s { 1.0 } else { 0.0 };
                            ks * c[a] * c[b] * (uu[r] * uu[s] + tu * (id - uu[r] * uu[s]))
                                + ks * dd[a] * dd[b] * (vv[r] * vv[s] + tv * (id - vv[r] * vv[s]))
                                + kg * ga[r] * gb[s]
                        })
                    });
                    push_block(t.v[a], t.v[b], blk, trip);
                }
            }
        }
        for bc in &self.bends {
            let k = (m.bending * bc.weight) as f64;
            let cv = (0..4)
                .map(|a| x[bc.v[a] as usize] * bc.k[a] as f64)
                .sum::<DVec3>()
                - d(bc.rest);
            for a in 0..4 {
                g[bc.v[a] as usize] += cv * (k * bc.k[a] as f64);
                for b in 0..4 {
                    let s = k * bc.k[a] as f64 * bc.k[b] as f64;
                    push_block(
                        bc.v[a],
                        bc.v[b],
                        [[s, 0.0, 0.0], [0.0, s, 0.0], [0.0, 0.0, s]],
                        trip,
                    );
                }
            }
        }
    }

    /// The Hessian assembled last, as a sparse matrix of `dim` rows.
    fn hessian(&mut self, dim: usize) -> Result<SparseColMat<usize, f64>, ImplicitError> {
        let fail = |e: &dyn std::fmt::Debug| ImplicitError::Factorisation(format!("{e:?}"));
        let count = self.triplets.len();
        if self.pattern.as_ref().is_none_or(|p| p.2 != count) {
            let pairs: Vec<Pair<usize, usize>> = self
                .triplets
                .iter()
                .map(|t| Pair {
                    row: t.row,
                    col: t.col,
                })
                .collect();
            let (symbolic, order) = SymbolicSparseColMat::try_new_from_indices(dim, dim, &pairs)
                .map_err(|e| fail(&e))?;
            self.pattern = Some((symbolic, order, count));
        }
        let Some((symbolic, order, _)) = &self.pattern else {
            return Err(ImplicitError::Factorisation("no pattern".into()));
        };
        self.values.clear();
        self.values.extend(self.triplets.iter().map(|t| t.val));
        SparseColMat::<usize, f64>::new_from_argsort(symbolic.clone(), order, &self.values)
            .map_err(|e| fail(&e))
    }

    /// The Newton step `-H^-1 grad` for the Hessian assembled last (`None` when nothing
    /// is free to move).
    fn newton_direction(&mut self, grad: &[DVec3]) -> Result<Option<Vec<DVec3>>, ImplicitError> {
        let fail = |e: &dyn std::fmt::Debug| ImplicitError::Factorisation(format!("{e:?}"));
        let dim = 3 * self.nfree;
        if dim == 0 {
            return Ok(None);
        }
        let a = self.hessian(dim)?;
        if self.symbolic.is_none() {
            self.symbolic =
                Some(SymbolicLlt::try_new(a.symbolic(), Side::Lower).map_err(|e| fail(&e))?);
        }
        let Some(sym) = self.symbolic.clone() else {
            return Ok(None);
        };
        let llt = Llt::try_new_with_symbolic(sym, a.as_ref(), Side::Lower).map_err(|e| fail(&e))?;
        let mut rhs = Mat::<f64>::zeros(dim, 1);
        for (i, &k) in self.dof.iter().enumerate() {
            if k != u32::MAX {
                for r in 0..3 {
                    rhs[(3 * k as usize + r, 0)] = -grad[i][r];
                }
            }
        }
        llt.solve_in_place(rhs.as_mut());
        Ok(Some(
            self.dof
                .iter()
                .map(|&k| {
                    if k == u32::MAX {
                        DVec3::ZERO
                    } else {
                        DVec3::new(
                            rhs[(3 * k as usize, 0)],
                            rhs[(3 * k as usize + 1, 0)],
                            rhs[(3 * k as usize + 2, 0)],
                        )
                    }
                })
                .collect(),
        ))
    }

    /// Advances one frame in `substeps` backward-Euler steps.
    fn frame(&mut self, frame: FrameInput<'_>) -> Result<(), ImplicitError> {
        let FrameInput {
            cloth,
            contacts,
            env,
            substeps,
            ..
        } = frame;
        let h = (env.frame_dt / substeps as f32) as f64;
        let n = cloth.len();
        let inertia = 1.0 / (h * h);
        let cp = self.material.contact_params(env.floor);
        let gvec = d(env.gravity);
        for _ in 0..substeps {
            let x0: Vec<DVec3> = cloth.x.iter().map(|&p| d(p)).collect();
            let y: Vec<DVec3> = (0..n)
                .map(|i| {
                    if cloth.is_pinned(i) {
                        x0[i]
                    } else {
                        x0[i] + d(cloth.v[i]) * h + gvec * h * h
                    }
                })
                .collect();
            let phi = |s: &Self, x: &[DVec3]| -> f64 {
                let mut e = s.energy(x);
                for i in 0..n {
                    e += 0.5 * inertia * cloth.mass[i] as f64 * (x[i] - y[i]).length_squared();
                }
                e
            };
            // Start from the better of the inertial prediction with gravity (a cloth in
            // flight) and without it (a cloth at rest, where the full fall of a long step
            // is far off and costs Newton most of its iterations).
            let coast: Vec<DVec3> = (0..n)
                .map(|i| {
                    if cloth.is_pinned(i) {
                        x0[i]
                    } else {
                        x0[i] + d(cloth.v[i]) * h
                    }
                })
                .collect();
            let (phi_y, phi_c) = (phi(self, &y), phi(self, &coast));
            let (mut x, mut phi_x) = if phi_c < phi_y {
                (coast, phi_c)
            } else {
                (y.clone(), phi_y)
            };
            let mut grad = vec![DVec3::ZERO; n];
            self.last_iterations = 0;
            let tolerance = self.speed_tolerance * h;
            for _ in 0..self.max_newton {
                self.last_iterations += 1;
                grad.iter_mut().for_each(|v| *v = DVec3::ZERO);
                self.assemble(&x, &mut grad, inertia, &cloth.mass);
                for i in 0..n {
                    grad[i] += (x[i] - y[i]) * (inertia * cloth.mass[i] as f64);
                }
                let Some(dx) = self.newton_direction(&grad)? else {
                    break;
                };
                let slope: f64 = grad.iter().zip(&dx).map(|(g, s)| g.dot(*s)).sum();
                let mut alpha = 1.0;
                let mut accepted = false;
                for _ in 0..12 {
                    let trial: Vec<DVec3> =
                        x.iter().zip(&dx).map(|(p, s)| *p + *s * alpha).collect();
                    let phi_t = phi(self, &trial);
                    if phi_t <= phi_x + 1e-4 * alpha * slope || phi_t <= phi_x {
                        x = trial;
                        phi_x = phi_t;
                        accepted = true;
                        break;
                    }
                    alpha *= 0.5;
                }
                let step = dx.iter().map(|s| s.length()).fold(0.0, f64::max) * alpha;
                if !accepted || step < tolerance {
                    break;
                }
            }
            let damp = (-(self.material.damping as f64) * h).exp();
            for i in 0..n {
                self.prev[i] = cloth.x[i];
                if !cloth.is_pinned(i) {
                    cloth.x[i] = x[i].as_vec3();
                    cloth.v[i] = ((x[i] - x0[i]) / h * damp).as_vec3();
                }
            }
            contacts.project(&mut cloth.x, &mut self.prev, &cloth.inv_mass, &cp);
            for i in 0..n {
                if !cloth.is_pinned(i) && cloth.x[i] != x[i].as_vec3() {
                    cloth.v[i] = (cloth.x[i] - self.prev[i]) / h as f32;
                }
            }
        }
        Ok(())
    }
}

impl Solver for Implicit {
    fn kind(&self) -> ModelKind {
        ModelKind::Implicit
    }

    fn step(&mut self, frame: FrameInput<'_>, _: &mut Drive<'_, '_>) -> Result<(), StepError> {
        self.frame(frame)
            .map_err(|ImplicitError::Factorisation(why)| StepError::Factorisation(why))
    }

    fn constraint_count(&self, cloth: &Cloth) -> usize {
        cloth.topology.edges.len()
    }

    fn pinned(&mut self, cloth: &Cloth, _vertex: u32) {
        self.repin(cloth);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;

    /// The cached pattern gives the matrix the triplets describe, at every assembly.
    #[test]
    fn the_cached_pattern_scatters_each_assembly_like_the_triplets() {
        let material = Material::default();
        let mut cloth =
            Cloth::new(ClothMesh::grid(0.2, 0.2, 6, 6, 0.0).unwrap(), &material).unwrap();
        cloth.pin(0);
        let mut s = Implicit::new(&cloth, &material);
        let dim = 3 * s.nfree;
        for round in 0..3 {
            let x: Vec<DVec3> = cloth
                .x
                .iter()
                .enumerate()
                .map(|(i, p)| d(*p) + DVec3::new(0.0, 0.01 * ((i * 7 + round) % 5) as f64, 0.0))
                .collect();
            let mut g = vec![DVec3::ZERO; x.len()];
            s.assemble(&x, &mut g, 3600.0, &cloth.mass);
            let cached = s.hessian(dim).unwrap().to_dense();
            let direct = SparseColMat::<usize, f64>::try_new_from_triplets(dim, dim, &s.triplets)
                .unwrap()
                .to_dense();
            let worst = (0..dim)
                .flat_map(|r| (0..dim).map(move |c| (r, c)))
                .map(|(r, c)| (cached[(r, c)] - direct[(r, c)]).abs())
                .fold(0.0, f64::max);
            assert!(worst == 0.0, "round {round}: entries differ by {worst}");
            assert!(direct[(3, 3)] > 0.0, "the matrix is not empty");
        }
    }
}
