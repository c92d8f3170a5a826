//! The global step: what Gauss-Seidel over vertices cannot do in a few sweeps is carry a
//! stretch across the whole cloth (a hanging cloth's weight, a pull at one corner). One
//! sparse solve does: `x += -L^-1 grad Phi`, with `L` a fixed matrix that majorizes the
//! Hessian of the inertia and the elastic energy (`M/h^2`, each triangle's warp and weft
//! rows as springs in every direction, each hinge's bending exactly), so each step lowers
//! the step's potential (Liu et al. 2017, "Quasi-Newton methods for real-time simulation
//! of hyperelastic materials", use the same matrix). Its fixed point is the implicit
//! step's, whatever `L` is: `L` decides only how fast it gets there. It is factored once
//! (sparse Cholesky, faer), again in a background thread after the mesh changes; until the
//! new factor is ready the old one serves (vertices it does not know take a Jacobi step).
//! As a preconditioner it is factored again every few steps with the vertices the
//! contact filter held still stiffened (`STIFFEN_EVERY`).

use std::thread::JoinHandle;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Par, Side};
use glam::{DVec3, Mat3, Vec3, Vec3A};

use super::elastic::Elastic;
use crate::solver::material::Material;

/// A factored `L`: `P L P^T = C C^T` with `C` lower triangular, solved for the three
/// coordinates at once. (faer's supernodal solve, one coordinate a column of a dense
/// right-hand side, spent much of its time copying blocks; this pass made a 128 x 128
/// drape's frame 5% faster.) `C` is kept in single precision: the factor only
/// preconditions the conjugate gradient, which runs in f64, and its solves are a resting
/// drape's largest cost (that and the backward solve's four sums below took the 64 x 64
/// drape-cube's and fit-cube's frames from 55 to 45 ms).
struct Factor {
    n: usize,
    /// `1 / C_jj`.
    inv_diag: Vec<f32>,
    /// `C` below the diagonal, column by column.
    by_col: Strict,
    /// The ordering: row `i` of the permuted system is row `fwd[i]` of `L`.
    fwd: Vec<u32>,
    /// `L`'s lower triangle, diagonal included (duplicates summed), for products.
    lower: Vec<(u32, u32, f64)>,
    /// What factoring `L` again with other diagonals takes.
    numeric: Numeric,
    /// The vertices whose diagonal is stiffened in this factor.
    stiff: Vec<bool>,
}

/// `L` and its symbolic factorisation, kept to factor it again with stiffened diagonals.
struct Numeric {
    sym: SymbolicCholesky<usize>,
    /// `L` (lower triangle), its values as they are factored.
    a: SparseColMat<usize, f64>,
    /// Where column `j`'s diagonal is in `a`'s values.
    diag_at: Vec<usize>,
    /// The factor's values, and scratch for computing them.
    val: Vec<f64>,
    mem: MemBuffer,
}

/// A strictly lower triangular matrix by columns: column `j`'s entries are in rows
/// `idx[ptr[j]..ptr[j + 1]]`, with values `val[..]`.
#[derive(Default)]
struct Strict {
    ptr: Vec<usize>,
    idx: Vec<u32>,
    val: Vec<f32>,
}

impl Strict {
    /// Column `j` (as a row of `C^T`) times `y`, summed in four parts: one sum is a
    /// chain of dependent additions, and a column's 30-40 entries would wait on each
    /// other (with four, a 64 x 64 fit-cube's frame went from 51 to 44 ms, one run each).
    #[inline]
    fn dot(&self, j: usize, y: &[Vec3A]) -> Vec3A {
        let (a, b) = (self.ptr[j], self.ptr[j + 1]);
        let (ic, vc) = (
            self.idx[a..b].chunks_exact(4),
            self.val[a..b].chunks_exact(4),
        );
        let (ir, vr) = (ic.remainder(), vc.remainder());
        let mut acc = [Vec3A::ZERO; 4];
        for (i4, v4) in ic.zip(vc) {
            for l in 0..4 {
                acc[l] += y[i4[l] as usize] * v4[l];
            }
        }
        for (l, (&i, &v)) in ir.iter().zip(vr).enumerate() {
            acc[l] += y[i as usize] * v;
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3])
    }
}

