//! The design file (`.saiho`): everything needed to resume a design — the live pieces
//! with their rest shapes and UVs, positions and velocities, pins, seams, the painted
//! texture, material, model, environment and the body.
//!
//! Layout (all integers little-endian):
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `SAIHODSN` |
//! | 4 | format version (`FORMAT`, currently 1) |
//! | 4 | header length `H` |
//! | H | header, UTF-8 JSON ([`Header`]): settings, counts, and the byte range of each section |
//! | ... | sections, in any order, at the offsets the header gives (relative to the end of the header) |
//! | 8 | FNV-1a 64 checksum of every byte before it |
//!
//! Sections: `x` and `v` (f32 x 3 per vertex), `tris` (per triangle: 3 u32 indices, 3 x 3
//! f32 rest corners, 3 x 2 f32 UVs), `body_vertices` (f32 x 3), `body_triangles` (u32 x 3),
//! `texture` (PNG, RGBA8). A reader refuses a newer format, a bad checksum, or any count,
//! index or value out of range, and builds nothing in that case.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use super::Seam;
use super::export::png_bytes;
use super::{TearMode, TearSettings, Texture};
use crate::body::{Body, BodyKind};
use crate::cloth::{Cloth, Environment, Material, ModelKind, Simulation};
use crate::error::GeometryError;
use crate::mesh::{ClothMesh, LiveMesh, MAX_VERTICES, Tri};

pub const MAGIC: &[u8; 8] = b"SAIHODSN";
pub const FORMAT: u32 = 1;
/// Largest texture side a design may carry.
const MAX_TEXTURE: usize = 8192;

#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    #[error("not a Saiho design file (bad magic bytes)")]
    NotADesign,
    #[error("the file is truncated ({0})")]
    Truncated(&'static str),
    #[error(
        "the design was written in format {found}, newer than this build reads ({FORMAT}); update Saiho"
    )]
    Newer { found: u32 },
    #[error("the design is corrupt: {0}")]
    Corrupt(String),
    #[error("the design's cloth is invalid: {0}")]
    Geometry(#[from] GeometryError),
    #[error("cannot read or write {path}: {source}")]
    Io {
        path: std::path::PathBuf,
        source: std::io::Error,
    },
}

fn corrupt(s: impl Into<String>) -> DesignError {
    DesignError::Corrupt(s.into())
}

#[derive(Serialize, Deserialize, Debug, Clone, PartialEq)]
pub struct Section {
    pub name: String,
    pub offset: u64,
    pub len: u64,
}

#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct SeamRecord {
    pub pairs: Vec<(u32, u32)>,
    pub max_force: f32,
}

