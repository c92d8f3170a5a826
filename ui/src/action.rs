//! What the UI asks for. Panels and input handling return [`Action`]s while egui lays out
//! the frame; the app applies them afterwards ([`App::apply`](crate::app::App::apply)).
//! What went out to the system is kept as [`Emitted`], for the status and for tests.

use glam::Vec3;
use shared::command::Command;

use crate::camera::Hit;

/// Which file operation a path is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathOp {
    Save,
    Load,
    Export,
}

/// One thing the user asked for this frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Send this command to cloth-sim.
    Command(Command),
    /// Save, load or export at a path (made absolute before it is sent: cloth-sim
    /// resolves it in its own working directory).
    Path(PathOp, String),
    /// Choose a tool (cloth-sim is told, with the paint colour and brush).
    SetTool(u32),
    /// The simulated pen's target and buttons.
    Pointer([f32; 3], u32),
    /// A click in the 3D view with the current tool (`hit`: the cloth under it).
    Click {
        tool: u32,
        hit: Option<Hit>,
        shift: bool,
        view_dir: Vec3,
    },
    /// Back to the default camera.
    ResetCamera,
    /// The camera fits the body and the cloth.
    FrameScene,
    /// Show or hide the map (the threads' stretch or the ease).
    ToggleStretchMap,
    /// Pause the simulation, or run it again (Space).
    ToggleSimulating,
    /// A line for the status bar.
    Status(String),
}

/// What the UI sent to the system.
#[derive(Clone, Debug, PartialEq)]
pub enum Emitted {
    Command(Command),
    /// The simulated pen's target and buttons.
    Pointer([f32; 3], u32),
}
