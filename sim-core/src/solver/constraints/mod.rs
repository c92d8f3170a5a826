//! The XPBD model's energy, shared with the implicit reference:
//!
//! * membrane, per triangle, with the deformation gradient `F = [F_u F_v]` in the material
//!   (warp/weft) frame taken from the UVs: stretch `C_u = |F_u| - 1`, `C_v = |F_v| - 1` with
//!   stiffness `stretch * area`, shear `C_s = F_u . F_v` with `shear * area`
//!   (Baraff & Witkin 1998 conditions; energy `k C^2 / 2`);
//! * bending, per hinge, the isometric bending model (Bergou et al. 2006): the linear
//!   vector constraint `C = sum_a K_a x_a - C_rest` with `K` the cotangent weights and
//!   stiffness `bending / (A0 + A1)`. That weight is calibrated so the energy equals the
//!   continuum `B/2 * integral (k1 + k2)^2 dA` for isometric bending (a cylinder in the
//!   tests); Bergou's `3 / (A0 + A1)` normalises the curvature differently.

use glam::{Mat2, Vec2, Vec3};

use crate::mesh::{ClothMesh, LiveMesh, Topology, edge_key, warp_of};
use crate::solver::Material;
use crate::solver::zones::MaterialZones;

/// One triangle's membrane: `F_u = sum c[a] x[a]`, `F_v = sum d[a] x[a]`.
#[derive(Clone, Copy, Debug)]
pub struct Membrane {
    pub v: [u32; 3],
    /// The triangle's slot in the live mesh (its index in the pattern until edited).
    pub id: u32,
    pub c: [f32; 3],
    pub d: [f32; 3],
    pub area: f32,
    /// The triangle's stretch and shear stiffness over the solver's material's (its
    /// piece's fabric: [`MaterialZones`]); 1 in a cloth of one material.
    pub ks: f32,
    pub kg: f32,
    /// The most this triangle's largest principal stretch may be, its fabric's
    /// `1 + strain_limit` (the xpbd model's hard limit; infinite: none).
    pub s_max: f32,
}

/// One hinge's isometric bending constraint.
#[derive(Clone, Copy, Debug)]
pub struct BendConstraint {
    pub v: [u32; 4],
    /// The hinge's edge, `edge_key(v[0], v[1])`.
    pub key: u64,
    pub k: [f32; 4],
    /// `sum K_a x_a` at rest (zero for a flat pattern).
    pub rest: Vec3,
    /// `1 / (A0 + A1)`, times the share of the rigidity in the direction the hinge bends
    /// and its piece's rigidity over the solver's: multiply by the solver's bending
    /// rigidity to get the stiffness.
    pub weight: f32,
}

/// The material frame of each triangle from its rest positions and UVs, with its zone's
/// stiffness over `material`'s (the solver's).
pub fn build_membranes(
    mesh: &ClothMesh,
    zones: &MaterialZones,
    material: &Material,
) -> Vec<Membrane> {
    mesh.triangles
        .iter()
        .enumerate()
        .map(|(t, &v)| {
            let rest = v.map(|i| mesh.positions[i as usize]);
            let m = membrane_of(v, t as u32, rest, v.map(|i| mesh.uvs[i as usize]));
            weigh_membrane(m, zones, material, &rest)
        })
        .collect()
}

/// `m` with its zone's stiffness over `material`'s (the solver's), and its zone's strain
/// limit (else `material`'s).
pub fn weigh_membrane(
    mut m: Membrane,
    zones: &MaterialZones,
    material: &Material,
    rest: &[Vec3; 3],
) -> Membrane {
    let s = zones.scales(rest, material);
    m.ks = s.stretch;
    m.kg = s.shear;
    m.s_max = s_max_of(zones.material_at(rest, material).strain_limit);
    m
}

/// The largest principal stretch a strain limit allows (0: no limit, infinite).
pub fn s_max_of(strain_limit: f32) -> f32 {
    if strain_limit > 0.0 {
        1.0 + strain_limit
    } else {
        f32::INFINITY
    }
}

