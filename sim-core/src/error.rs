//! Error types, one per kind of operation.

use std::path::PathBuf;

/// A triangle mesh that cannot be used (bad indices, NaN, degenerate or non-manifold).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GeometryError {
    #[error("the mesh has no triangles")]
    Empty,
    #[error("vertex {vertex} has a non-finite coordinate (NaN or infinity)")]
    NonFinite { vertex: usize },
    #[error("triangle {triangle} refers to a vertex past the end of the {vertices} vertices")]
    IndexOutOfRange { triangle: usize, vertices: usize },
    #[error("triangle {triangle} is degenerate (repeated vertex or zero area)")]
    Degenerate { triangle: usize },
    #[error(
        "edge ({a}, {b}) is shared by {count} triangles; the mesh must be manifold (at most 2)"
    )]
    NonManifoldEdge { a: u32, b: u32, count: usize },
    #[error("UV {vertex} is not finite")]
    BadUv { vertex: usize },
    #[error("the mesh has {vertices} vertices, more than the supported {max}")]
    TooLarge { vertices: usize, max: usize },
    #[error(
        "vertex {vertex} lies {at:.3e} m out, beyond the {max} m a scene holds (is the file in \
         another unit, or damaged?)"
    )]
    TooFar { vertex: usize, at: f32, max: f32 },
}

/// Failure to read a mesh file.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path} is not a readable OBJ file: {reason}")]
    Parse { path: PathBuf, reason: String },
    #[error("{path}: {source}")]
    Invalid {
        path: PathBuf,
        source: GeometryError,
    },
    #[error("{path} is not a solid body: {problem}")]
    NotSolid { path: PathBuf, problem: String },
    #[error(
        "{path}: {pairs} pairs of its triangles intersect; a cloth that starts crossed through itself stays crossed (untangle it in your modeller, or check it with `cloth-sim crossings`)"
    )]
    CrossesItself { path: PathBuf, pairs: usize },
}

/// A setting that is out of range.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ConfigError {
    #[error("{name} must be {rule}, got {value}")]
    OutOfRange {
        name: &'static str,
        rule: &'static str,
        value: String,
    },
    #[error("{name} must be between {min} and {max}{unit}, got {value}")]
    Range {
        name: &'static str,
        min: String,
        max: String,
        /// The unit, with its leading space (" m", " kg/m²"), or "".
        unit: &'static str,
        value: String,
    },
    #[error("{name} must be 0 or between {least} and {max}{unit}, got {value}")]
    RangeOrZero {
        name: &'static str,
        least: String,
        max: String,
        /// The unit, with its leading space, or "".
        unit: &'static str,
        value: String,
    },
    #[error(
        "the seed model is unstable at a step of {step_s:.3e} s: its stable bound is {bound_s:.3e} s \
         (stiffness {stiffness} N/m, unit masses); use at least {needed} substeps per frame or omit --substeps"
    )]
    UnstableStep {
        step_s: f64,
        bound_s: f64,
        stiffness: f32,
        needed: usize,
    },
    #[error("unknown {what} '{name}' (expected one of: {expected})")]
    Unknown {
        what: &'static str,
        name: String,
        expected: &'static str,
    },
}

/// `value` within `[min, max]` (NaN never is), or a `Range` error that gives the range.
pub fn check_range<T: PartialOrd + std::fmt::Display>(
    name: &'static str,
    value: T,
    min: T,
    max: T,
    unit: &'static str,
) -> Result<(), ConfigError> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(ConfigError::Range {
            name,
            min: min.to_string(),
            max: max.to_string(),
            unit,
            value: value.to_string(),
        })
    }
}

/// `value` 0 or within `[least, max]`: a material property that may be off, but when on
/// not so small that it only feeds the arithmetic subnormal numbers (a shear of 3.6e-43
/// N/m passed `[0, max]` and made a frame of a 170-vertex piece take 0.3-0.6 s, the
/// commands fuzzer's slow input of 2026-11-27).
pub fn check_range_or_zero(
    name: &'static str,
    value: f32,
    least: f32,
    max: f32,
    unit: &'static str,
) -> Result<(), ConfigError> {
    if value == 0.0 || (value >= least && value <= max) {
        Ok(())
    } else {
        Err(ConfigError::RangeOrZero {
            name,
            least: readable(least),
            max: readable(max),
            unit,
            value: readable(value),
        })
    }
}

/// `v` as a person reads it: `1e-9` and `1e7` rather than their 9 or 45 digits.
fn readable(v: f32) -> String {
    if v != 0.0 && v.is_finite() && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}