impl Factor {
    /// `z = L^-1 r` through `y`, a scratch vector.
    fn solve(&self, r: &[DVec3], y: &mut Vec<Vec3A>, z: &mut [DVec3]) {
        y.clear();
        y.extend(self.fwd.iter().map(|&i| r[i as usize].as_vec3a()));
        let c = &self.by_col;
        for j in 0..self.n {
            let yj = y[j] * self.inv_diag[j];
            y[j] = yj;
            for k in c.ptr[j]..c.ptr[j + 1] {
                y[c.idx[k] as usize] -= yj * c.val[k];
            }
        }
        for j in (0..self.n).rev() {
            y[j] = (y[j] - self.by_col.dot(j, y)) * self.inv_diag[j];
        }
        for (i, &f) in self.fwd.iter().enumerate() {
            z[f as usize] = y[i].as_dvec3();
        }
    }
}

/// The global step's matrix, factored, and the factorisation under way.
#[derive(Default)]
pub struct GlobalStep {
    factor: Option<Factor>,
    pending: Option<JoinHandle<Option<Factor>>>,
    /// The step length `h` and vertex count the current (or pending) factor is for.
    key: Option<(u32, usize, u64)>,
    /// Scratch for the factor's solves.
    y: Vec<Vec3A>,
    /// Vertices filtered since the factor was last stiffened, and global steps since.
    seen: Vec<bool>,
    since: usize,
    work: Work,
}

/// The filtered conjugate gradient's vectors, kept between steps.
#[derive(Default)]
struct Work {
    x: Vec<DVec3>,
    r: Vec<DVec3>,
    z: Vec<DVec3>,
    p: Vec<DVec3>,
    q: Vec<DVec3>,
}

impl std::fmt::Debug for GlobalStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GlobalStep")
            .field("n", &self.factor.as_ref().map(|f| f.n))
            .field("pending", &self.pending.is_some())
            .finish()
    }
}

