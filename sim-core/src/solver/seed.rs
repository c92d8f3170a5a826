//! The 2005 paper's model, kept as a selectable reference: unit masses, a spring on every
//! mesh edge with force `g_ij = k (1 - l_ij / l'_ij) d_ij` (`l` rest length, `l'` current
//! length, `d_ij = x_j - x_i`), gravity, explicit integration and no damping.
//!
//! Explicit here means symplectic (semi-implicit) Euler, `v += h f; x += h v`: forward
//! Euler gains energy at any step size for an undamped spring, so no step would be
//! stable. Symplectic Euler is stable for `h < 2 / omega_max`, where `omega_max^2` is the
//! largest eigenvalue of the stiffness matrix (unit masses). That matrix changes as the
//! cloth folds: [`seed_stable_step`] is the bound for the flat cloth at rest,
//! [`seed_safe_step`] the one for any shape, which the model steps under.

use glam::Vec3;

use super::material::ModelKind;
use super::model::{Drive, Environment, FrameInput, Solver, StepError};
use super::state::Cloth;
use crate::collision::{ContactCache, ContactParams};

#[derive(Clone, Debug)]
pub struct Seed {
    springs: Vec<(u32, u32, f32)>,
    k: f32,
    prev: Vec<Vec3>,
    force: Vec<Vec3>,
    contact: ContactParams,
}

impl Seed {
    pub fn new(cloth: &Cloth, k: f32, contact: ContactParams) -> Self {
        let springs = cloth
            .topology
            .edges
            .iter()
            .map(|e| {
                (
                    e.a,
                    e.b,
                    (cloth.rest.positions[e.a as usize] - cloth.rest.positions[e.b as usize])
                        .length(),
                )
            })
            .collect();
        Self {
            springs,
            k,
            prev: cloth.x.clone(),
            force: vec![Vec3::ZERO; cloth.len()],
            contact,
        }
    }

    /// Advances `substeps` steps of `frame_dt / substeps`.
    pub fn step(
        &mut self,
        cloth: &mut Cloth,
        contacts: &ContactCache,
        env: &Environment,
        substeps: usize,
    ) {
        let h = env.frame_dt / substeps as f32;
        for _ in 0..substeps {
            self.force.iter_mut().for_each(|f| *f = env.gravity); // unit masses
            for &(i, j, rest) in &self.springs {
                let d = cloth.x[j as usize] - cloth.x[i as usize];
                let l = d.length();
                if l > 1e-12 {
                    let f = d * (self.k * (1.0 - rest / l));
                    self.force[i as usize] += f;
                    self.force[j as usize] -= f;
                }
            }
            for i in 0..cloth.len() {
                self.prev[i] = cloth.x[i];
                if cloth.inv_mass[i] > 0.0 {
                    cloth.v[i] += self.force[i] * h;
                    cloth.x[i] += cloth.v[i] * h;
                } else {
                    cloth.v[i] = Vec3::ZERO;
                }
            }
            contacts.project(&mut cloth.x, &mut self.prev, &cloth.inv_mass, &self.contact);
            for i in 0..cloth.len() {
                if cloth.inv_mass[i] > 0.0 && cloth.x[i] != self.prev[i] + cloth.v[i] * h {
                    cloth.v[i] = (cloth.x[i] - self.prev[i]) / h;
                }
            }
        }
    }

    /// Total energy (kinetic + spring + gravity, unit masses), J: conserved up to
    /// bounded oscillation by a stable symplectic step without contact.
    pub fn energy(&self, cloth: &Cloth, gravity: Vec3) -> f64 {
        let mut e = 0.0f64;
        for i in 0..cloth.len() {
            if cloth.inv_mass[i] > 0.0 {
                e += 0.5 * cloth.v[i].length_squared() as f64 - gravity.dot(cloth.x[i]) as f64;
            }
        }
        for &(i, j, rest) in &self.springs {
            let s = (cloth.x[j as usize] - cloth.x[i as usize]).length() - rest;
            e += 0.5 * self.k as f64 * (s * s) as f64;
        }
        e
    }
}

