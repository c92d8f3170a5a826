//! Counting the cloth's self contacts as it is now, whatever model moved it: the pairs of
//! its primitives (a vertex and a triangle not holding it, two edges sharing no vertex)
//! closer than a gap, leaving out pairs that are neighbours in the pattern (in a flat
//! cloth every vertex is that close to the triangles around it). A fold's two layers,
//! or a cut piece lying on another, are what it counts.

use glam::Vec3;

use super::distance::{point_triangle, segment_segment};
use super::grid::{Aabb, BoxGrid, unique_edges};
use super::pairs::grid_cell;

/// Pairs of primitives of the cloth `(x, tris)` closer than `gap`, whose vertices lie at
/// least `exclusion` apart in the pattern (`pattern[v]`: vertex `v`'s place in it).
pub fn count_self_contacts(
    x: &[Vec3],
    tris: &[[u32; 3]],
    pattern: &[Vec3],
    gap: f32,
    exclusion: f32,
) -> usize {
    if gap.is_nan() || gap <= 0.0 || tris.is_empty() || pattern.len() < x.len() {
        return 0;
    }
    let far = |a: &[u32], b: &[u32]| {
        a.iter().all(|&i| {
            b.iter()
                .all(|&j| (pattern[i as usize] - pattern[j as usize]).length() >= exclusion)
        })
    };
    let tri_box = |t: &[u32; 3]| Aabb::of(&t.map(|v| x[v as usize])).grown(gap);
    let mut grid = BoxGrid::default();
    let cell = grid_cell(tris.iter().map(tri_box));
    grid.build(tris.iter().map(tri_box), cell);
    let mut used = vec![false; x.len()];
    for t in tris {
        for &v in t {
            used[v as usize] = true;
        }
    }
    let mut count = 0;
    for (i, &p) in x.iter().enumerate() {
        if !used[i] {
            continue;
        }
        grid.query(&Aabb::point(p), |k| {
            let t = tris[k as usize];
            if t.contains(&(i as u32)) || !far(&[i as u32], &t) {
                return;
            }
            let [a, b, c] = t.map(|v| x[v as usize]);
            if (point_triangle(p, a, b, c).0 - p).length() < gap {
                count += 1;
            }
        });
    }
    let edges = unique_edges(tris);
    let edge_box = |e: &[u32; 2]| Aabb::of(&e.map(|v| x[v as usize])).grown(gap);
    let cell = grid_cell(edges.iter().map(edge_box));
    grid.build(edges.iter().map(edge_box), cell);
    for (k, e) in edges.iter().enumerate() {
        let [p0, p1] = e.map(|v| x[v as usize]);
        grid.query(&Aabb::of(&[p0, p1]), |m| {
            let o = edges[m as usize];
            if m as usize <= k || o.iter().any(|v| e.contains(v)) || !far(e, &o) {
                return;
            }
            let [q0, q1] = o.map(|v| x[v as usize]);
            let (s, t) = segment_segment(p0, p1, q0, q1);
            if (p0.lerp(p1, s) - q0.lerp(q1, t)).length() < gap {
                count += 1;
            }
        });
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two squares of two triangles each, one `h` above the other, each its own pattern
    /// piece far from the other.
    fn layers(h: f32) -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec3>) {
        let mut x = Vec::new();
        for y in [0.0, h] {
            x.extend([
                Vec3::new(0.0, y, 0.0),
                Vec3::new(0.1, y, 0.0),
                Vec3::new(0.1, y, 0.1),
                Vec3::new(0.0, y, 0.1),
            ]);
        }
        let tris = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
        let pattern = (0..8)
            .map(|i| Vec3::new(i as f32 * 10.0, 0.0, 0.0))
            .collect();
        (x, tris, pattern)
    }

    #[test]
    fn layers_closer_than_the_gap_touch_and_farther_ones_do_not() {
        let (x, tris, pattern) = layers(0.002);
        // Each of the 8 vertices over (or under) the 2 triangles of the other layer,
        // within its square (corners on the shared diagonal see both triangles).
        let n = count_self_contacts(&x, &tris, &pattern, 0.004, 0.01);
        assert!(n >= 8, "{n}");
        let (x, tris, pattern) = layers(0.006);
        assert_eq!(count_self_contacts(&x, &tris, &pattern, 0.004, 0.01), 0);
    }

    #[test]
    fn pattern_neighbours_are_not_contacts() {
        let (x, tris, _) = layers(0.002);
        let same_place = vec![Vec3::ZERO; 8];
        assert_eq!(count_self_contacts(&x, &tris, &same_place, 0.004, 0.01), 0);
    }
}