impl Clone for GlobalStep {
    /// A clone starts without a factor (it is rebuilt on its first step).
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// How many global steps the factor serves before it is factored again with the diagonal
/// of every vertex the filter held still meanwhile (friction holding it) stiffened, the
/// symbolic factorisation kept. `L^-1` knows nothing of the filter, and the first
/// conjugate-gradient steps were spent undoing the moves it gave held vertices: on
/// fit-cube (a temporary probe, 2026-11-27) one step took 2% off the step's quadratic
/// model, against 96% with the factor stiffened for exactly the vertices held then, and
/// two steps with it did more than eight without. The held set changes by half from one
/// step to the next and a numeric factorisation costs about 7 ms at 4,225 vertices (a
/// seventh of a frame), so the factor is refreshed now and then with the vertices held
/// since, and 5 steps do the work of 8 (`DEFAULT_CG_ITERATIONS`, docs/models.md, Speed).
/// Vertices held only along a contact's normal (sliding) are not stiffened: a stiffer
/// diagonal holds them in every direction, and a cloth sliding down a slope then lost
/// the preconditioner's rigid translation and slid 0.5 m instead of 3.4.
const STIFFEN_EVERY: usize = 24;
/// The stiffening: `L`'s diagonal times `1 + STIFFEN`. Much more (100 or 10,000) helps
/// only while the set is exact: a vertex that has since slid or let go is then all but
/// frozen in the steps the factor serves.
const STIFFEN: f64 = 1.0;

/// Weight on a triangle's shear rows in `L`, times its shear stiffness: the Gauss-Newton
/// Hessian of `(F_u . F_v)^2` is at most twice `|F|^2` times the rows' outer products,
/// and a little more for the term in `F_u . F_v` itself.
const SHEAR_BOUND: f32 = 2.5;

/// `L`'s entries (lower triangle) for the elements of `elastic`, masses `mass`, step `h`;
/// rows of vertices that do not move are the identity.
fn assemble(
    elastic: &Elastic,
    mass: &[f32],
    free: &[bool],
    h: f32,
    m: &Material,
) -> Vec<Triplet<usize, usize, f64>> {
    let n = mass.len();
    let mut diag = vec![0.0f64; n];
    let mut trip = Vec::with_capacity(n + 9 * elastic.membranes.len());
    let inv_h2 = 1.0 / (h as f64 * h as f64);
    for i in 0..n {
        diag[i] = if free[i] {
            mass[i] as f64 * inv_h2
        } else {
            1.0
        };
    }
    let mut add = |a: u32, b: u32, v: f64, trip: &mut Vec<Triplet<usize, usize, f64>>| {
        let (a, b) = (a as usize, b as usize);
        if !(free[a] && free[b]) {
            return;
        }
        if a == b {
            diag[a] += v;
        } else {
            trip.push(Triplet::new(a.max(b), a.min(b), v));
        }
    };
    let rate = (m.shear_damping / h) as f64;
    for t in &elastic.membranes {
        let ks = (m.stretch * t.area * t.ks) as f64;
        let kg = (m.shear * t.area * t.kg * SHEAR_BOUND) as f64 * (1.0 + rate);
        let w = ks + kg;
        for a in 0..3 {
            for b in 0..3 {
                let v = w * (t.c[a] as f64 * t.c[b] as f64 + t.d[a] as f64 * t.d[b] as f64);
                if a >= b {
                    add(t.v[a], t.v[b], v, &mut trip);
                }
            }
        }
    }
    for bc in &elastic.bends {
        let kb = (m.bending * bc.weight) as f64;
        for a in 0..4 {
            for b in 0..=a {
                add(
                    bc.v[a],
                    bc.v[b],
                    kb * bc.k[a] as f64 * bc.k[b] as f64,
                    &mut trip,
                );
            }
        }
    }
    for (i, &d) in diag.iter().enumerate() {
        trip.push(Triplet::new(i, i, d));
    }
    trip
}

fn factor(n: usize, trip: Vec<Triplet<usize, usize, f64>>) -> Option<Factor> {
    let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).ok()?;
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
        ..Default::default()
    };
    let sym =
        factorize_symbolic_cholesky(a.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)
            .ok()?;
    let val = vec![0.0f64; sym.len_val()];
    let mem =
        MemBuffer::try_new(sym.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()))
            .ok()?;
    let SymbolicCholeskyRaw::Simplicial(simplicial) = sym.raw() else {
        return None;
    };
    let c = simplicial.factor();
    let (col_ptr, row) = (c.col_ptr(), c.row_idx());
    let fwd: Vec<u32> = match sym.perm() {
        Some(p) => p.arrays().0.iter().map(|&i| i as u32).collect(),
        None => (0..n as u32).collect(),
    };
    // Each column: its diagonal first (kept as its reciprocal), then the rest.
    let mut by_col = Strict {
        ptr: vec![0],
        ..Strict::default()
    };
    for j in 0..n {
        let (k, end) = (col_ptr[j], col_ptr[j + 1]);
        if k >= end || row[k] != j {
            return None;
        }
        by_col.idx.extend(row[k + 1..end].iter().map(|&i| i as u32));
        by_col.ptr.push(by_col.idx.len());
    }
    by_col.val = vec![0.0; by_col.idx.len()];
    let mut lower = Vec::with_capacity(a.compute_nnz());
    let mut diag_at = vec![usize::MAX; n];
    let mut at = 0;
    for j in 0..n {
        let rows = a.row_idx_of_col_raw(j);
        let vals = a.val_of_col(j);
        for (&i, &v) in rows.iter().zip(vals) {
            lower.push((i as u32, j as u32, v));
            if i == j {
                diag_at[j] = at;
            }
            at += 1;
        }
    }
    if diag_at.contains(&usize::MAX) {
        return None;
    }
    let mut f = Factor {
        n,
        inv_diag: vec![0.0; n],
        by_col,
        fwd,
        lower,
        stiff: Vec::new(),
        numeric: Numeric {
            sym,
            a,
            diag_at,
            val,
            mem,
        },
    };
    f.refactor(&[]).then_some(f)
}

