//! Writing a design: the sections, the header and the checksum.

use super::format::{
    DesignError, FORMAT, Header, MAGIC, SeamRecord, Section, corrupt, fnv1a, put_vec3s,
};
use super::store::write_atomically;
use crate::design::Design;
use crate::design::TearMode;
use crate::design::export::png_bytes;

impl Design {
    /// The design as bytes in the `.saiho` format.
    pub fn save_design(&self) -> Result<Vec<u8>, DesignError> {
        let mut sections: Vec<(String, Vec<u8>)> = Vec::new();
        let mut x = Vec::with_capacity(12 * self.sim.cloth.len());
        put_vec3s(&mut x, &self.sim.cloth.x);
        sections.push(("x".into(), x));
        let mut v = Vec::with_capacity(12 * self.sim.cloth.len());
        put_vec3s(&mut v, &self.sim.cloth.v);
        sections.push(("v".into(), v));
        let mut tris = Vec::with_capacity(72 * self.sim.cloth.live.tri_count());
        for (_, t) in self.sim.cloth.live.iter() {
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
        let (bv, bt) = match &self.sim.body {
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
            frame: self.sim.frame,
            model: self.sim.model.name().into(),
            substeps: self.sim.substeps,
            material: self.sim.material,
            gravity: self.sim.env.gravity.to_array(),
            frame_dt: self.sim.env.frame_dt,
            floor: self.sim.env.floor,
            body: self.sim.body.as_ref().map(|b| b.name.clone()),
            vertices: self.sim.cloth.len(),
            triangles: self.sim.cloth.live.tri_count(),
            body_vertices: self.sim.body.as_ref().map_or(0, |b| b.vertices.len()),
            body_triangles: self.sim.body.as_ref().map_or(0, |b| b.triangles.len()),
            pins: (0..self.sim.cloth.len() as u32)
                .filter(|&i| self.sim.cloth.is_pinned(i as usize))
                .collect(),
            seams: self
                .seams
                .iter()
                .map(|s| SeamRecord {
                    pairs: s.pairs.clone(),
                    max_force: s.max_force,
                    name: s.name.clone(),
                    eased: s.eased.iter().map(|t| t.map(|c| c.to_array())).collect(),
                    press_second: s.press_second,
                })
                .collect(),
            tear_enabled: self.tear.enabled,
            tear_threshold: self.tear.threshold,
            tear_split: self.tear.mode == TearMode::Split,
            guard: self.guarded(),
            texture_width: self.texture.width,
            texture_height: self.texture.height,
            sections: table,
            pieces: self.pieces.clone(),
            source: self.source.clone(),
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
        write_atomically(path, &bytes, None)
    }
}
