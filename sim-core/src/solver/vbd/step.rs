//! Vertex Block Descent (Chen, Macklin et al. 2024) with penetration-free contact.
//!
//! Each step of `h` minimises the incremental potential of backward Euler
//! `sum m/(2h^2) |x - y|^2 + E(x)`, `y = x + h v + h^2 g`, by Gauss-Seidel over vertices:
//! each vertex in turn takes one Newton step on its own 3 x 3 block with the others held.
//! Its fixed point is the implicit step's, so a settled cloth rests at the energy's
//! equilibrium whatever the iteration count (the implicit model is the judge of that).
//!
//! Once per frame the proximity search lists the pairs of primitives that can meet
//! (`collision::proximity`), and every position a vertex takes passes the guard, which
//! keeps it in its motion box and on its side of its pairs: nothing crosses, at any
//! speed and any stiffness. Contact energy (penalty and friction) acts within the
//! contact distance, which is the material's thickness.

use glam::{Mat3, Vec3};

use super::contact::{CONTACT_STIFFNESS, ContactTerms};
use super::elastic::{Elastic, Stiffness};
use super::global::GlobalStep;
use crate::collision::Body;
use crate::collision::proximity::{
    Aabb, ClothView, Guarded, Proximity, ProximityParams, constrain, unique_edges,
};
use crate::solver::material::Material;
use crate::solver::model::{ContactStats, Drive, Environment};
use crate::solver::motion::Motion;
use crate::solver::state::Cloth;

/// Default iterations per step (each a global step and a Gauss-Seidel sweep).
pub const DEFAULT_ITERATIONS: usize = 4;
/// Default conjugate-gradient iterations per global step (`global.rs`). With the factor
/// stiffened where the filter holds vertices still, 5 do about what 8 did without (frames
/// 0.8-1.0x as long; the cube, the dress and GarmentCode's garments weld and cover as
/// before). With 4, GarmentCode's jumpsuit slid off the mannequin in each of three runs
/// (docs/models.md, Speed).
pub const DEFAULT_CG_ITERATIONS: usize = 5;

/// The least separation every pair keeps, m.
const SEPARATION: f32 = 1e-4;

#[derive(Clone, Debug)]
pub struct Vbd {
    pub(super) material: Material,
    pub(super) elastic: Elastic,
    tris: Vec<[u32; 3]>,
    edges: Vec<[u32; 2]>,
    /// Each vertex's place in the pattern.
    pattern: Vec<Vec3>,
    /// Neighbours over a weld that the pattern places apart (contact leaves them out).
    bridged: Vec<Vec<u32>>,
    free: Vec<bool>,
    pub(super) prox: Proximity,
    boxes: Vec<Aabb>,
    /// The motion boxes' strays, and who is held.
    motion: Motion,
    xt: Vec<Vec3>,
    y: Vec<Vec3>,
    normals: Vec<Vec3>,
    area: Vec<f32>,
    has_stitch: Vec<bool>,
    /// Each vertex's hold in the drive's holds (`u32::MAX`: none).
    hold_of: Vec<u32>,
    /// The mean rest length of the live mesh's edges, m.
    mean_edge: f32,
    /// Iterations per step: each a global step (when on) and `sweeps` Gauss-Seidel sweeps.
    pub iterations: usize,
    pub sweeps: usize,
    pub global_steps: bool,
    /// Conjugate-gradient iterations of each global step while vertices touch the body.
    pub cg_iterations: usize,
    /// The contact search and its guard (on; off only to test the elastic solve alone:
    /// then the cloth passes through everything).
    pub contact: bool,
    global: GlobalStep,
    /// Bumped when the elements or the free vertices change (the global step refactors).
    version: u64,
    /// The step length of the current step, s.
    h: f32,
    force: Vec<Vec3>,
    step: Vec<Vec3>,
    /// Each vertex's directions the global step may move it in (`None`: all): a vertex
    /// touching the body or floor does not move along the contact's normal in it, nor at
    /// all while friction holds it (`contact_filter`).
    filter: Vec<Option<Mat3>>,
    /// Scratch for the filters: each vertex's contact push from the body or floor, its
    /// size and its (push-weighted) direction.
    push: Vec<(f32, Vec3)>,
    /// Each vertex's acceleration along gravity over the last step, m/s^2.
    accel: Vec<f32>,
    pub threads: usize,
    pub stats: ContactStats,
}

