//! The studio's panels, each its own struct: `tools` (left, top), `material`, `scene` and
//! `pieces` (left, below; `pieces` also opens the pattern view, which `pattern` draws), `status` (right), `view` (the 3D view in the middle). A panel draws
//! itself from the store and returns what the user asked for as `Action`s; the app
//! applies them after the frame is laid out.

mod material;
mod pattern;
mod pieces;
mod scene;
mod seams;
mod status;
mod tools;
mod view;

pub use material::{MaterialChoice, MaterialPanel};
pub use pieces::PiecesPanel;
pub use scene::ScenePanel;
pub use status::StatusPanel;
pub use tools::ToolsPanel;
pub use view::{DartDrag, Drag, ViewPanel};
