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

/// Each triangle takes its piece's strain limit: a knit's band none, the rest the
/// cloth's.
#[test]
fn a_triangle_takes_its_fabrics_strain_limit() {
    use crate::solver::zones::Zone;
    let m = ClothMesh::grid(1.0, 0.5, 8, 4, 0.0).unwrap();
    let woven = Material::default();
    let knit = Material {
        strain_limit: 0.0,
        ..woven
    };
    // The grid spans x -0.5..0.5: its left half a knit.
    let zones = MaterialZones::new(
        vec![Zone {
            lo: -0.6,
            hi: 0.0,
            material: knit,
        }],
        &woven,
    )
    .unwrap();
    assert!(!zones.is_empty(), "a limit alone makes a zone");
    let (mut left, mut right) = (0, 0);
    for mem in build_membranes(&m, &zones, &woven) {
        let x = mem.v.map(|i| m.positions[i as usize].x).iter().sum::<f32>() / 3.0;
        if x < 0.0 {
            assert_eq!(mem.s_max, f32::INFINITY);
            left += 1;
        } else {
            assert_eq!(mem.s_max, 1.0 + woven.strain_limit);
            right += 1;
        }
    }
    assert!(left > 10 && right > 10, "{left} {right}");
    assert_eq!(s_max_of(0.0), f32::INFINITY);
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
    // The grid's hinges bend in three directions only, and each takes B(θ) itself
    // there: the warp roll costs the warp's rigidity, the weft roll three times it.
    eprintln!(
        "grid: warp roll {:.3}, weft roll {:.3} x isotropic",
        aw / iw,
        af / if_
    );
    assert!((aw / iw - 1.0).abs() < 0.02, "{aw} {iw}");
    assert!((af / if_ / 3.0 - 1.0).abs() < 0.02, "{af} {if_}");
}

/// On hinges that bend every way (a mesher's), the shares are `B(θ)`'s mean,
/// 3/2 of its cos 2θ part and 6 times its cos 4θ part, and summed against cos⁴ over
/// the directions they give `B(φ)` back in every direction `φ`.
#[test]
fn fitted_shares_sum_back_to_the_fabric_on_every_direction() {
    let m = Material {
        bending_weft: 3.0,
        bending_bias: 1.8,
        ..Material::default()
    };
    let shares = HingeShares::fit(&HingeDirections::uniform(), &m, &MaterialZones::default());
    let (w, b) = (3.0f32, 1.8f32);
    let mixed = 2.0 * b - 0.5 * (1.0 + w);
    let analytic = [
        (3.0 + 3.0 * w + 2.0 * mixed) / 8.0,
        1.5 * (1.0 - w) / 2.0,
        6.0 * (1.0 + w - 2.0 * mixed) / 8.0,
    ];
    for k in 0..3 {
        assert!(
            (shares.base[k] - analytic[k]).abs() < 0.02,
            "{:?} {analytic:?}",
            shares.base
        );
    }
    for phi in [
        0.0f32,
        0.3,
        std::f32::consts::FRAC_PI_4,
        1.2,
        std::f32::consts::FRAC_PI_2,
    ] {
        let n = 3600;
        let avg = (0..n)
            .map(|k| {
                let th = k as f32 / n as f32 * std::f32::consts::TAU;
                shares.share(None, &m, th.cos().powi(2)) * (th - phi).cos().powi(4)
            })
            .sum::<f32>()
            / n as f32;
        let want = m.bending_share(phi.cos().powi(2)) * 3.0 / 8.0;
        assert!((avg / want - 1.0).abs() < 0.02, "{phi}: {avg} {want}");
    }
    // A bias much softer than the mean of warp and weft would need hinges of negative
    // weight: the shares stop short of that, every hinge at or over the floor.
    let soft = Material {
        bending_bias: 1.2,
        ..m
    };
    let shares = HingeShares::fit(
        &HingeDirections::uniform(),
        &soft,
        &MaterialZones::default(),
    );
    for i in 0..=180 {
        let th = i as f32 / 180.0 * std::f32::consts::PI;
        assert!(shares.share(None, &soft, th.cos().powi(2)) >= 0.05 - 1e-6);
    }
    // An isotropic fabric's hinges all take one, on any mesh.
    let iso = HingeShares::fit(
        &HingeDirections::default(),
        &Material::default(),
        &MaterialZones::default(),
    );
    assert_eq!(iso.base, [1.0, 0.0, 0.0]);
}
