//! Refit after the mesh's vertices move (same topology): keep each node's axes, recompute
//! its extents. For a body that deforms a little, far cheaper than a rebuild.

use glam::Vec3;

use super::build::fit_with_axes;
use super::tree::ObbTree;
use crate::error::GeometryError;

impl ObbTree {
    /// Moves the tree to new vertex positions. `vertices` must be the mesh the tree was
    /// built on, moved; nothing changes on error.
    pub fn refit(&mut self, vertices: &[Vec3]) -> Result<(), GeometryError> {
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite { vertex: i });
        }
        if let Some(t) = self
            .indices
            .iter()
            .position(|t| t.iter().any(|&i| i as usize >= vertices.len()))
        {
            return Err(GeometryError::IndexOutOfRange {
                triangle: t,
                vertices: vertices.len(),
            });
        }
        for (slot, &t) in self.tri_ids.iter().enumerate() {
            let [a, b, c] = self.indices[t as usize];
            self.tri_verts[slot] = [
                vertices[a as usize],
                vertices[b as usize],
                vertices[c as usize],
            ];
        }
        // Nodes cover contiguous slot ranges, so each box is refit directly from its range.
        let ids: Vec<u32> = (0..self.tri_verts.len() as u32).collect();
        for node in &mut self.nodes {
            let s = node.tri_start as usize;
            let range = &ids[s..s + node.tri_count as usize];
            node.obb = fit_with_axes(&self.tri_verts, range, node.obb.axes);
        }
        Ok(())
    }
}
