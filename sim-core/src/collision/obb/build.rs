//! Top-down construction: box axes from the covariance eigenvectors of a node's triangle
//! corners, split across the principal (longest) axis at the mean centroid, recursively.
//! Falls back to the other axes, then to a median split, so depth stays O(log n).

use glam::{Mat3, Vec3};
use parry3d::glamx::MatExt;

use super::geometry::Obb;
use super::tree::{BuildOptions, ObbNode, ObbTree};
use crate::error::GeometryError;

impl ObbTree {
    /// Builds the tree over `vertices`/`indices`. Fails on out-of-range indices, non-finite
    /// coordinates or an empty mesh.
    pub fn build(
        vertices: &[Vec3],
        indices: &[[u32; 3]],
        opts: BuildOptions,
    ) -> Result<Self, GeometryError> {
        if indices.is_empty() {
            return Err(GeometryError::Empty);
        }
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(GeometryError::NonFinite { vertex: i });
        }
        for (t, tri) in indices.iter().enumerate() {
            if tri.iter().any(|&i| i as usize >= vertices.len()) {
                return Err(GeometryError::IndexOutOfRange {
                    triangle: t,
                    vertices: vertices.len(),
                });
            }
        }
        let max_leaf = opts.max_leaf_triangles.max(1);
        let tris: Vec<[Vec3; 3]> = indices
            .iter()
            .map(|t| {
                [
                    vertices[t[0] as usize],
                    vertices[t[1] as usize],
                    vertices[t[2] as usize],
                ]
            })
            .collect();
        let centroids: Vec<Vec3> = tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0).collect();
        let mut order: Vec<u32> = (0..indices.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * indices.len() / max_leaf + 1);
        nodes.push(placeholder());
        let mut depth = 0;
        // Explicit work stack: (node index, start, count, depth).
        let mut work = vec![(0usize, 0usize, indices.len(), 1usize)];
        while let Some((node, start, count, d)) = work.pop() {
            depth = depth.max(d);
            let slice = &mut order[start..start + count];
            let obb = fit_obb(&tris, slice);
            nodes[node] = ObbNode {
                obb,
                tri_start: start as u32,
                tri_count: count as u32,
                child: u32::MAX,
            };
            if count <= max_leaf {
                continue;
            }
            let mid = split(&centroids, slice, &obb);
            let child = nodes.len();
            nodes.push(placeholder());
            nodes.push(placeholder());
            nodes[node].child = child as u32;
            // Right first so the left subtree is built (and laid out) first.
            work.push((child + 1, start + mid, count - mid, d + 1));
            work.push((child, start, mid, d + 1));
        }
        let tri_verts = order.iter().map(|&t| tris[t as usize]).collect();
        let mut slot_of = vec![0u32; order.len()];
        for (slot, &t) in order.iter().enumerate() {
            slot_of[t as usize] = slot as u32;
        }
        Ok(ObbTree {
            nodes,
            tri_ids: order,
            slot_of,
            tri_verts,
            indices: indices.to_vec(),
            depth,
        })
    }
}

fn placeholder() -> ObbNode {
    ObbNode {
        obb: Obb::aabb(Vec3::ZERO, Vec3::ZERO),
        tri_start: 0,
        tri_count: 0,
        child: u32::MAX,
    }
}

/// Covariance frame of the triangles' corners, sorted so `x_axis` has the largest variance.
pub(super) fn covariance_axes(tris: &[[Vec3; 3]], ids: &[u32]) -> Mat3 {
    let n = (ids.len() * 3) as f32;
    let mean = ids
        .iter()
        .map(|&t| tris[t as usize].iter().copied().sum::<Vec3>())
        .sum::<Vec3>()
        / n;
    let mut c = [[0.0f32; 3]; 3];
    for &t in ids {
        for p in tris[t as usize] {
            let d = p - mean;
            for i in 0..3 {
                for j in i..3 {
                    c[i][j] += d[i] * d[j];
                }
            }
        }
    }
    let cov = Mat3::from_cols(
        Vec3::new(c[0][0], c[0][1], c[0][2]),
        Vec3::new(c[0][1], c[1][1], c[1][2]),
        Vec3::new(c[0][2], c[1][2], c[2][2]),
    ) / n;
    let eig = cov.symmetric_eigen();
    let vals = eig.eigenvalues;
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&a, &b| vals[b].total_cmp(&vals[a]));
    let cols = [
        eig.eigenvectors.x_axis,
        eig.eigenvectors.y_axis,
        eig.eigenvectors.z_axis,
    ];
    let x = cols[idx[0]].normalize_or(Vec3::X);
    let mut y = cols[idx[1]] - x * x.dot(cols[idx[1]]);
    if y.length_squared() < 1e-12 {
        y = x.any_orthonormal_vector();
    }
    let y = y.normalize();
    let z = x.cross(y);
    if !(x.is_finite() && y.is_finite() && z.is_finite()) {
        return Mat3::IDENTITY;
    }
    Mat3::from_cols(x, y, z)
}

/// The tightest box with the given axes around the triangles' corners.
pub(super) fn fit_with_axes(tris: &[[Vec3; 3]], ids: &[u32], axes: Mat3) -> Obb {
    let at = axes.transpose();
    let mut mn = Vec3::splat(f32::INFINITY);
    let mut mx = Vec3::splat(f32::NEG_INFINITY);
    for &t in ids {
        for p in tris[t as usize] {
            let l = at * p;
            mn = mn.min(l);
            mx = mx.max(l);
        }
    }
    Obb {
        center: axes * ((mn + mx) * 0.5),
        axes,
        half: (mx - mn) * 0.5,
    }
}

fn fit_obb(tris: &[[Vec3; 3]], ids: &[u32]) -> Obb {
    fit_with_axes(tris, ids, covariance_axes(tris, ids))
}

/// Partitions `ids` and returns the size of the first half (always in `1..len`).
fn split(centroids: &[Vec3], ids: &mut [u32], obb: &Obb) -> usize {
    let axes = [obb.axes.x_axis, obb.axes.y_axis, obb.axes.z_axis];
    // Longest principal axis first, as in the paper, then the others.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| obb.half[b].total_cmp(&obb.half[a]));
    for &k in &order {
        let axis = axes[k];
        let mean = ids
            .iter()
            .map(|&t| axis.dot(centroids[t as usize]))
            .sum::<f32>()
            / ids.len() as f32;
        let mut lo = 0;
        for i in 0..ids.len() {
            if axis.dot(centroids[ids[i] as usize]) < mean {
                ids.swap(lo, i);
                lo += 1;
            }
        }
        // Accept a mean split unless it is badly unbalanced (keeps depth logarithmic).
        if lo >= ids.len() / 8 && lo <= ids.len() - ids.len() / 8 && lo > 0 && lo < ids.len() {
            return lo;
        }
    }
    // Median split along the longest axis.
    let axis = axes[order[0]];
    let mid = ids.len() / 2;
    ids.select_nth_unstable_by(mid, |&a, &b| {
        axis.dot(centroids[a as usize])
            .total_cmp(&axis.dot(centroids[b as usize]))
    });
    mid
}
