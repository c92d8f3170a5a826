//! OBJ input (through `tobj`, then validated) and output (written here: positions, UVs,
//! normals, faces, and an optional material library).

use std::io::Write;
use std::path::Path;

use glam::{Vec2, Vec3};

use super::cloth_mesh::ClothMesh;
use crate::error::LoadError;

/// The largest OBJ file read, bytes: room for the most vertices a mesh may have
/// ([`super::cloth_mesh::MAX_VERTICES`]) with their UVs and faces, refused before reading.
pub const MAX_OBJ_BYTES: u64 = 512 << 20;

/// The most triangles an OBJ may describe (faces fanned into triangles): twice the most
/// vertices a mesh may have, as a closed surface has.
pub const MAX_OBJ_TRIANGLES: usize = 2 * super::cloth_mesh::MAX_VERTICES;

/// Counts the vertices and the triangles of an OBJ's text (nothing kept) and refuses one
/// over the limits before any parser allocates for it: a 10-million-triangle file is
/// turned away holding only its text. Returns the counts of positions, UVs and normals.
pub fn check_obj_counts(path: &Path, text: &str) -> Result<[usize; 3], LoadError> {
    let (mut counts, mut triangles) = ([0usize; 3], 0usize);
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f") => triangles += words.count().saturating_sub(2),
            _ => {}
        }
    }
    let vertices = counts[0];
    let max_v = super::cloth_mesh::MAX_VERTICES;
    if vertices > max_v || triangles > MAX_OBJ_TRIANGLES {
        return Err(LoadError::Parse {
            path: path.to_owned(),
            reason: format!(
                "it has {vertices} vertices and {triangles} triangles, more than a mesh may \
                 have here ({max_v} vertices, {MAX_OBJ_TRIANGLES} triangles)"
            ),
        });
    }
    Ok(counts)
}

/// Checks every face's indices (position, UV and normal, counted from 1, or back from -1)
/// name an element the file has, with the line: `tobj` takes an index far out of range
/// as a huge number and overflows on it. (The body reader numbers its own.) `counts` are
/// the positions, UVs and normals [`check_obj_counts`] found.
fn check_face_indices(path: &Path, text: &str, counts: [usize; 3]) -> Result<(), LoadError> {
    let mut seen = [0usize; 3];
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => seen[0] += 1,
            Some("vt") => seen[1] += 1,
            Some("vn") => seen[2] += 1,
            // Lines and points too: tobj reads their indices the same way, though unused.
            Some("f" | "l" | "p") => {
                for w in words {
                    for (k, part) in w.split('/').enumerate().take(3) {
                        if part.is_empty() {
                            continue;
                        }
                        // Forward: any element of the file; backward: one already read.
                        let ok = part.parse::<i64>().is_ok_and(|i| {
                            (i > 0 && i as u64 <= counts[k] as u64)
                                || (i < 0 && i.unsigned_abs() <= seen[k] as u64)
                        });
                        if !ok {
                            let what = ["vertex", "texture coordinate", "normal"][k];
                            return Err(LoadError::Parse {
                                path: path.to_owned(),
                                reason: format!(
                                    "line {}: face index '{part}' names no {what} (the file has {})",
                                    n + 1,
                                    counts[k]
                                ),
                            });
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// The text of the OBJ file at `path`, with errors that say what is wrong: missing, a
/// directory, no permission, too large (before reading it), binary data.
pub fn read_obj_text(path: &Path) -> Result<String, LoadError> {
    let io = |source| LoadError::Io {
        path: path.to_owned(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_dir() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "it is a directory, not an OBJ file",
        )));
    }
    if meta.len() > MAX_OBJ_BYTES {
        return Err(LoadError::Parse {
            path: path.to_owned(),
            reason: format!(
                "it is {} MB, more than the {} MB an OBJ may have here ({} vertices at most)",
                meta.len() >> 20,
                MAX_OBJ_BYTES >> 20,
                super::cloth_mesh::MAX_VERTICES
            ),
        });
    }
    let bytes = std::fs::read(path).map_err(io)?;
    if let Some(at) = bytes.iter().position(|&b| b == 0) {
        return Err(LoadError::Parse {
            path: path.to_owned(),
            reason: format!("it holds binary data (a zero byte at offset {at}), not OBJ text"),
        });
    }
    // Comments and names in another encoding do not matter to the geometry.
    Ok(match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

/// Loads every object of an OBJ file into one mesh. Missing UVs become a planar projection
/// onto the mesh's two widest axes. The result is validated (finite, in range, no
/// degenerate triangle, manifold).
pub fn load_obj(path: &Path) -> Result<ClothMesh, LoadError> {
    parse_obj(path, &read_obj_text(path)?)
}

/// [`load_obj`] on text already read; `path` names it in errors.
pub fn parse_obj(path: &Path, text: &str) -> Result<ClothMesh, LoadError> {
    let counts = check_obj_counts(path, text)?;
    check_face_indices(path, text, counts)?;
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are not read: a cloth's look is its painted texture.
    let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
    let (models, _materials) = tobj::load_obj_buf(
        &mut std::io::Cursor::new(text.as_bytes()),
        &opts,
        no_materials,
    )
    .map_err(|e| LoadError::Parse {
        path: path.to_owned(),
        reason: e.to_string(),
    })?;
    let mut mesh = ClothMesh {
        positions: Vec::new(),
        uvs: Vec::new(),
        triangles: Vec::new(),
    };
    let mut has_uvs = true;
    for model in &models {
        let m = &model.mesh;
        let base = mesh.positions.len() as u32;
        let nv = m.positions.len() / 3;
        if m.positions.len() % 3 != 0 || m.indices.len() % 3 != 0 {
            return Err(LoadError::Parse {
                path: path.to_owned(),
                reason: "malformed vertex or face data".into(),
            });
        }
        mesh.positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2])),
        );
        if m.texcoords.len() == nv * 2 {
            mesh.uvs
                .extend(m.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])));
        } else {
            has_uvs = false;
            mesh.uvs.extend(std::iter::repeat_n(Vec2::ZERO, nv));
        }
        for f in m.indices.chunks_exact(3) {
            mesh.triangles.push([base + f[0], base + f[1], base + f[2]]);
        }
    }
    if !has_uvs {
        planar_uvs(&mut mesh);
    }
    mesh.validate().map_err(|source| LoadError::Invalid {
        path: path.to_owned(),
        source,
    })?;
    Ok(mesh)
}