impl Factor {
    /// Factors `L` again with its diagonal times `1 + STIFFEN` at the vertices `stiff`
    /// marks (the symbolic factorisation is kept: the pattern does not change). Returns
    /// false, leaving the factor unusable, when that fails.
    fn refactor(&mut self, stiff: &[bool]) -> bool {
        self.stiff.clear();
        self.stiff.extend_from_slice(stiff);
        let nm = &mut self.numeric;
        // `lower` lists `L`'s values in the order `a` keeps them.
        let vals = nm.a.val_mut();
        for (v, l) in vals.iter_mut().zip(&self.lower) {
            *v = l.2;
        }
        for (j, _) in stiff.iter().enumerate().take(self.n).filter(|(_, s)| **s) {
            let d = nm.diag_at[j];
            vals[d] += STIFFEN * self.lower[d].2;
        }
        let ok = nm
            .sym
            .factorize_numeric_llt(
                &mut nm.val,
                nm.a.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut nm.mem),
                Default::default(),
            )
            .is_ok();
        let SymbolicCholeskyRaw::Simplicial(simplicial) = nm.sym.raw() else {
            return false;
        };
        let col_ptr = simplicial.factor().col_ptr();
        let mut ok = ok;
        for j in 0..self.n {
            let (k, end) = (col_ptr[j], col_ptr[j + 1]);
            let d = nm.val[k];
            ok &= d > 0.0 && d.is_finite();
            self.inv_diag[j] = (1.0 / d) as f32;
            let out = &mut self.by_col.val[self.by_col.ptr[j]..self.by_col.ptr[j + 1]];
            for (o, &v) in out.iter_mut().zip(&nm.val[k + 1..end]) {
                *o = v as f32;
                ok &= v.is_finite();
            }
        }
        ok
    }
}

impl GlobalStep {
    /// Makes sure a factor for these elements and step is ready or under way: factored
    /// here the first time (nothing to step with otherwise), in the background after
    /// that. `version` changes whenever the elements or the free vertices do.
    pub fn prepare(
        &mut self,
        elastic: &Elastic,
        mass: &[f32],
        free: &[bool],
        h: f32,
        m: &Material,
        version: u64,
    ) {
        if let Some(job) = self.pending.take_if(|j| j.is_finished())
            && let Ok(Some(f)) = job.join()
        {
            self.factor = Some(f);
        }
        let key = (h.to_bits(), mass.len(), version);
        if self.key == Some(key) {
            return;
        }
        if self.pending.is_some() {
            // The last request is still being factored; ask again when it is done.
            return;
        }
        self.key = Some(key);
        let n = mass.len();
        let trip = assemble(elastic, mass, free, h, m);
        if self.factor.is_none() {
            self.factor = factor(n, trip);
        } else {
            self.pending = Some(std::thread::spawn(move || factor(n, trip)));
        }
    }

