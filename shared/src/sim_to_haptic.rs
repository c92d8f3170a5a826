//! cloth-sim -> haptic-loop: the local model the 1 kHz loop renders force from between
//! simulation frames (an intermediate representation, Mark et al. 1996).

use iceoryx2::prelude::ZeroCopySend;

use crate::{Checked, Header, finite3};

/// Most contact planes in a local model.
pub const MAX_PLANES: usize = 16;

#[derive(
    Clone, Copy, Debug, Default, PartialEq, ZeroCopySend, bytemuck::Pod, bytemuck::Zeroable,
)]
#[repr(C)]
#[type_name("saiho::LocalModel")]
pub struct LocalModel {
    pub header: Header,
    /// The simulation frame it describes.
    pub frame: u64,
    /// Send time of the newest device sample cloth-sim had read when it built this model
    /// (0: none), so the haptic loop can time the whole loop, ns.
    pub pen_sent_ns: u64,
    /// 1 while the pen pinches a vertex.
    pub pinching: u32,
    /// Pinch spring stiffness, N/m.
    pub stiffness: f32,
    /// The pinched vertex's position and velocity (extrapolate with the velocity).
    pub vertex_position: [f32; 3],
    pub vertex_velocity: [f32; 3],
    /// Planes near the pen tip, `(normal, offset)`: the surface is `n . x = offset`, free
    /// space on the normal's side.
    pub plane_count: u32,
    pub planes: [[f32; 4]; MAX_PLANES],
    /// Explicit padding (was implicit): every byte of a message is a field.
    pub _pad: u32,
}

impl Checked for LocalModel {
    const WHAT: &'static str = "local model";
    fn header(&self) -> &Header {
        &self.header
    }
    fn check_body(&self) -> Result<(), String> {
        if self.pinching > 1 {
            return Err(format!("pinching is {}", self.pinching));
        }
        if !(self.stiffness.is_finite() && self.stiffness >= 0.0) {
            return Err(format!("stiffness {}", self.stiffness));
        }
        finite3("vertex position", &self.vertex_position)?;
        finite3("vertex velocity", &self.vertex_velocity)?;
        let n = self.plane_count as usize;
        if n > MAX_PLANES {
            return Err(format!("{n} planes, at most {MAX_PLANES}"));
        }
        for p in &self.planes[..n] {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(format!("plane {p:?} is not finite"));
            }
            let len2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            if (len2 - 1.0).abs() > 1e-3 {
                return Err(format!("plane normal {p:?} is not unit length"));
            }
        }
        Ok(())
    }
}