/// The JSON header.
#[derive(Serialize, Deserialize, Debug, Clone)]
pub struct Header {
    pub format: u32,
    pub frame: u64,
    pub model: String,
    pub substeps: usize,
    pub material: Material,
    pub gravity: [f32; 3],
    pub frame_dt: f32,
    pub floor: Option<f32>,
    pub body: Option<String>,
    pub vertices: usize,
    pub triangles: usize,
    pub body_vertices: usize,
    pub body_triangles: usize,
    pub pins: Vec<u32>,
    pub seams: Vec<SeamRecord>,
    pub tear_enabled: bool,
    pub tear_threshold: f32,
    pub tear_split: bool,
    pub texture_width: usize,
    pub texture_height: usize,
    pub sections: Vec<Section>,
}

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn put_vec3s(out: &mut Vec<u8>, v: &[Vec3]) {
    for p in v {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
}

/// Reads little-endian values off a byte slice, failing cleanly at its end.
struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], DesignError> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.b.len())
            .ok_or(DesignError::Truncated("section"))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u32(&mut self) -> Result<u32, DesignError> {
        let s = self.take(4)?;
        Ok(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    }

    fn f32(&mut self) -> Result<f32, DesignError> {
        let v = f32::from_bits(self.u32()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(corrupt("a number is NaN or infinite"))
        }
    }

    fn vec3(&mut self) -> Result<Vec3, DesignError> {
        Ok(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }

    fn vec2(&mut self) -> Result<Vec2, DesignError> {
        Ok(Vec2::new(self.f32()?, self.f32()?))
    }
}

impl Simulation {
    /// The design as bytes in the `.saiho` format.
    pub fn save_design(&self) -> Result<Vec<u8>, DesignError> {
        let mut sections: Vec<(String, Vec<u8>)> = Vec::new();
        let mut x = Vec::with_capacity(12 * self.cloth.len());
        put_vec3s(&mut x, &self.cloth.x);
        sections.push(("x".into(), x));
        let mut v = Vec::with_capacity(12 * self.cloth.len());
        put_vec3s(&mut v, &self.cloth.v);
        sections.push(("v".into(), v));
        let mut tris = Vec::with_capacity(72 * self.cloth.live.tri_count());
        for (_, t) in self.cloth.live.iter() {
            for i in t.v {
                tris.extend_from_slice(&i.to_le_bytes());
            }
            put_vec3s(&mut tris, &t.rest);
            for uv in t.uv {
                tris.extend_from_slice(&uv.x.to_le_bytes());
                tris.extend_from_slice(&uv.y.to_le_bytes());
            }
        }
        sections.push(("tris".into(), tris));
        let (bv, bt) = match &self.body {
            Some(b) => {
                let mut bv = Vec::new();
                put_vec3s(&mut bv, &b.vertices);
                let mut bt = Vec::new();
                for t in &b.triangles {
                    for i in t {
                        bt.extend_from_slice(&i.to_le_bytes());
                    }
                }
                (bv, bt)
            }
            None => (Vec::new(), Vec::new()),
        };
        sections.push(("body_vertices".into(), bv));
        sections.push(("body_triangles".into(), bt));
        let png = match &self.png_cache {
            Some((v, bytes)) if *v == self.texture.version => bytes.clone(),
            _ => png_bytes(&self.texture).map_err(corrupt)?,
        };
        sections.push(("texture".into(), png));
        let mut offset = 0u64;
        let table: Vec<Section> = sections
            .iter()
            .map(|(name, b)| {
                let s = Section {
                    name: name.clone(),
                    offset,
                    len: b.len() as u64,
                };
                offset += b.len() as u64;
                s
            })
            .collect();
        let header = Header {
            format: FORMAT,
            frame: self.frame,
            model: self.model.name().into(),
            substeps: self.substeps,
            material: self.material,
            gravity: self.env.gravity.to_array(),
            frame_dt: self.env.frame_dt,
            floor: self.env.floor,
            body: self.body.as_ref().map(|b| b.name.clone()),
            vertices: self.cloth.len(),
            triangles: self.cloth.live.tri_count(),
            body_vertices: self.body.as_ref().map_or(0, |b| b.vertices.len()),
            body_triangles: self.body.as_ref().map_or(0, |b| b.triangles.len()),
            pins: (0..self.cloth.len() as u32)
                .filter(|&i| self.cloth.is_pinned(i as usize))
                .collect(),
            seams: self
                .seams
                .iter()
                .map(|s| SeamRecord {
                    pairs: s.pairs.clone(),
                    max_force: s.max_force,
                })
                .collect(),
            tear_enabled: self.tear.enabled,
            tear_threshold: self.tear.threshold,
            tear_split: self.tear.mode == TearMode::Split,
            texture_width: self.texture.width,
            texture_height: self.texture.height,
            sections: table,
        };
        let json = serde_json::to_vec(&header).map_err(|e| corrupt(e.to_string()))?;
        let mut out = Vec::with_capacity(24 + json.len() + offset as usize);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT.to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(&json);
        for (_, b) in &sections {
            out.extend_from_slice(b);
        }
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        Ok(out)
    }

    /// Encodes the texture for design files now if it changed since the last time, so
    /// that `save_design` does not (encoding 1024 x 1024 takes tens of milliseconds).
    pub fn refresh_png_cache(&mut self) -> Result<(), DesignError> {
        if self
            .png_cache
            .as_ref()
            .is_none_or(|(v, _)| *v != self.texture.version)
        {
            let bytes = png_bytes(&self.texture).map_err(corrupt)?;
            self.png_cache = Some((self.texture.version, bytes));
        }
        Ok(())
    }

    /// Writes the design to `path` (through a temporary file, so a crash mid-write never
    /// leaves a half-written design in its place).
    pub fn save_design_file(&self, path: &std::path::Path) -> Result<(), DesignError> {
        let bytes = self.save_design()?;
        let io = |source| DesignError::Io {
            path: path.to_owned(),
            source,
        };
        let tmp = path.with_extension("saiho.tmp");
        std::fs::write(&tmp, bytes).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    pub fn load_design_file(path: &std::path::Path) -> Result<Self, DesignError> {
        let bytes = std::fs::read(path).map_err(|source| DesignError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::load_design(&bytes)
    }

    /// Rebuilds a simulation from `.saiho` bytes, checking everything.
    pub fn load_design(bytes: &[u8]) -> Result<Self, DesignError> {
        if bytes.len() < 8 || &bytes[..8] != MAGIC {
            return Err(DesignError::NotADesign);
        }
        if bytes.len() < 24 {
            return Err(DesignError::Truncated("header"));
        }
        let version = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
        if version > FORMAT {
            return Err(DesignError::Newer { found: version });
        }
        if version == 0 {
            return Err(corrupt("format version 0"));
        }
        let (body_bytes, sum) = bytes.split_at(bytes.len() - 8);
        let stored = u64::from_le_bytes([
            sum[0], sum[1], sum[2], sum[3], sum[4], sum[5], sum[6], sum[7],
        ]);
        if fnv1a(body_bytes) != stored {
            return Err(corrupt(
                "checksum mismatch (the file was damaged or truncated)",
            ));
        }
        let hlen = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
        let data_start = 16usize
            .checked_add(hlen)
            .filter(|&e| e <= body_bytes.len())
            .ok_or(DesignError::Truncated("header"))?;
        let header: Header = serde_json::from_slice(&body_bytes[16..data_start])
            .map_err(|e| corrupt(format!("header: {e}")))?;
        let data = &body_bytes[data_start..];
        let section = |name: &str| -> Result<&[u8], DesignError> {
            let s = header
                .sections
                .iter()
                .find(|s| s.name == name)
                .ok_or_else(|| corrupt(format!("section '{name}' is missing")))?;
            let start = usize::try_from(s.offset).map_err(|_| corrupt("section offset"))?;
            let len = usize::try_from(s.len).map_err(|_| corrupt("section length"))?;
            start
                .checked_add(len)
                .filter(|&e| e <= data.len())
                .map(|e| &data[start..e])
                .ok_or(DesignError::Truncated("section"))
        };
        let h = &header;
        let model = ModelKind::parse(&h.model).map_err(|e| corrupt(e.to_string()))?;
        h.material.validate().map_err(|e| corrupt(e.to_string()))?;
        let n = h.vertices;
        if n == 0 || n > MAX_VERTICES || h.triangles == 0 || h.triangles > 4 * MAX_VERTICES {
            return Err(corrupt(format!(
                "{} vertices and {} triangles",
                h.vertices, h.triangles
            )));
        }
        let exact = |name: &'static str, want: usize| -> Result<&[u8], DesignError> {
            let s = section(name)?;
            if s.len() == want {
                Ok(s)
            } else {
                Err(corrupt(format!(
                    "section '{name}' has {} bytes, expected {want}",
                    s.len()
                )))
            }
        };
        let read3 = |b: &[u8], count: usize| -> Result<Vec<Vec3>, DesignError> {
            let mut c = Cursor { b, at: 0 };
            (0..count).map(|_| c.vec3()).collect()
        };
        let x = read3(exact("x", 12 * n)?, n)?;
        let v = read3(exact("v", 12 * n)?, n)?;
        let mut c = Cursor {
            b: exact("tris", 72 * h.triangles)?,
            at: 0,
        };
        let mut live = LiveMesh::default();
        for _ in 0..n {
            live.push_vertex();
        }
        for k in 0..h.triangles {
            let idx = [c.u32()?, c.u32()?, c.u32()?];
            let rest = [c.vec3()?, c.vec3()?, c.vec3()?];
            let uv = [c.vec2()?, c.vec2()?, c.vec2()?];
            let t = Tri { v: idx, rest, uv };
            if t.rest_area() <= 0.0 {
                return Err(GeometryError::Degenerate { triangle: k }.into());
            }
            live.set(k as u32, Some(t))?;
        }
        live.validate(&x)?;
        // The pattern mesh the non-editing models use: each vertex's rest position and
        // UV from the first triangle that uses it.
        let mut rest_pos = x.clone();
        let mut rest_uv = vec![Vec2::ZERO; n];
        let mut seen = vec![false; n];
        for (_, t) in live.iter() {
            for k in 0..3 {
                let i = t.v[k] as usize;
                if !seen[i] {
                    seen[i] = true;
                    rest_pos[i] = t.rest[k];
                    rest_uv[i] = t.uv[k];
                }
            }
        }
        let pattern = ClothMesh {
            positions: rest_pos,
            uvs: rest_uv,
            triangles: live.triangles(),
        };
        let mut cloth = Cloth::from_parts(pattern, live, x, v, &h.material)?;
        cloth.live.edited = true;
        for &p in &h.pins {
            if p as usize >= n {
                return Err(corrupt(format!("pin {p} past the {n} vertices")));
            }
            cloth.set_pinned(p as usize, true);
        }
        let body = match &h.body {
            None => None,
            Some(name) => Some(load_body(name, h, &section)?),
        };
        let gravity = Vec3::from_array(h.gravity);
        if !(gravity.is_finite() && h.frame_dt.is_finite() && h.frame_dt > 0.0) {
            return Err(corrupt("gravity or frame duration"));
        }
        if h.floor.is_some_and(|f| !f.is_finite()) {
            return Err(corrupt("floor height"));
        }
        let env = Environment {
            gravity,
            frame_dt: h.frame_dt,
            floor: h.floor,
        };
        if h.substeps == 0 || h.substeps > 10_000 {
            return Err(corrupt(format!("{} substeps", h.substeps)));
        }
        let mut sim = Simulation::new(cloth, body, model, h.material, env, Some(h.substeps))
            .map_err(|e| corrupt(e.to_string()))?;
        sim.frame = h.frame;
        for s in &h.seams {
            if s.pairs
                .iter()
                .any(|&(a, b)| a as usize >= n || b as usize >= n)
                || !(s.max_force.is_finite() && s.max_force > 0.0)
            {
                return Err(corrupt(
                    "a seam refers to a missing vertex or has a bad force",
                ));
            }
            sim.seams.push(Seam {
                pairs: s.pairs.clone(),
                max_force: s.max_force,
            });
        }
        if !(h.tear_threshold.is_finite() && h.tear_threshold > 1.0) {
            return Err(corrupt("tear threshold"));
        }
        sim.tear = TearSettings {
            enabled: h.tear_enabled,
            threshold: h.tear_threshold,
            mode: if h.tear_split {
                TearMode::Split
            } else {
                TearMode::Delete
            },
            ..TearSettings::default()
        };
        sim.texture = decode_texture(section("texture")?, h.texture_width, h.texture_height)?;
        Ok(sim)
    }
}

fn load_body<'a>(
    name: &str,
    h: &Header,
    section: &dyn Fn(&str) -> Result<&'a [u8], DesignError>,
) -> Result<Body, DesignError> {
    let (nv, nt) = (h.body_vertices, h.body_triangles);
    if nv == 0 || nt == 0 || nv > MAX_VERTICES || nt > 4 * MAX_VERTICES {
        return Err(corrupt("body size"));
    }
    let bv = section("body_vertices")?;
    let bt = section("body_triangles")?;
    if bv.len() != 12 * nv || bt.len() != 12 * nt {
        return Err(corrupt("body sections do not match their counts"));
    }
    let mut c = Cursor { b: bv, at: 0 };
    let vertices: Vec<Vec3> = (0..nv).map(|_| c.vec3()).collect::<Result<_, _>>()?;
    let mut c = Cursor { b: bt, at: 0 };
    let mut triangles = Vec::with_capacity(nt);
    for _ in 0..nt {
        let t = [c.u32()?, c.u32()?, c.u32()?];
        if t.iter().any(|&i| i as usize >= nv) {
            return Err(corrupt("a body triangle refers to a missing vertex"));
        }
        triangles.push(t);
    }
    // Built-in bodies come back with their exact signed distance when the mesh matches.
    if let Ok(kind) = BodyKind::parse(name)
        && !matches!(kind, BodyKind::Obj(_))
        && let Ok(b) = kind.build()
        && b.vertices == vertices
        && b.triangles == triangles
    {
        return Ok(b);
    }
    Ok(Body::new(name, vertices, triangles, None)?)
}

fn decode_texture(bytes: &[u8], w: usize, h: usize) -> Result<Texture, DesignError> {
    if w == 0 || h == 0 || w > MAX_TEXTURE || h > MAX_TEXTURE {
        return Err(corrupt(format!("texture size {w} x {h}")));
    }
    let bad = |e: png::DecodingError| corrupt(format!("texture: {e}"));
    let mut dec = png::Decoder::new_with_limits(
        std::io::Cursor::new(bytes),
        png::Limits {
            bytes: 4 * w * h + (1 << 20),
        },
    );
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(bad)?;
    let (iw, ih) = (reader.info().width as usize, reader.info().height as usize);
    if (iw, ih) != (w, h) {
        return Err(corrupt(format!(
            "texture is {iw} x {ih}, the header says {w} x {h}"
        )));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| corrupt("texture size"))?;
    let mut buf = vec![0u8; size];
    let info = reader.next_frame(&mut buf).map_err(bad)?;
    if info.color_type != png::ColorType::Rgba || info.bit_depth != png::BitDepth::Eight {
        return Err(corrupt("texture is not 8-bit RGBA"));
    }
    buf.truncate(4 * w * h);
    if buf.len() != 4 * w * h {
        return Err(corrupt("texture data is short"));
    }
    let mut t = Texture::new(w, h, [0; 4]);
    t.rgba = buf;
    Ok(t)
}
