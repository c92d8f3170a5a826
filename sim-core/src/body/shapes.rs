//! Body shapes: cube and sphere (the paper's experiment and a smooth test body), a
//! procedural mannequin made of capsules and ellipsoids, and OBJ files.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::surface::Body;
use crate::error::{ConfigError, GeometryError, LoadError};

/// Which body a scene uses.
#[derive(Clone, Debug, PartialEq)]
pub enum BodyKind {
    /// The paper's cube: 0.4 m, resting on the floor.
    Cube,
    /// A 0.3 m-radius sphere resting on the floor.
    Sphere,
    /// A standing figure about 1.75 m tall, feet on the floor.
    Mannequin,
    /// A closed, outward-wound OBJ surface in metres, Y up.
    Obj(PathBuf),
}

impl BodyKind {
    /// Parses `cube`, `sphere`, `mannequin` or a path ending in `.obj`.
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "cube" => Ok(Self::Cube),
            "sphere" => Ok(Self::Sphere),
            "mannequin" => Ok(Self::Mannequin),
            p if p.to_ascii_lowercase().ends_with(".obj") => Ok(Self::Obj(PathBuf::from(p))),
            other => Err(ConfigError::Unknown {
                what: "body",
                name: other.to_string(),
                expected: "cube, sphere, mannequin or a path to an .obj file",
            }),
        }
    }

    pub fn name(&self) -> String {
        match self {
            Self::Cube => "cube".into(),
            Self::Sphere => "sphere".into(),
            Self::Mannequin => "mannequin".into(),
            Self::Obj(p) => p.display().to_string(),
        }
    }

    pub fn build(&self) -> Result<Body, LoadError> {
        let internal = |e: GeometryError| LoadError::Invalid {
            path: PathBuf::from(self.name()),
            source: e,
        };
        match self {
            Self::Cube => cube(Vec3::new(0.0, 0.2, 0.0), 0.2, 8).map_err(internal),
            Self::Sphere => sphere(Vec3::new(0.0, 0.3, 0.0), 0.3, 4).map_err(internal),
            Self::Mannequin => mannequin().map_err(internal),
            Self::Obj(path) => obj_body(path),
        }
    }
}

/// A solid primitive with a signed distance (exact for boxes, spheres and capsules; a
/// first-order estimate for ellipsoids whose sign is exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    Box { center: Vec3, half: Vec3 },
    Ellipsoid { center: Vec3, radii: Vec3 },
    Capsule { a: Vec3, b: Vec3, radius: f32 },
}

impl Primitive {
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        match *self {
            Self::Box { center, half } => {
                let q = (p - center).abs() - half;
                q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
            }
            Self::Ellipsoid { center, radii } => {
                let k = ((p - center) / radii).length();
                (k - 1.0) * radii.min_element()
            }
            Self::Capsule { a, b, radius } => {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                (p - (a + ab * t)).length() - radius
            }
        }
    }
}

/// The exact solid of a primitive-built body (a union).
#[derive(Clone, Debug, PartialEq)]
pub struct Analytic {
    pub parts: Vec<Primitive>,
}

impl Analytic {
    pub fn signed_distance(&self, p: Vec3) -> f32 {
        self.parts
            .iter()
            .map(|s| s.signed_distance(p))
            .fold(f32::INFINITY, f32::min)
    }
}

/// Merges vertices closer than `eps` so shared edges are shared indices.
fn weld(vertices: &[Vec3], triangles: &[[u32; 3]], eps: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut map: HashMap<[i64; 3], u32> = HashMap::new();
    let mut out = Vec::new();
    let remap: Vec<u32> = vertices
        .iter()
        .map(|p| {
            let key = [
                (p.x / eps).round() as i64,
                (p.y / eps).round() as i64,
                (p.z / eps).round() as i64,
            ];
            *map.entry(key).or_insert_with(|| {
                out.push(*p);
                (out.len() - 1) as u32
            })
        })
        .collect();
    let tris = triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
        .collect();
    (out, tris)
}

/// An axis-aligned cube with each face split into `n` x `n` quads.
pub fn cube(center: Vec3, half: f32, n: usize) -> Result<Body, GeometryError> {
    let mut v = Vec::new();
    let mut t = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let normal = Vec3::AXES[axis] * sign;
            let u = Vec3::AXES[(axis + 1) % 3];
            let w = normal.cross(u);
            let base = v.len() as u32;
            for j in 0..=n {
                for i in 0..=n {
                    let a = (i as f32 / n as f32) * 2.0 - 1.0;
                    let b = (j as f32 / n as f32) * 2.0 - 1.0;
                    v.push(center + (normal + u * a + w * b) * half);
                }
            }
            let row = (n + 1) as u32;
            for j in 0..n as u32 {
                for i in 0..n as u32 {
                    let a = base + j * row + i;
                    // u x w = normal, so (a, a+1, a+row) winds outward.
                    t.push([a, a + 1, a + row + 1]);
                    t.push([a, a + row + 1, a + row]);
                }
            }
        }
    }
    let (v, t) = weld(&v, &t, half * 1e-4);
    Body::new(
        "cube",
        v,
        t,
        Some(Analytic {
            parts: vec![Primitive::Box {
                center,
                half: Vec3::splat(half),
            }],
        }),
    )
}

