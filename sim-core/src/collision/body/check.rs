//! Reading a body from an OBJ file and checking that it is a solid: closed, manifold,
//! consistently wound, enclosing a positive volume. Problems are named in the file's own
//! numbering (1-based `v` order) with the line of the face, so the user can find them; an
//! inside-out surface, or parts of it wound the wrong way, are turned outward and the
//! repair is said.
//!
//! The reader is our own (not `tobj`) because `tobj` renumbers vertices; it takes `v` and
//! `f` lines (`i`, `i/t`, `i//n`, `i/t/n`, negative indices counting back), fans polygons
//! into triangles and ignores everything else.

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;

use crate::error::LoadError;

/// A body as read and checked: its vertices (those the faces use), outward-wound
/// triangles, and what was repaired.
#[derive(Debug)]
pub struct CheckedBody {
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub repairs: Vec<String>,
}

/// A face triangle: vertices in the file's numbering (0-based here) and its line.
#[derive(Clone, Copy, Debug)]
struct Face {
    v: [u32; 3],
    line: usize,
}

fn bad(path: &Path, reason: String) -> LoadError {
    LoadError::Parse {
        path: path.to_owned(),
        reason,
    }
}

fn not_solid(path: &Path, problem: String) -> LoadError {
    LoadError::NotSolid {
        path: path.to_owned(),
        problem,
    }
}

/// Reads `path` and checks it (see the module's doc).
#[cfg(test)]
pub fn read_body_obj(path: &Path) -> Result<CheckedBody, LoadError> {
    check_body_text(path, &crate::mesh::obj::read_obj_text(path)?)
}

/// [`read_body_obj`] on text already read; `path` names it in errors.
pub fn check_body_text(path: &Path, text: &str) -> Result<CheckedBody, LoadError> {
    crate::mesh::obj::check_obj_counts(path, text)?;
    let (vertices, faces) = parse(path, text)?;
    check(path, &vertices, faces)
}

fn parse(path: &Path, text: &str) -> Result<(Vec<Vec3>, Vec<Face>), LoadError> {
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let mut words = raw.split_whitespace();
        match words.next() {
            Some("v") => {
                let mut c = [0.0f32; 3];
                for x in &mut c {
                    *x = words
                        .next()
                        .and_then(|w| w.parse::<f32>().ok())
                        .ok_or_else(|| {
                            bad(path, format!("line {line}: a vertex needs three numbers"))
                        })?;
                }
                if !c.iter().all(|x| x.is_finite()) {
                    return Err(bad(
                        path,
                        format!("line {line}: vertex {} is not finite", vertices.len() + 1),
                    ));
                }
                if let Some(far) = c.iter().find(|x| x.abs() > crate::mesh::MAX_COORD) {
                    return Err(bad(
                        path,
                        format!(
                            "line {line}: vertex {} lies {far:.3e} m out, beyond the {} m a \
                             scene holds (another unit, or a damaged file?)",
                            vertices.len() + 1,
                            crate::mesh::MAX_COORD
                        ),
                    ));
                }
                vertices.push(Vec3::from(c));
            }
            Some("f") => {
                let mut ids = Vec::with_capacity(4);
                for w in words {
                    let first = w.split('/').next().unwrap_or("");
                    let i: i64 = first.parse().map_err(|_| {
                        bad(path, format!("line {line}: '{w}' is not a vertex index"))
                    })?;
                    let n = vertices.len() as i64;
                    let idx = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || idx < 0 || idx >= n {
                        return Err(bad(
                            path,
                            format!(
                                "line {line}: vertex {i} does not exist (there are {n} so far)"
                            ),
                        ));
                    }
                    ids.push(idx as u32);
                }
                if ids.len() < 3 {
                    return Err(bad(
                        path,
                        format!("line {line}: a face needs three vertices"),
                    ));
                }
                for k in 1..ids.len() - 1 {
                    faces.push(Face {
                        v: [ids[0], ids[k], ids[k + 1]],
                        line,
                    });
                }
            }
            _ => {}
        }
    }
    if faces.is_empty() {
        return Err(bad(path, "no faces".into()));
    }
    Ok((vertices, faces))
}

/// The edges of the faces: per undirected edge, the faces on it and whether each runs
/// it from the lower index to the higher.
type Edges = HashMap<(u32, u32), Vec<(usize, bool)>>;