/// The largest stable symplectic-Euler step for springs of stiffness `k` on the cloth's
/// edges with unit masses, for the cloth flat at rest: `2 / sqrt(lambda_max)`,
/// `lambda_max` of the rest stiffness matrix `K = sum_e k (u u^T)` (block graph
/// Laplacian), by 300 power iterations. Pinned vertices are fixed (their rows are
/// removed).
///
/// This is the bound of the linear analysis and it is tight at rest, but a draping cloth
/// leaves it: where the cloth folds, a vertex's springs turn toward the same direction
/// and stiffen it beyond anything the flat lattice has. The model steps under
/// [`seed_safe_step`] instead.
pub fn seed_stable_step(cloth: &Cloth, k: f32) -> f64 {
    largest_stable_step(cloth, k, true)
}

/// The largest stable symplectic-Euler step for any shape the cloth takes while its
/// springs are at or beyond their rest length (folded, crumpled or stretched):
/// `2 / sqrt(k lambda_max(L))`, `L` the edge graph's Laplacian over the free vertices.
///
/// Why it holds: each spring's stiffness is `k u u^T` along it plus `k (1 - l/l')` across
/// it, both between 0 and `k` when the spring is not compressed, so for any motion `x`,
/// `x^T K x <= k sum_e |x_a - x_b|^2 <= k lambda_max(L) |x|^2`, whatever the directions
/// `u`. Equality is reached by a cloth whose springs all point one way. A compressed
/// spring only lowers the largest stiffness. On the square grid (diagonals alternating)
/// this step is 0.75x the rest bound.
pub fn seed_safe_step(cloth: &Cloth, k: f32) -> f64 {
    largest_stable_step(cloth, k, false)
}

/// `2 / sqrt(lambda_max)` of the unit-mass stiffness with springs along their rest
/// directions (`along_rest`), or of `k` times the graph Laplacian (every spring as stiff
/// in every direction).
fn largest_stable_step(cloth: &Cloth, k: f32, along_rest: bool) -> f64 {
    let n = cloth.len();
    let edges: Vec<(usize, usize, [f64; 3])> = cloth
        .topology
        .edges
        .iter()
        .map(|e| {
            let d = cloth.rest.positions[e.b as usize] - cloth.rest.positions[e.a as usize];
            let u = d.normalize_or_zero();
            (
                e.a as usize,
                e.b as usize,
                [u.x as f64, u.y as f64, u.z as f64],
            )
        })
        .collect();
    let free: Vec<f64> = (0..n)
        .map(|i| if cloth.is_pinned(i) { 0.0 } else { 1.0 })
        .collect();
    // Deterministic pseudo-random start with a component along every mode.
    let mut s = 0x9E37_79B9_7F4A_7C15u64;
    let mut x: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            std::array::from_fn(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * free[i]
            })
        })
        .collect();
    let mut y = vec![[0.0f64; 3]; n];
    let mut lambda = 0.0;
    for _ in 0..300 {
        y.iter_mut().for_each(|v| *v = [0.0; 3]);
        for &(a, b, u) in &edges {
            let d = [x[a][0] - x[b][0], x[a][1] - x[b][1], x[a][2] - x[b][2]];
            let f = if along_rest {
                let proj = (d[0] * u[0] + d[1] * u[1] + d[2] * u[2]) * k as f64;
                u.map(|c| proj * c)
            } else {
                d.map(|c| c * k as f64)
            };
            for c in 0..3 {
                y[a][c] += f[c];
                y[b][c] -= f[c];
            }
        }
        let mut num = 0.0;
        let mut den = 0.0;
        for i in 0..n {
            for c in 0..3 {
                y[i][c] *= free[i];
                num += x[i][c] * y[i][c];
                den += x[i][c] * x[i][c];
            }
        }
        if den == 0.0 {
            break;
        }
        lambda = num / den;
        let norm = y
            .iter()
            .flat_map(|v| v.iter())
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt();
        if norm == 0.0 {
            break;
        }
        for i in 0..n {
            for c in 0..3 {
                x[i][c] = y[i][c] / norm;
            }
        }
    }
    if lambda <= 0.0 {
        f64::INFINITY
    } else {
        2.0 / lambda.sqrt()
    }
}

impl Solver for Seed {
    fn kind(&self) -> ModelKind {
        ModelKind::Seed
    }

    fn step(&mut self, f: FrameInput<'_>, _: &mut Drive<'_, '_>) -> Result<(), StepError> {
        Seed::step(self, f.cloth, f.contacts, f.env, f.substeps);
        Ok(())
    }

    fn constraint_count(&self, cloth: &Cloth) -> usize {
        cloth.topology.edges.len()
    }

    fn energy(&self, cloth: &Cloth, gravity: Vec3) -> Option<f64> {
        Some(Seed::energy(self, cloth, gravity))
    }
}