/// An icosphere (`subdiv` 4 gives 5,120 triangles).
pub fn sphere(center: Vec3, radius: f32, subdiv: usize) -> Result<Body, GeometryError> {
    let (v, t) = icosphere(subdiv);
    let v = v.into_iter().map(|p| center + p * radius).collect();
    Body::new(
        "sphere",
        v,
        t,
        Some(Analytic {
            parts: vec![Primitive::Ellipsoid {
                center,
                radii: Vec3::splat(radius),
            }],
        }),
    )
}

pub(crate) fn icosphere(subdiv: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut v: Vec<Vec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdiv {
        let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
        let mut next = Vec::with_capacity(t.len() * 4);
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<Vec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                (v.len() - 1) as u32
            })
        };
        for [a, b, c] in t {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    (v, t)
}

/// The mannequin's parts, metres, feet on the floor, facing +Z, arms slightly out.
pub fn mannequin_parts() -> Vec<Primitive> {
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
        parts.push(Primitive::Capsule {
            a: Vec3::new(s * 0.25, 1.42, 0.0),
            b: Vec3::new(s * 0.31, 1.12, 0.0),
            radius: 0.045,
        });
        parts.push(Primitive::Capsule {
            a: Vec3::new(s * 0.31, 1.12, 0.0),
            b: Vec3::new(s * 0.34, 0.86, 0.04),
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
    let analytic = Analytic {
        parts: mannequin_parts(),
    };
    let (v, t) = surface_nets(|p| analytic.signed_distance(p), MANNEQUIN_CELL);
    Body::new("mannequin", v, t, Some(analytic))
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

fn obj_body(path: &Path) -> Result<Body, LoadError> {
    let mesh = crate::mesh::obj::load_obj(path)?;
    Body::new(
        path.display().to_string(),
        mesh.positions,
        mesh.triangles,
        None,
    )
    .map_err(|source| LoadError::Invalid {
        path: path.to_owned(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_signs_are_right_everywhere() {
        let b = cube(Vec3::new(0.0, 0.2, 0.0), 0.2, 4).unwrap();
        let a = b.analytic.clone().unwrap();
        // Points near faces, edges and corners, inside and out.
        let mut rng = 1u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((rng >> 33) as f32 / (1u64 << 31) as f32) * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let p = Vec3::new(next() * 0.3, 0.2 + next() * 0.3, next() * 0.3);
            let want = a.signed_distance(p);
            let got = b.signed_distance(p, 10.0).unwrap();
            assert!((got - want).abs() < 1e-4, "p {p} mesh {got} exact {want}");
        }
    }

    #[test]
    fn sphere_and_mannequin_sizes() {
        let s = sphere(Vec3::ZERO, 1.0, 4).unwrap();
        assert_eq!(s.triangles.len(), 5120);
        assert!((s.signed_distance(Vec3::new(0.0, 2.0, 0.0), 10.0).unwrap() - 1.0).abs() < 1e-2);
        assert!(s.signed_distance(Vec3::new(0.0, 0.5, 0.0), 10.0).unwrap() < -0.45);
        let m = mannequin().unwrap();
        let n = m.triangles.len();
        assert!((5_000..=15_000).contains(&n), "mannequin has {n} triangles");
        let (mn, mx) = m.bounds();
        assert!(mn.y >= -1e-3 && (1.7..1.85).contains(&mx.y), "{mn} {mx}");
        // Watertight, manifold and consistently wound: every edge has two triangles, one
        // each way (where the arm meets the torso, surface nets let two sheets touch
        // along an edge; `split_pinches` gives them their own vertices).
        let mut count: std::collections::HashMap<(u32, u32), (i32, i32)> = Default::default();
        for t in &m.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let c = count.entry((a.min(b), a.max(b))).or_default();
                c.0 += 1;
                c.1 += if a < b { 1 } else { -1 };
            }
        }
        assert!(
            count.values().all(|&c| c == (2, 0)),
            "the mannequin surface has holes, flipped faces or edges of 3+ triangles"
        );
        // The mesh's inside/outside agrees with the exact union, also where parts meet.
        let a = m.analytic.clone().unwrap();
        for p in [
            Vec3::new(0.018, 1.556, 0.044),
            Vec3::new(-0.015, 1.60, 0.011),
            Vec3::new(0.2, 1.44, 0.0),
            Vec3::new(0.0, 0.9, 0.0),
        ] {
            let (mesh_d, exact) = (m.signed_distance(p, 1.0).unwrap(), a.signed_distance(p));
            assert_eq!(
                mesh_d < 0.0,
                exact < 0.0,
                "{p}: mesh {mesh_d} exact {exact}"
            );
        }
        // A point in the chest is inside, one in front of it outside.
        assert!(m.penetration(Vec3::new(0.0, 1.3, 0.0)) > 0.05);
        assert_eq!(m.penetration(Vec3::new(0.0, 1.3, 0.3)), 0.0);
    }

    #[test]
    fn unknown_body_is_an_error() {
        assert!(BodyKind::parse("teapot").is_err());
        assert_eq!(BodyKind::parse("cube"), Ok(BodyKind::Cube));
        assert!(matches!(BodyKind::parse("x/y.OBJ"), Ok(BodyKind::Obj(_))));
    }
}
