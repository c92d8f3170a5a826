//! The drape test's measures, from the mesh: the shadow's outline seen from above
//! (the projected mesh's outer envelope round the centre), its area, the drape
//! coefficient, the nodes (folds) and their depths, and a top-view picture.

use glam::{Vec2, Vec3};

/// Directions the outline is sampled in (a quarter of a degree apart).
pub const DIRECTIONS: usize = 1440;

/// The shadow's outline: the farthest the projected mesh reaches from the centre in each
/// of [`DIRECTIONS`] directions (radians from +X towards -Z, as seen from above), m.
pub fn outline(positions: &[Vec3], triangles: &[[u32; 3]], centre: Vec3) -> Vec<f32> {
    let n = DIRECTIONS;
    let step = std::f32::consts::TAU / n as f32;
    let flat = |i: u32| {
        let p = positions[i as usize] - centre;
        Vec2::new(p.x, -p.z)
    };
    let mut r = vec![0.0f32; n];
    let mut seen = std::collections::HashSet::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            if !seen.insert((a, b)) {
                continue;
            }
            let (p, q) = (flat(a), flat(b));
            for end in [p, q] {
                let bin = bin_of(end, step, n);
                r[bin] = r[bin].max(end.length());
            }
            // Every direction the side sweeps through: where its ray crosses the side.
            let (ap, aq) = (angle(p), angle(q));
            let mut span = aq - ap;
            if span > std::f32::consts::PI {
                span -= std::f32::consts::TAU;
            } else if span < -std::f32::consts::PI {
                span += std::f32::consts::TAU;
            }
            let (lo, hi) = if span >= 0.0 {
                (ap, ap + span)
            } else {
                (ap + span, ap)
            };
            let first = (lo / step).ceil() as i64;
            let last = (hi / step).floor() as i64;
            for k in first..=last {
                let th = k as f32 * step;
                let dir = Vec2::new(th.cos(), th.sin());
                if let Some(d) = ray_hits(dir, p, q) {
                    let bin = k.rem_euclid(n as i64) as usize;
                    r[bin] = r[bin].max(d);
                }
            }
        }
    }
    r
}

fn angle(p: Vec2) -> f32 {
    p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU)
}

fn bin_of(p: Vec2, step: f32, n: usize) -> usize {
    ((angle(p) / step).round() as usize) % n
}

/// Distance along the unit ray `dir` from the origin to the segment `p`-`q`, if it
/// crosses it.
fn ray_hits(dir: Vec2, p: Vec2, q: Vec2) -> Option<f32> {
    let e = q - p;
    let den = dir.perp_dot(e);
    if den.abs() < 1e-12 {
        return None;
    }
    let t = p.perp_dot(e) / den;
    let s = p.perp_dot(dir) / den;
    (t >= 0.0 && (-1e-6..=1.0 + 1e-6).contains(&s)).then_some(t)
}

/// The area inside an outline of radii, m².
pub fn area(radii: &[f32]) -> f64 {
    let step = std::f64::consts::TAU / radii.len() as f64;
    radii.iter().map(|&r| 0.5 * (r as f64).powi(2) * step).sum()
}

/// The drape coefficient: `(shadow - disc) / (specimen - disc)`.
pub fn drape_coefficient(shadow: f64, disc_radius: f64, specimen_radius: f64) -> f64 {
    let (ad, as_) = (
        std::f64::consts::PI * disc_radius.powi(2),
        std::f64::consts::PI * specimen_radius.powi(2),
    );
    (shadow - ad) / (as_ - ad)
}

/// One node (fold) of the drape: its direction, radians, and depth, m (how far its crest
/// reaches out beyond the troughs on either side, averaged).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Node {
    pub angle_rad: f32,
    pub depth_m: f32,
}

