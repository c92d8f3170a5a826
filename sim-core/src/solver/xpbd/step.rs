//! The XPBD solver: its state, one frame of substeps, and the order of its passes.

use rustc_hash::FxHashMap as HashMap;

use glam::Vec3;

use super::flutter::Flutter;
use super::groups::{Compliance, Group, Loc, solve_bending, solve_membranes, split_groups};
use super::guard::Guard;
use super::limits::{CoarseScratch, StretchLimits};
use super::settle::Settle;
use super::sewing::SewingWatch;
use super::strain_limit::{credit_moves, limit_membranes};
use super::tethers::{solve_tethers, stretch_limits, tethers};
use crate::collision::contact::StaticFriction;
use crate::collision::{Body, ContactCache};
use crate::solver::constraints::{BendConstraint, Elements, HingeShares, Membrane, elements_of};
use crate::solver::material::Material;
use crate::solver::model::{Drive, Environment, StretchFloor};
use crate::solver::state::Cloth;
use crate::solver::stitch::{hold, stitch};

/// Passes the strain limit makes again after the guard's pass, each over the membranes its
/// full pass there projected, and how far each goes toward the limit. One Gauss-Seidel
/// pass leaves a triangle past the limit where its neighbours' projections pulled its
/// shared corners after its own. Measured on the 64 x 64 drapes, limit 0.2, densities
/// 0.15, 0.15001, 0.15002 (docs/models.md): the mannequin's worst side ended 1.254, 1.249,
/// 1.251x its rest length with none, 1.244, 1.244, 1.246x with two whole ones and 1.233,
/// 1.235, 1.236x with two at 0.3. Whole ones shook vertices below the cube's corners in a
/// two-substep cycle (drape-cube at 7e-6 J; 1e-7 J at 0.3, 1.4e-7 at 0.5, 1.9e-6 at 0.7).
/// Two more in the pass before the guard kept the sewn dress from coming to rest at all.
const LIMIT_PASSES_AGAIN: usize = 2;
/// How far each of those passes goes toward the limit (above).
const LIMIT_AGAIN_RELAX: f32 = 0.3;
/// The membranes in the second half from which the strain limit's pass over the halves
/// takes a second thread. Handing work to a thread costs 36-126 µs on this VM, twice a
/// substep here: on the 64 x 64 mannequin drape (about 4,000 a half) it took the resting
/// frame from 4.7-5.1 to 5.8 ms (two alternating pairs of runs); on the 2 x 8k dress
/// (about 15,000) it saved 1-2 ms.
const LIMIT_PARALLEL_FROM: usize = 8_000;