/// One triangle's membrane from its rest corners and their UVs.
pub fn membrane_of(v: [u32; 3], id: u32, rest: [Vec3; 3], uv: [Vec2; 3]) -> Membrane {
    let [x0, x1, x2] = rest;
    let (e1, e2) = (x1 - x0, x2 - x0);
    let n = e1.cross(e2);
    let area = 0.5 * n.length();
    let n = n.normalize_or(Vec3::Y);
    let tangent = warp_of(rest, uv);
    let bitangent = n.cross(tangent);
    let p1 = Vec2::new(e1.dot(tangent), e1.dot(bitangent));
    let p2 = Vec2::new(e2.dot(tangent), e2.dot(bitangent));
    let dm = Mat2::from_cols(p1, p2);
    let inv = if dm.determinant().abs() > 1e-20 {
        dm.inverse()
    } else {
        Mat2::ZERO
    };
    // F = Ds * inv, Ds = [x1 - x0, x2 - x0]; column j of F is sum over rows of inv.
    let (p, q, r, s) = (inv.x_axis.x, inv.y_axis.x, inv.x_axis.y, inv.y_axis.y);
    Membrane {
        v,
        id,
        c: [-(p + r), p, r],
        d: [-(q + s), q, s],
        area,
        ks: 1.0,
        kg: 1.0,
        s_max: f32::INFINITY,
    }
}

/// Bins of the hinges' bending directions over half a turn.
const DIRECTION_BINS: usize = 36;

/// The directions a mesh's hinges bend in (across their edge, from the warp of their
/// first triangle), each weighted by its hinge's base weight: a histogram over half a
/// turn. A mesher's hinges point every way; a square grid's only along the warp, the
/// weft and one diagonal. What [`HingeShares`] fits a fabric's anisotropy to.
#[derive(Clone, Debug, PartialEq)]
pub struct HingeDirections {
    bins: [f64; DIRECTION_BINS],
}

impl Default for HingeDirections {
    fn default() -> Self {
        Self {
            bins: [0.0; DIRECTION_BINS],
        }
    }
}

impl HingeDirections {
    /// Every direction alike (a mesh whose hinges point every way).
    #[cfg(test)]
    pub fn uniform() -> Self {
        Self {
            bins: [1.0; DIRECTION_BINS],
        }
    }

    /// Counts a hinge of base weight `weight` bending at `θ` from the warp, given `cos θ`
    /// and `sin θ` (the sign of each does not matter: half a turn apart is the same).
    pub fn add(&mut self, cos: f32, sin: f32, weight: f32) {
        if !(weight.is_finite() && weight > 0.0) {
            return;
        }
        // Bins centred on multiples of five degrees: a grid's warp, weft and diagonal
        // each fall in one, whatever the rounding.
        let th = (sin as f64)
            .atan2(cos as f64)
            .rem_euclid(std::f64::consts::PI);
        let k =
            (th / std::f64::consts::PI * DIRECTION_BINS as f64).round() as usize % DIRECTION_BINS;
        self.bins[k] += weight as f64;
    }

    /// How evenly the hinges' directions spread, 0 to 1: 1 when no few directions hold
    /// most of the weight (a mesher's), 0 when four bins of five degrees hold 90% or more
    /// (a square grid's warp, weft and diagonal).
    fn spread(&self) -> f32 {
        let total: f64 = self.bins.iter().sum();
        if total <= 0.0 {
            return 1.0;
        }
        let mut sorted = self.bins;
        sorted.sort_by(|a, b| b.total_cmp(a));
        let top4 = sorted[..4].iter().sum::<f64>() / total;
        // Evenly spread, four bins hold 4/36 = 0.11 of the weight.
        (((0.9 - top4) / (0.9 - 0.3)).clamp(0.0, 1.0)) as f32
    }

