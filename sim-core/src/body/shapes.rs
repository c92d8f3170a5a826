//! Body shapes: cube and sphere (the paper's experiment and a smooth test body), a
//! procedural mannequin made of capsules and ellipsoids, and OBJ files.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat3, Quat, Vec3};

use super::body::Body;
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
        let internal = |e: GeometryError| LoadError::Invalid { path: PathBuf::from(self.name()), source: e };
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
        self.parts.iter().map(|s| s.signed_distance(p)).fold(f32::INFINITY, f32::min)
    }
}

/// Merges vertices closer than `eps` so shared edges are shared indices.
fn weld(vertices: &[Vec3], triangles: &[[u32; 3]], eps: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut map: HashMap<[i64; 3], u32> = HashMap::new();
    let mut out = Vec::new();
    let remap: Vec<u32> = vertices
        .iter()
        .map(|p| {
            let key = [(p.x / eps).round() as i64, (p.y / eps).round() as i64, (p.z / eps).round() as i64];
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
    Body::new("cube", v, t, Some(Analytic { parts: vec![Primitive::Box { center, half: Vec3::splat(half) }] }))
}

/// An icosphere (`subdiv` 4 gives 5,120 triangles).
pub fn sphere(center: Vec3, radius: f32, subdiv: usize) -> Result<Body, GeometryError> {
    let (v, t) = icosphere(subdiv);
    let v = v.into_iter().map(|p| center + p * radius).collect();
    Body::new("sphere", v, t, Some(Analytic { parts: vec![Primitive::Ellipsoid { center, radii: Vec3::splat(radius) }] }))
}

fn icosphere(subdiv: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
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

/// Revolves a profile `(radius, height)` from bottom pole to top pole around +Y.
fn revolve(profile: &[(f32, f32)], segments: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut v = vec![Vec3::new(0.0, profile[0].1, 0.0)];
    let rings = &profile[1..profile.len() - 1];
    for &(r, y) in rings {
        for s in 0..segments {
            let a = s as f32 / segments as f32 * std::f32::consts::TAU;
            v.push(Vec3::new(r * a.cos(), y, -r * a.sin()));
        }
    }
    let top = v.len() as u32;
    v.push(Vec3::new(0.0, profile[profile.len() - 1].1, 0.0));
    let seg = segments as u32;
    let ring = |k: usize, s: u32| 1 + k as u32 * seg + s % seg;
    let mut t = Vec::new();
    for s in 0..seg {
        t.push([0, ring(0, s + 1), ring(0, s)]);
    }
    for k in 0..rings.len() - 1 {
        for s in 0..seg {
            let (a, b, c, d) = (ring(k, s), ring(k, s + 1), ring(k + 1, s), ring(k + 1, s + 1));
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
    }
    let last = rings.len() - 1;
    for s in 0..seg {
        t.push([top, ring(last, s), ring(last, s + 1)]);
    }
    (v, t)
}

fn primitive_mesh(p: &Primitive, segments: usize, rings: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let half_pi = std::f32::consts::FRAC_PI_2;
    match *p {
        Primitive::Ellipsoid { center, radii } => {
            let profile: Vec<(f32, f32)> = (0..=rings)
                .map(|k| {
                    let th = -half_pi + std::f32::consts::PI * k as f32 / rings as f32;
                    (th.cos().max(0.0), th.sin())
                })
                .collect();
            let (v, t) = revolve(&profile, segments);
            (v.into_iter().map(|q| center + q * radii).collect(), t)
        }
        Primitive::Capsule { a, b, radius } => {
            let len = (b - a).length();
            let half = rings / 2;
            let mut profile = Vec::new();
            for k in 0..=half {
                let th = -half_pi + half_pi * k as f32 / half as f32;
                profile.push((radius * th.cos().max(0.0), radius * th.sin()));
            }
            for k in 0..=half {
                let th = half_pi * k as f32 / half as f32;
                profile.push((radius * th.cos().max(0.0), len + radius * th.sin()));
            }
            let (v, t) = revolve(&profile, segments);
            let rot = Quat::from_rotation_arc(Vec3::Y, (b - a).normalize_or(Vec3::Y));
            (v.into_iter().map(|q| a + rot * q).collect(), t)
        }
        Primitive::Box { center, half } => {
            let unit = Mat3::from_diagonal(half);
            let (v, t) = icosphere(0);
            (v.into_iter().map(|q| center + unit * q).collect(), t)
        }
    }
}

/// The mannequin's parts, metres, feet on the floor, facing +Z, arms slightly out.
pub fn mannequin_parts() -> Vec<Primitive> {
    let mut parts = vec![
        Primitive::Ellipsoid { center: Vec3::new(0.0, 1.30, 0.0), radii: Vec3::new(0.18, 0.20, 0.11) },
        Primitive::Ellipsoid { center: Vec3::new(0.0, 1.03, 0.0), radii: Vec3::new(0.165, 0.22, 0.105) },
        Primitive::Capsule { a: Vec3::new(0.0, 1.44, 0.0), b: Vec3::new(0.0, 1.56, 0.0), radius: 0.055 },
        Primitive::Ellipsoid { center: Vec3::new(0.0, 1.66, 0.01), radii: Vec3::new(0.08, 0.11, 0.095) },
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

/// The procedural mannequin: each part meshed, and triangles buried inside another part
/// dropped, so the surface is (nearly) the union's boundary.
pub fn mannequin() -> Result<Body, GeometryError> {
    let parts = mannequin_parts();
    let mut v = Vec::new();
    let mut t = Vec::new();
    for (k, part) in parts.iter().enumerate() {
        let (pv, pt) = primitive_mesh(part, 36, 24);
        let base = v.len() as u32;
        for tri in pt {
            let buried = parts.iter().enumerate().any(|(j, other)| {
                j != k && tri.iter().all(|&i| other.signed_distance(pv[i as usize]) < -1e-4)
            });
            if !buried {
                t.push(tri.map(|i| i + base));
            }
        }
        v.extend(pv);
    }
    // Drop vertices no triangle uses.
    let mut used = vec![u32::MAX; v.len()];
    let mut out = Vec::new();
    for tri in &mut t {
        for i in tri.iter_mut() {
            if used[*i as usize] == u32::MAX {
                used[*i as usize] = out.len() as u32;
                out.push(v[*i as usize]);
            }
            *i = used[*i as usize];
        }
    }
    Body::new("mannequin", out, t, Some(Analytic { parts }))
}

fn obj_body(path: &Path) -> Result<Body, LoadError> {
    let mesh = crate::mesh::obj::load_obj(path)?;
    Body::new(path.display().to_string(), mesh.positions, mesh.triangles, None)
        .map_err(|source| LoadError::Invalid { path: path.to_owned(), source })
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
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
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