    /// The step `-L^-1 g` into `out`, each vertex `i` kept to the directions its
    /// projector `filter[i]` passes (`None`: all): the minimiser of the quadratic model
    /// `g . d + d^T L d / 2` over those directions, by conjugate gradients preconditioned
    /// with the factor (Baraff and Witkin 1998's filtered PCG). Without filters that is one
    /// solve. Vertices past the factor's (new since it was built) do not move. Returns
    /// false when there is no factor.
    pub fn solve(
        &mut self,
        g: &[Vec3],
        free: &[bool],
        filter: &[Option<Mat3>],
        iterations: usize,
        out: &mut [Vec3],
    ) -> bool {
        let Some(f) = &mut self.factor else {
            return false;
        };
        let n = f.n;
        let k = n.min(g.len()).min(out.len());
        // Every few steps, stiffen the vertices the filter held still since the last time.
        self.seen.resize(n, false);
        for i in 0..k {
            self.seen[i] |= free[i] && filter.get(i).is_some_and(|s| *s == Some(Mat3::ZERO));
        }
        self.since += 1;
        if self.since >= STIFFEN_EVERY {
            if f.stiff != self.seen && !f.refactor(&self.seen) && !f.refactor(&[]) {
                // Factored afresh at the next `prepare`.
                self.factor = None;
                self.key = None;
                return false;
            }
            self.seen.iter_mut().for_each(|s| *s = false);
            self.since = 0;
        }
        let f = &*f;
        let w = &mut self.work;
        for v in [&mut w.x, &mut w.r, &mut w.z, &mut w.p, &mut w.q] {
            v.clear();
            v.resize(n, DVec3::ZERO);
        }
        let y = &mut self.y;
        let project = |i: usize, v: DVec3| -> DVec3 {
            match filter.get(i).copied().flatten() {
                Some(s) => s.as_dmat3() * v,
                None => v,
            }
        };
        for i in 0..k {
            if free[i] {
                w.r[i] = project(i, -g[i].as_dvec3());
            }
        }
        let precondition = |r: &[DVec3], z: &mut [DVec3], y: &mut Vec<Vec3A>| {
            f.solve(r, y, z);
            for (i, v) in z.iter_mut().enumerate() {
                *v = if i < k && free[i] {
                    project(i, *v)
                } else {
                    DVec3::ZERO
                };
            }
        };
        precondition(&w.r, &mut w.z, y);
        w.p.clone_from(&w.z);
        let mut rho: f64 = w.r.iter().zip(&w.z).map(|(a, b)| a.dot(*b)).sum();
        let any_filter = filter.iter().take(k).any(|s| s.is_some());
        let rho0 = rho;
        for it in 0..iterations.max(1) {
            if it > 0 && (rho.is_nan() || rho <= 1e-8 * rho0) {
                break;
            }
            // q = S L p
            w.q.iter_mut().for_each(|q| *q = DVec3::ZERO);
            for &(r, c, v) in &f.lower {
                let (r, c) = (r as usize, c as usize);
                w.q[r] += w.p[c] * v;
                if r != c {
                    w.q[c] += w.p[r] * v;
                }
            }
            for i in 0..n {
                w.q[i] = if i < k && free[i] {
                    project(i, w.q[i])
                } else {
                    DVec3::ZERO
                };
            }
            let pq: f64 = w.p.iter().zip(&w.q).map(|(a, b)| a.dot(*b)).sum();
            if pq.is_nan() || pq <= 0.0 {
                break;
            }
            let alpha = rho / pq;
            for i in 0..n {
                w.x[i] += w.p[i] * alpha;
                w.r[i] -= w.q[i] * alpha;
            }
            if !any_filter {
                break;
            }
            precondition(&w.r, &mut w.z, y);
            let next: f64 = w.r.iter().zip(&w.z).map(|(a, b)| a.dot(*b)).sum();
            let beta = next / rho;
            rho = next;
            for i in 0..n {
                w.p[i] = w.z[i] + w.p[i] * beta;
            }
        }
        for (i, o) in out.iter_mut().enumerate() {
            *o = if i < k { w.x[i].as_vec3() } else { Vec3::ZERO };
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factor's own solve inverts `L`: `L z = r` for a matrix whose ordering permutes
    /// its rows (a ring of springs with cross links, so the fill-reducing order is not the
    /// identity), to the single precision it is kept in.
    #[test]
    fn the_factor_solves_its_matrix() {
        let n = 60;
        let mut trip = Vec::new();
        for i in 0..n {
            trip.push(Triplet::new(i, i, 5.0 + (i % 7) as f64));
            let j = (i + 1) % n;
            trip.push(Triplet::new(i.max(j), i.min(j), -1.0));
            let k = (i * 17 + 5) % n;
            if k != i {
                trip.push(Triplet::new(i.max(k), i.min(k), -0.5));
            }
        }
        let f = factor(n, trip).expect("positive definite");
        assert!(
            f.fwd.iter().enumerate().any(|(i, &p)| p as usize != i),
            "the test needs a permuting order"
        );
        let r: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(i as f64, (i * i % 13) as f64 - 6.0, 1.0))
            .collect();
        let mut z = vec![DVec3::ZERO; n];
        f.solve(&r, &mut Vec::new(), &mut z);
        let lz = product(&f, &z);
        for i in 0..n {
            assert!(
                (lz[i] - r[i]).length() < 1e-5 * (1.0 + r[i].length()),
                "row {i}: {} vs {}",
                lz[i],
                r[i]
            );
        }
    }

    /// `L` of a square cloth of springs, `m` vertices a side: inertia `1` on the diagonal,
    /// springs of stiffness `k` to the four neighbours.
    fn sheet(m: usize, k: f64) -> Vec<Triplet<usize, usize, f64>> {
        let mut diag = vec![1.0; m * m];
        let mut trip = Vec::new();
        for y in 0..m {
            for x in 0..m {
                let i = y * m + x;
                for j in [(x + 1 < m).then(|| i + 1), (y + 1 < m).then(|| i + m)]
                    .into_iter()
                    .flatten()
                {
                    trip.push(Triplet::new(j, i, -k));
                    diag[i] += k;
                    diag[j] += k;
                }
            }
        }
        trip.extend(diag.iter().enumerate().map(|(i, &d)| Triplet::new(i, i, d)));
        trip
    }

    fn product(f: &Factor, d: &[DVec3]) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; d.len()];
        for &(i, j, v) in &f.lower {
            let (i, j) = (i as usize, j as usize);
            out[i] += d[j] * v;
            if i != j {
                out[j] += d[i] * v;
            }
        }
        out
    }

    /// Factored again with some diagonals stiffened, the factor solves that matrix, and
    /// factored again with none, `L` itself.
    #[test]
    fn a_stiffened_factor_solves_the_stiffened_matrix() {
        let n = 100;
        // (To the single precision the factor is kept in.)
        let mut f = factor(n, sheet(10, 50.0)).expect("positive definite");
        let stiff: Vec<bool> = (0..n).map(|i| i % 3 == 0).collect();
        let r: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(1.0, (i % 7) as f64 - 3.0, (i % 5) as f64))
            .collect();
        let mut z = vec![DVec3::ZERO; n];
        let mut residual = |f: &Factor, stiffened: bool| {
            f.solve(&r, &mut Vec::new(), &mut z);
            let mut lz = product(f, &z);
            for &(i, j, v) in &f.lower {
                if i == j && stiffened && stiff[i as usize] {
                    lz[i as usize] += z[i as usize] * (v * STIFFEN);
                }
            }
            (0..n)
                .map(|i| (lz[i] - r[i]).length() / (1.0 + r[i].length()))
                .fold(0.0, f64::max)
        };
        assert!(f.refactor(&stiff));
        assert!(residual(&f, true) < 1e-4, "stiffened");
        let other = residual(&f, false);
        assert!(other > 1e-2, "the stiffening changed nothing: {other}");
        assert!(f.refactor(&[]));
        let back = residual(&f, false);
        assert!(back < 1e-4, "back to L: {back}");
    }

    /// With a band of vertices held still by the filter, the conjugate gradient
    /// preconditioned with the factor stiffened there lowers the step's quadratic model
    /// much further in two steps than with `L`'s own factor, and both reach the same step.
    #[test]
    fn stiffening_the_held_vertices_speeds_the_filtered_solve() {
        let m = 24;
        let n = m * m;
        let free = vec![true; n];
        let filter: Vec<Option<Mat3>> = (0..n).map(|i| (i / m < 6).then_some(Mat3::ZERO)).collect();
        let g: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(0.1 * (i % 3) as f32, -1.0, 0.05 * (i % 4) as f32))
            .collect();
        let model = |f: &Factor, d: &[Vec3]| -> f64 {
            let d: Vec<DVec3> = d.iter().map(|v| v.as_dvec3()).collect();
            let ld = product(f, &d);
            (0..n)
                .map(|i| g[i].as_dvec3().dot(d[i]) + 0.5 * d[i].dot(ld[i]))
                .sum()
        };
        let run = |calls: usize, iterations: usize| {
            let mut gs = GlobalStep {
                factor: factor(n, sheet(m, 400.0)),
                ..GlobalStep::default()
            };
            let mut out = vec![Vec3::ZERO; n];
            for _ in 0..calls {
                assert!(gs.solve(&g, &free, &filter, iterations, &mut out));
            }
            let f = gs.factor.as_ref().unwrap();
            assert_eq!(
                f.stiff.iter().filter(|s| **s).count() > 0,
                calls >= STIFFEN_EVERY
            );
            (model(f, &out), out)
        };
        let (best, exact) = run(1, 200);
        let (plain, _) = run(1, 2);
        let (stiffened, _) = run(STIFFEN_EVERY, 2);
        let (_, exact_stiffened) = run(STIFFEN_EVERY, 200);
        assert!(best < 0.0);
        assert!(
            stiffened - best < 0.1 * (plain - best),
            "two steps left {} stiffened against {} plain (of {best})",
            stiffened - best,
            plain - best
        );
        for i in 0..n {
            assert!(
                (exact[i] - exact_stiffened[i]).length() < 1e-4,
                "vertex {i}"
            );
            if i / m < 6 {
                assert_eq!(exact[i], Vec3::ZERO);
            }
        }
    }
}