    /// The coefficients `[a0, a2, a4]` of a hinge's share `a0 + a2 cos 2θ + a4 cos 4θ`
    /// for `m`'s anisotropy on these directions (see [`HingeShares`]).
    fn fit(&self, m: &Material) -> [f32; 3] {
        let (w, b) = (m.bending_weft, m.bending_bias);
        let mixed = 2.0 * b - 0.5 * (1.0 + w);
        // B(θ) = b0 + b2 cos 2θ + b4 cos 4θ (warp 1, weft w, the bias through `mixed`).
        let plain = [
            (3.0 + 3.0 * w + 2.0 * mixed) / 8.0,
            (1.0 - w) / 2.0,
            (1.0 + w - 2.0 * mixed) / 8.0,
        ];
        let even = [plain[0], 1.5 * plain[1], 6.0 * plain[2]];
        let at = |t: f32| -> [f32; 3] { [0, 1, 2].map(|k| plain[k] + t * (even[k] - plain[k])) };
        let floor = 0.05 * w.min(1.0);
        let positive = |c: [f32; 3]| {
            (0..=90).all(|i| {
                let th = i as f32 / 90.0 * std::f32::consts::FRAC_PI_2;
                c[0] + c[1] * (2.0 * th).cos() + c[2] * (4.0 * th).cos() >= floor
            })
        };
        // As far toward the even mesh's correction as the directions' spread allows, and
        // no further than keeps every hinge's share at or over the floor (a bias much
        // softer than the mean of warp and weft would need hinges of negative weight).
        let mut t = self.spread();
        if !positive(at(t)) {
            let (mut lo, mut hi) = (0.0f32, t);
            for _ in 0..20 {
                let mid = 0.5 * (lo + hi);
                if positive(at(mid)) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            t = lo;
        }
        at(t)
    }
}

/// How much of a fabric's rigidity each bending hinge takes, by the direction `θ` it
/// bends in: `a0 + a2 cos 2θ + a4 cos 4θ`, chosen for the mesh's own hinge directions so
/// that the hinges together bend as the fabric does ([`Material::bending_share`]).
///
/// A bend of curvature κ in direction φ bends a hinge of direction θ by about
/// κ cos²(θ - φ), so its energy goes as cos⁴(θ - φ). On a mesh whose hinges point every
/// way (the mesher's) a hinge weighted by `B(θ)` itself therefore takes a share of the
/// other directions' rigidity: a warp bend of a fabric whose weft is three times stiffer
/// came out 1.6x the warp's rigidity (Peirce's cantilever, `tests/fabrics.rs`). Summed
/// against cos⁴ over every direction, a share keeps its mean, 2/3 of its cos 2θ part and
/// 1/6 of its cos 4θ part, so there each hinge takes `B(θ)`'s mean, 3/2 of its cos 2θ
/// part and 6 times its cos 4θ part, and the sum is `B(φ)` in every direction. A square
/// grid's hinges bend along the warp, the weft and one diagonal only, and there `B(θ)`
/// itself is exact: a grid rolled along the warp costs the warp's rigidity and along the
/// weft the weft's (a test). Between the two, by how evenly the mesh's directions spread
/// ([`HingeDirections`]), and never so far that a hinge's share falls under a twentieth
/// of the softer of warp and weft (a bias much softer than their mean would need hinges
/// of negative weight). One choice per material (the solver's and each zone's) over the
/// whole mesh's directions.
#[derive(Clone, Debug, PartialEq)]
pub struct HingeShares {
    base: [f32; 3],
    zones: Vec<[f32; 3]>,
}

impl HingeShares {
    /// Fits `material` (the solver's) and each zone's material to `dirs`.
    pub fn fit(dirs: &HingeDirections, material: &Material, zones: &MaterialZones) -> Self {
        let one = |m: &Material| {
            if m.isotropic_bending() {
                [1.0, 0.0, 0.0]
            } else {
                dirs.fit(m)
            }
        };
        Self {
            base: one(material),
            zones: zones.zones().iter().map(|z| one(&z.material)).collect(),
        }
    }

