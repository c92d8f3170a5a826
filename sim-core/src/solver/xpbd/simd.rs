//! The XPBD constraint passes, eight constraints of one colour at a time in SIMD lanes
//! (`wide::f32x8`). Constraints are packed at build time into structure-of-arrays blocks
//! of eight (indices, coefficients and inverse masses as lanes), so a block is a few
//! vector loads, the arithmetic, and a scatter of positions. Constraints of a colour share
//! no vertex, so lanes never conflict; the arithmetic is the scalar solver's, lane for lane.

use glam::Vec3;
use wide::f32x8;

use crate::solver::constraints::{BendConstraint, Membrane};

pub const LANES: usize = 8;

/// Eight membranes of one colour.
#[derive(Clone, Debug)]
pub struct MembraneBlock {
    idx: [[u32; LANES]; 3],
    c: [f32x8; 3],
    d: [f32x8; 3],
    /// Area times the stretch and the shear scale (`Membrane::ks`, `kg`).
    stretch_area: f32x8,
    shear_area: f32x8,
    w: [f32x8; 3],
}

/// Eight hinges of one colour.
#[derive(Clone, Debug)]
pub struct BendBlock {
    idx: [[u32; LANES]; 4],
    k: [f32x8; 4],
    weight: f32x8,
    rest: [f32x8; 3],
    /// `w_a * k_a` per corner and `sum w_a k_a^2`.
    wk: [f32x8; 4],
    wkk: f32x8,
}

fn lanes<T>(items: &[T], f: impl Fn(&T) -> f32) -> f32x8 {
    let mut a = [0.0f32; LANES];
    for (l, it) in items.iter().enumerate() {
        a[l] = f(it);
    }
    f32x8::new(a)
}

impl MembraneBlock {
    pub fn pack(m: &[Membrane], w: &[f32]) -> Self {
        debug_assert_eq!(m.len(), LANES);
        Self {
            idx: std::array::from_fn(|a| std::array::from_fn(|l| m[l].v[a])),
            c: std::array::from_fn(|a| lanes(m, |t| t.c[a])),
            d: std::array::from_fn(|a| lanes(m, |t| t.d[a])),
            stretch_area: lanes(m, |t| t.area * t.ks),
            shear_area: lanes(m, |t| t.area * t.kg),
            w: std::array::from_fn(|a| lanes(m, |t| w[t.v[a] as usize])),
        }
    }
}

#[inline]
fn set_lane(v: &mut f32x8, lane: usize, x: f32) {
    let mut a = v.to_array();
    a[lane] = x;
    *v = f32x8::new(a);
}

impl MembraneBlock {
    /// Makes one lane a no-op (its triangle was removed).
    pub fn disable(&mut self, lane: usize) {
        for a in 0..3 {
            set_lane(&mut self.c[a], lane, 0.0);
            set_lane(&mut self.d[a], lane, 0.0);
            set_lane(&mut self.w[a], lane, 0.0);
        }
    }

    /// The inverse mass of one lane's corner.
    pub fn set_w(&mut self, lane: usize, corner: usize, w: f32) {
        set_lane(&mut self.w[corner], lane, w);
    }
}

impl BendBlock {
    /// Makes one lane a no-op (its hinge is gone).
    pub fn disable(&mut self, lane: usize) {
        for a in 0..4 {
            set_lane(&mut self.k[a], lane, 0.0);
            set_lane(&mut self.wk[a], lane, 0.0);
        }
        for r in 0..3 {
            set_lane(&mut self.rest[r], lane, 0.0);
        }
        set_lane(&mut self.wkk, lane, 0.0);
    }

    /// The inverse mass of one lane's corner.
    pub fn set_w(&mut self, lane: usize, corner: usize, w: f32) {
        let k = self.k[corner].to_array()[lane];
        set_lane(&mut self.wk[corner], lane, w * k);
        let wkk: f32 = (0..4)
            .map(|a| self.wk[a].to_array()[lane] * self.k[a].to_array()[lane])
            .sum();
        set_lane(&mut self.wkk, lane, wkk);
    }

