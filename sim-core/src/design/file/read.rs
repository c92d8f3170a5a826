//! Reading a design: every count, index and value checked before anything is built.

use glam::{Vec2, Vec3};

use super::format::{
    Cursor, DesignError, FORMAT, Header, MAGIC, MAX_PIECES, MAX_TEXTURE, corrupt, fnv1a,
};
use crate::collision::{Body, BodyKind};
use crate::design::{Design, Seam, TearMode, TearSettings, Texture};
use crate::error::GeometryError;
use crate::mesh::{ClothMesh, LiveMesh, MAX_COORD, MAX_VERTICES, Tri};
use crate::solver::{Cloth, Environment, MAX_FRAME_SUBSTEPS, ModelKind, Simulation};

/// The fastest a loaded cloth's vertex moves, m/s (a falling cloth reaches a few); faster
/// ones are slowed to it (a velocity of 1e30 m/s sent the first frame's contact boxes
/// over billions of grid cells).
const MAX_SPEED: f32 = 1000.0;
/// Longest pattern path a design file may name, bytes (Linux's PATH_MAX).
const MAX_SOURCE: usize = 4096;

impl Design {
    pub fn load_design_file(path: &std::path::Path) -> Result<Self, DesignError> {
        let bytes = std::fs::read(path).map_err(|source| DesignError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::load_design(&bytes)
    }

    /// Rebuilds a design from `.saiho` bytes, checking everything.
    pub fn load_design(bytes: &[u8]) -> Result<Self, DesignError> {
        let (header, data) = open(bytes)?;
        let h = &header;
        let sections = Sections { header: h, data };
        let model = ModelKind::parse(&h.model).map_err(|e| corrupt(e.to_string()))?;
        h.material.validate().map_err(|e| corrupt(e.to_string()))?;
        let mut cloth = read_cloth(h, &sections)?;
        if h.pieces.len() > MAX_PIECES {
            return Err(corrupt(format!(
                "{} pieces (at most {MAX_PIECES})",
                h.pieces.len()
            )));
        }
        for r in &h.pieces {
            r.check().map_err(corrupt)?;
        }
        // Each piece hangs as its fabric, whatever the model.
        let (zones, fabric_notes) = crate::design::fabric_zones(&h.pieces, &h.material)
            .map_err(|e| corrupt(e.to_string()))?;
        cloth.set_zones(zones, h.material.density);
        let body = match &h.body {
            None => None,
            Some(name) => Some(load_body(name, h, &sections)?),
        };
        let env = read_environment(h)?;
        if h.substeps == 0 || h.substeps > MAX_FRAME_SUBSTEPS {
            return Err(corrupt(format!("{} substeps", h.substeps)));
        }
        let mut sim = Simulation::new(cloth, body, model, h.material, env, Some(h.substeps))
            .map_err(|e| corrupt(e.to_string()))?;
        if h.guard && model != ModelKind::Xpbd {
            return Err(corrupt(format!(
                "the guard against crossing is on for the {} model, which has none",
                model.name()
            )));
        }
        sim.set_guard(h.guard);
        // A cloth that blew up was saved moving faster than any cloth does; it loads (a
        // design this build wrote must), slowed to MAX_SPEED, and says so.
        let mut slowed = 0;
        for v in &mut sim.cloth.v {
            if v.length() > MAX_SPEED {
                *v = v.normalize_or_zero() * MAX_SPEED;
                slowed += 1;
            }
        }
        if slowed > 0 {
            sim.notices.push(format!(
                "{slowed} vertices were saved moving faster than {MAX_SPEED} m/s (the cloth had \
                 blown up, or the file is damaged); they load at {MAX_SPEED} m/s"
            ));
        }
        sim.frame = h.frame;
        let texture = decode_texture(sections.get("texture")?, h.texture_width, h.texture_height)?;
        let mut design = Design::with_texture(sim, texture);
        design.seams = read_seams(h)?;
        design.pieces = h.pieces.clone();
        // A path, or nothing: anything else is left out, the design loads.
        if h.source.len() <= MAX_SOURCE && !h.source.chars().any(char::is_control) {
            design.source = h.source.clone();
        } else {
            design.sim.notices.push(format!(
                "the design file names its pattern with {} bytes that are not a path; \
                 left out (the design is whole)",
                h.source.len()
            ));
        }
        design.sim.notices.extend(fabric_notes);
        design.tear = read_tear(h)?;
        let crossed = design.sim.crossings();
        if crossed.self_pairs > 0 || crossed.body_pairs > 0 {
            design.sim.notices.push(format!(
                "the design's cloth crosses itself in {} pairs of triangles and the body in {} \
                 (it was saved so, as the xpbd model leaves it); it loads as it is: the vbd \
                 model and xpbd's guard keep every pair from crossing further but do not \
                 untangle these",
                crossed.self_pairs, crossed.body_pairs
            ));
        }
        Ok(design)
    }
}

/// Checks the container (magic, version, checksum) and parses the header; returns it and
/// the bytes its section offsets are relative to.
fn open(bytes: &[u8]) -> Result<(Header, &[u8]), DesignError> {
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
    Ok((header, &body_bytes[data_start..]))
}

/// The sections of one file, by name.
struct Sections<'a> {
    header: &'a Header,
    data: &'a [u8],
}

