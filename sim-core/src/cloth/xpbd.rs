//! Small-steps XPBD (Macklin, Storey, Lu et al. 2019): many substeps, one Gauss-Seidel
//! pass each. Compliance is the inverse of a physical stiffness (membrane moduli times
//! area, bending rigidity times the hinge weight), and the time-scaled compliance
//! `alpha / h^2` is recomputed for the substep, so material stiffness does not depend on
//! the substep count. With one iteration per substep the Lagrange multipliers start at
//! zero every substep and need not be stored.
//!
//! Gauss-Seidel moves a correction about one vertex per pass, so with few passes a long
//! hanging span stretches more than its material would (the sag then depends on the
//! substep count). Long-range attachments (Kim, Chentanez & Mueller 2012) fix that for
//! pinned cloth: every free vertex gets a unilateral tether to its nearest pins, as long
//! as the geodesic rest distance times `1 + strain`, where `strain` is what the material
//! itself would stretch under its full weight (`density * g * extent / stretch`). Tethers
//! never make the cloth stiffer than its material; they only stop the solver's lag.
//! Cloth held up by a body instead of pins gets the same remedy from the stretch limits
//! (`limits`): a coarse lattice of unilateral links solved before and after the
//! membranes.

use glam::Vec3;

use super::coloring::color_order;
use std::collections::HashMap;

use super::constraints::{BendConstraint, Membrane, bend_of, membrane_of};
use super::contact::{ContactCache, ContactParams};
use super::limits::{Bounded, RestGraph, StretchLimits};
use super::material::Material;
use super::sim::Environment;
use super::state::Cloth;
use super::xpbd_simd::{self, BendBlock, LANES, MembraneBlock};
use crate::mesh::bounds;

/// Constraints whose vertices all lie in one contiguous vertex range, with indices
/// relative to the range's start, coloured and packed into SIMD blocks.
#[derive(Clone, Debug, Default)]
pub(super) struct Group {
    /// Start and end of the group's vertex range; constraints hold indices relative to
    /// `off`.
    pub(super) off: u32,
    end: usize,
    pub(super) membranes: Vec<Membrane>,
    pub(super) bends: Vec<BendConstraint>,
    /// Start of each colour in `membranes` / `bends`, then the end.
    pub(super) membrane_colors: Vec<usize>,
    pub(super) bend_colors: Vec<usize>,
    /// Per colour: full SIMD blocks, then the colour's remainder (solved scalar).
    pub(super) membrane_batches: Vec<(Vec<MembraneBlock>, std::ops::Range<usize>)>,
    pub(super) bend_batches: Vec<(Vec<BendBlock>, std::ops::Range<usize>)>,
}

impl Group {
    fn new(
        range: std::ops::Range<usize>,
        mut membranes: Vec<Membrane>,
        mut bends: Vec<BendConstraint>,
        w: &[f32],
    ) -> Self {
        let off = range.start as u32;
        for m in &mut membranes {
            m.v = m.v.map(|i| i - off);
        }
        for b in &mut bends {
            b.v = b.v.map(|i| i - off);
        }
        // Spatial order first (locality), then colour (independence within a colour).
        membranes.sort_by_key(|m| m.v.iter().copied().min().unwrap_or(0));
        bends.sort_by_key(|b| b.v.iter().copied().min().unwrap_or(0));
        let len = range.end - range.start;
        let membrane_colors = color_order(&mut membranes, len, |m| &m.v[..]);
        let bend_colors = color_order(&mut bends, len, |b| &b.v[..]);
        let w = &w[range.clone()];
        Self {
            off,
            end: range.end,
            membrane_batches: batches(&membranes, &membrane_colors, |c| MembraneBlock::pack(c, w)),
            bend_batches: batches(&bends, &bend_colors, |c| BendBlock::pack(c, w)),
            membranes,
            bends,
            membrane_colors,
            bend_colors,
        }
    }

