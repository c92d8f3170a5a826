//! Long-range attachments (Kim, Chentanez & Mueller 2012): unilateral tethers from free
//! vertices to their nearest pins, and the stretch limits' setup, both with the slack of
//! the material's own strain under the cloth's weight.

use glam::Vec3;

use super::graph::{Bounded, RestGraph};
use super::limits::StretchLimits;
use crate::mesh::bounds;
use crate::solver::material::Material;
use crate::solver::state::Cloth;

/// The slack of tethers and stretch limits: the strain the material itself takes under
/// the cloth's full weight (`density * g * extent / stretch`); with pieces of several
/// fabrics (zones), the stretchiest's, so no link holds a soft piece tighter than its
/// fabric would (a stiff piece then gets less of their help).
pub(super) fn own_strain(cloth: &Cloth, material: &Material) -> f32 {
    let (mn, mx) = bounds(&cloth.rest.positions);
    let extent = (mx - mn).length();
    let (density, stretch) = cloth
        .zones
        .zones()
        .iter()
        .map(|z| (z.material.density, z.material.stretch))
        .fold((material.density, material.stretch), |a, b| {
            if b.0 * a.1 > a.0 * b.1 { b } else { a }
        });
    density * 9.81 * extent / stretch
}

/// The long-range stretch limits for `cloth` (none when they are off), with the same
/// slack as the tethers: what the material itself stretches under the cloth's weight.
pub(super) fn stretch_limits(
    cloth: &Cloth,
    material: &Material,
    keep: Option<StretchLimits>,
) -> StretchLimits {
    if !material.stretch_limits {
        return StretchLimits::default();
    }
    let strain = own_strain(cloth, material);
    match keep {
        Some(mut limits) if !limits.is_empty() => {
            limits.set_strain(strain);
            limits
        }
        _ => StretchLimits::build(cloth, strain),
    }
}

/// Unilateral tethers: pull a vertex back inside its sphere around the pin.
pub(super) fn solve_tethers(tethers: &[(u32, u32, f32)], x: &mut [Vec3]) {
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