/// Projects positions onto the two axes with the largest extent, normalised to [0, 1].
fn planar_uvs(mesh: &mut ClothMesh) {
    let (mn, mx) = super::bounds(&mesh.positions);
    let ext = mx - mn;
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| ext[b].total_cmp(&ext[a]));
    for (uv, p) in mesh.uvs.iter_mut().zip(&mesh.positions) {
        let u = (p[axes[0]] - mn[axes[0]]) / ext[axes[0]].max(1e-9);
        let v = (p[axes[1]] - mn[axes[1]]) / ext[axes[1]].max(1e-9);
        *uv = Vec2::new(u, v);
    }
}

/// Area-weighted vertex normals.
pub fn vertex_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let fnrm = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += fnrm;
        }
    }
    for v in &mut n {
        *v = v.normalize_or(Vec3::Y);
    }
    n
}

/// Writes an OBJ with positions, optional UVs, normals and faces. `mtl` names a material
/// library and material to reference (written separately).
pub fn write_obj(
    path: &Path,
    name: &str,
    positions: &[Vec3],
    uvs: Option<&[Vec2]>,
    triangles: &[[u32; 3]],
    mtl: Option<(&str, &str)>,
) -> std::io::Result<()> {
    let normals = vertex_normals(positions, triangles);
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "# Saiho cloth-sim export: metres, Y up")?;
    if let Some((lib, _)) = mtl {
        writeln!(w, "mtllib {lib}")?;
    }
    writeln!(w, "o {name}")?;
    for p in positions {
        writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
    }
    if let Some(uvs) = uvs {
        for t in uvs {
            writeln!(w, "vt {} {}", t.x, t.y)?;
        }
    }
    for n in &normals {
        writeln!(w, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    if let Some((_, mat)) = mtl {
        writeln!(w, "usemtl {mat}")?;
    }
    for t in triangles {
        let [a, b, c] = t.map(|i| i + 1);
        if uvs.is_some() {
            writeln!(w, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
        } else {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        }
    }
    w.flush()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A scratch path `name` in a directory of its own ([`forget`] removes both).
    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("saiho-obj-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// Removes a scratch path of [`tmp`] and its directory.
    pub(crate) fn forget(p: &Path) {
        if let Some(dir) = p.parent() {
            let _ = std::fs::remove_dir_all(dir);
        }
    }

    /// Too many vertices or triangles is refused from a count of the lines, before any
    /// parser allocates for them.
    #[test]
    fn too_many_vertices_or_triangles_is_refused_before_parsing() {
        let max = crate::mesh::MAX_VERTICES;
        let mut text = "v\n".repeat(max);
        assert!(check_obj_counts(Path::new("a.obj"), &text).is_ok());
        text.push_str("v 0 0 0\n");
        let e = parse_obj(Path::new("many.obj"), &text)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{} vertices", max + 1)) && e.contains("many.obj"),
            "{e}"
        );
        // One polygon fanned into more triangles than allowed.
        let mut face = String::from("v 0 0 0\nf");
        for i in 0..MAX_OBJ_TRIANGLES + 3 {
            face.push_str(if i % 2 == 0 { " 1" } else { " 1/1" });
        }
        // (The body reader calls the same check first.)
        let e = check_obj_counts(Path::new("fan.obj"), &face)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{} triangles", MAX_OBJ_TRIANGLES + 1)),
            "{e}"
        );
    }

    /// Found by the obj fuzz target: a UV index of -7877777 reached `tobj` as a huge
    /// number and overflowed there. Each out-of-range index is refused with its line.
    #[test]
    fn face_indices_out_of_range_are_refused_with_the_line() {
        let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
        let e = |face: &str| {
            parse_obj(Path::new("f.obj"), &format!("{head}{face}\n"))
                .map(|_| ())
                .unwrap_err()
                .to_string()
        };
        assert!(
            e("f 1/1 2/2 3/-7877777")
                .contains("line 7: face index '-7877777' names no texture coordinate")
        );
        assert!(e("f 1 2 4").contains("'4' names no vertex (the file has 3)"));
        assert!(e("f 1 2 0").contains("'0' names no vertex"));
        assert!(e("f 1//1 2//1 3//1").contains("names no normal (the file has 0)"));
        assert!(e("f 1 2 x").contains("'x' names no vertex"));
        // A polyline's too (tobj overflowed on it though it is not kept).
        assert!(e("f 1 2 3\nl 2/-45/5 1").contains("line 8: face index '-45'"));
        // In range, counted back from the last: fine.
        let ok = parse_obj(Path::new("f.obj"), &format!("{head}f -3/-3 -2/-2 -1/-1\n"));
        assert!(ok.is_ok(), "{ok:?}");
    }

    #[test]
    fn round_trip_keeps_geometry_and_uvs() {
        let m = ClothMesh::grid(1.0, 0.5, 4, 3, 0.2).unwrap();
        let p = tmp("rt.obj");
        write_obj(&p, "cloth", &m.positions, Some(&m.uvs), &m.triangles, None).unwrap();
        let back = load_obj(&p).unwrap();
        // tobj renumbers vertices by first use, so compare triangle by triangle.
        assert_eq!(back.triangles.len(), m.triangles.len());
        for (ta, tb) in back.triangles.iter().zip(&m.triangles) {
            for k in 0..3 {
                let (a, b) = (ta[k] as usize, tb[k] as usize);
                assert!((back.positions[a] - m.positions[b]).length() < 1e-6);
                assert!((back.uvs[a] - m.uvs[b]).length() < 1e-6);
            }
        }
        forget(&p);
    }

    #[test]
    fn bad_files_give_clear_errors() {
        let mut made = Vec::new();
        let p = tmp("nan.obj");
        made.push(p.clone());
        std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n").unwrap();
        let e = load_obj(&p).unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
        let p = tmp("degen.obj");
        made.push(p.clone());
        std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap();
        assert!(load_obj(&p).unwrap_err().to_string().contains("degenerate"));
        let p = tmp("nonmanifold.obj");
        made.push(p.clone());
        std::fs::write(
            &p,
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
        )
        .unwrap();
        assert!(
            load_obj(&p)
                .unwrap_err()
                .to_string()
                .contains("shared by 3")
        );
        let p = tmp("range.obj");
        made.push(p.clone());
        std::fs::write(&p, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
        assert!(load_obj(&p).is_err());
        assert!(matches!(
            load_obj(Path::new("/nonexistent/x.obj")),
            Err(LoadError::Io { .. })
        ));
        made.iter().for_each(|p| forget(p));
    }

    /// Files `read_obj_text` and the readers must refuse saying why: a directory, binary
    /// data, a coordinate out of range, too large, no permission (the body's reader is
    /// checked on the same files in `collision::body::check`).
    pub(crate) fn unreadable(name: &str) -> Vec<(std::path::PathBuf, &'static str)> {
        let dir = tmp(&format!("{name}-adir"));
        std::fs::create_dir_all(&dir).unwrap();
        let garbage = tmp(&format!("{name}-garbage.obj"));
        let bytes: Vec<u8> = (0..4096u32)
            .map(|i| (i.wrapping_mul(2654435761) >> 24) as u8)
            .chain([0])
            .collect();
        std::fs::write(&garbage, &bytes).unwrap();
        let far = tmp(&format!("{name}-far.obj"));
        std::fs::write(
            &far,
            "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n",
        )
        .unwrap();
        // Too large: refused from its size, before reading (a sparse file takes no disk).
        let huge = tmp(&format!("{name}-huge.obj"));
        std::fs::File::create(&huge)
            .unwrap()
            .set_len(MAX_OBJ_BYTES + 1)
            .unwrap();
        let mut out = vec![
            (dir, "is a directory"),
            (garbage, "binary data"),
            (far, "1.000e30 m out"),
            (huge, "more than the 512 MB"),
        ];
        // No permission (root reads anything, so only as another user).
        let locked = tmp(&format!("{name}-locked.obj"));
        std::fs::write(&locked, "v 0 0 0\n").unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o000)).unwrap();
        if std::fs::read(&locked).is_err() {
            out.push((locked, "ermission denied"));
        } else {
            forget(&locked);
        }
        out
    }

    /// What the issue found saying "read error", "open file failed" or "degenerate" now
    /// says what is wrong.
    #[test]
    fn unreadable_files_say_why() {
        for (p, why) in unreadable("cloth") {
            let e = load_obj(&p).unwrap_err().to_string();
            assert!(e.contains(why), "{}: {e}", p.display());
            forget(&p);
        }
    }
}