    /// One pass over the group's membranes then hinges. `x` and `w` are the group's range.
    fn solve(&self, x: &mut [Vec3], prev: &[Vec3], w: &[f32], k: &Compliance) {
        let (a_stretch, a_shear, a_bend) = (k.stretch, k.shear, k.bend);
        let shear = a_shear.is_finite().then_some((a_shear, k.shear_gamma));
        for (blocks, rest) in &self.membrane_batches {
            for b in blocks {
                xpbd_simd::membranes8(b, x, prev, a_stretch, shear);
            }
            solve_membranes(&self.membranes[rest.clone()], x, prev, w, k);
        }
        if a_bend.is_finite() {
            for (blocks, rest) in &self.bend_batches {
                for b in blocks {
                    xpbd_simd::bends8(b, x, a_bend);
                }
                solve_bending(&self.bends[rest.clone()], x, w, a_bend);
            }
        }
    }
}

/// Where a constraint lives: an item of one of the three groups (packed or in a colour's
/// scalar remainder), or the list of constraints added by edits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Loc {
    None,
    Group { group: u8, item: u32 },
    Extra(u32),
}

/// One substep's XPBD compliances (already divided by h^2; per unit area for membranes,
/// `INFINITY` for a constraint that is off) and the shear damping ratio
/// `gamma = shear_damping / h`.
pub(super) struct Compliance {
    pub stretch: f32,
    pub shear: f32,
    pub bend: f32,
    pub shear_gamma: f32,
}

#[derive(Clone, Debug)]
pub struct Xpbd {
    pub(super) prev: Vec<Vec3>,
    pub(super) normals: Vec<Vec3>,
    /// A third of the area of the triangles around each vertex (for air drag).
    pub(super) area: Vec<f32>,
    pub(super) material: Material,
    /// (vertex, pin, maximum length) long-range attachments.
    pub(super) tethers: Vec<(u32, u32, f32)>,
    /// Long-range stretch limits, coarse level first (see `limits`), and the inverse
    /// masses they use this frame.
    pub(super) limits: StretchLimits,
    link_w: Vec<f32>,
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
    /// The pointer's spring, while pinching.
    pub(crate) pinch: Option<crate::edit::Pinch>,
    /// The pinch force on the cloth in each substep of the last frame, N.
    pub(crate) pinch_forces: Vec<Vec3>,
    /// Substeps of the last frame whose pinch was scaled down to its force limit.
    pub(crate) pinch_limited: usize,
    /// Open seam stitches: (a, b, largest force in N).
    pub(crate) stitches: Vec<(u32, u32, f32)>,
}

/// Stiffness of a seam stitch, N/m (its force is also capped per seam).
const STITCH_STIFFNESS: f32 = 100.0;

impl Xpbd {
    pub fn new(cloth: &Cloth, material: &Material) -> Self {
        Self::with_limits(cloth, material, None)
    }

