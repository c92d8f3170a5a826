//! The haptic device behind one trait, one file per backend: `sim` (the simulated pen,
//! first-class: a pen mass held by a spring-damper hand, driven by a script or by the
//! UI's pointer), `openhaptics` (a Phantom through libHD) and `replay` (a recorded device
//! log played back).

pub mod openhaptics;
mod replay;
mod sim;

pub use openhaptics::OpenHaptics;
pub use replay::{LOG_HEADER, Record, Replay};
use shared::sim_to_haptic::{
    DEFAULT_WORKSPACE_CENTRE, DEFAULT_WORKSPACE_SCALE, TOUCH_HALF_EXTENT_M,
};
pub use sim::{Script, SimDevice, Still, TargetSource};

/// What a device reports at a tick (scene frame, metres, Y up).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeviceState {
    pub position: [f32; 3],
    pub velocity: [f32; 3],
    pub buttons: u32,
}

#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum DeviceError {
    /// (A static description: this error can happen at every tick, which must not
    /// allocate.)
    #[error("device error {code:#06x}: {what}")]
    Device { code: u32, what: &'static str },
    #[error("cannot open the device: {0}")]
    Open(String),
}

/// A haptic device: read the pen, then command a force, once per tick.
pub trait HapticDevice {
    fn name(&self) -> &str;
    /// Reads the pen at the start of a tick, `dt` seconds after the previous one.
    fn read(&mut self, dt: f32) -> Result<DeviceState, DeviceError>;
    /// Commands the force (N, scene frame) for this tick.
    fn write_force(&mut self, force: [f32; 3]) -> Result<(), DeviceError>;
    /// Maps the device into `ws` from the next read on (a device that reports scene
    /// positions already, like a replay, ignores it).
    fn set_workspace(&mut self, _ws: Workspace) {}
}

/// A device that can also take the UI's pointer as its hand target (the sim pen).
pub trait PointerTarget {
    fn set_pointer(&mut self, _target: [f32; 3], _buttons: u32) {}
}

/// The Touch's workspace, about 160 x 120 x 70 mm, mapped into the scene at a scale
/// (scene metres per device metre) around a centre. cloth-sim chooses the mapping for its
/// scene (`LocalModel::workspace`: the default, grown to reach the whole body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Workspace {
    pub half_extent_m: [f32; 3],
    pub scale: f32,
    pub centre: [f32; 3],
}

impl Default for Workspace {
    fn default() -> Self {
        Self {
            half_extent_m: TOUCH_HALF_EXTENT_M,
            scale: DEFAULT_WORKSPACE_SCALE,
            centre: DEFAULT_WORKSPACE_CENTRE,
        }
    }
}

impl Workspace {
    /// The mapping a local model carries (`[centre, scale]`, all zero for the default;
    /// the model was checked).
    pub fn from_wire(w: [f32; 4]) -> Self {
        if w == [0.0; 4] {
            return Self::default();
        }
        Self {
            scale: w[3],
            centre: [w[0], w[1], w[2]],
            ..Self::default()
        }
    }

    /// Clamps a scene point into the mapped workspace.
    pub fn clamp(&self, p: [f32; 3]) -> [f32; 3] {
        std::array::from_fn(|i| {
            let h = self.half_extent_m[i] * self.scale;
            p[i].clamp(self.centre[i] - h, self.centre[i] + h)
        })
    }
}