    pub fn pack(b: &[BendConstraint], w: &[f32]) -> Self {
        debug_assert_eq!(b.len(), LANES);
        let k: [f32x8; 4] = std::array::from_fn(|a| lanes(b, |h| h.k[a]));
        let wv: [f32x8; 4] = std::array::from_fn(|a| lanes(b, |h| w[h.v[a] as usize]));
        let wk: [f32x8; 4] = std::array::from_fn(|a| wv[a] * k[a]);
        Self {
            idx: std::array::from_fn(|a| std::array::from_fn(|l| b[l].v[a])),
            wkk: wk[0] * k[0] + wk[1] * k[1] + wk[2] * k[2] + wk[3] * k[3],
            k,
            wk,
            weight: lanes(b, |h| h.weight),
            rest: std::array::from_fn(|r| lanes(b, |h| h.rest[r])),
        }
    }
}

#[inline(always)]
fn gather(x: &[Vec3], idx: &[u32; LANES]) -> [f32x8; 3] {
    let mut a = [[0.0f32; LANES]; 3];
    for l in 0..LANES {
        let p = x[idx[l] as usize];
        a[0][l] = p.x;
        a[1][l] = p.y;
        a[2][l] = p.z;
    }
    [f32x8::new(a[0]), f32x8::new(a[1]), f32x8::new(a[2])]
}

#[inline(always)]
fn scatter(x: &mut [Vec3], idx: &[u32; LANES], p: &[f32x8; 3]) {
    let (a, b, c) = (p[0].to_array(), p[1].to_array(), p[2].to_array());
    for l in 0..LANES {
        x[idx[l] as usize] = Vec3::new(a[l], b[l], c[l]);
    }
}

#[inline(always)]
fn dot(a: &[f32x8; 3], b: &[f32x8; 3]) -> f32x8 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn lin3(p: &[[f32x8; 3]; 3], k: &[f32x8; 3]) -> [f32x8; 3] {
    [
        p[0][0] * k[0] + p[1][0] * k[1] + p[2][0] * k[2],
        p[0][1] * k[0] + p[1][1] * k[1] + p[2][1] * k[2],
        p[0][2] * k[0] + p[1][2] * k[1] + p[2][2] * k[2],
    ]
}

/// Warp stretch, weft stretch and shear of eight membranes; `shear` is its compliance and
/// damping ratio (see `solve_membranes`), `None` when shear is off.
#[inline(never)]
pub fn membranes8(
    b: &MembraneBlock,
    x: &mut [Vec3],
    prev: &[Vec3],
    a_stretch: f32,
    shear: Option<(f32, f32)>,
) {
    let mut p = [
        gather(x, &b.idx[0]),
        gather(x, &b.idx[1]),
        gather(x, &b.idx[2]),
    ];
    let zero = f32x8::splat(0.0);
    let tiny = f32x8::splat(1e-9);
    let one = f32x8::splat(1.0);
    let at_stretch = f32x8::splat(a_stretch) / b.stretch_area;
    let wv = &b.w;
    for coeff in [&b.c, &b.d] {
        let f = lin3(&p, coeff);
        let len = dot(&f, &f).sqrt();
        let ok = len.simd_gt(tiny);
        let denom = wv[0] * coeff[0] * coeff[0]
            + wv[1] * coeff[1] * coeff[1]
            + wv[2] * coeff[2] * coeff[2]
            + at_stretch;
        let dl = ok.select((one - len) / (denom * len.max(tiny)), zero);
        for a in 0..3 {
            let s = wv[a] * coeff[a] * dl;
            for r in 0..3 {
                p[a][r] += f[r] * s;
            }
        }
    }
    if let Some((a_shear, gamma)) = shear {
        let (c, d) = (&b.c, &b.d);
        let fu = lin3(&p, c);
        let fv = lin3(&p, d);
        let g: [[f32x8; 3]; 3] = std::array::from_fn(|a| {
            [
                fv[0] * c[a] + fu[0] * d[a],
                fv[1] * c[a] + fu[1] * d[a],
                fv[2] * c[a] + fu[2] * d[a],
            ]
        });
        let mut cs = dot(&fu, &fv);
        // The shear rate since the substep began: grad C . (x - x_prev).
        let gamma = if gamma > 0.0 {
            let mut rate = zero;
            for a in 0..3 {
                let q = gather(prev, &b.idx[a]);
                rate += g[a][0] * (p[a][0] - q[0])
                    + g[a][1] * (p[a][1] - q[1])
                    + g[a][2] * (p[a][2] - q[2]);
            }
            let gamma = f32x8::splat(gamma);
            cs += gamma * rate;
            gamma
        } else {
            zero
        };
        let denom = (one + gamma)
            * (wv[0] * dot(&g[0], &g[0]) + wv[1] * dot(&g[1], &g[1]) + wv[2] * dot(&g[2], &g[2]))
            + f32x8::splat(a_shear) / b.shear_area;
        let ok = denom.simd_gt(zero);
        let dl = ok.select(-cs / denom.max(tiny), zero);
        for a in 0..3 {
            let s = wv[a] * dl;
            for r in 0..3 {
                p[a][r] += g[a][r] * s;
            }
        }
    }
    for a in 0..3 {
        scatter(x, &b.idx[a], &p[a]);
    }
}

