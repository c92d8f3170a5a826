//! The body's side of the proximity search: its triangles, edges and vertices, each in a
//! spatial hash built once (a body never moves), so a cloth vertex finds the body
//! triangles near it, a cloth edge the body edges, and a cloth triangle the body's
//! corners, without touching the rest of the body.
//!
//! Only the body's *creases* are listed as edges, and only vertices on a crease as
//! corners: an edge whose two faces lie in one plane (within `FLAT`) cannot poke between
//! cloth vertices that each keep clear of those faces (a segment between two points
//! above a plane stays above it), so a cube's faces, however finely triangulated, give
//! their twelve rims and eight corners and nothing else.

use glam::Vec3;

use super::grid::{Aabb, BoxGrid, unique_edges};

/// The angle between two faces' normals under which their edge is flat, rad: a cloth
/// edge of length `L` lying over such an edge dips at most `L * FLAT / 4` toward it, under
/// the least separation (0.1 mm) for `L` up to 0.4 m.
const FLAT: f32 = 1.0e-3;

/// A body's primitives in three hashes.
#[derive(Clone, Debug, Default)]
pub struct BodyGrids {
    /// The creases.
    pub edges: Vec<[u32; 2]>,
    /// The vertices on a crease (body vertex indices; `vertices` holds their slots).
    pub corners: Vec<u32>,
    pub triangles: BoxGrid,
    pub edge_grid: BoxGrid,
    pub vertices: BoxGrid,
}

impl BodyGrids {
    /// The hashes of an (already checked) closed surface.
    pub fn new(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        let mut edges = unique_edges(triangles);
        let at = |i: u32| vertices[i as usize];
        // Each edge's faces' normals; an edge is a crease when they differ.
        let mut normals: std::collections::HashMap<[u32; 2], (Vec3, Vec3)> =
            std::collections::HashMap::with_capacity(edges.len());
        for t in triangles {
            let [a, b, c] = t.map(at);
            let n = (b - a).cross(c - a).normalize_or_zero();
            for [u, v] in [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]] {
                let e = normals
                    .entry([u.min(v), u.max(v)])
                    .or_insert((n, Vec3::ZERO));
                if e.0 != n {
                    e.1 = n;
                }
            }
        }
        let crease = |e: &[u32; 2]| {
            normals
                .get(e)
                .is_none_or(|(a, b)| *b == Vec3::ZERO || a.dot(*b) < FLAT.cos())
        };
        edges.retain(crease);
        let mut corners: Vec<u32> = edges.iter().flatten().copied().collect();
        corners.sort_unstable();
        corners.dedup();
        let mean_edge = if edges.is_empty() {
            0.01
        } else {
            edges
                .iter()
                .map(|&[a, b]| (at(a) - at(b)).length())
                .sum::<f32>()
                / edges.len() as f32
        };
        // Cells of about two edges: a triangle covers a few, a cloth vertex's box one or two.
        let cell = (2.0 * mean_edge).max(0.01);
        let mut g = Self {
            edges,
            corners,
            ..Self::default()
        };
        g.triangles
            .build(triangles.iter().map(|t| Aabb::of(&t.map(at))), cell);
        g.edge_grid
            .build(g.edges.iter().map(|e| Aabb::of(&e.map(at))), cell);
        g.vertices
            .build(g.corners.iter().map(|&i| Aabb::point(at(i))), cell);
        g
    }
}