/// The nodes of an outline: crests standing at least `min_depth` m above the troughs on
/// both sides, after a 5° moving average takes out the mesh's facets.
pub fn nodes(radii: &[f32], min_depth: f32) -> Vec<Node> {
    let n = radii.len();
    let half = (n / 144).max(1); // 2.5° each side
    let smooth: Vec<f32> = (0..n)
        .map(|i| {
            let sum: f32 = (0..=2 * half).map(|k| radii[(i + n + k - half) % n]).sum();
            sum / (2 * half + 1) as f32
        })
        .collect();
    // Alternating extrema round the circle, starting at the global minimum.
    let start = (0..n)
        .min_by(|&a, &b| smooth[a].total_cmp(&smooth[b]))
        .unwrap_or(0);
    let mut ext: Vec<(usize, f32, bool)> = vec![(start, smooth[start], false)];
    for k in 1..=n {
        let i = (start + k) % n;
        let v = smooth[i];
        let last = ext.len() - 1;
        let (_, lv, peak) = ext[last];
        if peak {
            if v >= lv {
                ext[last] = (i, v, true);
            } else {
                ext.push((i, v, false));
            }
        } else if v <= lv {
            ext[last] = (i, v, false);
        } else {
            ext.push((i, v, true));
        }
    }
    // Merge away crest-trough pairs shallower than `min_depth`.
    loop {
        let m = ext.len();
        if m < 3 {
            break;
        }
        let weakest = (1..m - 1)
            .map(|j| (j, (ext[j].1 - ext[j + 1].1).abs()))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match weakest {
            Some((j, d)) if d < min_depth => {
                // Keep the higher crest (or lower trough) of the two pairs it joins.
                let keep_j = if ext[j].2 {
                    ext[j].1 >= ext.get(j + 2).map_or(f32::MIN, |e| e.1)
                } else {
                    ext[j].1 <= ext.get(j + 2).map_or(f32::MAX, |e| e.1)
                };
                if keep_j && j + 2 < m {
                    ext.remove(j + 2);
                    ext.remove(j + 1);
                } else {
                    ext.remove(j + 1);
                    ext.remove(j);
                }
            }
            _ => break,
        }
    }
    let step = std::f32::consts::TAU / n as f32;
    let m = ext.len();
    (0..m)
        .filter(|&j| ext[j].2)
        .map(|j| {
            let before = ext[(j + m - 1) % m].1;
            let after = ext[(j + 1) % m].1;
            Node {
                angle_rad: ext[j].0 as f32 * step,
                depth_m: ext[j].1 - 0.5 * (before + after),
            }
        })
        .filter(|n| n.depth_m >= min_depth)
        .collect()
}

/// A top view of the shadow as an RGBA picture `size` pixels square covering
/// `half_width` m either side of the centre: the shadow dark, the disc lighter, the
/// specimen's flat outline as a ring.
pub fn top_view(
    radii: &[f32],
    disc_radius: f32,
    specimen_radius: f32,
    size: usize,
    half_width: f32,
) -> Vec<u8> {
    let mut rgba = vec![255u8; size * size * 4];
    let n = radii.len();
    let px = 2.0 * half_width / size as f32;
    for j in 0..size {
        for i in 0..size {
            let x = (i as f32 + 0.5) * px - half_width;
            let y = half_width - (j as f32 + 0.5) * px;
            let r = (x * x + y * y).sqrt();
            let th = y.atan2(x).rem_euclid(std::f32::consts::TAU);
            let bin = ((th / std::f32::consts::TAU * n as f32).round() as usize) % n;
            let colour: [u8; 3] = if r <= disc_radius {
                [120, 130, 160]
            } else if r <= radii[bin] {
                [40, 50, 90]
            } else if (r - specimen_radius).abs() < px {
                [170, 170, 170]
            } else {
                [255, 255, 255]
            };
            let o = (j * size + i) * 4;
            rgba[o..o + 3].copy_from_slice(&colour);
        }
    }
    rgba
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat disc's outline is its radius all round, and its area the disc's.
    #[test]
    fn a_flat_disc_casts_its_own_shadow() {
        let outline_pts = crate::mesh::mesher::Outline::ellipse(0.15, 0.15, 0.01);
        let mesh = crate::mesh::mesher::mesh_outline(&outline_pts, 0.01).expect("mesh");
        let r = outline(&mesh.positions, &mesh.triangles, Vec3::ZERO);
        assert!(r.iter().all(|&x| (x - 0.15).abs() < 2e-4), "{r:?}");
        let a = area(&r);
        let want = std::f64::consts::PI * 0.15f64.powi(2);
        assert!((a / want - 1.0).abs() < 3e-3, "{a} {want}");
        assert!((drape_coefficient(a, 0.09, 0.15) - 1.0).abs() < 0.01);
    }

    /// A star of eight crests is eight nodes with their depth; a wobble under the
    /// threshold is none.
    #[test]
    fn crests_are_counted_with_their_depth() {
        let r: Vec<f32> = (0..DIRECTIONS)
            .map(|i| {
                let th = i as f32 / DIRECTIONS as f32 * std::f32::consts::TAU;
                0.12 + 0.02 * (8.0 * th).cos() + 0.0005 * (50.0 * th).sin()
            })
            .collect();
        let found = nodes(&r, 0.005);
        assert_eq!(found.len(), 8, "{found:?}");
        for n in &found {
            assert!((n.depth_m - 0.04).abs() < 0.004, "{n:?}");
        }
        let flat: Vec<f32> = (0..DIRECTIONS)
            .map(|i| 0.12 + 0.001 * (i as f32 * 0.05).sin())
            .collect();
        assert!(nodes(&flat, 0.005).is_empty());
    }
}