impl Vbd {
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        let mut v = Self {
            material: *material,
            elastic: Elastic::default(),
            tris: Vec::new(),
            edges: Vec::new(),
            pattern: Vec::new(),
            bridged: Vec::new(),
            free: Vec::new(),
            prox: Proximity::default(),
            boxes: Vec::new(),
            motion: Motion::default(),
            xt: Vec::new(),
            y: Vec::new(),
            normals: Vec::new(),
            area: Vec::new(),
            has_stitch: Vec::new(),
            hold_of: Vec::new(),
            mean_edge: 0.0,
            iterations: DEFAULT_ITERATIONS,
            sweeps: 1,
            global_steps: true,
            cg_iterations: DEFAULT_CG_ITERATIONS,
            contact: true,
            global: GlobalStep::default(),
            version: 0,
            h: 0.0,
            force: Vec::new(),
            step: Vec::new(),
            filter: Vec::new(),
            push: Vec::new(),
            accel: Vec::new(),
            threads: 1,
            stats: ContactStats::default(),
        };
        v.rebuild(cloth);
        v
    }

    /// Rebuilds everything that depends on the live mesh (after an edit or a new
    /// material); what the vertices strayed last frame is kept.
    pub(super) fn rebuild(&mut self, cloth: &Cloth) {
        let n = cloth.len();
        self.elastic = Elastic::new(cloth, &self.material);
        self.tris = cloth.live.triangles();
        self.edges = unique_edges(&self.tris);
        self.mean_edge = cloth.live.mean_rest_side();
        self.pattern = cloth.live.pattern_places(n);
        let exclusion = 2.0 * self.material.thickness + 2.0 * self.mean_edge;
        self.bridged = cloth.live.bridged_neighbours(n, &self.pattern, exclusion);
        self.area = vec![0.0; n];
        for (_, t) in cloth.live.iter() {
            let a = t.rest_area() / 3.0;
            for k in 0..3 {
                self.area[t.v[k] as usize] += a;
            }
        }
        self.refresh_free(cloth);
        self.motion.resize(n);
        self.has_stitch.resize(n, false);
        self.normals.resize(n, Vec3::Y);
        // The pairs referred to the old mesh.
        self.prox.clear();
        self.version += 1;
    }

    pub(super) fn refresh_free(&mut self, cloth: &Cloth) {
        self.version += 1;
        self.free = (0..cloth.len())
            .map(|i| cloth.inv_mass[i] > 0.0 && cloth.live.vertex_alive(i as u32))
            .collect();
    }

    fn params(&self, env: &Environment) -> ProximityParams {
        let r = self.material.thickness;
        ProximityParams {
            radius: r,
            delta: SEPARATION,
            // As `rebuild`'s `bridged`.
            rest_exclusion: 2.0 * r + 2.0 * self.mean_edge,
            floor: env.floor,
            threads: self.threads,
        }
    }

    /// One frame of `substeps` steps.
    #[inline(never)]
    pub(super) fn frame(
        &mut self,
        cloth: &mut Cloth,
        body: Option<&Body>,
        env: &Environment,
        substeps: usize,
        drive: &mut Drive<'_, '_>,
    ) {
        let n = cloth.len();
        if self.free.len() != n {
            self.rebuild(cloth);
        }
        let h = env.frame_dt / substeps as f32;
        self.h = h;
        self.has_stitch.iter_mut().for_each(|s| *s = false);
        for s in drive.stitches {
            for v in [s.a, s.b] {
                if let Some(f) = self.has_stitch.get_mut(v as usize) {
                    *f = true;
                }
            }
        }
        self.hold_of.clear();
        self.hold_of.resize(n, u32::MAX);
        for (k, hd) in drive.holds.iter().enumerate() {
            if let Some(o) = self.hold_of.get_mut(hd.vertex as usize) {
                *o = k as u32;
            }
        }
        drive.grip.begin_frame();
        if self.global_steps {
            self.global.prepare(
                &self.elastic,
                &cloth.mass,
                &self.free,
                h,
                &self.material,
                self.version,
            );
        }
        self.stats = ContactStats::default();
        let groups = self.search_groups(cloth, env, substeps);
        let mut k = 0;
        for g in 0..groups {
            let steps = (g + 1) * substeps / groups - g * substeps / groups;
            self.search(cloth, body, env, drive, steps as f32 * h);
            for _ in 0..steps {
                drive.grip.follow(k, substeps, &mut *drive.pen, cloth, body);
                self.substep(cloth, env, h, drive);
                k += 1;
            }
            self.motion.note_stray(cloth, &self.free);
        }
        self.motion.end_frame(drive);
    }

    /// How many searches this frame takes ([`Motion::searches`]).
    pub(super) fn search_groups(&self, cloth: &Cloth, env: &Environment, substeps: usize) -> usize {
        Motion::searches(cloth, &self.free, self.mean_edge, env, substeps, 0)
    }

    /// The proximity search for the next `span` seconds: motion boxes, then pairs.
    fn search(
        &mut self,
        cloth: &Cloth,
        body: Option<&Body>,
        env: &Environment,
        drive: &Drive<'_, '_>,
        span: f32,
    ) {
        self.motion
            .boxes(&mut self.boxes, cloth, &self.free, env, drive, span);
        let params = self.params(env);
        let t0 = std::time::Instant::now();
        if !self.contact {
            self.prox.clear();
            for b in &mut self.boxes {
                *b = b.grown(1e3);
            }
        } else {
            self.prox.detect(
                &ClothView {
                    x: &cloth.x,
                    boxes: &self.boxes,
                    tris: &self.tris,
                    edges: &self.edges,
                    pattern: &self.pattern,
                    bridged: &self.bridged,
                    free: &self.free,
                },
                body,
                &params,
            );
        }
        self.stats.pairs = self.prox.counts;
        self.stats.detect_us += t0.elapsed().as_micros() as u64;
        self.update_normals(cloth);
    }

    fn substep(&mut self, cloth: &mut Cloth, env: &Environment, h: f32, drive: &mut Drive<'_, '_>) {
        let n = cloth.len();
        let m = self.material;
        let inv_h2 = 1.0 / (h * h);
        self.xt.clone_from(&cloth.x);
        self.y.clear();
        self.y
            .extend((0..n).map(|i| cloth.x[i] + cloth.v[i] * h + env.gravity * (h * h)));
        let stiffness = Stiffness::of(&m, h);
        let contact = ContactTerms {
            radius: m.thickness,
            stiffness: CONTACT_STIFFNESS,
            friction: m.friction,
        };
        // The pinch's springs this step: each held vertex to its goal, all scaled so
        // their pull stays within the force limit.
        let grip = drive.grip.pinch.as_ref().map(|p| {
            let k = p.stiffness / p.held.len().max(1) as f32;
            let pull = self.grip_pull(p, &cloth.x, k);
            let scale = match p.force_limit {
                Some(limit) if pull.length() > limit => limit / pull.length(),
                _ => 1.0,
            };
            (k * scale, scale < 1.0)
        });
        // Start from the inertial prediction with as much of gravity as the vertex felt
        // last step (VBD's adaptive initialisation: a cloth at rest on the body starts
        // where it is, not a step's fall below it), meeting contacts inelastically.
        let g_len = env.gravity.length();
        let g_dir = env.gravity.normalize_or_zero();
        self.accel.resize(n, 0.0);
        for i in 0..n {
            if !self.free[i] {
                continue;
            }
            let a = self.accel[i].clamp(0.0, g_len);
            let init = cloth.x[i] + cloth.v[i] * h + g_dir * (a * h * h);
            let target = self.inelastic(i, init, &cloth.x, m.thickness);
            self.guarded(i, target, &mut cloth.x);
        }
        let grip_k = grip.map(|(k, _)| k);
        for _ in 0..self.iterations {
            if self.global_steps {
                self.global_step(cloth, &stiffness, &contact, grip_k, drive);
            }
            for _ in 0..self.sweeps {
                self.sweep(cloth, &stiffness, &contact, grip_k, drive, inv_h2);
            }
        }
        // Velocities, with the material's mass damping and the air's drag on the normal
        // velocity (as in the XPBD model).
        let damp = (-m.damping * h).exp();
        for i in 0..n {
            if !self.free[i] {
                cloth.v[i] = Vec3::ZERO;
                continue;
            }
            let mut v = (cloth.x[i] - self.xt[i]) * (damp / h);
            let nrm = self.normals[i];
            let kd = m.drag * self.area[i] * cloth.inv_mass[i] * h;
            v -= nrm * (v.dot(nrm) * kd / (1.0 + kd));
            self.accel[i] = ((v - cloth.v[i]) / h).dot(g_dir);
            cloth.v[i] = v;
        }
        if let (Some((k, limited)), Some(p)) = (grip, &drive.grip.pinch) {
            let force = self.grip_pull(p, &cloth.x, k);
            drive.grip.forces.push(force);
            if limited {
                drive.grip.limited += 1;
            }
        }
    }

    /// One Gauss-Seidel sweep: each vertex takes a Newton step on its own block, the
    /// others held, through the guard.
    fn sweep(
        &mut self,
        cloth: &mut Cloth,
        stiffness: &Stiffness,
        contact: &ContactTerms,
        grip_k: Option<f32>,
        drive: &Drive<'_, '_>,
        inv_h2: f32,
    ) {
        for i in 0..cloth.len() {
            if !self.free[i] {
                continue;
            }
            let x = &cloth.x;
            let mi = cloth.mass[i] * inv_h2;
            let mut f = (self.y[i] - x[i]) * mi;
            let mut hess = Mat3::from_diagonal(Vec3::splat(mi));
            self.elastic
                .add_vertex(i, x, &self.xt, stiffness, &mut f, &mut hess);
            contact.add_vertex(i, &self.prox, x, &self.xt, &mut f, &mut hess);
            if let (Some(k), Some(p)) = (grip_k, &drive.grip.pinch)
                && self.motion.held[i] != u32::MAX
            {
                let off = p.held[self.motion.held[i] as usize].1;
                f += (p.target + off - x[i]) * k;
                hess += Mat3::from_diagonal(Vec3::splat(k));
            }
            if self.has_stitch[i] {
                stitch_terms(i, x, drive.stitches, &mut f, &mut hess);
            }
            if let Some(hd) = drive.holds.get(self.hold_of[i] as usize) {
                hold_terms(hd, x[i], &mut f, &mut hess);
            }
            let det = hess.determinant();
            if !(det.is_finite() && det.abs() > 1e-30) {
                continue;
            }
            let dx = hess.inverse() * f;
            if dx.is_finite() {
                let target = x[i] + dx;
                self.guarded(i, target, &mut cloth.x);
            }
        }
    }

    /// The global step (`global.rs`): every vertex moves by `-L^-1 grad`, each through the
    /// guard.
    fn global_step(
        &mut self,
        cloth: &mut Cloth,
        stiffness: &Stiffness,
        contact: &ContactTerms,
        grip_k: Option<f32>,
        drive: &Drive<'_, '_>,
    ) {
        let n = cloth.len();
        let inv_h2 = 1.0 / (self.h * self.h);
        // The force (minus the gradient of the step's potential) on every vertex.
        self.force.clear();
        self.force
            .extend((0..n).map(|i| (self.y[i] - cloth.x[i]) * (cloth.mass[i] * inv_h2)));
        self.elastic
            .add_forces(&cloth.x, &self.xt, stiffness, &mut self.force);
        // Contact stays out: `L` knows nothing of it, and the sum of many contacts'
        // pushes would throw the whole cloth (its lowest mode is only `M/h^2` stiff). The
        // sweeps resolve contact, where each vertex's block has its contact's stiffness.
        if let (Some(k), Some(p)) = (grip_k, &drive.grip.pinch) {
            for &(v, off) in &p.held {
                if let Some(f) = self.force.get_mut(v as usize) {
                    *f += (p.target + off - cloth.x[v as usize]) * k;
                }
            }
        }
        for i in 0..n {
            if self.has_stitch[i] {
                let mut hess = Mat3::ZERO;
                stitch_terms(i, &cloth.x, drive.stitches, &mut self.force[i], &mut hess);
            }
        }
        for hd in drive.holds {
            let i = hd.vertex as usize;
            if let (Some(f), Some(&x)) = (self.force.get_mut(i), cloth.x.get(i)) {
                let mut hess = Mat3::ZERO;
                hold_terms(hd, x, f, &mut hess);
            }
        }
        // `solve` takes the gradient.
        for f in &mut self.force {
            *f = -*f;
        }
        self.step.resize(n, Vec3::ZERO);
        self.contact_filter(&cloth.x, &cloth.mass, contact);
        let cg = self.cg_iterations;
        if !self
            .global
            .solve(&self.force, &self.free, &self.filter, cg, &mut self.step)
        {
            return;
        }
        for i in 0..n {
            if self.free[i] && self.step[i].is_finite() {
                let target = cloth.x[i] + self.step[i];
                self.guarded(i, target, &mut cloth.x);
            }
        }
    }

    /// The global step's filters: each cloth vertex within the contact distance of the
    /// body or floor keeps still along the contact's normal (the sweeps, which know the
    /// contact's stiffness, move it there), and still in every direction while friction
    /// holds it: when the force it would take to keep it where the step began (inertia
    /// included) lies, along the surface, within the friction cone of the contact's push
    /// (Baraff and Witkin 1998 filter sticking contacts whole). Otherwise the global step,
    /// which knows no friction, would slide it freely, and a cloth pulled at one corner
    /// would skate over the floor.
    fn contact_filter(&mut self, x: &[Vec3], mass: &[f32], contact: &ContactTerms) {
        let r = self.material.thickness;
        self.filter.clear();
        self.filter.resize(x.len(), None);
        self.push.clear();
        self.push.resize(x.len(), (0.0, Vec3::ZERO));
        for pair in &self.prox.pairs {
            if pair.body_bound == f32::NEG_INFINITY || !pair.energy {
                continue;
            }
            let gap = pair.gap(x);
            if gap >= r {
                continue;
            }
            for k in 0..4 {
                if pair.v[k] == crate::collision::proximity::NONE || pair.w[k].abs() < 0.25 {
                    continue;
                }
                let v = pair.v[k] as usize;
                let lambda = contact.stiffness * (contact.radius - gap) * pair.w[k].abs();
                let (sum, dir) = &mut self.push[v];
                *sum += lambda;
                *dir += pair.n * lambda;
                let s = self.filter[v].get_or_insert(Mat3::IDENTITY);
                let d = *s * pair.n;
                let len2 = d.length_squared();
                if len2 > 0.1 {
                    let dd = Mat3::from_cols(d * d.x, d * d.y, d * d.z) * (1.0 / len2);
                    *s -= dd;
                }
            }
        }
        let inv_h2 = 1.0 / (self.h * self.h);
        for (i, s) in self.filter.iter_mut().enumerate() {
            let (lambda, dir) = self.push[i];
            let Some(n) = dir.try_normalize() else {
                continue;
            };
            if s.is_none() {
                continue;
            }
            // `force` holds the gradient at `x` here; at the step's start the inertia
            // pulls harder by `m/h^2 (x - xt)`.
            let hold = -self.force[i] + (x[i] - self.xt[i]) * (mass[i] * inv_h2);
            if n.dot(hold) > 0.0 {
                // Pulled off the surface: it needs no push, and lets go (a corner lifted
                // from the floor peels the cloth off it).
                *s = None;
                continue;
            }
            if contact.friction <= 0.0 {
                continue;
            }
            let along = hold - n * n.dot(hold);
            let limit = contact.friction * lambda;
            if along.length() <= limit {
                *s = Some(Mat3::ZERO);
            } else {
                // Sliding: kinetic friction against the way it is pushed.
                self.force[i] += along.normalize_or_zero() * limit;
            }
        }
    }

    /// The pinch's total pull on the free vertices it holds, springs of stiffness `k`.
    fn grip_pull(&self, p: &crate::solver::pinch::Pinch, x: &[Vec3], k: f32) -> Vec3 {
        p.held
            .iter()
            .filter(|(v, _)| self.free.get(*v as usize) == Some(&true))
            .map(|&(v, off)| (p.target + off - x[v as usize]) * k)
            .sum()
    }

    /// `target` for vertex `i`, raised out of the contacts it would go deeper into (to
    /// the contact distance `r`, or where it is when already closer): a falling vertex
    /// meets the body or another layer without bouncing.
    fn inelastic(&self, i: usize, mut target: Vec3, x: &[Vec3], r: f32) -> Vec3 {
        for &role in self.prox.roles(i) {
            let pair = &self.prox.pairs[(role / 4) as usize];
            let k = (role % 4) as usize;
            let w = pair.w[k];
            if !pair.energy || w.abs() < 0.5 {
                continue;
            }
            let now = pair.gap(x);
            let then = now + w * pair.n.dot(target - x[i]);
            let floor = now.min(r);
            if then < floor {
                target += pair.n * ((floor - then) / w);
            }
        }
        target
    }

    /// Moves vertex `i` toward `target` as far as the guard allows.
    #[inline]
    fn guarded(&mut self, i: usize, target: Vec3, x: &mut [Vec3]) {
        let (p, how) = constrain(i, target, x, &self.boxes[i], &self.prox);
        match how {
            Guarded::Free => {}
            Guarded::Projected => self.stats.projected += 1,
            Guarded::Shortened => self.stats.shortened += 1,
        }
        x[i] = p;
    }

    fn update_normals(&mut self, cloth: &Cloth) {
        self.normals.iter_mut().for_each(|n| *n = Vec3::ZERO);
        for t in &self.tris {
            let [a, b, c] = t.map(|i| cloth.x[i as usize]);
            let nrm = (b - a).cross(c - a);
            for &i in t {
                self.normals[i as usize] += nrm;
            }
        }
        for nrm in &mut self.normals {
            *nrm = nrm.normalize_or(Vec3::Y);
        }
    }
}