impl<'a> Sections<'a> {
    fn get(&self, name: &str) -> Result<&'a [u8], DesignError> {
        let s = self
            .header
            .sections
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| corrupt(format!("section '{name}' is missing")))?;
        let start = usize::try_from(s.offset).map_err(|_| corrupt("section offset"))?;
        let len = usize::try_from(s.len).map_err(|_| corrupt("section length"))?;
        start
            .checked_add(len)
            .filter(|&e| e <= self.data.len())
            .map(|e| &self.data[start..e])
            .ok_or(DesignError::Truncated("section"))
    }

    /// Section `name`, which must be `want` bytes long.
    fn exact(&self, name: &'static str, want: usize) -> Result<&'a [u8], DesignError> {
        let s = self.get(name)?;
        if s.len() == want {
            Ok(s)
        } else {
            Err(corrupt(format!(
                "section '{name}' has {} bytes, expected {want}",
                s.len()
            )))
        }
    }
}

/// The cloth: positions, velocities, the live triangles with their rest corners and UVs,
/// the pattern mesh the non-editing models use, and the pins.
fn read_cloth(h: &Header, sections: &Sections) -> Result<Cloth, DesignError> {
    let n = h.vertices;
    if n == 0 || n > MAX_VERTICES || h.triangles == 0 || h.triangles > 4 * MAX_VERTICES {
        return Err(corrupt(format!(
            "the header claims {} vertices and {} triangles (a design has 1 to {MAX_VERTICES} \
             vertices and 1 to {} triangles)",
            h.vertices,
            h.triangles,
            4 * MAX_VERTICES
        )));
    }
    let read3 = |b: &[u8], count: usize| -> Result<Vec<Vec3>, DesignError> {
        let mut c = Cursor { b, at: 0 };
        (0..count).map(|_| c.vec3()).collect()
    };
    let x = read3(sections.exact("x", 12 * n)?, n)?;
    let v = read3(sections.exact("v", 12 * n)?, n)?;
    // Within the scene's bounds, as a frame leaves them (a vertex past them is a
    // divergence): 1e30 m loaded and its first frame blew up, again at every restart.
    if let Some(i) = x.iter().position(|p| p.abs().max_element() > MAX_COORD) {
        return Err(corrupt(format!(
            "vertex {i} lies at {:?} m, beyond the {MAX_COORD} m a scene spans",
            x[i]
        )));
    }
    let mut c = Cursor {
        b: sections.exact("tris", 72 * h.triangles)?,
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
        if rest.iter().any(|p| p.abs().max_element() > MAX_COORD) {
            return Err(corrupt(format!(
                "triangle {k}'s rest shape lies beyond the {MAX_COORD} m a scene spans"
            )));
        }
        let t = Tri { v: idx, rest, uv };
        if t.rest_area() <= 0.0 {
            return Err(GeometryError::Degenerate { triangle: k }.into());
        }
        live.set(k as u32, Some(t))?;
    }
    live.validate(&x)?;
    let pattern = pattern_of(&live, &x);
    let mut cloth = Cloth::from_parts(pattern, live, x, v, &h.material)?;
    cloth.live.edited = true;
    for &p in &h.pins {
        if p as usize >= n {
            return Err(corrupt(format!("pin {p} past the {n} vertices")));
        }
        cloth.set_pinned(p as usize, true);
    }
    Ok(cloth)
}

