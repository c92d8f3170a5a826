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

use faer::Mat;
use glam::{DMat3, DVec3, Vec3};

use super::constraints::{BendConstraint, Membrane, build_bending, build_membranes};
use super::material::{Material, ModelKind};
use super::model::{Drive, FrameInput, Solver, StepError};
use super::state::Cloth;

mod hessian;
use hessian::{Entries, Factor};

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
    factor: Option<Factor>,
    /// The Hessian's lower triangle.
    entries: Entries,
    prev: Vec<Vec3>,
    /// Newton iterations per step (upper bound), and the tolerance: Newton stops when
    /// its step moves no vertex faster than this, m/s (the step over `h`).
    pub max_newton: usize,
    pub speed_tolerance: f64,
    /// Newton iterations used by the last step, and whether it reached the tolerance.
    pub last_iterations: usize,
    pub last_converged: bool,
    /// For runs that measure only where the cloth comes to rest: fewer Newton
    /// iterations while it moves (`None`: every step solved to the tolerance).
    pub early_stop: Option<EarlyStop>,
}

/// Newton stops after `iterations` in a step that starts with the cloth moving faster
/// than `calm_speed` (its mass-weighted RMS speed, m/s). Each iteration still lowers
/// the step's potential, so the cloth still falls toward rest; once it is calm, every
/// step is solved to the tolerance again, so the state it settles in is backward
/// Euler's rest, as without the stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EarlyStop {
    pub iterations: usize,
    pub calm_speed: f64,
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
            factor: None,
            entries: Entries::default(),
            prev: cloth.x.clone(),
            max_newton: 20,
            speed_tolerance: SPEED_TOLERANCE,
            last_iterations: 0,
            last_converged: false,
            early_stop: None,
        }
    }

    /// Refreshes the free/pinned split after pins changed.
    pub fn repin(&mut self, cloth: &Cloth) {
        let material = self.material;
        *self = Self {
            max_newton: self.max_newton,
            speed_tolerance: self.speed_tolerance,
            early_stop: self.early_stop,
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

    /// Gradient of `E` into `g` (3 per vertex) and the Hessian's lower triangle into
    /// `entries`, in a fixed order so the pattern never changes: exact, or with its
    /// indefinite parts dropped.
    fn assemble(&mut self, x: &[DVec3], g: &mut [DVec3], inertia: f64, mass: &[f32], exact: bool) {
        let m = self.material;
        let dof = &self.dof;
        let trip = &mut self.entries;
        trip.begin();
        for (i, &k) in dof.iter().enumerate() {
            if k != u32::MAX {
                for r in 0..3 {
                    let at = 3 * k as usize + r;
                    trip.add(at, at, inertia * mass[i] as f64);
                }
            }
        }
        let push_block = |a: u32, b: u32, blk: [[f64; 3]; 3], trip: &mut Entries| {
            let (da, db) = (dof[a as usize], dof[b as usize]);
            if da == u32::MAX || db == u32::MAX {
                return;
            }
            for r in 0..3 {
                for c in 0..3 {
                    let (row, col) = (3 * da as usize + r, 3 * db as usize + c);
                    if row >= col {
                        trip.add(row, col, blk[r][c]);
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
            // The stretch's transverse stiffness is negative in compression, and the
            // shear's curvature term indefinite: the projected Hessian drops both.
            let (tu, tv) = if exact {
                (1.0 - 1.0 / lu, 1.0 - 1.0 / lv)
            } else {
                ((1.0 - 1.0 / lu).max(0.0), (1.0 - 1.0 / lv).max(0.0))
            };
            let curl = if exact { kg * sh } else { 0.0 };
            // Vertex a's block against b's: c_a c_b A + d_a d_b B + c_a d_b C + d_a c_b C^T,
            // from the stretch along u (A) and v (B) and the shear (all three).
            let outer = |p: DVec3, q: DVec3| DMat3::from_cols(p * q.x, p * q.y, p * q.z);
            let id = DMat3::IDENTITY;
            let am = (outer(uu, uu) * (1.0 - tu) + id * tu) * ks + outer(fv, fv) * kg;
            let bm = (outer(vv, vv) * (1.0 - tv) + id * tv) * ks + outer(fu, fu) * kg;
            let cm = outer(fv, fu) * kg + id * curl;
            let cmt = cm.transpose();
            for a in 0..3 {
                for b in 0..3 {
                    let m = am * (c[a] * c[b])
                        + bm * (dd[a] * dd[b])
                        + cm * (c[a] * dd[b])
                        + cmt * (dd[a] * c[b]);
                    push_block(t.v[a], t.v[b], m.transpose().to_cols_array_2d(), trip);
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

    /// The Newton step `-H^-1 grad` for the Hessian assembled last (`None` when nothing
    /// is free to move). Fails when the Hessian is not positive definite.
    fn newton_direction(&mut self, grad: &[DVec3]) -> Result<Option<Vec<DVec3>>, ImplicitError> {
        let dim = 3 * self.nfree;
        if dim == 0 {
            return Ok(None);
        }
        let a = self.entries.matrix(dim)?;
        if self.factor.is_none() {
            self.factor = Some(Factor::new(a)?);
        }
        let Some(factor) = self.factor.as_mut() else {
            return Ok(None);
        };
        let mut rhs = Mat::<f64>::zeros(dim, 1);
        for (i, &k) in self.dof.iter().enumerate() {
            if k != u32::MAX {
                for r in 0..3 {
                    rhs[(3 * k as usize + r, 0)] = -grad[i][r];
                }
            }
        }
        factor.solve(a, rhs.as_mut())?;
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

    /// The gradient of the step's potential at `x` into `grad`, and the Newton step for
    /// it: with the exact Hessian while `exact` (cleared when that is not positive
    /// definite), else the projected one.
    fn direction(
        &mut self,
        x: &[DVec3],
        y: &[DVec3],
        grad: &mut [DVec3],
        inertia: f64,
        mass: &[f32],
        exact: &mut bool,
    ) -> Result<Option<Vec<DVec3>>, ImplicitError> {
        loop {
            grad.iter_mut().for_each(|v| *v = DVec3::ZERO);
            self.assemble(x, grad, inertia, mass, *exact);
            for i in 0..x.len() {
                grad[i] += (x[i] - y[i]) * (inertia * mass[i] as f64);
            }
            match self.newton_direction(grad) {
                Err(_) if *exact => *exact = false,
                result => return result,
            }
        }
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
            self.last_converged = false;
            let tolerance = self.speed_tolerance * h;
            let iterations = match self.early_stop {
                Some(stop) if rms_speed(cloth) > stop.calm_speed => {
                    stop.iterations.clamp(1, self.max_newton)
                }
                _ => self.max_newton,
            };
            // Each step tries the exact Hessian first (near rest it is positive definite
            // and Newton converges quadratically), and the projected one from its first
            // failure on.
            let mut exact = true;
            for _ in 0..iterations {
                self.last_iterations += 1;
                let Some(dx) =
                    self.direction(&x, &y, &mut grad, inertia, &cloth.mass, &mut exact)?
                else {
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
                if accepted && step < tolerance {
                    self.last_converged = true;
                }
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

/// The cloth's mass-weighted RMS speed over its free vertices, m/s.
fn rms_speed(cloth: &Cloth) -> f64 {
    let (mut mv2, mut m) = (0.0, 0.0);
    for i in 0..cloth.len() {
        if !cloth.is_pinned(i) {
            mv2 += cloth.mass[i] as f64 * cloth.v[i].length_squared() as f64;
            m += cloth.mass[i] as f64;
        }
    }
    if m > 0.0 { (mv2 / m).sqrt() } else { 0.0 }
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
    use faer::sparse::SparseColMat;

    use super::*;
    use crate::mesh::ClothMesh;

    fn sheet() -> (Cloth, Material) {
        let material = Material::default();
        let mut cloth =
            Cloth::new(ClothMesh::grid(0.2, 0.2, 6, 6, 0.0).unwrap(), &material).unwrap();
        cloth.pin(0);
        (cloth, material)
    }

    /// The sheet crumpled: some sides stretched, some compressed, the faces sheared.
    fn crumpled(cloth: &Cloth, round: usize) -> Vec<DVec3> {
        cloth
            .x
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let k = ((i * 7 + round) % 5) as f64;
                d(*p) * (0.9 + 0.04 * k) + DVec3::new(0.003 * k, 0.01 * k, -0.002 * k)
            })
            .collect()
    }

    /// Each assembly after the first adds its entries into the first one's pattern, and
    /// gives the matrix its entries describe (as faer sums them from triplets).
    #[test]
    fn each_assembly_adds_into_the_first_ones_pattern() {
        let (cloth, material) = sheet();
        let mut s = Implicit::new(&cloth, &material);
        let dim = 3 * s.nfree;
        for round in 0..3 {
            let x = crumpled(&cloth, round);
            let mut fresh = Implicit::new(&cloth, &material);
            let mut g = vec![DVec3::ZERO; x.len()];
            fresh.assemble(&x, &mut g, 3600.0, &cloth.mass, round == 1);
            let direct = SparseColMat::<usize, f64>::try_new_from_triplets(
                dim,
                dim,
                fresh.entries.triplets(),
            )
            .unwrap()
            .to_dense();
            s.assemble(&x, &mut g, 3600.0, &cloth.mass, round == 1);
            let kept = s.entries.matrix(dim).unwrap().to_dense();
            let scale = (0..dim).map(|r| direct[(r, r)].abs()).fold(0.0, f64::max);
            let worst = (0..dim)
                .flat_map(|r| (0..dim).map(move |c| (r, c)))
                .map(|(r, c)| (kept[(r, c)] - direct[(r, c)]).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= 1e-14 * scale,
                "round {round}: entries differ by {worst}"
            );
            assert!(direct[(3, 3)] > 0.0, "the matrix is not empty");
        }
    }

    /// The exact Hessian is the gradient's derivative (central differences), on a sheet
    /// with sides in compression, where the projected one leaves out the negative
    /// transverse stiffness and the shear's curvature.
    #[test]
    fn the_exact_hessian_is_the_gradients_derivative() {
        let (cloth, material) = sheet();
        let x = crumpled(&cloth, 0);
        let mut s = Implicit::new(&cloth, &material);
        let dim = 3 * s.nfree;
        let mut g = vec![DVec3::ZERO; x.len()];
        s.assemble(&x, &mut g, 0.0, &cloth.mass, true);
        let exact = s.entries.matrix(dim).unwrap().to_dense();
        s.assemble(&x, &mut g, 0.0, &cloth.mass, false);
        let projected = s.entries.matrix(dim).unwrap().to_dense();
        let at = |m: &faer::Mat<f64>, r: usize, c: usize| m[(r.max(c), r.min(c))];
        let grad = |s: &mut Implicit, x: &[DVec3]| {
            let mut g = vec![DVec3::ZERO; x.len()];
            s.assemble(x, &mut g, 0.0, &cloth.mass, true);
            g
        };
        let (mut worst, mut scale, mut projected_off) = (0.0f64, 0.0f64, 0.0f64);
        for v in [5, 12, 20, 33] {
            let k = s.dof[v] as usize;
            for axis in 0..3 {
                let eps = 1e-6;
                let (mut up, mut down) = (x.clone(), x.clone());
                up[v][axis] += eps;
                down[v][axis] -= eps;
                let (gu, gd) = (grad(&mut s, &up), grad(&mut s, &down));
                for (i, &kk) in s.dof.iter().enumerate() {
                    if kk == u32::MAX {
                        continue;
                    }
                    for r in 0..3 {
                        let fd = (gu[i][r] - gd[i][r]) / (2.0 * eps);
                        let (row, col) = (3 * kk as usize + r, 3 * k + axis);
                        worst = worst.max((at(&exact, row, col) - fd).abs());
                        projected_off = projected_off.max((at(&projected, row, col) - fd).abs());
                        scale = scale.max(fd.abs());
                    }
                }
            }
        }
        assert!(
            worst <= 1e-5 * scale,
            "exact Hessian off by {worst} of {scale}"
        );
        assert!(
            projected_off > 1e-3 * scale,
            "the crumpled sheet has indefinite parts the projection drops ({projected_off})"
        );
    }

    /// A sheet hung by one edge and released flat: with the early stop its steps take at
    /// most the stop's iterations while it swings and are solved to the tolerance once it
    /// is calm, and it comes to rest where it does with every step solved.
    #[test]
    fn the_early_stop_cuts_only_the_fast_steps_and_rests_where_the_full_solve_does() {
        use crate::collision::contact::ContactCache;
        use crate::solver::Environment;
        let material = Material::default();
        let hang = |stop: Option<EarlyStop>| {
            let mut cloth =
                Cloth::new(ClothMesh::grid(0.3, 0.3, 8, 8, 0.0).unwrap(), &material).unwrap();
            for i in 0..9 {
                cloth.pin(i);
            }
            let mut s = Implicit::new(&cloth, &material);
            s.early_stop = stop;
            let env = Environment {
                frame_dt: 0.05,
                floor: None,
                ..Environment::default()
            };
            let contacts = ContactCache::new(cloth.len());
            let (mut fast_most, mut calm, mut calm_solved) = (0, 0, 0);
            for _ in 0..120 {
                let fast = rms_speed(&cloth) > 0.01;
                let frame = FrameInput {
                    cloth: &mut cloth,
                    body: None,
                    contacts: &contacts,
                    env: &env,
                    substeps: 1,
                };
                s.frame(frame).unwrap();
                if fast {
                    fast_most = fast_most.max(s.last_iterations);
                } else {
                    calm += 1;
                    calm_solved += usize::from(s.last_converged);
                }
            }
            (cloth.x, fast_most, calm, calm_solved)
        };
        let stop = EarlyStop {
            iterations: 3,
            calm_speed: 0.01,
        };
        let (early, early_most, calm, calm_solved) = hang(Some(stop));
        let (full, full_most, ..) = hang(None);
        assert!(
            full_most > 3,
            "the full solve took {full_most} iterations at most"
        );
        assert!(early_most <= 3, "a fast step took {early_most} iterations");
        assert!(
            calm > 20 && calm_solved == calm,
            "{calm_solved} of {calm} calm steps solved"
        );
        let apart = early
            .iter()
            .zip(&full)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f32::max);
        assert!(apart < 1e-3, "the two rests are {apart} m apart");
        assert!(
            full.iter().map(|p| p.y).fold(0.0, f32::min) < -0.25,
            "the sheet hangs"
        );
    }
}