    /// As `new`, keeping `limits` (rescaled to the material's strain) when given: after a
    /// material change the lattice, its order and its path lengths stay as they were.
    pub(crate) fn with_limits(
        cloth: &Cloth,
        material: &Material,
        limits: Option<StretchLimits>,
    ) -> Self {
        let live = &cloth.live;
        let membranes: Vec<Membrane> = live
            .iter()
            .map(|(slot, t)| membrane_of(t.v, slot, t.rest, t.uv))
            .collect();
        let bends: Vec<BendConstraint> = live
            .hinge_keys()
            .into_iter()
            .filter_map(|k| live.hinge(k))
            .filter_map(|(v, r0, r1)| bend_of(v, r0, r1))
            .collect();
        let mut area = vec![0.0f32; cloth.len()];
        for m in &membranes {
            for &i in &m.v {
                area[i as usize] += m.area / 3.0;
            }
        }
        let groups = split_groups(cloth.len(), &membranes, &bends, &cloth.inv_mass);
        let mut membrane_loc = vec![Loc::None; live.slots()];
        let mut bend_loc = HashMap::with_capacity(bends.len());
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
            tethers: tethers(cloth, material),
            limits: stretch_limits(cloth, material, limits, groups[0].end),
            link_w: Vec::new(),
            groups,
            membrane_loc,
            bend_loc,
            extra_membranes: Vec::new(),
            extra_bends: Vec::new(),
            threads: 1,
            pinch: None,
            pinch_forces: Vec::new(),
            pinch_limited: 0,
            stitches: Vec::new(),
        }
    }

    /// Solves every membrane and hinge once, each part between two passes of its stretch
    /// limits: the two halves (in parallel when `threads > 1`), then the boundary.
    fn solve_constraints(&self, x: &mut [Vec3], prev: &[Vec3], w: &[f32], k: &Compliance) {
        let mid = self.groups[0].end;
        let limits = &self.limits;
        let lw = &self.link_w[..];
        {
            let (xa, xb) = x.split_at_mut(mid);
            let (pa, pb) = prev.split_at(mid);
            let (wa, wb) = w.split_at(mid);
            let (lwa, lwb) = lw.split_at(mid);
            let [ga, gb, _] = &self.groups;
            // The stretch limits once more after the membranes, which undo part of the
            // first pass (on the mannequin drape, measured with a 24-6-3 lattice: mean
            // strain 9.7% with one pass, 5.9% with two).
            let half = |part: usize, g: &Group, x: &mut [Vec3], p: &[Vec3], w: &[f32], lw| {
                limits.solve(part, x, lw);
                g.solve(x, p, w, k);
                limits.solve(part, x, lw);
            };
            if self.threads > 1 && !gb.membranes.is_empty() {
                std::thread::scope(|s| {
                    s.spawn(|| half(1, gb, xb, pb, wb, lwb));
                    half(0, ga, xa, pa, wa, lwa);
                });
            } else {
                half(0, ga, xa, pa, wa, lwa);
                half(1, gb, xb, pb, wb, lwb);
            }
        }
        limits.solve(2, x, lw);
        self.groups[2].solve(x, prev, w, k);
        solve_membranes(&self.extra_membranes, x, prev, w, k);
        if k.bend.is_finite() {
            solve_bending(&self.extra_bends, x, w, k.bend);
        }
        limits.solve(2, x, lw);
    }

    pub fn constraint_count(&self) -> usize {
        let membranes = self
            .membrane_loc
            .iter()
            .filter(|l| **l != Loc::None)
            .count();
        3 * membranes + self.bend_loc.len()
    }

    /// Advances one frame of `env.frame_dt` in `substeps` substeps.
    pub fn step(
        &mut self,
        cloth: &mut Cloth,
        contacts: &ContactCache,
        env: &Environment,
        substeps: usize,
        pen: &mut dyn FnMut(usize, usize) -> Option<crate::edit::PenInput>,
    ) {
        let h = env.frame_dt / substeps as f32;
        let cp = ContactParams {
            thickness: self.material.thickness,
            friction: self.material.friction,
            floor: env.floor,
        };
        self.update_normals(cloth);
        self.pinch_forces.clear();
        self.pinch_limited = 0;
        let damp = (-self.material.damping * h).exp();
        let m = self.material;
        let inv_h2 = 1.0 / (h * h);
        let compliance = Compliance {
            stretch: inv_h2 / m.stretch,
            shear: if m.shear > 0.0 {
                inv_h2 / m.shear
            } else {
                f32::INFINITY
            },
            bend: if m.bending > 0.0 {
                inv_h2 / m.bending
            } else {
                f32::INFINITY
            },
            shear_gamma: m.shear_damping / h,
        };
        super::limits::link_weights(
            &cloth.inv_mass,
            &cloth.x,
            contacts,
            self.material.thickness,
            &mut self.link_w,
        );
        for k in 0..substeps {
            if let Some(p) = &mut self.pinch
                && let Some(input) = pen(k, substeps)
                && input.target.is_finite()
            {
                p.target = input.target;
                p.force_limit = input
                    .force_limit
                    .filter(|f| f.is_finite())
                    .map(|f| f.max(0.0));
            }
            let g = env.gravity * h;
            for i in 0..cloth.len() {
                self.prev[i] = cloth.x[i];
                if cloth.inv_mass[i] > 0.0 {
                    cloth.v[i] += g;
                    cloth.x[i] += cloth.v[i] * h;
                }
            }
            solve_tethers(&self.tethers, &mut cloth.x);
            self.solve_constraints(&mut cloth.x, &self.prev, &cloth.inv_mass, &compliance);
            // Tethers of one vertex to two pins conflict within a pass; three passes settle
            // them (they are cheap: two per free vertex).
            for _ in 0..3 {
                solve_tethers(&self.tethers, &mut cloth.x);
            }
            for &st in &self.stitches {
                crate::edit::stitch(&mut cloth.x, &cloth.inv_mass, st, inv_h2, STITCH_STIFFNESS);
            }
            if let Some(p) = &self.pinch {
                // Zero-length XPBD springs to the pointer: compliance 1 / stiffness each.
                // Their corrections are found first, then applied scaled down together if
                // their force would exceed the limit.
                let k = p.stiffness / p.held.len().max(1) as f32;
                let alpha = inv_h2 / k;
                let correction = |i: usize, offset: Vec3, x: &[Vec3]| {
                    let w = *cloth.inv_mass.get(i)?;
                    let x = *x.get(i)?;
                    (w > 0.0).then(|| ((p.target + offset - x) * (w / (w + alpha)), w))
                };
                let mut force = Vec3::ZERO;
                for &(v, offset) in &p.held {
                    if let Some((dx, w)) = correction(v as usize, offset, &cloth.x) {
                        force += dx * (inv_h2 / w);
                    }
                }
                let scale = match p.force_limit {
                    Some(limit) if force.length() > limit => {
                        self.pinch_limited += 1;
                        limit / force.length()
                    }
                    _ => 1.0,
                };
                // Held vertices are distinct, so each correction is the one summed above.
                for &(v, offset) in &p.held {
                    if let Some((dx, _)) = correction(v as usize, offset, &cloth.x) {
                        cloth.x[v as usize] += dx * scale;
                    }
                }
                self.pinch_forces.push(force * scale);
            }
            contacts.project(&mut cloth.x, &mut self.prev, &cloth.inv_mass, &cp);
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

/// One pass over every triangle: warp stretch, weft stretch, then shear. Shear is damped
/// (XPBD constraint damping, Macklin et al. 2016 eq. 26): its rate since the substep
/// began, `grad C . (x - x_prev)`, is part of the correction, weighted by `k.shear_gamma`.
fn solve_membranes(
    membranes: &[Membrane],
    x: &mut [Vec3],
    prev: &[Vec3],
    w: &[f32],
    k: &Compliance,
) {
    for m in membranes {
        let [i0, i1, i2] = m.v.map(|i| i as usize);
        let wv = [w[i0], w[i1], w[i2]];
        if wv[0] + wv[1] + wv[2] == 0.0 {
            continue;
        }
        let mut p = [x[i0], x[i1], x[i2]];
        let at_stretch = k.stretch / m.area;
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
        if k.shear.is_finite() {
            let fu = p[0] * m.c[0] + p[1] * m.c[1] + p[2] * m.c[2];
            let fv = p[0] * m.d[0] + p[1] * m.d[1] + p[2] * m.d[2];
            let g = [
                fv * m.c[0] + fu * m.d[0],
                fv * m.c[1] + fu * m.d[1],
                fv * m.c[2] + fu * m.d[2],
            ];
            // C + gamma * rate, over (1 + gamma) grad C W grad C^T + alpha.
            let gamma = k.shear_gamma;
            let mut c = fu.dot(fv);
            if gamma > 0.0 {
                let q = [prev[i0], prev[i1], prev[i2]];
                let rate: f32 = (0..3).map(|a| g[a].dot(p[a] - q[a])).sum();
                c += gamma * rate;
            }
            let denom = (1.0 + gamma)
                * (wv[0] * g[0].length_squared()
                    + wv[1] * g[1].length_squared()
                    + wv[2] * g[2].length_squared())
                + k.shear / m.area;
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

/// Per colour (`colors` as `color_order` returns them): the colour's full SIMD blocks of
/// `LANES`, then the range of its remainder, solved scalar.
fn batches<T, B>(
    items: &[T],
    colors: &[usize],
    pack: impl Fn(&[T]) -> B,
) -> Vec<(Vec<B>, std::ops::Range<usize>)> {
    colors
        .windows(2)
        .map(|r| {
            let full = r[0] + (r[1] - r[0]) / LANES * LANES;
            (
                items[r[0]..full].chunks_exact(LANES).map(&pack).collect(),
                full..r[1],
            )
        })
        .collect()
}

/// The slack of tethers and stretch limits: the strain the material itself takes under
/// the cloth's full weight (`density * g * extent / stretch`).
fn own_strain(cloth: &Cloth, material: &Material) -> f32 {
    let (mn, mx) = bounds(&cloth.rest.positions);
    let extent = (mx - mn).length();
    material.density * 9.81 * extent / material.stretch
}

/// The long-range stretch limits for `cloth` (none when they are off), with the same
/// slack as the tethers: what the material itself stretches under the cloth's weight.
fn stretch_limits(
    cloth: &Cloth,
    material: &Material,
    keep: Option<StretchLimits>,
    mid: usize,
) -> StretchLimits {
    if !material.stretch_limits {
        return StretchLimits::default();
    }
    let strain = own_strain(cloth, material);
    match keep {
        Some(mut limits) if !limits.is_empty() => {
            limits.set_strain(strain);
            limits.split(mid);
            limits
        }
        _ => StretchLimits::build(cloth, strain, mid),
    }
}

/// Unilateral tethers: pull a vertex back inside its sphere around the pin.
fn solve_tethers(tethers: &[(u32, u32, f32)], x: &mut [Vec3]) {
    for &(i, p, max) in tethers {
        let d = x[i as usize] - x[p as usize];
        let l = d.length();
        if l > max {
            x[i as usize] -= d * ((l - max) / l);
        }
    }
}

/// Tethers from every free vertex to its (up to) two nearest pins by geodesic rest
/// distance along mesh edges (Dijkstra from each pin; with more than 8 pins, one
/// multi-source pass and the nearest pin only).
pub(super) fn tethers(cloth: &Cloth, material: &Material) -> Vec<(u32, u32, f32)> {
    let pins: Vec<u32> = (0..cloth.len() as u32)
        .filter(|&i| cloth.is_pinned(i as usize))
        .collect();
    if !material.tethers || pins.is_empty() || pins.len() == cloth.len() {
        return Vec::new();
    }
    let n = cloth.len();
    // Rest lengths from the live triangles, so cut pieces lose their tethers.
    let graph = RestGraph::of(cloth);
    let mut search = Bounded::new(n);
    let strain = own_strain(cloth, material);
    let mut out = Vec::new();
    if pins.len() > 8 {
        let mut nearest = vec![(f32::INFINITY, u32::MAX); n];
        search.run_from(&graph, &pins, f32::INFINITY, |v, d, pin| {
            nearest[v as usize] = (d, pin);
        });
        for (i, &(d, pin)) in nearest.iter().enumerate() {
            if !cloth.is_pinned(i) && d.is_finite() {
                out.push((i as u32, pin, d * (1.0 + strain)));
            }
        }
        return out;
    }
    let mut best: Vec<[(f32, u32); 2]> = vec![[(f32::INFINITY, u32::MAX); 2]; n];
    for &p in &pins {
        search.run_from(&graph, &[p], f32::INFINITY, |v, d, _| {
            let b = &mut best[v as usize];
            if d < b[0].0 {
                b[1] = b[0];
                b[0] = (d, p);
            } else if d < b[1].0 {
                b[1] = (d, p);
            }
        });
    }
    for i in 0..n {
        if cloth.is_pinned(i) {
            continue;
        }
        for &(d, p) in &best[i] {
            if d.is_finite() {
                out.push((i as u32, p, d * (1.0 + strain)));
            }
        }
    }
    out
}

/// Splits the vertex range at its middle: constraints entirely below go to the first
/// half, entirely above to the second, the rest to the boundary group.
fn split_groups(
    n: usize,
    membranes: &[Membrane],
    bends: &[BendConstraint],
    w: &[f32],
) -> [Group; 3] {
    let mid = (n / 2) as u32;
    let side = |v: &[u32]| {
        if v.iter().all(|&i| i < mid) {
            0
        } else if v.iter().all(|&i| i >= mid) {
            1
        } else {
            2
        }
    };
    let mut ms: [Vec<Membrane>; 3] = Default::default();
    let mut bs: [Vec<BendConstraint>; 3] = Default::default();
    for m in membranes {
        ms[side(&m.v)].push(*m);
    }
    for b in bends {
        bs[side(&b.v)].push(*b);
    }
    let [m0, m1, m2] = ms;
    let [b0, b1, b2] = bs;
    let mid = mid as usize;
    [
        Group::new(0..mid, m0, b0, w),
        Group::new(mid..n, m1, b1, w),
        Group::new(0..n, m2, b2, w),
    ]
}
