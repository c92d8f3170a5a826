//! What a scenario says when it cannot run: its settings, its files, its pattern or its
//! start (`ScenarioError`).

use std::path::PathBuf;

use crate::design::EditError;
use crate::design::export::ExportError;
use crate::design::file::DesignError;
use crate::error::{ConfigError, GeometryError, LoadError};
use crate::mesh::mesher::MeshError;
use crate::solver::StepError;

#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("body: {0}")]
    Body(#[from] LoadError),
    #[error("cloth: {0}")]
    Cloth(#[from] GeometryError),
    #[error("cloth: {0}")]
    ClothFile(LoadError),
    #[error("piece: {0}")]
    Piece(#[from] MeshError),
    #[error("piece {path}: {reason}")]
    PieceFile { path: PathBuf, reason: String },
    #[error("pattern {0}")]
    Pattern(#[from] crate::design::garment::ImportError),
    #[error("garment: {0}")]
    Garment(#[from] crate::design::garment::GarmentError),
    #[error(
        "the cloth starts crossing itself in {self_pairs} pairs of triangles and the body in {body_pairs}{which}; nothing untangles that, so nothing was run"
    )]
    StartsCrossed {
        self_pairs: usize,
        body_pairs: usize,
        /// Which pieces of a pattern, and how many pairs each (empty for a cloth).
        which: String,
    },
    #[error(transparent)]
    Step(#[from] StepError),
    #[error("{0}")]
    Edit(#[from] EditError),
    #[error(transparent)]
    Export(#[from] ExportError),
    #[error(transparent)]
    Design(#[from] DesignError),
    #[error("cannot write {path}: {source}")]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
}