#[derive(Clone, Debug)]
pub struct Xpbd {
    pub(super) prev: Vec<Vec3>,
    pub(super) normals: Vec<Vec3>,
    /// A third of the area of the triangles around each vertex (for air drag).
    pub(super) area: Vec<f32>,
    pub(super) material: Material,
    /// The hinges' anisotropic shares fitted when the elements were built: hinges an
    /// edit makes take the same.
    pub(super) shares: HingeShares,
    /// (vertex, pin, maximum length) long-range attachments.
    pub(super) tethers: Vec<(u32, u32, f32)>,
    /// Long-range stretch limits, coarse level first (see `limits`), and the inverse
    /// masses they use this frame.
    pub(super) limits: StretchLimits,
    link_w: Vec<f32>,
    coarse: CoarseScratch,
    /// The vertices the strain limit moved before and after the guard's pass, and where
    /// every vertex began the substep (scratch).
    limited: [Vec<u32>; 2],
    /// A bit per vertex, for putting the limit's moved vertices in order (scratch).
    limited_bits: Vec<u64>,
    /// What the strain limit's pass over the second half moved and projected (scratch).
    limited_b: (Vec<u32>, Vec<Membrane>),
    start: Vec<Vec3>,
    /// The static friction the body's contact left unused this substep, which holds back
    /// the limit's moves of the vertices lying on it, and where they were before them.
    friction_left: StaticFriction,
    before_limit: Vec<Vec3>,
    /// Scratch for damping the cloth's flutter once a frame (`flutter`).
    flutter: Flutter,
    /// This frame's least limit on a triangle's stretch (`Drive::stretch_floor`).
    stretch_floor: StretchFloor,
    /// The membranes the strain limit's pass projected, in the whole cloth's indices
    /// (scratch for its passes again).
    active: [Vec<Membrane>; 2],
    /// The vertex range split in two halves, solved side by side, then the constraints
    /// that straddle the split (the third, boundary group). The halves share no vertex, so
    /// the result is the same whether they run on one thread or two.
    pub(super) groups: [Group; 3],
    /// Membranes (by triangle slot) and hinges (by edge key): where each one is.
    pub(super) membrane_loc: Vec<Loc>,
    pub(super) bend_loc: HashMap<u64, Loc>,
    /// Constraints created by edits since the last build, solved after the groups.
    pub(super) extra_membranes: Vec<Membrane>,
    pub(super) extra_bends: Vec<BendConstraint>,
    /// Threads for the halves (1 or 2).
    pub threads: usize,
    /// The cloth's vertex count when the groups were packed: no packed constraint names
    /// a vertex at or past it.
    pub(super) built: usize,
    /// Contact that is never crossed (`guard`, switched on by `Solver::set_guard`);
    /// `None` (the default): the body's contact planes only.
    pub(super) guard: Option<Guard>,
    /// Frames after an edit whose stretch is taken up without becoming speed.
    pub(super) settle: Settle,
    /// Whether the seams' stitches still draw their pairs together (`sewing`).
    sewing: SewingWatch,
}