fn edges_of(faces: &[Face]) -> Edges {
    let mut edges: Edges = HashMap::with_capacity(faces.len() * 2);
    for (f, face) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (face.v[k], face.v[(k + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((f, a < b));
        }
    }
    edges
}

fn check(path: &Path, vertices: &[Vec3], mut faces: Vec<Face>) -> Result<CheckedBody, LoadError> {
    for f in &faces {
        let [a, b, c] = f.v.map(|i| vertices[i as usize]);
        if f.v[0] == f.v[1]
            || f.v[1] == f.v[2]
            || f.v[0] == f.v[2]
            || (b - a).cross(c - a) == Vec3::ZERO
        {
            return Err(not_solid(
                path,
                format!("the face on line {} has no area", f.line),
            ));
        }
    }
    // Where a surface looks open, a vertex repeated at the same position is the same
    // vertex (exporters split them where texture coordinates differ); it is named by its
    // first occurrence. Only vertices on open edges are joined, so closed parts that
    // happen to touch (a mannequin's limbs) stay apart.
    let mut open = vec![false; vertices.len()];
    for (&(a, b), on) in &edges_of(&faces) {
        if on.len() == 1 {
            open[a as usize] = true;
            open[b as usize] = true;
        }
    }
    let mut first: HashMap<[u32; 3], u32> = HashMap::new();
    let canon: Vec<u32> = (0..vertices.len() as u32)
        .map(|i| {
            if open[i as usize] {
                *first
                    .entry(vertices[i as usize].to_array().map(f32::to_bits))
                    .or_insert(i)
            } else {
                i
            }
        })
        .collect();
    for f in &mut faces {
        f.v = f.v.map(|i| canon[i as usize]);
        if f.v[0] == f.v[1] || f.v[1] == f.v[2] || f.v[0] == f.v[2] {
            return Err(not_solid(
                path,
                format!("the face on line {} has no area", f.line),
            ));
        }
    }
    let edges = edges_of(&faces);
    // The first problem edge in file order: a hole, or more than two faces on an edge.
    let mut worst: Option<((usize, u32, u32), String)> = None;
    for (&(a, b), on) in &edges {
        let lines: Vec<String> = on.iter().map(|&(f, _)| faces[f].line.to_string()).collect();
        let at = (
            on.iter().map(|&(f, _)| faces[f].line).min().unwrap_or(0),
            a,
            b,
        );
        let problem = match on.len() {
            1 => format!(
                "it is not closed: the edge from vertex {} to vertex {} has a face on one side only (line {}); a hole there lets the cloth in",
                a + 1,
                b + 1,
                lines[0]
            ),
            2 => continue,
            n => format!(
                "it is not manifold: the edge from vertex {} to vertex {} is shared by {n} faces (lines {})",
                a + 1,
                b + 1,
                lines.join(", ")
            ),
        };
        if worst.as_ref().is_none_or(|(l, _)| at < *l) {
            worst = Some((at, problem));
        }
    }
    if let Some((_, problem)) = worst {
        return Err(not_solid(path, problem));
    }
    let flip = orient(path, vertices, &faces, &edges)?;
    let mut repairs = Vec::new();
    let mut triangles: Vec<[u32; 3]> = faces
        .iter()
        .zip(&flip)
        .map(|(f, &fl)| if fl { [f.v[0], f.v[2], f.v[1]] } else { f.v })
        .collect();
    let flipped = flip.iter().filter(|&&f| f).count();
    if flipped == faces.len() {
        repairs.push(format!(
            "{}: the surface was wound inside out (its faces pointed inward); turned it outward",
            path.display()
        ));
    } else if flipped > 0 {
        repairs.push(format!(
            "{}: {flipped} of its {} faces were wound the other way from their neighbours; turned them outward",
            path.display(),
            faces.len()
        ));
    }
    // Keep only the vertices the faces use.
    let mut new_index = vec![u32::MAX; vertices.len()];
    let mut used = Vec::new();
    for t in &mut triangles {
        for v in t.iter_mut() {
            if new_index[*v as usize] == u32::MAX {
                new_index[*v as usize] = used.len() as u32;
                used.push(vertices[*v as usize]);
            }
            *v = new_index[*v as usize];
        }
    }
    Ok(CheckedBody {
        vertices: used,
        triangles,
        repairs,
    })
}

/// Which faces to turn over so that every part winds consistently and outward (positive
/// volume). Refuses a surface that cannot be wound consistently or encloses no volume.
fn orient(
    path: &Path,
    vertices: &[Vec3],
    faces: &[Face],
    edges: &Edges,
) -> Result<Vec<bool>, LoadError> {
    let mut neighbours: Vec<Vec<(usize, bool)>> = vec![Vec::new(); faces.len()];
    for on in edges.values() {
        if let [(f, df), (g, dg)] = on[..] {
            // Consistent when the two faces run their shared edge opposite ways.
            let same_way = df == dg;
            neighbours[f].push((g, same_way));
            neighbours[g].push((f, same_way));
        }
    }
    let mut flip: Vec<Option<bool>> = vec![None; faces.len()];
    let mut stack = Vec::new();
    for start in 0..faces.len() {
        if flip[start].is_some() {
            continue;
        }
        flip[start] = Some(false);
        stack.push(start);
        let mut part = vec![start];
        while let Some(f) = stack.pop() {
            let ff = flip[f].unwrap_or(false);
            for &(g, same_way) in &neighbours[f] {
                let want = ff ^ same_way;
                match flip[g] {
                    None => {
                        flip[g] = Some(want);
                        stack.push(g);
                        part.push(g);
                    }
                    Some(have) if have != want => {
                        return Err(not_solid(
                            path,
                            format!(
                                "it cannot be wound consistently (one-sided, like a Möbius strip): see the faces on lines {} and {}",
                                faces[f].line, faces[g].line
                            ),
                        ));
                    }
                    Some(_) => {}
                }
            }
        }
        // Six times the part's signed volume as now wound, about its first vertex (the
        // choice of origin cancels out on a closed part), and its size for scale.
        let o = vertices[faces[start].v[0] as usize].as_dvec3();
        let (mut volume6, mut lo, mut hi) = (0.0f64, o, o);
        for &f in &part {
            let [a, b, c] = faces[f].v.map(|i| vertices[i as usize].as_dvec3() - o);
            let d = a.dot(b.cross(c));
            volume6 += if flip[f] == Some(true) { -d } else { d };
            lo = lo.min(a + o).min(b + o).min(c + o);
            hi = hi.max(a + o).max(b + o).max(c + o);
        }
        let size = (hi - lo).max_element();
        if volume6.abs() <= 1.0e-9 * size * size * size {
            return Err(not_solid(
                path,
                format!(
                    "the part starting at the face on line {} encloses no volume",
                    faces[start].line
                ),
            ));
        }
        if volume6 < 0.0 {
            for &f in &part {
                flip[f] = flip[f].map(|x| !x);
            }
        }
    }
    Ok(flip.into_iter().map(|f| f.unwrap_or(false)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::BodyKind;

    /// `text` read as the body file `name` (written to a scratch directory of its own,
    /// removed after).
    fn read_text(name: &str, text: &str) -> Result<CheckedBody, LoadError> {
        let dir = std::env::temp_dir().join(format!("saiho-body-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let read = read_body_obj(&p);
        let _ = std::fs::remove_dir_all(&dir);
        read
    }

    const CUBE_V: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
    /// The unit cube's faces, wound outward (counter-clockwise seen from outside).
    const CUBE_F: [[u32; 3]; 12] = [
        [1, 4, 3],
        [1, 3, 2],
        [5, 6, 7],
        [5, 7, 8],
        [1, 2, 6],
        [1, 6, 5],
        [4, 8, 7],
        [4, 7, 3],
        [1, 5, 8],
        [1, 8, 4],
        [2, 3, 7],
        [2, 7, 6],
    ];

    fn cube(faces: impl Iterator<Item = [u32; 3]>) -> String {
        let mut s = CUBE_V.to_string();
        for [a, b, c] in faces {
            s += &format!("f {a} {b} {c}\n");
        }
        s
    }

    fn volume(b: &CheckedBody) -> f32 {
        b.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| b.vertices[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn refusal(name: &str, text: &str) -> String {
        read_text(name, text).unwrap_err().to_string()
    }

    #[test]
    fn a_closed_outward_cube_is_taken_as_it_is() {
        let b = read_text("cube.obj", &cube(CUBE_F.into_iter())).unwrap();
        assert_eq!((b.vertices.len(), b.triangles.len()), (8, 12));
        assert!(b.repairs.is_empty(), "{:?}", b.repairs);
        assert!((volume(&b) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn an_inside_out_surface_is_turned_outward_and_said() {
        let inside_out = cube(CUBE_F.into_iter().map(|[a, b, c]| [a, c, b]));
        let b = read_text("inside-out.obj", &inside_out).unwrap();
        assert!((volume(&b) - 1.0).abs() < 1e-6);
        assert_eq!(b.repairs.len(), 1);
        assert!(b.repairs[0].contains("inside out"), "{:?}", b.repairs);

        // One face wound against its neighbours: only it is turned.
        let one = cube(
            CUBE_F
                .into_iter()
                .enumerate()
                .map(|(i, [a, b, c])| if i == 5 { [a, c, b] } else { [a, b, c] }),
        );
        let b = read_text("one-flipped.obj", &one).unwrap();
        assert!((volume(&b) - 1.0).abs() < 1e-6);
        assert!(
            b.repairs[0].contains("1 of its 12 faces"),
            "{:?}",
            b.repairs
        );
    }

    #[test]
    fn quads_uv_indices_negative_indices_and_split_vertices_are_read() {
        // The cube as quads, written the way exporters do: `v/vt/vn`, relative indices,
        // and the top face's vertices repeated (a UV seam).
        let text = format!(
            "# exported\no cube\n{CUBE_V}vt 0 0\nvn 0 0 1\n\
             f 1/1/1 4/1/1 3/1/1 2/1/1\n\
             f 1//1 2//1 6//1 5//1\n\
             f 4 8 7 3\n\
             f 1 5 8 4\n\
             f 2 3 7 6\n\
             v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
             f -4 -3 -2 -1\n"
        );
        let b = read_text("quads.obj", &text).unwrap();
        assert_eq!((b.vertices.len(), b.triangles.len()), (8, 12));
        assert!((volume(&b) - 1.0).abs() < 1e-6);
        assert!(b.repairs.is_empty(), "{:?}", b.repairs);
    }

    #[test]
    fn surfaces_that_are_not_solids_are_refused_in_the_files_terms() {
        // A hole: the last face is missing. Its edges are named by the file's numbers.
        let e = refusal("hole.obj", &cube(CUBE_F.into_iter().take(11)));
        assert!(
            e.contains("not a solid body") && e.contains("not closed"),
            "{e}"
        );
        // Its open edges are on lines 11, 13 and 19: the first is named.
        let first = "the edge from vertex 6 to vertex 7 has a face on one side only (line 11)";
        assert!(e.contains(first), "{e}");

        let e = refusal("one.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        assert!(e.contains("not closed"), "{e}");

        // A fin on the cube's first edge: three faces on one edge.
        let fin = cube(CUBE_F.into_iter()) + "v -1 -1 0\nf 1 4 9\n";
        let e = refusal("fin.obj", &fin);
        assert!(
            e.contains("not manifold") && e.contains("shared by 3 faces"),
            "{e}"
        );
        assert!(e.contains("vertex 1 to vertex 4"), "{e}");

        let flat = cube(CUBE_F.into_iter()) + "v 2 0 0\nf 1 2 9\n";
        let e = refusal("flat.obj", &flat);
        assert!(e.contains("the face on line 22 has no area"), "{e}");

        // Two triangles back to back: closed and manifold, but no volume.
        let e = refusal("sheet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n");
        assert!(e.contains("encloses no volume"), "{e}");

        let e = refusal("missing.obj", "v 0 0 0\nv 1 0 0\nf 1 2 5\n");
        assert!(
            e.contains("line 3") && e.contains("vertex 5 does not exist"),
            "{e}"
        );
        let e = refusal("nan.obj", "v 0 0 0\nv 1 nan 0\n");
        assert!(e.contains("line 2") && e.contains("not finite"), "{e}");
        let e = refusal("empty.obj", "# nothing\n");
        assert!(e.contains("no faces"), "{e}");
    }

    #[test]
    fn the_built_in_bodies_exported_as_obj_read_back_as_solids() {
        for name in ["cube", "sphere", "mannequin", "mannequin-apose"] {
            let body = BodyKind::parse(name).unwrap().build().unwrap();
            let dir = std::env::temp_dir().join(format!("saiho-body-{}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            let p = dir.join(format!("{name}.obj"));
            crate::mesh::obj::write_obj(&p, name, &body.vertices, None, &body.triangles, None)
                .unwrap();
            let back = read_body_obj(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
            let _ = std::fs::remove_dir_all(&dir);
            assert!(back.repairs.is_empty(), "{name}: {:?}", back.repairs);
            assert_eq!(back.triangles.len(), body.triangles.len(), "{name}");
        }
    }

    /// The body's reader refuses what the cloth's does, saying why.
    #[test]
    fn unreadable_bodies_say_why() {
        for (p, why) in crate::mesh::obj::tests::unreadable("body") {
            let e = read_body_obj(&p).err().unwrap().to_string();
            assert!(e.contains(why), "{}: {e}", p.display());
            crate::mesh::obj::tests::forget(&p);
        }
    }
}