/// The pattern mesh the non-editing models use: each vertex's rest position and UV from
/// the first triangle that uses it.
fn pattern_of(live: &LiveMesh, x: &[Vec3]) -> ClothMesh {
    let n = x.len();
    let mut rest_pos = x.to_vec();
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
    ClothMesh {
        positions: rest_pos,
        uvs: rest_uv,
        triangles: live.triangles(),
    }
}

fn read_environment(h: &Header) -> Result<Environment, DesignError> {
    let gravity = Vec3::from_array(h.gravity);
    if !(gravity.is_finite() && h.frame_dt.is_finite() && h.frame_dt > 0.0) {
        return Err(corrupt("gravity or frame duration"));
    }
    if h.floor.is_some_and(|f| !f.is_finite()) {
        return Err(corrupt("floor height"));
    }
    Ok(Environment {
        gravity,
        frame_dt: h.frame_dt,
        floor: h.floor,
    })
}

fn read_seams(h: &Header) -> Result<Vec<Seam>, DesignError> {
    let n = h.vertices;
    h.seams
        .iter()
        .map(|s| {
            if s.pairs
                .iter()
                .any(|&(a, b)| a as usize >= n || b as usize >= n)
                || !(s.max_force.is_finite() && s.max_force > 0.0)
            {
                return Err(corrupt(
                    "a seam refers to a missing vertex or has a bad force",
                ));
            }
            if s.name.chars().count() > crate::design::MAX_NAME {
                return Err(corrupt("a seam's name is too long"));
            }
            // Each was a triangle of the cloth, and a flat mesh has fewer triangles than
            // twice its vertices (which no edit removes).
            if s.eased.len() > 2 * n || !s.eased.iter().flatten().flatten().all(|c| c.is_finite()) {
                return Err(corrupt(
                    "a seam's eased triangles are not numbers or too many",
                ));
            }
            Ok(Seam {
                pairs: s.pairs.clone(),
                max_force: s.max_force,
                name: s.name.clone(),
                eased: s.eased.iter().map(|t| t.map(Vec3::from)).collect(),
                press_second: s.press_second,
            })
        })
        .collect()
}

fn read_tear(h: &Header) -> Result<TearSettings, DesignError> {
    if !(h.tear_threshold.is_finite() && h.tear_threshold > 1.0) {
        return Err(corrupt("tear threshold"));
    }
    Ok(TearSettings {
        enabled: h.tear_enabled,
        threshold: h.tear_threshold,
        mode: if h.tear_split {
            TearMode::Split
        } else {
            TearMode::Delete
        },
        ..TearSettings::default()
    })
}

fn load_body(name: &str, h: &Header, sections: &Sections) -> Result<Body, DesignError> {
    let (nv, nt) = (h.body_vertices, h.body_triangles);
    if nv == 0 || nt == 0 || nv > MAX_VERTICES || nt > 4 * MAX_VERTICES {
        return Err(corrupt("body size"));
    }
    let bv = sections.get("body_vertices")?;
    let bt = sections.get("body_triangles")?;
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
