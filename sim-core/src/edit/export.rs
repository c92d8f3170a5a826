//! Export of the live design for ordinary tools: OBJ (positions, per-corner UVs, vertex
//! normals) with an MTL whose diffuse map is the painted texture as PNG.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::Texture;
use crate::cloth::Simulation;

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
}

/// Encodes an RGBA8 texture as PNG bytes.
pub fn png_bytes(t: &Texture) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, t.width as u32, t.height as u32);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Fast);
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        w.write_image_data(&t.rgba).map_err(|e| e.to_string())?;
        w.finish().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Writes `dir/name.obj`, `dir/name.mtl` and `dir/name.png`; returns the three paths.
/// Only vertices some triangle uses are written (renumbered in order).
pub fn export_obj(sim: &Simulation, dir: &Path, name: &str) -> Result<Vec<PathBuf>, ExportError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
    {
        return Err(ExportError::BadName(name.into()));
    }
    let live = &sim.cloth.live;
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
    let x = &sim.cloth.x;
    let mut index = vec![0u32; x.len()];
    let mut normals = vec![Vec3::ZERO; x.len()];
    for (_, t) in live.iter() {
        let [a, b, c] = t.v.map(|i| x[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in &t.v {
            normals[i as usize] += n;
        }
    }
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
            let n = n.normalize_or(Vec3::Y);
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
    let bytes = png_bytes(&sim.texture).map_err(|reason| ExportError::Png {
        path: png.clone(),
        reason,
    })?;
    std::fs::write(&png, bytes).map_err(io(&png))?;
    Ok(vec![obj, mtl, png])
}
