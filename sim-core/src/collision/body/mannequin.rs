//! The procedural mannequin: capsules and ellipsoids, one closed surface of their union
//! by surface nets, with the pinched edges split so the mesh is manifold.

use std::collections::HashMap;

use glam::Vec3;

use super::analytic::{Analytic, Primitive};
use super::surface::Body;
use crate::error::GeometryError;

/// The left arm (+X, the figure faces +Z): shoulder, elbow and wrist, m; the right arm
/// is its mirror image.
pub const ARM: [Vec3; 3] = [
    Vec3::new(0.25, 1.42, 0.0),
    Vec3::new(0.31, 1.12, 0.0),
    Vec3::new(0.34, 0.86, 0.04),
];
/// The upper arm's radius, m (the forearm's is smaller).
pub const ARM_RADIUS: f32 = 0.045;

/// How the mannequin holds its arms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pose {
    /// Hanging, slightly out (`ARM`).
    Hanging,
    /// Held out, the upper arm `A_POSE_DEG` below the horizontal, as GarmentCode's and
    /// CLO's avatars stand to be dressed: their sleeves are cut and placed for it.
    A,
}

/// The A-pose's upper arm, degrees below the horizontal (GarmentCode's sleeves run at
/// 50.5 degrees).
pub const A_POSE_DEG: f32 = 50.0;

impl Pose {
    /// The body's name for the mannequin in this pose.
    pub fn body_name(self) -> &'static str {
        match self {
            Self::Hanging => "mannequin",
            Self::A => "mannequin-apose",
        }
    }

    /// The pose of the mannequin body named `name`, if it is one.
    pub fn of_body(name: &str) -> Option<Self> {
        [Self::Hanging, Self::A]
            .into_iter()
            .find(|p| p.body_name() == name)
    }

    /// The left arm's shoulder, elbow and wrist in this pose (the right is its mirror):
    /// `ARM` turned about the shoulder, in the body's plane.
    pub fn arm(self) -> [Vec3; 3] {
        match self {
            Self::Hanging => ARM,
            Self::A => {
                let upper = ARM[1] - ARM[0];
                let now = (-upper.y).atan2(upper.x);
                let turn = glam::Quat::from_rotation_z(now - A_POSE_DEG.to_radians());
                ARM.map(|p| ARM[0] + turn * (p - ARM[0]))
            }
        }
    }
}

/// The mannequin's parts, metres, feet on the floor, facing +Z, arms slightly out.
pub fn mannequin_parts() -> Vec<Primitive> {
    posed_parts(Pose::Hanging)
}

/// The mannequin's parts with its arms in `pose`.
pub fn posed_parts(pose: Pose) -> Vec<Primitive> {
    let arm = pose.arm();
    let mut parts = vec![
        Primitive::Ellipsoid {
            center: Vec3::new(0.0, 1.30, 0.0),
            radii: Vec3::new(0.18, 0.20, 0.11),
        },
        Primitive::Ellipsoid {
            center: Vec3::new(0.0, 1.03, 0.0),
            radii: Vec3::new(0.165, 0.22, 0.105),
        },
        Primitive::Capsule {
            a: Vec3::new(0.0, 1.44, 0.0),
            b: Vec3::new(0.0, 1.56, 0.0),
            radius: 0.055,
        },
        Primitive::Ellipsoid {
            center: Vec3::new(0.0, 1.66, 0.01),
            radii: Vec3::new(0.08, 0.11, 0.095),
        },
    ];
    for s in [-1.0f32, 1.0] {
        parts.push(Primitive::Capsule {
            a: Vec3::new(s * 0.15, 1.44, 0.0),
            b: Vec3::new(s * 0.25, 1.44, 0.0),
            radius: 0.055,
        });
        let side = Vec3::new(s, 1.0, 1.0);
        parts.push(Primitive::Capsule {
            a: arm[0] * side,
            b: arm[1] * side,
            radius: ARM_RADIUS,
        });
        parts.push(Primitive::Capsule {
            a: arm[1] * side,
            b: arm[2] * side,
            radius: 0.038,
        });
        parts.push(Primitive::Capsule {
            a: Vec3::new(s * 0.09, 0.90, 0.0),
            b: Vec3::new(s * 0.10, 0.48, 0.0),
            radius: 0.075,
        });
        parts.push(Primitive::Capsule {
            a: Vec3::new(s * 0.10, 0.48, 0.0),
            b: Vec3::new(s * 0.10, 0.07, 0.0),
            radius: 0.052,
        });
    }
    parts
}

