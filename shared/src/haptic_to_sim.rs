//! haptic-loop -> cloth-sim (and cloth-ui): the pen, and the force it rendered.

use iceoryx2::prelude::ZeroCopySend;

use crate::{Checked, Header, finite3};

/// Pen button bits in [`DeviceSample::buttons`].
pub const BUTTON_1: u32 = 1;
pub const BUTTON_2: u32 = 2;

/// The pen at one haptic tick (latest value, 1 kHz). Positions are in the scene frame
/// (metres, Y up), mapped from the device workspace by the haptic process.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::DeviceSample")]
pub struct DeviceSample {
    pub header: Header,
    /// The haptic loop's tick counter.
    pub tick: u64,
    pub position: [f32; 3],
    pub velocity: [f32; 3],
    pub buttons: u32,
    /// 1 when the device reports no error.
    pub device_ok: u32,
}

impl Checked for DeviceSample {
    const WHAT: &'static str = "device sample";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        finite3("position", &self.position)?;
        finite3("velocity", &self.velocity)?;
        if self.buttons & !(BUTTON_1 | BUTTON_2) != 0 {
            return Err(format!("unknown button bits {:#x}", self.buttons));
        }
        if self.device_ok > 1 {
            return Err(format!("device_ok is {}", self.device_ok));
        }
        Ok(())
    }
}

/// The force the haptic loop rendered on the pen at a tick, N, scene frame. cloth-sim
/// applies the opposite to the cloth.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::AppliedForce")]
pub struct AppliedForce {
    pub header: Header,
    pub tick: u64,
    pub force: [f32; 3],
    /// The local model frame the force came from (0: none).
    pub model_frame: u32,
}

impl Checked for AppliedForce {
    const WHAT: &'static str = "applied force";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        finite3("force", &self.force)
    }
}