impl Xpbd {
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        Self::with_limits(cloth, material, None)
    }

    /// As `new`, keeping `limits` (rescaled to the material's strain) when given: after a
    /// material change the lattice, its order and its path lengths stay as they were.
    pub(super) fn with_limits(
        cloth: &Cloth,
        material: &Material,
        limits: Option<StretchLimits>,
    ) -> Self {
        let live = &cloth.live;
        let Elements {
            membranes,
            bends,
            shares,
        } = elements_of(live, material, &cloth.zones);
        let mut area = vec![0.0f32; cloth.len()];
        for m in &membranes {
            for &i in &m.v {
                area[i as usize] += m.area / 3.0;
            }
        }
        let groups = split_groups(cloth.len(), &membranes, &bends, &cloth.inv_mass);
        let mut membrane_loc = vec![Loc::None; live.slots()];
        let mut bend_loc = HashMap::with_capacity_and_hasher(bends.len(), Default::default());
        for (g, group) in groups.iter().enumerate() {
            for (item, m) in group.membranes.iter().enumerate() {
                membrane_loc[m.id as usize] = Loc::Group {
                    group: g as u8,
                    item: item as u32,
                };
            }
            for (item, b) in group.bends.iter().enumerate() {
                bend_loc.insert(
                    b.key,
                    Loc::Group {
                        group: g as u8,
                        item: item as u32,
                    },
                );
            }
        }
        Self {
            prev: cloth.x.clone(),
            normals: vec![Vec3::Y; cloth.len()],
            area,
            material: *material,
            shares,
            tethers: tethers(cloth, material),
            limits: stretch_limits(cloth, material, limits),
            link_w: Vec::new(),
            coarse: CoarseScratch::default(),
            limited: [Vec::new(), Vec::new()],
            limited_bits: Vec::new(),
            limited_b: (Vec::new(), Vec::new()),
            start: Vec::new(),
            friction_left: StaticFriction::default(),
            before_limit: Vec::new(),
            flutter: Flutter::default(),
            stretch_floor: StretchFloor::NONE,
            active: [Vec::new(), Vec::new()],
            groups,
            membrane_loc,
            bend_loc,
            extra_membranes: Vec::new(),
            extra_bends: Vec::new(),
            threads: 1,
            built: cloth.len(),
            guard: None,
            settle: Settle::default(),
            sewing: SewingWatch::default(),
        }
    }

    /// Solves every membrane and hinge once between two passes of the stretch limits: the
    /// two halves (in parallel when `threads > 1`), then the boundary.
    fn solve_constraints(
        &self,
        x: &mut [Vec3],
        prev: &[Vec3],
        w: &[f32],
        k: &Compliance,
        coarse: &mut CoarseScratch,
    ) {
        let mid = self.groups[0].end;
        let lw = &self.link_w[..];
        self.limits.solve_coarse(x, lw, coarse);
        {
            let (xa, xb) = x.split_at_mut(mid);
            let (pa, pb) = prev.split_at(mid);
            let (wa, wb) = w.split_at(mid);
            let [ga, gb, _] = &self.groups;
            if self.threads > 1 && !gb.membranes.is_empty() {
                std::thread::scope(|s| {
                    s.spawn(|| gb.solve(xb, pb, wb, k));
                    ga.solve(xa, pa, wa, k);
                });
            } else {
                ga.solve(xa, pa, wa, k);
                gb.solve(xb, pb, wb, k);
            }
        }
        self.groups[2].solve(x, prev, w, k);
        solve_membranes(&self.extra_membranes, x, prev, w, k);
        if k.bend.is_finite() {
            solve_bending(&self.extra_bends, x, prev, w, (k.bend, k.bend_gamma));
        }
        // The stretch limits once more after the membranes, which undo part of the
        // first pass (on the 64 x 64 mannequin drape with patches, mean / largest strain
        // 0.81% / 0.53 after the membranes only, 0.73% / 0.42 before and after; with
        // node vertices alone and a 24-6-3 lattice, 9.7% and 5.9% mean).
        self.limits.solve_coarse(x, lw, coarse);
    }

    /// The strain limit's pass over every membrane (`strain_limit`): the two halves, the
    /// boundary, then the edits' membranes; then `again` more over the membranes it
    /// projected, each [`LIMIT_AGAIN_RELAX`] of the way. The vertices it moves are added
    /// to `moved`. The two halves in parallel when `threads > 1` and the cloth is large
    /// ([`LIMIT_PARALLEL_FROM`]; they share no vertex, so the cloth and the lists come out
    /// as one thread's): on the sewn 2 x 8k dress at rest about 3,000 triangles are at
    /// their limit, and the pass was a fifth of the frame (`perf`).
    fn limit_strain(&mut self, x: &mut [Vec3], w: &[f32], moved: &mut Vec<u32>, again: usize) {
        let [ga, gb, gc] = &self.groups;
        let mid = ga.end;
        let [active, next] = &mut self.active;
        active.clear();
        let (moved_b, active_b) = &mut self.limited_b;
        moved_b.clear();
        active_b.clear();
        let (wa, wb) = w.split_at(mid);
        let (xa, xb) = x.split_at_mut(mid);
        let floor = self.stretch_floor;
        let whole = (floor, 1.0);
        let mut second =
            || limit_membranes(&gb.membranes, xb, wb, whole, (gb.off, moved_b, active_b));
        if self.threads > 1 && gb.membranes.len() >= LIMIT_PARALLEL_FROM {
            std::thread::scope(|s| {
                s.spawn(second);
                limit_membranes(&ga.membranes, xa, wa, whole, (0, moved, active));
            });
        } else {
            limit_membranes(&ga.membranes, xa, wa, whole, (0, moved, active));
            second();
        }
        moved.extend_from_slice(moved_b);
        active.extend_from_slice(active_b);
        limit_membranes(&gc.membranes, x, w, whole, (0, moved, active));
        limit_membranes(&self.extra_membranes, x, w, whole, (0, moved, active));
        for _ in 0..again {
            next.clear();
            let part = (floor, LIMIT_AGAIN_RELAX);
            limit_membranes(active, x, w, part, (0, moved, next));
        }
    }

    /// Whether any triangle has a strain limit: the cloth's material has one, or a
    /// piece's fabric does (each triangle's own is its membrane's `s_max`).
    fn limits_strain(&self, cloth: &Cloth) -> bool {
        self.material.strain_limit > 0.0
            || (cloth.zones.zones().iter()).any(|z| z.material.strain_limit > 0.0)
    }

    /// The end of a substep's positions: the strain limit (when on) and the guard's pass.
    ///
    /// The limit runs once before the guard, and where the guard did not let a vertex go
    /// (pressed into the body, the solver's lag pushes a vertex on the crown of the head
    /// several mm into it every substep, and the guard's projection of that leaves little
    /// of the limit's move along the surface), once more from where the guard put it,
    /// which it then checks again for the vertices moved. Limited before the guard only,
    /// the mannequin drape's most stretched sides were 1.27-1.28x their rest length, 1.25x
    /// with both, 1.233-1.236x with [`LIMIT_PASSES_AGAIN`] in the second (docs/models.md).
    /// A vertex the limit moved keeps as velocity only what it really moved (credited
    /// with every vertex at the substep's end, `credit_pushes`). The first pass's move of a vertex lying on the body is held back
    /// by the static friction its contact left unused this substep (`StaticFriction`):
    /// the limit no longer drags resting cloth along the body as if it had no friction
    /// (the 128 x 128 mannequin drape crept at up to 9 cm/s and never settled; now it
    /// does, docs/models.md). `limit`: whether any triangle has a limit (`limits_strain`,
    /// once a frame).
    fn limit_and_guard(&mut self, cloth: &mut Cloth, limit: bool) {
        let [mut before, mut after] = std::mem::take(&mut self.limited);
        before.clear();
        after.clear();
        let w = &cloth.inv_mass[..];
        if limit {
            self.before_limit.clear();
            self.before_limit.extend_from_slice(&cloth.x);
            self.limit_strain(&mut cloth.x, w, &mut before, 0);
            for &i in &before {
                let i = i as usize;
                (self.friction_left).hold(i, self.before_limit[i], &mut cloth.x[i]);
            }
        }
        if let Some(g) = &mut self.guard {
            g.enforce(&mut cloth.x, &mut self.prev, self.threads);
        }
        if limit && self.guard.is_some() {
            self.limit_strain(&mut cloth.x, w, &mut after, LIMIT_PASSES_AGAIN);
            in_order_once(&mut after, &mut self.limited_bits, cloth.x.len());
            if let Some(g) = &mut self.guard {
                g.enforce_only(&mut cloth.x, &after, self.threads);
            }
        }
        self.limited = [before, after];
    }

    /// Advances one frame of `env.frame_dt` in `substeps` substeps.
    ///
    /// Out of line, with the cloth as its own argument: a `&mut` parameter tells LLVM
    /// nothing else points into the cloth. Inlined into the trait method (which gets the
    /// cloth inside a `FrameInput`), that guarantee was lost and the per-vertex loops
    /// reloaded the cloth's arrays after every store: 2.2% more instructions per frame on
    /// the 64 x 64 drape (callgrind), 0.07% out of line.
    #[inline(never)]
    pub(super) fn frame(
        &mut self,
        cloth: &mut Cloth,
        body: Option<&Body>,
        contacts: &ContactCache,
        env: &Environment,
        substeps: usize,
        drive: &mut Drive<'_, '_>,
    ) {
        let h = env.frame_dt / substeps as f32;
        let cp = self.material.contact_params(env.floor);
        self.update_normals(cloth);
        drive.grip.begin_frame();
        let damp = (-self.material.damping * h).exp();
        let settling = self.settle.begin_frame(&cloth.v);
        let m = self.material;
        let inv_h2 = 1.0 / (h * h);
        super::limits::link_weights(
            &cloth.inv_mass,
            &cloth.x,
            contacts,
            self.material.thickness,
            &mut self.link_w,
        );
        let mut coarse = std::mem::take(&mut self.coarse);
        // While a seam is being sewn its stitches pull the cloth across, and the links take
        // their loose lengths (`limits`); not once every open pair has stopped closing.
        let loose = self.sewing.looseness(drive.stitches, &cloth.x);
        (self.limits).node_weights(&self.link_w, loose, &mut coarse);
        let compliance = Compliance::of(&m, h, loose > 0.0 || drive.grip.pinch.is_some());
        let searches = self
            .guard
            .as_ref()
            .map_or(1, |g| g.searches(cloth, env, substeps));
        if let Some(g) = &mut self.guard {
            g.begin_frame();
        }
        let limit = self.limits_strain(cloth);
        self.stretch_floor = drive.stretch_floor;
        for k in 0..substeps {
            // The substeps this search covers start here.
            let group = k * searches / substeps;
            if let Some(g) = &mut self.guard
                && k == group * substeps / searches
            {
                let span = ((group + 1) * substeps / searches - k) as f32 * h;
                let (th, threads) = (m.thickness, self.threads);
                g.search(cloth, body, env, drive, (span, th, threads), (k, substeps));
            }
            drive.grip.follow(k, substeps, &mut *drive.pen, cloth, body);
            if let Some(g) = &mut self.guard {
                g.begin_substep(&cloth.x);
            }
            self.start.clear();
            self.start.extend_from_slice(&cloth.x);
            let g = env.gravity * h;
            for i in 0..cloth.len() {
                self.prev[i] = cloth.x[i];
                if cloth.inv_mass[i] > 0.0 {
                    cloth.v[i] += g;
                    cloth.x[i] += cloth.v[i] * h;
                }
            }
            // Stitches before the cloth's constraints, which have the last word, so no side
            // is left stretched at the substep's end. After them, a stitch had the last
            // word: its 0.5 N moved a light border vertex (a few hundredths of a gram) up
            // to 25 cm in a substep with its neighbours left behind, and garments ended
            // with sides at 12-17x their rest length. Where the cloth resists, one pass
            // now undoes most of a stitch's pull (docs/garments.md).
            for st in drive.stitches {
                stitch(&mut cloth.x, &cloth.inv_mass, st, inv_h2);
            }
            for hd in drive.holds {
                hold(&mut cloth.x, &cloth.inv_mass, hd, inv_h2);
            }
            solve_tethers(&self.tethers, &mut cloth.x);
            self.solve_constraints(
                &mut cloth.x,
                &self.prev,
                &cloth.inv_mass,
                &compliance,
                &mut coarse,
            );
            // Tethers of one vertex to two pins conflict within a pass; three passes settle
            // them (they are cheap: two per free vertex).
            for _ in 0..3 {
                solve_tethers(&self.tethers, &mut cloth.x);
            }
            drive.grip.pull(&mut cloth.x, &cloth.inv_mass, inv_h2);
            let spare = limit.then_some(&mut self.friction_left);
            contacts.project_keeping(&mut cloth.x, &mut self.prev, &cloth.inv_mass, &cp, spare);
            if let Some(g) = &mut self.guard {
                g.respond(
                    &mut cloth.x,
                    &mut self.prev,
                    &cloth.inv_mass,
                    m.thickness,
                    m.friction,
                    env.floor,
                );
            }
            self.limit_and_guard(cloth, limit);
            self.credit_pushes(&cloth.x);
            // Settling after an edit: what gravity gave since the frame began.
            let gain = settling.then(|| env.gravity.length() * h * (k + 1) as f32);
            self.velocities(cloth, h, damp, gain);
            if let Some(g) = &mut self.guard
                && (k + 1) * searches % substeps < searches
            {
                // The last substep of this search's span.
                g.note_stray(cloth);
            }
        }
        self.coarse = coarse;
        self.damp_flutter(cloth, drive.stitches.is_empty(), env.frame_dt);
        if let Some(g) = &mut self.guard {
            g.end_frame(drive);
        }
    }

    /// Damps the cloth's flutter at the frame's end, but not while a stitch pulls
    /// (`unstitched` false): sewing is left as it was (`flutter`).
    fn damp_flutter(&mut self, cloth: &mut Cloth, unstitched: bool, dt: f32) {
        if unstitched {
            (self.flutter).damp(cloth, &self.normals, dt);
        }
    }

    /// Contact moved `prev` out with a vertex by the push it gave to what was already too
    /// close at the substep's start (so the push is no velocity); of that shift each
    /// vertex keeps only as much as it really moved that way by the substep's end
    /// (`credit_moves`): the strain limit's vertices, and those pushed and then held back
    /// by the cloth round them. (The guard credits the vertices it holds at its pass.) Without it a vertex in a resting stack
    /// of layers, pushed back up each substep to where it began, kept 0.1 m/s downward
    /// that it never had, and `fold` never settled (docs/models.md).
    fn credit_pushes(&mut self, x: &[Vec3]) {
        let n = x.len().min(self.start.len()).min(self.prev.len());
        credit_moves(&mut self.prev, &self.start, x, 0..n as u32);
    }

    /// The substep's velocities from its moves: the material's mass damping, air drag on
    /// the normal velocity (integrated implicitly: always stable), and, while settling
    /// after an edit, no vertex faster than its frame's start plus `gain`.
    fn velocities(&self, cloth: &mut Cloth, h: f32, damp: f32, gain: Option<f32>) {
        let inv_h = 1.0 / h;
        for i in 0..cloth.len() {
            if cloth.inv_mass[i] == 0.0 {
                cloth.v[i] = Vec3::ZERO;
                continue;
            }
            let mut v = (cloth.x[i] - self.prev[i]) * inv_h * damp;
            let n = self.normals[i];
            let vn = v.dot(n);
            let k = self.material.drag * self.area[i] * cloth.inv_mass[i] * h;
            v -= n * (vn * k / (1.0 + k));
            if let Some(gain) = gain {
                v = self.settle.cap(i, v, gain);
            }
            cloth.v[i] = v;
        }
    }

    fn update_normals(&mut self, cloth: &Cloth) {
        self.normals.iter_mut().for_each(|n| *n = Vec3::ZERO);
        for (_, t) in cloth.live.iter() {
            let [a, b, c] = t.v.map(|i| cloth.x[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in &t.v {
                self.normals[i as usize] += n;
            }
        }
        for n in &mut self.normals {
            *n = n.normalize_or(Vec3::Y);
        }
    }
}

/// Sorts `list` (vertex indices under `n`) and drops repeats, by a bit per vertex: what
/// `sort_unstable` and `dedup` give, without the sort. The strain limit's second pass
/// lists each corner of every triangle it projects, once per pass: on the sewn 2 x 8k
/// dress at rest tens of thousands of entries a substep, whose sort was 5-6% of the
/// frame (`perf --call-graph dwarf`).
fn in_order_once(list: &mut Vec<u32>, bits: &mut Vec<u64>, n: usize) {
    bits.clear();
    bits.resize(n.div_ceil(64), 0);
    for &i in list.iter() {
        if let Some(word) = bits.get_mut(i as usize / 64) {
            *word |= 1 << (i % 64);
        }
    }
    list.clear();
    for (k, &word) in bits.iter().enumerate() {
        let mut word = word;
        while word != 0 {
            list.push((k * 64) as u32 + word.trailing_zeros());
            word &= word - 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::in_order_once;

    #[test]
    fn in_order_once_is_a_sort_and_dedup() {
        let mut seed = 11u64;
        let mut bits = Vec::new();
        for n in [1usize, 63, 64, 65, 1000] {
            let mut list: Vec<u32> = (0..3 * n)
                .map(|_| {
                    seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                    ((seed >> 33) % n as u64) as u32
                })
                .collect();
            let mut expect = list.clone();
            expect.sort_unstable();
            expect.dedup();
            in_order_once(&mut list, &mut bits, n);
            assert_eq!(list, expect, "n = {n}");
        }
    }
}
