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

/// `m` with its zone's stiffness over `material`'s (the solver's).
pub fn weigh_membrane(
    mut m: Membrane,
    zones: &MaterialZones,
    material: &Material,
    rest: &[Vec3; 3],
) -> Membrane {
    let s = zones.scales(rest, material);
    m.ks = s.stretch;
    m.kg = s.shear;
    m
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
    }
}

/// Scales a hinge's weight by its material's rigidity in the direction it bends: across
/// its edge `edge` (rest), at `warp` (the warp direction of its first triangle, whose
/// rest corners are `rest`), and by that triangle's zone's rigidity over `material`'s
/// (the solver's). A hinge across a seam between two fabrics takes its first triangle's.
pub fn orient_bend(
    b: &mut BendConstraint,
    material: &Material,
    zones: &MaterialZones,
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
    b.weight *= own.hinge_bending_share(1.0 - along * along);
}

fn cot(a: Vec3, b: Vec3) -> f32 {
    let s = a.cross(b).length();
    if s < 1e-20 { 0.0 } else { a.dot(b) / s }
}

/// Bending constraints for every interior edge, weighted for their material's
/// anisotropy and zone (`material` is the solver's).
pub fn build_bending(
    mesh: &ClothMesh,
    topology: &Topology,
    material: &Material,
    zones: &MaterialZones,
) -> Vec<BendConstraint> {
    topology
        .hinges
        .iter()
        .filter_map(|h| {
            let [x0, x1, x2, x3] = h.v.map(|i| mesh.positions[i as usize]);
            let mut b = bend_of(h.v, [x0, x1, x2], [x0, x1, x3])?;
            let uv = [h.v[0], h.v[1], h.v[2]].map(|i| mesh.uvs[i as usize]);
            let warp = warp_of([x0, x1, x2], uv);
            orient_bend(&mut b, material, zones, &[x0, x1, x2], warp, x1 - x0);
            Some(b)
        })
        .collect()
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

/// The bending hinge of the live mesh's edge `key`, weighted for its material
/// (`material` is the solver's).
pub fn live_bend(
    live: &LiveMesh,
    key: u64,
    material: &Material,
    zones: &MaterialZones,
) -> Option<BendConstraint> {
    let (v, r0, r1) = live.hinge(key)?;
    let mut b = bend_of(v, r0, r1)?;
    let warp = live.hinge_warp(key).unwrap_or(Vec3::X);
    orient_bend(&mut b, material, zones, &r0, warp, r0[1] - r0[0]);
    Some(b)
}

/// The membranes and bending hinges of a live mesh, the elements every model built on
/// this energy (xpbd, implicit, vbd) starts from, each weighted for its zone against
/// `material` (the solver's).
pub fn elements_of(
    live: &LiveMesh,
    material: &Material,
    zones: &MaterialZones,
) -> (Vec<Membrane>, Vec<BendConstraint>) {
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
    let bends = live
        .hinge_keys()
        .into_iter()
        .filter_map(|k| live_bend(live, k, material, zones))
        .collect();
    (membranes, bends)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_state_satisfies_every_constraint() {
        let m = ClothMesh::grid(1.0, 0.7, 7, 5, 0.3).unwrap();
        for mem in build_membranes(&m, &MaterialZones::default(), &Material::default()) {
            let x = mem.v.map(|i| m.positions[i as usize]);
            let fu: Vec3 = (0..3).map(|a| x[a] * mem.c[a]).sum();
            let fv: Vec3 = (0..3).map(|a| x[a] * mem.d[a]).sum();
            assert!(
                (fu.length() - 1.0).abs() < 1e-4
                    && (fv.length() - 1.0).abs() < 1e-4
                    && fu.dot(fv).abs() < 1e-4
            );
            // Warp follows +U (the grid's +X).
            assert!(fu.x > 0.99, "{fu}");
        }
        let t = Topology::build(&m.triangles).unwrap();
        assert!(
            bending_energy(
                &build_bending(&m, &t, &Material::default(), &MaterialZones::default()),
                &m.positions,
                1.0
            ) < 1e-9
        );
    }

    #[test]
    fn stretching_along_warp_is_measured() {
        let m = ClothMesh::grid(1.0, 1.0, 4, 4, 0.0).unwrap();
        for mem in build_membranes(&m, &MaterialZones::default(), &Material::default()) {
            let x = mem
                .v
                .map(|i| m.positions[i as usize] * Vec3::new(1.1, 1.0, 1.0));
            let fu: Vec3 = (0..3).map(|a| x[a] * mem.c[a]).sum();
            let fv: Vec3 = (0..3).map(|a| x[a] * mem.d[a]).sum();
            assert!((fu.length() - 1.1).abs() < 1e-4 && (fv.length() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn bending_energy_matches_a_cylinder() {
        // Roll a 0.3 x 0.3 sheet onto a cylinder of radius R around the Z axis; the
        // continuum energy is B/2 * integral (1/R)^2 dA = B A / (2 R^2).
        let (w, r, b) = (0.3f32, 0.5f32, 2.0e-5f32);
        let m = ClothMesh::grid(w, w, 60, 60, 0.0).unwrap();
        let t = Topology::build(&m.triangles).unwrap();
        let bends = build_bending(&m, &t, &Material::default(), &MaterialZones::default());
        let rolled: Vec<Vec3> = m
            .positions
            .iter()
            .map(|p| {
                let th = p.x / r;
                Vec3::new(r * th.sin(), r * (1.0 - th.cos()), p.z)
            })
            .collect();
        let got = bending_energy(&bends, &rolled, b);
        let want = (b * w * w / (2.0 * r * r)) as f64;
        // Boundary hinges are missing from a finite sheet: allow a few percent.
        assert!(
            (got / want - 1.0).abs() < 0.06,
            "discrete {got} continuum {want}"
        );
    }

    /// A sheet rolled so its warp bends costs the warp rigidity; rolled the other way,
    /// the weft's (three times more here), up to the diagonal hinges' share.
    #[test]
    fn anisotropic_bending_follows_the_grain() {
        let (w, r) = (0.3f32, 0.5f32);
        let m = ClothMesh::grid(w, w, 40, 40, 0.0).unwrap();
        let t = Topology::build(&m.triangles).unwrap();
        let roll = |along_x: bool| -> Vec<Vec3> {
            m.positions
                .iter()
                .map(|p| {
                    let s = if along_x { p.x } else { p.z };
                    let th = s / r;
                    let (a, h) = (r * th.sin(), r * (1.0 - th.cos()));
                    if along_x {
                        Vec3::new(a, h, p.z)
                    } else {
                        Vec3::new(p.x, h, a)
                    }
                })
                .collect()
        };
        let iso = Material::default();
        let aniso = Material {
            bending_weft: 3.0,
            bending_bias: 2.0,
            ..Material::default()
        };
        let energy = |mat: &Material, along_x: bool| {
            bending_energy(
                &build_bending(&m, &t, mat, &MaterialZones::default()),
                &roll(along_x),
                1.0,
            )
        };
        let (iw, if_) = (energy(&iso, true), energy(&iso, false));
        assert!((iw / if_ - 1.0).abs() < 0.02, "isotropic: {iw} {if_}");
        let (aw, af) = (energy(&aniso, true), energy(&aniso, false));
        // Warp roll: at least the warp's, less than the bias's; weft roll: above the bias's.
        assert!(aw >= 0.99 * iw && aw < 2.0 * iw, "{aw} {iw}");
        assert!(af > 2.0 * if_ && af <= 3.01 * if_, "{af} {if_}");
    }
}
