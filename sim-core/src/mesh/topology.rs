//! Edges and hinges (pairs of triangles sharing an edge) of a triangle mesh.

use super::edge::{edge_ends, edge_key};
use crate::error::GeometryError;

/// A unique undirected edge `(a < b)` with the triangles on each side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge {
    pub a: u32,
    pub b: u32,
    /// Triangles beside the edge; `tris[1] == u32::MAX` on a boundary edge.
    pub tris: [u32; 2],
}

/// Two triangles sharing edge `(v[0], v[1])`, with opposite corners `v[2]` and `v[3]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hinge {
    pub v: [u32; 4],
}

#[derive(Clone, Debug, Default)]
pub struct Topology {
    pub edges: Vec<Edge>,
    pub hinges: Vec<Hinge>,
}

impl Topology {
    /// The edges and hinges of `triangles`, O(t log t) by sorting half-edges. Fails on
    /// an edge shared by more than two triangles.
    pub fn build(triangles: &[[u32; 3]]) -> Result<Self, GeometryError> {
        let mut half: Vec<(u64, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b, opp) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let key = edge_key(a, b);
                half.push((key, t as u32, opp));
            }
        }
        half.sort_unstable();
        let mut edges = Vec::with_capacity(half.len() / 2 + 1);
        let mut hinges = Vec::new();
        let mut i = 0;
        while i < half.len() {
            let key = half[i].0;
            let mut j = i;
            while j < half.len() && half[j].0 == key {
                j += 1;
            }
            let (a, b) = edge_ends(key);
            let count = j - i;
            if count > 2 {
                return Err(GeometryError::NonManifoldEdge { a, b, count });
            }
            let second = if count == 2 { half[i + 1].1 } else { u32::MAX };
            edges.push(Edge {
                a,
                b,
                tris: [half[i].1, second],
            });
            if count == 2 {
                hinges.push(Hinge {
                    v: [a, b, half[i].2, half[i + 1].2],
                });
            }
            i = j;
        }
        Ok(Self { edges, hinges })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::ClothMesh;

    #[test]
    fn grid_topology_counts() {
        let (nx, nz) = (3usize, 2usize);
        let m = ClothMesh::grid(1.0, 1.0, nx, nz, 0.0).unwrap();
        let t = Topology::build(&m.triangles).unwrap();
        // Horizontal + vertical + one diagonal per cell.
        assert_eq!(t.edges.len(), nx * (nz + 1) + nz * (nx + 1) + nx * nz);
        let boundary = t.edges.iter().filter(|e| e.tris[1] == u32::MAX).count();
        assert_eq!(boundary, 2 * (nx + nz));
        assert_eq!(t.hinges.len(), t.edges.len() - boundary);
    }
}
