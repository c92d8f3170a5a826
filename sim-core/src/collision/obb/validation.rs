//! Structural checks of a built tree: used by tests and available to callers after a refit.

use super::tree::ObbTree;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ValidationError {
    #[error("node {node}: children do not partition its triangle range")]
    BadPartition { node: usize },
    #[error("node {node}: axes are not orthonormal")]
    AxesNotOrthonormal { node: usize },
    #[error("node {node}: triangle slot {slot} pokes out of the box by {excess} m")]
    TriangleOutside {
        node: usize,
        slot: usize,
        excess: f32,
    },
    #[error("triangle order is not a permutation")]
    NotAPermutation,
    #[error("the tree is deeper ({depth}) than its query stack allows")]
    TooDeep { depth: usize },
}

impl ObbTree {
    /// Checks: leaves partition the triangles, children partition their parent, axes are
    /// orthonormal, and every triangle lies inside every box on its path.
    pub fn validate(&self) -> Result<(), ValidationError> {
        let mut seen = vec![false; self.tri_ids.len()];
        for &t in &self.tri_ids {
            match seen.get_mut(t as usize) {
                Some(s) if !*s => *s = true,
                _ => return Err(ValidationError::NotAPermutation),
            }
        }
        if self.depth >= 120 {
            return Err(ValidationError::TooDeep { depth: self.depth });
        }
        for (i, node) in self.nodes.iter().enumerate() {
            let a = node.obb.axes;
            let ortho = (a.transpose() * a - glam::Mat3::IDENTITY)
                .to_cols_array()
                .iter()
                .all(|x| x.abs() < 1e-4);
            if !ortho {
                return Err(ValidationError::AxesNotOrthonormal { node: i });
            }
            let s = node.tri_start as usize;
            for slot in s..s + node.tri_count as usize {
                for p in self.tri_verts[slot] {
                    let l = node.obb.to_local(p);
                    let excess = (l.abs() - node.obb.half).max_element();
                    let tol = 1e-4
                        * (1.0 + node.obb.half.max_element() + node.obb.center.abs().max_element());
                    if excess > tol {
                        return Err(ValidationError::TriangleOutside {
                            node: i,
                            slot,
                            excess,
                        });
                    }
                }
            }
            if !node.is_leaf() {
                let (l, r) = (
                    &self.nodes[node.child as usize],
                    &self.nodes[node.child as usize + 1],
                );
                let ok = l.tri_start == node.tri_start
                    && l.tri_start + l.tri_count == r.tri_start
                    && r.tri_start + r.tri_count == node.tri_start + node.tri_count
                    && l.tri_count > 0
                    && r.tri_count > 0;
                if !ok {
                    return Err(ValidationError::BadPartition { node: i });
                }
            }
        }
        Ok(())
    }
}
