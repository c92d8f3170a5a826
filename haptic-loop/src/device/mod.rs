//! The haptic device behind one trait, one file per backend: `sim` (the simulated pen,
//! first-class: a pen mass held by a spring-damper hand, driven by a script or by the
//! UI's pointer), `openhaptics` (a Phantom through libHD) and `replay` (a recorded device
//! log played back).

pub mod openhaptics;
mod replay;
mod sim;

pub use openhaptics::OpenHaptics;
pub use replay::{LOG_HEADER, Record, Replay};
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
}

/// A device that can also take the UI's pointer as its hand target (the sim pen).
pub trait PointerTarget {
    fn set_pointer(&mut self, _target: [f32; 3], _buttons: u32) {}
}

/// The Touch's workspace, about 160 x 120 x 70 mm, mapped into the scene at a scale
/// (scene metres per device metre) around a centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Workspace {
    pub half_extent_m: [f32; 3],
    pub scale: f32,
    pub centre: [f32; 3],
}

impl Default for Workspace {
    fn default() -> Self {
        Self {
            half_extent_m: [0.080, 0.060, 0.035],
            scale: 5.0,
            centre: [0.0, 0.6, 0.0],
        }
    }
}

impl Workspace {
    /// Clamps a scene point into the mapped workspace.
    pub fn clamp(&self, p: [f32; 3]) -> [f32; 3] {
        std::array::from_fn(|i| {
            let h = self.half_extent_m[i] * self.scale;
            p[i].clamp(self.centre[i] - h, self.centre[i] + h)
        })
    }
}