/// The procedural mannequin: one closed surface of the parts' union, extracted
/// from the union's signed distance by surface nets at `MANNEQUIN_CELL` and projected onto
/// the exact surface. (Meshing each part and trimming buried triangles leaves gaps where
/// parts meet, and a point in such a gap gets the wrong inside/outside sign.) Manifold
/// but for two edges where the right arm meets the torso: surface nets let two sheets
/// touch there, four triangles on each edge.
pub fn mannequin() -> Result<Body, GeometryError> {
    posed_mannequin(Pose::Hanging)
}

/// The mannequin with its arms in `pose`, named for it ([`Pose::body_name`]).
pub fn posed_mannequin(pose: Pose) -> Result<Body, GeometryError> {
    let analytic = Analytic {
        parts: posed_parts(pose),
    };
    let (v, t) = surface_nets(|p| analytic.signed_distance(p), MANNEQUIN_CELL);
    Body::new(pose.body_name(), v, t, Some(analytic))
}

/// Grid spacing for the mannequin's surface, m (about 10k triangles).
pub const MANNEQUIN_CELL: f32 = 0.021;

/// Surface nets over the union's bounding box: one vertex per cell the surface crosses,
/// one quad (two triangles) per grid edge with a sign change, wound outward.
fn surface_nets(sdf: impl Fn(Vec3) -> f32, h: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    // Bounds from a coarse scan of where the field is negative, padded by two cells.
    let (lo, hi) = (Vec3::new(-1.0, -0.1, -0.5), Vec3::new(1.0, 2.0, 0.5));
    let min = lo - Vec3::splat(2.0 * h);
    let dims = ((hi - lo) / h).ceil().as_uvec3() + glam::UVec3::splat(5);
    let (nx, ny, nz) = (dims.x as usize, dims.y as usize, dims.z as usize);
    let at = |i: usize, j: usize, k: usize| min + Vec3::new(i as f32, j as f32, k as f32) * h;
    let idx = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
    let mut field = vec![0.0f32; nx * ny * nz];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                field[idx(i, j, k)] = sdf(at(i, j, k));
            }
        }
    }
    let inside = |i: usize, j: usize, k: usize| field[idx(i, j, k)] < 0.0;
    // One vertex per mixed cell (cell (i,j,k) spans points i..i+1 etc.).
    let mut cell_vertex = vec![u32::MAX; nx * ny * nz];
    let mut verts = Vec::new();
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let mut sum = Vec3::ZERO;
                let mut count = 0;
                for (a, b) in CUBE_EDGES {
                    let pa = (i + a[0], j + a[1], k + a[2]);
                    let pb = (i + b[0], j + b[1], k + b[2]);
                    let (fa, fb) = (field[idx(pa.0, pa.1, pa.2)], field[idx(pb.0, pb.1, pb.2)]);
                    if (fa < 0.0) != (fb < 0.0) {
                        let t = fa / (fa - fb);
                        sum += at(pa.0, pa.1, pa.2).lerp(at(pb.0, pb.1, pb.2), t);
                        count += 1;
                    }
                }
                if count > 0 {
                    cell_vertex[idx(i, j, k)] = verts.len() as u32;
                    verts.push(sum / count as f32);
                }
            }
        }
    }
    let mut tris = Vec::new();
    let n = [nx, ny, nz];
    for k in 1..nz - 1 {
        for j in 1..ny - 1 {
            for i in 1..nx - 1 {
                let p = [i, j, k];
                for axis in 0..3 {
                    let mut q = p;
                    q[axis] += 1;
                    if q[axis] >= n[axis] {
                        continue;
                    }
                    let (a_in, b_in) = (inside(p[0], p[1], p[2]), inside(q[0], q[1], q[2]));
                    if a_in == b_in {
                        continue;
                    }
                    let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                    let cell = |du: usize, dw: usize| {
                        let mut c = p;
                        c[u] -= du;
                        c[w] -= dw;
                        cell_vertex[idx(c[0], c[1], c[2])]
                    };
                    let mut quad = [cell(1, 1), cell(0, 1), cell(0, 0), cell(1, 0)];
                    if quad.contains(&u32::MAX) {
                        continue;
                    }
                    if !a_in {
                        quad.reverse();
                    }
                    // Split along the shorter diagonal.
                    let [q0, q1, q2, q3] = quad.map(|v| verts[v as usize]);
                    if (q0 - q2).length_squared() <= (q1 - q3).length_squared() {
                        tris.push([quad[0], quad[1], quad[2]]);
                        tris.push([quad[0], quad[2], quad[3]]);
                    } else {
                        tris.push([quad[0], quad[1], quad[3]]);
                        tris.push([quad[1], quad[2], quad[3]]);
                    }
                }
            }
        }
    }
    // Project onto the exact surface (Newton steps along the numerical gradient).
    let e = h * 1e-2;
    for p in &mut verts {
        for _ in 0..4 {
            let d = sdf(*p);
            let g = Vec3::new(
                sdf(*p + Vec3::X * e) - sdf(*p - Vec3::X * e),
                sdf(*p + Vec3::Y * e) - sdf(*p - Vec3::Y * e),
                sdf(*p + Vec3::Z * e) - sdf(*p - Vec3::Z * e),
            ) / (2.0 * e);
            let step = g.normalize_or_zero() * d;
            if step.length() < h * 0.5 {
                *p -= step;
            }
        }
    }
    // Projection can collapse a triangle; drop those.
    tris.retain(|t| {
        let [a, b, c] = t.map(|i| verts[i as usize]);
        (b - a).cross(c - a).length_squared() > 1e-16
    });
    split_pinches(&mut verts, &mut tris);
    (verts, tris)
}

