//! The XPBD constraints packed for solving: three groups (the two halves of the vertex
//! range and the constraints straddling them), each greedily coloured and packed into
//! SIMD blocks of eight, and the scalar passes over membranes and hinges.

use glam::Vec3;

use super::coloring::color_order;
use super::simd::{self, BendBlock, LANES, MembraneBlock};
use crate::solver::constraints::{BendConstraint, Membrane};

/// Constraints whose vertices all lie in one contiguous vertex range, with indices
/// relative to the range's start, coloured and packed into SIMD blocks.
#[derive(Clone, Debug, Default)]
pub(super) struct Group {
    /// Start and end of the group's vertex range; constraints hold indices relative to
    /// `off`.
    pub(super) off: u32,
    pub(super) end: usize,
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
    pub(super) fn new(
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
    pub(super) fn solve(&self, x: &mut [Vec3], prev: &[Vec3], w: &[f32], k: &Compliance) {
        let (a_stretch, a_shear, a_bend) = (k.stretch, k.shear, k.bend);
        let shear = a_shear.is_finite().then_some((a_shear, k.shear_gamma));
        for (blocks, rest) in &self.membrane_batches {
            for b in blocks {
                simd::membranes8(b, x, prev, a_stretch, shear);
            }
            solve_membranes(&self.membranes[rest.clone()], x, prev, w, k);
        }
        if a_bend.is_finite() {
            for (blocks, rest) in &self.bend_batches {
                for b in blocks {
                    simd::bends8(b, x, prev, a_bend, k.bend_gamma);
                }
                solve_bending(
                    &self.bends[rest.clone()],
                    x,
                    prev,
                    w,
                    (a_bend, k.bend_gamma),
                );
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

/// One substep's XPBD compliances (already divided by h^2; per unit area and scale for
/// membranes,
/// `INFINITY` for a constraint that is off) and the damping ratios of shear and bending,
/// `gamma = shear_damping / h` and `bend_damping / h`.
pub(super) struct Compliance {
    pub stretch: f32,
    pub shear: f32,
    pub bend: f32,
    pub shear_gamma: f32,
    pub bend_gamma: f32,
}

impl Compliance {
    /// The compliances of `m` for a substep of `h` seconds. While the cloth is `handled`
    /// (a seam being sewn, or the pen holding it) the hinges are not damped: their
    /// damping is for a cloth coming to rest. Damped while sewing (along the whole
    /// constraint, in a first try), a test's sewn dress kept a pair of a seam open; while
    /// the pen carried a corner over, the fold scenario's layers came down crumpled and
    /// its later frames took 1.6x as long (docs/collision.md).
    pub(super) fn of(m: &crate::solver::material::Material, h: f32, handled: bool) -> Self {
        let inv_h2 = 1.0 / (h * h);
        let or_off = |k: f32| if k > 0.0 { inv_h2 / k } else { f32::INFINITY };
        Self {
            stretch: inv_h2 / m.stretch,
            shear: or_off(m.shear),
            bend: or_off(m.bending),
            shear_gamma: m.shear_damping / h,
            bend_gamma: if handled { 0.0 } else { m.bend_damping / h },
        }
    }
}

/// One pass over every triangle: warp stretch, weft stretch, then shear. Shear is damped
/// (XPBD constraint damping, Macklin et al. 2016 eq. 26): its rate since the substep
/// began, `grad C . (x - x_prev)`, is part of the correction, weighted by `k.shear_gamma`.
pub(super) fn solve_membranes(
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
        let at_stretch = k.stretch / (m.area * m.ks);
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
                + k.shear / (m.area * m.kg);
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

/// One pass over every hinge. The constraint is linear, so its gradient is `K_a I`. Like
/// shear, bending is damped (Macklin et al. 2016 eq. 26) by `gamma`, across the hinge
/// only: along `n = edge x (wing - wing)` its rate since the substep began,
/// `n . sum K_a (x_a - x_prev_a)`, is part of the correction; along the cloth the
/// constraint moves in-plane (stretch) motion too, which damping there would undo.
/// `a` is `(compliance, gamma)`.
pub(super) fn solve_bending(
    bends: &[BendConstraint],
    x: &mut [Vec3],
    prev: &[Vec3],
    w: &[f32],
    (a_bend, gamma): (f32, f32),
) {
    for b in bends {
        let idx = b.v.map(|i| i as usize);
        let p = idx.map(|i| x[i]);
        let c = p[0] * b.k[0] + p[1] * b.k[1] + p[2] * b.k[2] + p[3] * b.k[3] - b.rest;
        let mut denom = a_bend / b.weight;
        for a in 0..4 {
            denom += w[idx[a]] * b.k[a] * b.k[a];
        }
        if denom <= 0.0 {
            continue;
        }
        let mut dl = -c / denom;
        if gamma > 0.0 {
            let n = (p[1] - p[0]).cross(p[2] - p[3]);
            let nn = n.length_squared();
            if nn > 1e-20 {
                let soft = a_bend / b.weight;
                let wkk = denom - soft;
                let rate: Vec3 = (0..4).map(|a| (p[a] - prev[idx[a]]) * b.k[a]).sum();
                let (cn, rn) = (n.dot(c) / nn, n.dot(rate) / nn);
                let damped = -(cn + gamma * rn) / (soft + (1.0 + gamma) * wkk);
                dl += n * (damped + cn / denom);
            }
        }
        for a in 0..4 {
            x[idx[a]] += dl * (w[idx[a]] * b.k[a]);
        }
    }
}

/// Per colour (`colors` as `color_order` returns them): the colour's full SIMD blocks of
/// `LANES`, then the range of its remainder, solved scalar.
pub(super) fn batches<T, B>(
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

/// Splits the vertex range at its middle: constraints entirely below go to the first
/// half, entirely above to the second, the rest to the boundary group.
pub(super) fn split_groups(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::constraints::bend_of;

    /// A flat hinge of 1 cm sides in the z = 0 plane: edge 0-1 along x, wings 2 (y > 0)
    /// and 3 (y < 0); `off` is the index of its first vertex.
    fn hinge(off: u32) -> (BendConstraint, [Vec3; 4]) {
        let p = [
            Vec3::ZERO,
            Vec3::new(0.01, 0.0, 0.0),
            Vec3::new(0.004, 0.009, 0.0),
            Vec3::new(0.006, -0.008, 0.0),
        ];
        let b = bend_of(
            [off, off + 1, off + 2, off + 3],
            [p[0], p[1], p[2]],
            [p[0], p[1], p[3]],
        )
        .unwrap();
        (b, p)
    }

    fn bend(x: &mut [Vec3], prev: &[Vec3], gamma: f32) {
        let (b, _) = hinge(0);
        solve_bending(&[b], x, prev, &[1e4; 4], (1.0, gamma));
    }

    /// The damping resists a hinge's folding: a hinge lying flat (no bend to correct) whose
    /// wing came down 1 mm across it since the substep began is pushed back up, and the
    /// harder the larger `gamma`; motion along the cloth (a wing stretched along the
    /// edge) is not resisted: the hinge is corrected as if it had not moved.
    #[test]
    fn hinge_damping_resists_folding_and_leaves_stretching_alone() {
        let (_, flat) = hinge(0);
        let mut prev = flat;
        prev[2].z += 1e-3;
        let mut undamped = flat;
        bend(&mut undamped, &prev, 0.0);
        assert_eq!(undamped, flat, "flat: nothing to correct undamped");
        let lift = |gamma: f32| {
            let mut x = flat;
            bend(&mut x, &prev, gamma);
            x[2].z
        };
        let (some, more) = (lift(0.5), lift(5.0));
        assert!(some > 1e-5 && more > some, "wing lifted {some}, {more}");
        assert!(more < 1e-3, "not past where it began: {more}");

        // Bent, and stretched along the hinge since the substep began (wing 2 moved 2 mm
        // along the edge): corrected as if it had not moved.
        let mut x = flat;
        x[2].z += 2e-4;
        let mut prev_along = x;
        prev_along[2].x -= 2e-3;
        let mut still = x;
        bend(&mut still, &x.clone(), 5.0);
        assert!((still[2] - x[2]).length() > 1e-6, "the bend is corrected");
        let mut moved = x;
        bend(&mut moved, &prev_along, 5.0);
        for (a, b) in still.iter().zip(&moved) {
            assert!((*a - *b).length() < 1e-9, "{a} {b}");
        }
    }

    /// The SIMD pass is the scalar pass, lane for lane, with and without damping: eight
    /// separate hinges, bent and moving.
    #[test]
    fn eight_hinges_in_lanes_match_the_scalar_pass() {
        let mut bends = Vec::new();
        let mut x = Vec::new();
        let mut prev = Vec::new();
        for h in 0..LANES as u32 {
            let (b, p) = hinge(4 * h);
            bends.push(b);
            let s = h as f32 + 1.0;
            for (a, q) in p.iter().enumerate() {
                let wobble = Vec3::new(0.1 * s, -0.2, 0.3 * a as f32) * 1e-3;
                prev.push(*q + Vec3::new(0.0, 0.0, 0.4e-3 * s * (a % 2) as f32));
                x.push(*q + wobble + Vec3::new(0.0, 0.0, 1e-3 * s * (a == 2) as u8 as f32));
            }
        }
        let w: Vec<f32> = (0..x.len()).map(|i| 1e4 * (1.0 + 0.1 * i as f32)).collect();
        for gamma in [0.0, 0.6] {
            let mut scalar = x.clone();
            solve_bending(&bends, &mut scalar, &prev, &w, (3.0, gamma));
            let mut lanes = x.clone();
            simd::bends8(&BendBlock::pack(&bends, &w), &mut lanes, &prev, 3.0, gamma);
            let moved: f32 = scalar.iter().zip(&x).map(|(a, b)| (*a - *b).length()).sum();
            assert!(moved > 1e-6, "the pass moved nothing (gamma {gamma})");
            for (a, b) in scalar.iter().zip(&lanes) {
                assert!((*a - *b).length() < 1e-8, "gamma {gamma}: {a} {b}");
            }
        }
    }
}
