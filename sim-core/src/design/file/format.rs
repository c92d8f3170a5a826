//! The `.saiho` container: magic, format version, JSON header with a table of sections,
//! the sections, and a checksum; the little-endian readers and writers the sections use.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use crate::error::GeometryError;
use crate::solver::Material;

pub const MAGIC: &[u8; 8] = b"SAIHODSN";
/// The format this build writes: 2 adds the pieces (names, fabrics, grain, placement,
/// outlines). Every earlier format still loads.
pub const FORMAT: u32 = 2;
/// Most pieces a design may carry.
pub(super) const MAX_PIECES: usize = 10_000;
/// Largest texture side a design may carry.
pub(super) const MAX_TEXTURE: usize = 8192;

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

pub(super) fn corrupt(s: impl Into<String>) -> DesignError {
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
    /// Files written before seams had names have none.
    #[serde(default)]
    pub name: String,
    /// The rest corners of the triangles its welds eased into it (`Seam::eased`); none
    /// in files written before they were kept.
    #[serde(default)]
    pub eased: Vec<[[f32; 3]; 3]>,
    /// A dart pressed toward its second leg (`Seam::press_second`); written only when
    /// set, and false in files written before a dart's press could be chosen.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub press_second: bool,
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
    /// The xpbd model's guard against crossing is on (files from before it was saved
    /// have none: off).
    #[serde(default)]
    pub guard: bool,
    pub texture_width: usize,
    pub texture_height: usize,
    pub sections: Vec<Section>,
    /// The named pieces (format 2; none in format 1).
    #[serde(default)]
    pub pieces: Vec<crate::design::PieceRecord>,
    /// The pattern file the design was made from (`Design::source`); files written
    /// before it was kept (2026-12-03) have none.
    #[serde(default)]
    pub source: String,
}

pub(super) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

pub(super) fn put_vec3s(out: &mut Vec<u8>, v: &[Vec3]) {
    for p in v {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
}

/// Reads little-endian values off a byte slice, failing cleanly at its end.
pub(super) struct Cursor<'a> {
    pub(super) b: &'a [u8],
    pub(super) at: usize,
}

impl<'a> Cursor<'a> {
    pub(super) fn take(&mut self, n: usize) -> Result<&'a [u8], DesignError> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.b.len())
            .ok_or(DesignError::Truncated("section"))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }

    pub(super) fn u32(&mut self) -> Result<u32, DesignError> {
        let s = self.take(4)?;
        Ok(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
    }

    pub(super) fn f32(&mut self) -> Result<f32, DesignError> {
        let v = f32::from_bits(self.u32()?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(corrupt("a number is NaN or infinite"))
        }
    }

    pub(super) fn vec3(&mut self) -> Result<Vec3, DesignError> {
        Ok(Vec3::new(self.f32()?, self.f32()?, self.f32()?))
    }

    pub(super) fn vec2(&mut self) -> Result<Vec2, DesignError> {
        Ok(Vec2::new(self.f32()?, self.f32()?))
    }
}