/// Vertex `i`'s seam stitches: zero-length springs to the other end, each pulling no
/// harder than its limit.
fn stitch_terms(
    i: usize,
    x: &[Vec3],
    stitches: &[crate::solver::stitch::Stitch],
    f: &mut Vec3,
    hess: &mut Mat3,
) {
    let k = crate::solver::stitch::STITCH_STIFFNESS;
    for s in stitches {
        let other = if s.a as usize == i {
            s.b
        } else if s.b as usize == i {
            s.a
        } else {
            continue;
        };
        let Some(&xo) = x.get(other as usize) else {
            continue;
        };
        let pull = (xo - x[i]) * k;
        let len = pull.length();
        let scale = if len > s.max_force {
            s.max_force / len
        } else {
            1.0
        };
        *f += pull * scale;
        *hess += Mat3::from_diagonal(Vec3::splat(k * scale));
    }
}

/// A held vertex at `x`: past its plane, a spring back onto it along the normal, pulling
/// no harder than its limit.
fn hold_terms(hd: &crate::solver::stitch::Hold, x: Vec3, f: &mut Vec3, hess: &mut Mat3) {
    let k = crate::solver::stitch::HOLD_STIFFNESS;
    let pull = k * hd.past(x);
    if !(pull > 0.0 && pull.is_finite()) {
        return;
    }
    let scale = if pull > hd.max_force {
        hd.max_force / pull
    } else {
        1.0
    };
    let nrm = hd.normal;
    *f += nrm * (pull * scale);
    *hess += Mat3::from_cols(nrm * nrm.x, nrm * nrm.y, nrm * nrm.z) * (k * scale);
}