    /// The share of a hinge of `own` (its triangle's material, zone `zone`) bending at
    /// `θ` from the warp, given `cos²θ`.
    fn share(&self, zone: Option<usize>, own: &Material, cos2: f32) -> f32 {
        let a = zone
            .and_then(|z| self.zones.get(z))
            .copied()
            .unwrap_or(self.base);
        let c2t = 2.0 * cos2.clamp(0.0, 1.0) - 1.0;
        let c4t = 2.0 * c2t * c2t - 1.0;
        (a[0] + a[1] * c2t + a[2] * c4t).max(0.05 * own.bending_weft.min(1.0))
    }
}

/// The direction a hinge bends in, from the warp: `(cos θ, sin θ)` in its triangle's
/// material frame, for a hinge whose (rest) edge is `edge` and whose first triangle has
/// warp `warp` and normal `normal`.
fn bend_direction(edge: Vec3, warp: Vec3, normal: Vec3) -> (f32, f32) {
    let e = edge.normalize_or(Vec3::X);
    let weft = normal
        .normalize_or(Vec3::Y)
        .cross(warp)
        .normalize_or(Vec3::Z);
    // The bending direction is across the edge: turn the edge's angle by a quarter.
    let (ce, se) = (e.dot(warp), e.dot(weft));
    (-se, ce)
}

/// Scales a hinge's weight by its material's rigidity in the direction it bends: across
/// its edge `edge` (rest), at `warp` (the warp direction of its first triangle, whose
/// rest corners are `rest`), with the share `shares` fitted for the mesh, and by that
/// triangle's zone's rigidity over `material`'s (the solver's). A hinge across a seam
/// between two fabrics takes its first triangle's.
pub fn orient_bend(
    b: &mut BendConstraint,
    material: &Material,
    zones: &MaterialZones,
    shares: &HingeShares,
    rest: &[Vec3; 3],
    warp: Vec3,
    edge: Vec3,
) {
    let own = zones.material_at(rest, material);
    b.weight *= zones.scales(rest, material).bending;
    if own.isotropic_bending() {
        return;
    }
    // The hinge bends the yarns that cross its edge: cos² of the angle between the
    // bending direction and the warp is sin² of the edge's angle to the warp.
    let along = edge.normalize_or(Vec3::X).dot(warp);
    b.weight *= shares.share(zones.zone_index(rest), own, 1.0 - along * along);
}

fn cot(a: Vec3, b: Vec3) -> f32 {
    let s = a.cross(b).length();
    if s < 1e-20 { 0.0 } else { a.dot(b) / s }
}

/// Bending constraints for every interior edge, weighted for their material's
/// anisotropy (fitted to this mesh's hinge directions) and zone (`material` is the
/// solver's).
pub fn build_bending(
    mesh: &ClothMesh,
    topology: &Topology,
    material: &Material,
    zones: &MaterialZones,
) -> Vec<BendConstraint> {
    let raw: Vec<(BendConstraint, [Vec3; 3], Vec3)> = topology
        .hinges
        .iter()
        .filter_map(|h| {
            let [x0, x1, x2, x3] = h.v.map(|i| mesh.positions[i as usize]);
            let b = bend_of(h.v, [x0, x1, x2], [x0, x1, x3])?;
            let uv = [h.v[0], h.v[1], h.v[2]].map(|i| mesh.uvs[i as usize]);
            Some((b, [x0, x1, x2], warp_of([x0, x1, x2], uv)))
        })
        .collect();
    let shares = HingeShares::fit(&directions(&raw), material, zones);
    raw.into_iter()
        .map(|(mut b, r, warp)| {
            orient_bend(&mut b, material, zones, &shares, &r, warp, r[1] - r[0]);
            b
        })
        .collect()
}

/// The bending directions of hinges `(hinge, first triangle's rest corners, its warp)`.
fn directions(raw: &[(BendConstraint, [Vec3; 3], Vec3)]) -> HingeDirections {
    let mut d = HingeDirections::default();
    for (b, r, warp) in raw {
        let normal = (r[1] - r[0]).cross(r[2] - r[0]);
        let (c, s) = bend_direction(r[1] - r[0], *warp, normal);
        d.add(c, s, b.weight);
    }
    d
}

/// The hinge `v = [a, b, c, d]` between triangles `(a, b, c)` and `(a, b, d)`, from each
/// triangle's own rest corners (`r0` for `a, b, c`; `r1` for `a, b, d`). When the two agree
/// on the shared edge the rest shape is theirs; otherwise (a seam between two pattern
/// pieces) the hinge rests flat.
pub fn bend_of(v: [u32; 4], r0: [Vec3; 3], r1: [Vec3; 3]) -> Option<BendConstraint> {
    let [x0, x1, x2] = r0;
    let e0 = x1 - x0;
    let e1 = x2 - x0;
    let e3 = x2 - x1;
    let f0 = r1[1] - r1[0];
    let e2 = r1[2] - r1[0];
    let e4 = r1[2] - r1[1];
    let c01 = cot(e0, e1);
    let c02 = cot(f0, e2);
    let c03 = cot(-e0, e3);
    let c04 = cot(-f0, e4);
    let a0 = 0.5 * e0.cross(e1).length();
    let a1 = 0.5 * f0.cross(e2).length();
    if a0 + a1 <= 1e-20 {
        return None;
    }
    let k = [c03 + c04, c01 + c02, -c01 - c03, -c02 - c04];
    let same_edge =
        (r0[0] - r1[0]).length() + (r0[1] - r1[1]).length() <= 1e-6 * (1.0 + e0.length());
    let rest = if same_edge {
        x0 * k[0] + x1 * k[1] + x2 * k[2] + r1[2] * k[3]
    } else {
        Vec3::ZERO
    };
    Some(BendConstraint {
        v,
        key: edge_key(v[0], v[1]),
        k,
        rest,
        weight: 1.0 / (a0 + a1),
    })
}

/// Total bending energy of positions `x` for rigidity `b`, J.
pub fn bending_energy(bends: &[BendConstraint], x: &[Vec3], b: f32) -> f64 {
    bends
        .iter()
        .map(|c| {
            let cv =
                c.v.iter()
                    .zip(c.k)
                    .map(|(&i, k)| x[i as usize] * k)
                    .sum::<Vec3>()
                    - c.rest;
            0.5 * (b * c.weight) as f64 * cv.length_squared() as f64
        })
        .sum()
}

/// The bending hinge of the live mesh's edge `key`, unweighted: the hinge, its first
/// triangle's rest corners and warp.
fn live_hinge(live: &LiveMesh, key: u64) -> Option<(BendConstraint, [Vec3; 3], Vec3)> {
    let (v, r0, r1) = live.hinge(key)?;
    let b = bend_of(v, r0, r1)?;
    let warp = live.hinge_warp(key).unwrap_or(Vec3::X);
    Some((b, r0, warp))
}

/// The bending hinge of the live mesh's edge `key`, weighted for its material
/// (`material` is the solver's; `shares` fitted when the elements were built).
pub fn live_bend(
    live: &LiveMesh,
    key: u64,
    material: &Material,
    zones: &MaterialZones,
    shares: &HingeShares,
) -> Option<BendConstraint> {
    let (mut b, r0, warp) = live_hinge(live, key)?;
    orient_bend(&mut b, material, zones, shares, &r0, warp, r0[1] - r0[0]);
    Some(b)
}

/// The elements of a live mesh: what every model built on this energy (xpbd, implicit,
/// vbd) starts from.
#[derive(Clone, Debug)]
pub struct Elements {
    pub membranes: Vec<Membrane>,
    pub bends: Vec<BendConstraint>,
    /// The hinges' shares of an anisotropic fabric, fitted to this mesh: hinges made
    /// later by an edit take the same ([`live_bend`]).
    pub shares: HingeShares,
}

/// The membranes and bending hinges of a live mesh, each weighted for its zone against
/// `material` (the solver's), the hinges' anisotropy fitted to the mesh's directions.
pub fn elements_of(live: &LiveMesh, material: &Material, zones: &MaterialZones) -> Elements {
    let membranes = live
        .iter()
        .map(|(slot, t)| {
            weigh_membrane(
                membrane_of(t.v, slot, t.rest, t.uv),
                zones,
                material,
                &t.rest,
            )
        })
        .collect();
    let raw: Vec<(BendConstraint, [Vec3; 3], Vec3)> = live
        .hinge_keys()
        .into_iter()
        .filter_map(|k| live_hinge(live, k))
        .collect();
    let shares = HingeShares::fit(&directions(&raw), material, zones);
    let bends = raw
        .into_iter()
        .map(|(mut b, r, warp)| {
            orient_bend(&mut b, material, zones, &shares, &r, warp, r[1] - r[0]);
            b
        })
        .collect();
    Elements {
        membranes,
        bends,
        shares,
    }
}

#[cfg(test)]
mod tests;