/// Where two cells inside the shape meet only along an edge, surface nets give that edge
/// four triangles: two sheets of the surface touch there. Pairs each sheet's two
/// triangles (the two that bound the same wedge of solid around the edge) and gives the
/// second sheet its own copies of the edge's vertices, at the same place, for its whole
/// fan around each; the mesh is then manifold.
fn split_pinches(verts: &mut Vec<Vec3>, tris: &mut [[u32; 3]]) {
    let key = |i: u32, j: u32| (i.min(j), i.max(j));
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            edges
                .entry(key(tri[k], tri[(k + 1) % 3]))
                .or_default()
                .push(t);
        }
    }
    let mut pinched: Vec<((u32, u32), [usize; 4])> = edges
        .iter()
        .filter_map(|(&e, ts)| Some((e, <[usize; 4]>::try_from(ts.as_slice()).ok()?)))
        .collect();
    pinched.sort_unstable();
    // The sheet (0 or 1) each triangle on a pinched edge belongs to, per edge.
    let mut sheet: HashMap<((u32, u32), usize), usize> = HashMap::new();
    for &((i, j), ts) in &pinched {
        let (pi, axis) = (
            verts[i as usize],
            (verts[j as usize] - verts[i as usize]).normalize(),
        );
        let (u, w) = axis.any_orthonormal_pair();
        // Each triangle as the angle of its third corner around the edge, and whether its
        // normal faces the way that angle grows.
        let mut around: Vec<(f32, bool, usize)> = ts
            .iter()
            .map(|&t| {
                let tri = tris[t];
                let o = tri.iter().copied().find(|&v| v != i && v != j).unwrap_or(i);
                let d = verts[o as usize] - pi;
                let [a, b, c] = tri.map(|v| verts[v as usize]);
                let n = (b - a).cross(c - a);
                (d.dot(w).atan2(d.dot(u)), n.dot(axis.cross(d)) > 0.0, t)
            })
            .collect();
        around.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Solid lies between a triangle facing back and the next one facing on.
        let mut next_sheet = 0;
        for k in 0..4 {
            let (a, b) = (around[k], around[(k + 1) % 4]);
            if !a.1 && b.1 && next_sheet < 2 {
                sheet.insert(((i, j), a.2), next_sheet);
                sheet.insert(((i, j), b.2), next_sheet);
                next_sheet += 1;
            }
        }
    }
    // Around each vertex of a pinched edge, triangles are one fan when they share a
    // manifold edge at the vertex, or the same sheet of a pinched one. Every fan but the
    // first gets its own copy of the vertex.
    let mut ends: Vec<u32> = pinched.iter().flat_map(|&((i, j), _)| [i, j]).collect();
    ends.sort_unstable();
    ends.dedup();
    for v in ends {
        let fan: Vec<usize> = (0..tris.len()).filter(|&t| tris[t].contains(&v)).collect();
        let mut group: Vec<usize> = (0..fan.len()).collect();
        fn root(g: &mut [usize], mut x: usize) -> usize {
            while g[x] != x {
                g[x] = g[g[x]];
                x = g[x];
            }
            x
        }
        for a in 0..fan.len() {
            for b in a + 1..fan.len() {
                let (ta, tb) = (tris[fan[a]], tris[fan[b]]);
                let joined = ta.iter().any(|&w| {
                    if w == v || !tb.contains(&w) {
                        return false;
                    }
                    let e = key(v, w);
                    match edges.get(&e).map(Vec::len) {
                        Some(2) => true,
                        Some(4) => {
                            let (sa, sb) = (sheet.get(&(e, fan[a])), sheet.get(&(e, fan[b])));
                            sa.is_some() && sa == sb
                        }
                        _ => false,
                    }
                });
                if joined {
                    let (ra, rb) = (root(&mut group, a), root(&mut group, b));
                    group[ra.max(rb)] = ra.min(rb);
                }
            }
        }
        let mut copy_of_root: HashMap<usize, u32> = HashMap::new();
        let first = root(&mut group, 0);
        for k in 0..fan.len() {
            let r = root(&mut group, k);
            if r == first {
                continue;
            }
            let copy = *copy_of_root.entry(r).or_insert_with(|| {
                verts.push(verts[v as usize]);
                verts.len() as u32 - 1
            });
            for c in tris[fan[k]].iter_mut().filter(|c| **c == v) {
                *c = copy;
            }
        }
    }
}

