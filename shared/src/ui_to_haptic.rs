//! cloth-ui -> haptic-loop: the mouse driving the simulated pen.

use iceoryx2::prelude::ZeroCopySend;

use crate::haptic_to_sim::{BUTTON_1, BUTTON_2};
use crate::{Checked, Header, finite3};

/// Where the simulated pen's hand should go (scene frame, metres), and its buttons.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::PointerInput")]
pub struct PointerInput {
    pub header: Header,
    pub target: [f32; 3],
    pub buttons: u32,
    pub _reserved: u32,
    /// Explicit padding (was implicit): every byte of a message is a field.
    pub _pad: u32,
}

impl Checked for PointerInput {
    const WHAT: &'static str = "pointer input";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        finite3("target", &self.target)?;
        if self.buttons & !(BUTTON_1 | BUTTON_2) != 0 {
            return Err(format!("unknown button bits {:#x}", self.buttons));
        }
        Ok(())
    }
}
