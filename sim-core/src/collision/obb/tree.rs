//! The tree's data layout: a flat array of nodes in depth-first order, each covering a
//! contiguous range of a permuted triangle array.

use glam::Vec3;

use super::geometry::Obb;

/// One node. Every node covers `tri_start .. tri_start + tri_count` of the tree's triangle
/// order; an internal node's two children sit at `child` and `child + 1`.
#[derive(Clone, Copy, Debug)]
pub struct ObbNode {
    pub obb: Obb,
    pub tri_start: u32,
    pub tri_count: u32,
    /// Index of the first child; `u32::MAX` for a leaf.
    pub child: u32,
}

impl ObbNode {
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.child == u32::MAX
    }
}

/// Build parameters.
#[derive(Clone, Copy, Debug)]
pub struct BuildOptions {
    /// A node with at most this many triangles becomes a leaf.
    pub max_leaf_triangles: usize,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            max_leaf_triangles: 4,
        }
    }
}

/// An OBB tree over a triangle mesh. The tree keeps its own copy of the triangle corners in
/// tree order so leaf tests read memory sequentially.
#[derive(Clone, Debug)]
pub struct ObbTree {
    pub(super) nodes: Vec<ObbNode>,
    /// Original triangle index for each slot of the tree order.
    pub(super) tri_ids: Vec<u32>,
    /// Inverse of `tri_ids`: the tree slot of each original triangle.
    pub(super) slot_of: Vec<u32>,
    /// Triangle corners in tree order.
    pub(super) tri_verts: Vec<[Vec3; 3]>,
    /// The mesh's index buffer (original order), kept for refit.
    pub(super) indices: Vec<[u32; 3]>,
    pub(super) depth: usize,
}

impl ObbTree {
    pub fn nodes(&self) -> &[ObbNode] {
        &self.nodes
    }

    pub fn triangle_count(&self) -> usize {
        self.tri_ids.len()
    }

    /// Depth of the deepest leaf (the root has depth 1).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Corners of the triangle with original index `tri`.
    pub fn triangle(&self, tri: u32) -> Option<[Vec3; 3]> {
        self.slot_of
            .get(tri as usize)
            .map(|&slot| self.tri_verts[slot as usize])
    }
}
