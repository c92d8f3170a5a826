//! Body shapes: which body a scene uses, the cube and sphere (the paper's experiment and
//! a smooth test body), and OBJ files; the mannequin is in `mannequin`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::analytic::{Analytic, Primitive};
use super::mannequin::{Pose, mannequin, posed_mannequin};
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
    /// The same figure with its arms held out (an A-pose), as GarmentCode's patterns
    /// are placed for.
    MannequinAPose,
    /// A human figure, 1.72 m, its arms held out 45 degrees below the horizontal:
    /// GarmentCode's average body (MIT), the body its patterns are cut and placed for.
    Human,
    /// A closed, outward-wound OBJ surface in metres, Y up.
    Obj(PathBuf),
}

impl BodyKind {
    /// Parses `cube`, `sphere`, `mannequin`, `mannequin-apose`, `human` or a path ending
    /// in `.obj`.
    pub fn parse(s: &str) -> Result<Self, ConfigError> {
        match s {
            "cube" => Ok(Self::Cube),
            "sphere" => Ok(Self::Sphere),
            "mannequin" => Ok(Self::Mannequin),
            "mannequin-apose" => Ok(Self::MannequinAPose),
            HUMAN => Ok(Self::Human),
            p if p.to_ascii_lowercase().ends_with(".obj") => Ok(Self::Obj(PathBuf::from(p))),
            other => Err(ConfigError::Unknown {
                what: "body",
                name: other.to_string(),
                expected: "cube, sphere, mannequin, mannequin-apose, human or a path to an .obj file",
            }),
        }
    }

    pub fn name(&self) -> String {
        match self {
            Self::Cube => "cube".into(),
            Self::Sphere => "sphere".into(),
            Self::Mannequin => Pose::Hanging.body_name().into(),
            Self::MannequinAPose => Pose::A.body_name().into(),
            Self::Human => HUMAN.into(),
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
            Self::MannequinAPose => posed_mannequin(Pose::A).map_err(internal),
            Self::Human => body_from_obj_text(Path::new(HUMAN), HUMAN_OBJ),
            Self::Obj(path) => obj_body(path),
        }
    }
}

/// The human body's name.
pub const HUMAN: &str = "human";

/// The human body's surface: GarmentCode's `mean_all.obj`, decimated to 11,874 triangles
/// and freed of the places where it crossed itself (`bench/make_human_body.py`).
const HUMAN_OBJ: &str = include_str!("../../../assets/human.obj");

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

/// A body from an OBJ file: checked to be a solid (closed, manifold, consistently wound,
/// enclosing a volume), its winding turned outward if it was not (`Body::repairs` says so).
fn obj_body(path: &Path) -> Result<Body, LoadError> {
    body_from_obj_text(path, &crate::mesh::obj::read_obj_text(path)?)
}

/// A body from OBJ text already read, checked as [`BodyKind`]'s files are; `path` names
/// it in errors and is its name.
pub fn body_from_obj_text(path: &Path, text: &str) -> Result<Body, LoadError> {
    let checked = super::check::check_body_text(path, text)?;
    let mut body = Body::new(
        path.display().to_string(),
        checked.vertices,
        checked.triangles,
        None,
    )
    .map_err(|source| LoadError::Invalid {
        path: path.to_owned(),
        source,
    })?;
    body.repairs = checked.repairs;
    Ok(body)
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
    fn the_human_body_is_a_clean_solid_of_a_human_size() {
        let b = BodyKind::parse("human").unwrap().build().unwrap();
        assert_eq!(b.name, "human");
        assert_eq!(b.triangles.len(), 11_874);
        // Outward and closed as it is: nothing was flipped or repaired.
        assert!(b.repairs.is_empty(), "{:?}", b.repairs);
        let (mn, mx) = b.bounds();
        assert!(
            mn.y.abs() < 1e-3 && (1.70..1.74).contains(&mx.y),
            "{mn} {mx}"
        );
        // Arms held out: 1.3 m across the hands.
        assert!((1.25..1.35).contains(&(mx.x - mn.x)), "{mn} {mx}");
        // It does not pass through itself (the original did, at the lips and the
        // crotch; `bench/make_human_body.py` smoothed them).
        assert_eq!(
            crate::collision::crossings::count_self(&b.vertices, &b.triangles),
            0
        );
        // The chest and the head are inside, the air in front of the chest outside.
        assert!(b.penetration(Vec3::new(0.0, 1.2, 0.0)) > 0.08);
        assert_eq!(b.penetration(Vec3::new(0.0, 1.2, 0.3)), 0.0);
        assert!(b.penetration(Vec3::new(0.0, 1.62, 0.01)) > 0.05);
    }

    #[test]
    fn unknown_body_is_an_error() {
        assert!(BodyKind::parse("teapot").is_err());
        assert_eq!(BodyKind::parse("cube"), Ok(BodyKind::Cube));
        assert!(matches!(BodyKind::parse("x/y.OBJ"), Ok(BodyKind::Obj(_))));
    }
}