const CUBE_EDGES: [([usize; 3], [usize; 3]); 12] = [
    ([0, 0, 0], [1, 0, 0]),
    ([0, 1, 0], [1, 1, 0]),
    ([0, 0, 1], [1, 0, 1]),
    ([0, 1, 1], [1, 1, 1]),
    ([0, 0, 0], [0, 1, 0]),
    ([1, 0, 0], [1, 1, 0]),
    ([0, 0, 1], [0, 1, 1]),
    ([1, 0, 1], [1, 1, 1]),
    ([0, 0, 0], [0, 0, 1]),
    ([1, 0, 0], [1, 0, 1]),
    ([0, 1, 0], [0, 1, 1]),
    ([1, 1, 0], [1, 1, 1]),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The A-pose turns the arm about the shoulder: the same shoulder and lengths, the
    /// upper arm 50 degrees below the horizontal, the hand out from the hips.
    #[test]
    fn the_a_pose_holds_the_arm_out_at_its_angle() {
        let (hang, a) = (Pose::Hanging.arm(), Pose::A.arm());
        assert_eq!(a[0], hang[0]);
        for k in 1..3 {
            let (l0, l1) = ((hang[k] - hang[0]).length(), (a[k] - a[0]).length());
            assert!((l0 - l1).abs() < 1e-5, "{l0} {l1}");
        }
        let upper = a[1] - a[0];
        let below = (-upper.y).atan2(upper.x).to_degrees();
        assert!((below - A_POSE_DEG).abs() < 0.01, "{below}");
        assert!(a[2].x > 0.55 && a[2].y > 0.95, "{}", a[2]);
    }
}
