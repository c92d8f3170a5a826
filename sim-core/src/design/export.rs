//! Export of the live design for ordinary tools: OBJ (positions, per-corner UVs, vertex
//! normals) with an MTL whose diffuse map is the painted texture as PNG, and binary glTF
//! 2.0 (`.glb`, the texture embedded).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::document::Design;
use super::texture::Texture;

#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("cannot write {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot encode {path} as PNG: {reason}")]
    Png { path: PathBuf, reason: String },
    #[error("export name '{0}' must be a plain file name (letters, digits, '-', '_', '.')")]
    BadName(String),
    #[error("the cloth has no triangles left to export")]
    Empty,
    #[error("seam allowance must be between 0 and 100 mm, got {0}")]
    BadAllowance(f64),
}

fn check_name(name: &str) -> Result<(), ExportError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
    {
        return Err(ExportError::BadName(name.into()));
    }
    Ok(())
}

/// Encodes an RGBA8 texture as PNG bytes.
pub fn png_bytes(t: &Texture) -> Result<Vec<u8>, String> {
    crate::mesh::png::rgba_png(&t.rgba, t.width, t.height)
}

/// Writes `dir/name.obj`, `dir/name.mtl` and `dir/name.png`; returns the three paths.
/// Only vertices some triangle uses are written (renumbered in order).
pub fn export_obj(design: &Design, dir: &Path, name: &str) -> Result<Vec<PathBuf>, ExportError> {
    check_name(name)?;
    let live = &design.sim.cloth.live;
    if live.tri_count() == 0 {
        return Err(ExportError::Empty);
    }
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| ExportError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let (obj, mtl, png) = (
        dir.join(format!("{name}.obj")),
        dir.join(format!("{name}.mtl")),
        dir.join(format!("{name}.png")),
    );
    let x = &design.sim.cloth.x;
    let mut index = vec![0u32; x.len()];
    let normals = vertex_normals(design);
    let mut s = String::with_capacity(64 * (x.len() + 3 * live.tri_count()));
    let _ = writeln!(s, "# Saiho cloth export\nmtllib {name}.mtl\no {name}");
    let mut next = 1u32;
    for (i, p) in x.iter().enumerate() {
        if live.vertex_alive(i as u32) {
            index[i] = next;
            next += 1;
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
    }
    for (i, n) in normals.iter().enumerate() {
        if live.vertex_alive(i as u32) {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
    }
    for (_, t) in live.iter() {
        for uv in &t.uv {
            let _ = writeln!(s, "vt {} {}", uv.x, uv.y);
        }
    }
    let _ = writeln!(s, "usemtl cloth\ns off");
    for (k, (_, t)) in live.iter().enumerate() {
        let vt = 3 * k as u32 + 1;
        let [a, b, c] = t.v.map(|i| index[i as usize]);
        let _ = writeln!(s, "f {a}/{vt}/{a} {b}/{}/{b} {c}/{}/{c}", vt + 1, vt + 2);
    }
    std::fs::write(&obj, s).map_err(io(&obj))?;
    let m = format!(
        "# Saiho cloth material\nnewmtl cloth\nKa 0 0 0\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd {name}.png\n"
    );
    std::fs::write(&mtl, m).map_err(io(&mtl))?;
    let bytes = png_bytes(&design.texture).map_err(|reason| ExportError::Png {
        path: png.clone(),
        reason,
    })?;
    std::fs::write(&png, bytes).map_err(io(&png))?;
    Ok(vec![obj, mtl, png])
}

/// Vertex normals of the live mesh (area-weighted), by vertex index.
fn vertex_normals(design: &Design) -> Vec<Vec3> {
    let x = &design.sim.cloth.x;
    let mut normals = vec![Vec3::ZERO; x.len()];
    for (_, t) in design.sim.cloth.live.iter() {
        let [a, b, c] = t.v.map(|i| x[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in &t.v {
            normals[i as usize] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or(Vec3::Y)).collect()
}

fn pad4(v: &mut Vec<u8>, byte: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(byte);
    }
}

/// Writes `dir/name.glb`: one mesh (a vertex per distinct position + UV pair, so seams in
/// the texture stay sharp), one double-sided material whose base colour is the texture.
pub fn export_glb(design: &Design, dir: &Path, name: &str) -> Result<PathBuf, ExportError> {
    check_name(name)?;
    let all: Vec<u32> = design.sim.cloth.live.iter().map(|(s, _)| s).collect();
    let part = Part {
        name: name.into(),
        fabric: None,
        slots: all,
    };
    write_glb(design, &dir.join(format!("{name}.glb")), &[part])
}

/// Writes `dir/garment.glb`: the garment as its pieces, one named mesh and node each (as
/// [`Design::piece_list`] names them: "front", "back", "front 2" once cut), their fabric
/// in the node's `extras`, one material and texture shared, so that a tool opening it
/// (Blender, a viewer) lists the pieces. A sewn vertex is in both pieces' meshes.
pub fn export_garment_glb(design: &Design, dir: &Path) -> Result<PathBuf, ExportError> {
    let parts: Vec<Part> = (design.listed().into_iter())
        .map(|(info, slots)| Part {
            name: info.name,
            fabric: Some(info.fabric),
            slots,
        })
        .collect();
    write_glb(design, &dir.join("garment.glb"), &parts)
}

/// The JSON chunk of the binary glTF `glb`, once its container checks out: the magic,
/// version 2, the length it declares, a JSON chunk and then a BIN chunk as long as the
/// JSON's buffer says (what a reader checks before it trusts the file).
pub fn glb_json(glb: &[u8]) -> Result<serde_json::Value, String> {
    let u32_at = |k: usize| {
        (glb.get(k..k + 4)).map(|b| u32::from_le_bytes(b.try_into().unwrap_or_default()) as usize)
    };
    if glb.get(0..4) != Some(&b"glTF"[..]) || u32_at(4) != Some(2) || u32_at(8) != Some(glb.len()) {
        return Err("not a binary glTF 2.0 of its declared length".into());
    }
    let json_len = u32_at(12).ok_or("no JSON chunk")?;
    let json = (glb.get(20..20 + json_len))
        .filter(|_| glb.get(16..20) == Some(&b"JSON"[..]))
        .ok_or("no JSON chunk")?;
    let json: serde_json::Value = serde_json::from_slice(json).map_err(|e| e.to_string())?;
    let bin_len = u32_at(20 + json_len).ok_or("no BIN chunk")?;
    if glb.get(24 + json_len..28 + json_len) != Some(&b"BIN\0"[..])
        || json["buffers"][0]["byteLength"] != bin_len
    {
        return Err("the BIN chunk is not the buffer the JSON declares".into());
    }
    Ok(json)
}

/// A named mesh of a glTF export: the live triangle slots it holds.
struct Part {
    name: String,
    fabric: Option<String>,
    slots: Vec<u32>,
}

/// The vertex arrays of one part's mesh: a vertex per distinct position + UV pair.
#[derive(Default)]
struct PartMesh {
    pos: Vec<Vec3>,
    nrm: Vec<Vec3>,
    uv: Vec<[f32; 2]>,
    idx: Vec<u32>,
}

impl PartMesh {
    fn of(design: &Design, normals: &[Vec3], slots: &[u32]) -> Self {
        let mut m = Self::default();
        let mut index_of: std::collections::HashMap<(u32, u32, u32), u32> =
            std::collections::HashMap::new();
        for t in slots.iter().filter_map(|&s| design.sim.cloth.live.tri(s)) {
            for k in 0..3 {
                let v = t.v[k];
                let key = (v, t.uv[k].x.to_bits(), t.uv[k].y.to_bits());
                let next = index_of.len() as u32;
                let i = *index_of.entry(key).or_insert_with(|| {
                    m.pos.push(design.sim.cloth.x[v as usize]);
                    m.nrm.push(normals[v as usize]);
                    // glTF's UV origin is the top-left corner.
                    m.uv.push([t.uv[k].x, 1.0 - t.uv[k].y]);
                    next
                });
                m.idx.push(i);
            }
        }
        m
    }
}

/// Writes `parts` to `path` as binary glTF 2.0, a mesh and a node each.
fn write_glb(design: &Design, path: &Path, parts: &[Part]) -> Result<PathBuf, ExportError> {
    if design.sim.cloth.live.tri_count() == 0 || parts.iter().all(|p| p.slots.is_empty()) {
        return Err(ExportError::Empty);
    }
    let path = path.to_owned();
    let dir = path.parent().unwrap_or(Path::new("."));
    let io = |source| ExportError::Io {
        path: path.clone(),
        source,
    };
    std::fs::create_dir_all(dir).map_err(|source| ExportError::Io {
        path: dir.to_owned(),
        source,
    })?;
    let normals = vertex_normals(design);
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut view = |bin: &mut Vec<u8>, bytes: &[u8], target: Option<u32>| -> usize {
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        pad4(bin, 0);
        let mut v =
            serde_json::json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = t.into();
        }
        views.push(v);
        views.len() - 1
    };
    let f32s = |v: &[f32]| v.iter().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
    let (mut accessors, mut meshes, mut nodes) = (Vec::new(), Vec::new(), Vec::new());
    for part in parts.iter().filter(|p| !p.slots.is_empty()) {
        let m = PartMesh::of(design, &normals, &part.slots);
        let lo = m
            .pos
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |a, &p| a.min(p));
        let hi = m
            .pos
            .iter()
            .fold(Vec3::splat(f32::NEG_INFINITY), |a, &p| a.max(p));
        let flat3: Vec<f32> = m.pos.iter().flat_map(|p| p.to_array()).collect();
        let flatn: Vec<f32> = m.nrm.iter().flat_map(|p| p.to_array()).collect();
        let flatuv: Vec<f32> = m.uv.iter().flatten().copied().collect();
        let vp = view(&mut bin, &f32s(&flat3), Some(34962));
        let vn = view(&mut bin, &f32s(&flatn), Some(34962));
        let vt = view(&mut bin, &f32s(&flatuv), Some(34962));
        let ix: Vec<u8> = m.idx.iter().flat_map(|i| i.to_le_bytes()).collect();
        let vi = view(&mut bin, &ix, Some(34963));
        let (n, a) = (m.pos.len(), accessors.len());
        accessors.extend([
            serde_json::json!({"bufferView": vp, "componentType": 5126, "count": n,
                "type": "VEC3", "min": lo.to_array(), "max": hi.to_array()}),
            serde_json::json!({"bufferView": vn, "componentType": 5126, "count": n, "type": "VEC3"}),
            serde_json::json!({"bufferView": vt, "componentType": 5126, "count": n, "type": "VEC2"}),
            serde_json::json!({"bufferView": vi, "componentType": 5125, "count": m.idx.len(),
                "type": "SCALAR"}),
        ]);
        let mut node = serde_json::json!({"mesh": meshes.len(), "name": part.name});
        if let Some(f) = &part.fabric {
            node["extras"] = serde_json::json!({"fabric": f});
        }
        nodes.push(node);
        meshes.push(serde_json::json!({"name": part.name, "primitives": [{
            "attributes": {"POSITION": a, "NORMAL": a + 1, "TEXCOORD_0": a + 2},
            "indices": a + 3, "material": 0, "mode": 4}]}));
    }
    let png = png_bytes(&design.texture).map_err(|reason| ExportError::Png {
        path: path.clone(),
        reason,
    })?;
    let vimg = view(&mut bin, &png, None);
    let json = serde_json::json!({
        "asset": {"version": "2.0", "generator": "Saiho sim-core"},
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [{"name": "cloth", "doubleSided": true, "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}],
        "images": [{"bufferView": vimg, "mimeType": "image/png"}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    let mut js = serde_json::to_vec(&json).map_err(|e| ExportError::Png {
        path: path.clone(),
        reason: e.to_string(),
    })?;
    pad4(&mut js, b' ');
    let total = 12 + 8 + js.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(js.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&js);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    std::fs::write(&path, out).map_err(io)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gltf_json(path: &Path) -> serde_json::Value {
        glb_json(&std::fs::read(path).unwrap()).unwrap()
    }

    #[test]
    fn the_garment_glb_has_a_named_mesh_per_piece_and_the_cloth_glb_one() {
        let d = crate::design::tests::sewn_dress(0.05, 0);
        let dir = std::env::temp_dir().join(format!("saiho-garment-glb-{}", std::process::id()));
        let garment = gltf_json(&export_garment_glb(&d, &dir).unwrap());
        let cloth = gltf_json(&export_glb(&d, &dir, "cloth").unwrap());
        let _ = std::fs::remove_dir_all(&dir);
        let names: Vec<&str> = (garment["nodes"].as_array().unwrap().iter())
            .map(|n| n["name"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["front", "back"]);
        assert_eq!(garment["nodes"][0]["extras"]["fabric"], "cotton");
        assert_eq!(garment["scenes"][0]["nodes"], serde_json::json!([0, 1]));
        // Every triangle in one piece's mesh, each mesh's own vertices.
        let count = |json: &serde_json::Value, mesh: usize, what: &str| {
            let p = &json["meshes"][mesh]["primitives"][0];
            let a = if what == "indices" {
                &p["indices"]
            } else {
                &p["attributes"][what]
            };
            json["accessors"][a.as_u64().unwrap() as usize]["count"]
                .as_u64()
                .unwrap()
        };
        let tris = d.sim.cloth.live.tri_count() as u64;
        assert_eq!(
            count(&garment, 0, "indices") + count(&garment, 1, "indices"),
            3 * tris
        );
        assert_eq!(count(&cloth, 0, "indices"), 3 * tris);
        let list = d.piece_list();
        for (k, info) in list.iter().enumerate() {
            assert_eq!(count(&garment, k, "indices"), 3 * info.triangles as u64);
            // A vertex per distinct place and UV: at least the piece's vertices.
            assert!(count(&garment, k, "POSITION") >= info.vertices as u64);
        }
        assert_eq!(cloth["nodes"].as_array().unwrap().len(), 1);
        // Cut short or not glTF, a file is refused.
        let mut bytes = b"glTF".to_vec();
        bytes.extend_from_slice(&2u32.to_le_bytes());
        bytes.extend_from_slice(&99u32.to_le_bytes());
        assert!(glb_json(&bytes).is_err());
        assert!(glb_json(b"not glTF at all").is_err());
    }
}
