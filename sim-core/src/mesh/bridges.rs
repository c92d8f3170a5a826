//! Vertices near each other over the cloth but far apart in the pattern: the two sides of
//! a seam's weld. Contact leaves out pairs that are neighbours in the pattern (a cloth
//! does not push against its own next triangle), and measures that in the pattern; a weld
//! joins two places of the pattern that lie apart, so without this the triangles on the
//! two sides of a sewn seam would push each other apart to the cloth's thickness while
//! the seam holds them together, and a sewn garment crumples (the fit-cube's flaps did).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::Vec3;

use super::live::LiveMesh;

/// Two rest places closer than this are the same place of the pattern, m.
const SAME_PLACE: f32 = 1e-6;

/// A vertex and how far from the search's start, for the heap (nearest first).
#[derive(Clone, Copy, PartialEq)]
struct Reach(f32, u32);

impl Eq for Reach {}

impl Ord for Reach {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Reach {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl LiveMesh {
    /// For each of `n` vertices, the vertices within `radius` of it along the cloth's
    /// edges (rest lengths) through a vertex the pattern places at two places or more (a
    /// weld), that lie `radius` or more apart at their `places` in the pattern: the
    /// neighbours the pattern's distance misses. Sorted; empty for a vertex far from
    /// every weld (most of them).
    pub fn bridged_neighbours(&self, n: usize, places: &[Vec3], radius: f32) -> Vec<Vec<u32>> {
        let mut out = vec![Vec::new(); n];
        if places.len() < n || radius <= 0.0 {
            return out;
        }
        // The edges with their rest lengths, and the vertices at two places.
        let mut adj: Vec<Vec<(u32, f32)>> = vec![Vec::new(); n];
        let mut joined = vec![false; n];
        for (_, t) in self.iter() {
            for k in 0..3 {
                let (a, b) = (t.v[k] as usize, t.v[(k + 1) % 3] as usize);
                if a >= n || b >= n {
                    continue;
                }
                let len = (t.rest[k] - t.rest[(k + 1) % 3]).length();
                adj[a].push((b as u32, len));
                adj[b].push((a as u32, len));
                if (t.rest[k] - places[a]).length() > SAME_PLACE {
                    joined[a] = true;
                }
            }
        }
        let mut dist = vec![f32::INFINITY; n];
        let mut reached: Vec<(u32, f32)> = Vec::new();
        let mut heap = BinaryHeap::new();
        for s in (0..n).filter(|&s| joined[s]) {
            // Every vertex within `radius` of the weld (edge paths: never shorter than
            // over the cloth, so this may miss a neighbour, never invent one).
            reached.clear();
            dist[s] = 0.0;
            heap.push(Reach(0.0, s as u32));
            while let Some(Reach(d, v)) = heap.pop() {
                if d > dist[v as usize] {
                    continue;
                }
                reached.push((v, d));
                for &(w, len) in &adj[v as usize] {
                    let dw = d + len;
                    if dw < radius && dw < dist[w as usize] {
                        dist[w as usize] = dw;
                        heap.push(Reach(dw, w));
                    }
                }
            }
            for &(v, _) in &reached {
                dist[v as usize] = f32::INFINITY;
            }
            for (i, &(u, du)) in reached.iter().enumerate() {
                for &(w, dw) in &reached[i + 1..] {
                    if du + dw < radius
                        && (places[u as usize] - places[w as usize]).length() >= radius
                    {
                        out[u as usize].push(w);
                        out[w as usize].push(u);
                    }
                }
            }
        }
        for list in &mut out {
            list.sort_unstable();
            list.dedup();
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::mesh::{ClothMesh, LiveMesh};

    /// Two strips of one row of cells side by side in the pattern, 10 cm apart, each
    /// 1 cm cells; `weld` joins the first strip's right end to the second's left end.
    fn strips(weld: bool) -> (LiveMesh, Vec<Vec3>) {
        let mesh = ClothMesh::grid(0.21, 0.01, 21, 1, 0.0).unwrap();
        let mut live = LiveMesh::from_mesh(&mesh);
        // Cut the middle cells away: two strips of 5 cells, the gap between them 11 cm.
        let cut: Vec<u32> = live
            .iter()
            .filter(|(_, t)| {
                let c = (t.rest[0] + t.rest[1] + t.rest[2]) / 3.0;
                c.x > -0.055 && c.x < 0.055
            })
            .map(|(s, _)| s)
            .collect();
        for s in cut {
            live.set(s, None).unwrap();
        }
        let places = live.pattern_places(mesh.positions.len());
        if weld {
            // Vertex 5 (x = -0.055, the first strip's right end, top row) takes the
            // place of vertex 16 (x = 0.055): the second strip's triangles at 16 now
            // name 5.
            let slots: Vec<u32> = live.tris_of(16).to_vec();
            for s in slots {
                let mut t = *live.tri(s).unwrap();
                for v in &mut t.v {
                    if *v == 16 {
                        *v = 5;
                    }
                }
                live.set(s, Some(t)).unwrap();
            }
        }
        (live, places)
    }

    #[test]
    fn the_two_sides_of_a_weld_are_neighbours_and_nothing_else_is() {
        let (live, places) = strips(false);
        let n = places.len();
        assert!(
            live.bridged_neighbours(n, &places, 0.03)
                .iter()
                .all(Vec::is_empty)
        );
        let (live, places) = strips(true);
        let near = live.bridged_neighbours(n, &places, 0.03);
        // 4 (1 cm left of the weld) and 17 (1 cm right of it) are 2 cm apart over the
        // cloth, 13 cm in the pattern.
        assert!(near[4].contains(&17) && near[17].contains(&4), "{near:?}");
        // 3 and 18 are 4 cm apart over the cloth: beyond 3 cm.
        assert!(!near[3].contains(&18));
        // Pairs on one side stay the pattern's business.
        assert!(!near[4].contains(&3));
    }
}