/// Isometric bending of eight hinges, damped by `gamma` across the hinge (see
/// `solve_bending`).
#[inline(never)]
pub fn bends8(b: &BendBlock, x: &mut [Vec3], prev: &[Vec3], a_bend: f32, gamma: f32) {
    let mut p = [
        gather(x, &b.idx[0]),
        gather(x, &b.idx[1]),
        gather(x, &b.idx[2]),
        gather(x, &b.idx[3]),
    ];
    let k = &b.k;
    let cv: [f32x8; 3] = std::array::from_fn(|r| {
        p[0][r] * k[0] + p[1][r] * k[1] + p[2][r] * k[2] + p[3][r] * k[3] - b.rest[r]
    });
    let zero = f32x8::splat(0.0);
    let tiny = f32x8::splat(1e-30);
    let soft = f32x8::splat(a_bend) / b.weight;
    let inv_of = |denom: f32x8| {
        denom
            .simd_gt(zero)
            .select(f32x8::splat(-1.0) / denom.max(tiny), zero)
    };
    let inv = inv_of(soft + b.wkk);
    // Damped, across the hinge (along n = edge x (wing 2 - wing 3)) the correction is
    // -(C_n + gamma rate_n) / (alpha + (1 + gamma) sum w k^2) in place of the undamped
    // one, with the rate sum k_a (x_a - x_prev_a) since the substep began: `n` and the
    // difference of the two, worked out before the positions move.
    let damped = (gamma > 0.0).then(|| {
        let e: [f32x8; 3] = std::array::from_fn(|r| p[1][r] - p[0][r]);
        let d: [f32x8; 3] = std::array::from_fn(|r| p[2][r] - p[3][r]);
        let n = [
            e[1] * d[2] - e[2] * d[1],
            e[2] * d[0] - e[0] * d[2],
            e[0] * d[1] - e[1] * d[0],
        ];
        let nn = dot(&n, &n);
        let inv_nn = nn
            .simd_gt(f32x8::splat(1e-20))
            .select(f32x8::splat(1.0) / nn.max(tiny), zero);
        let mut rate = [zero; 3];
        for a in 0..4 {
            let o = gather(prev, &b.idx[a]);
            for r in 0..3 {
                rate[r] += k[a] * (p[a][r] - o[r]);
            }
        }
        let g = f32x8::splat(gamma);
        let cn = dot(&n, &cv) * inv_nn;
        let rn = dot(&n, &rate) * inv_nn;
        let inv_d = inv_of(soft + (f32x8::splat(1.0) + g) * b.wkk);
        (n, (cn + g * rn) * inv_d - cn * inv)
    });
    // Undamped: the correction -C / (alpha + sum w k^2), for all three components alike.
    for a in 0..4 {
        let s = b.wk[a] * inv;
        for r in 0..3 {
            p[a][r] += cv[r] * s;
        }
    }
    if let Some((n, sn)) = damped {
        for a in 0..4 {
            let s = b.wk[a] * sn;
            for r in 0..3 {
                p[a][r] += n[r] * s;
            }
        }
    }
    for a in 0..4 {
        scatter(x, &b.idx[a], &p[a]);
    }
}
