//! cloth-sim -> haptic-loop: the local model the 1 kHz loop renders force from between
//! simulation frames (an intermediate representation, Mark et al. 1996).

use iceoryx2::prelude::ZeroCopySend;

use crate::{Checked, Header, finite3};

/// Most contact planes in a local model.
pub const MAX_PLANES: usize = 16;

/// Half the Touch's workspace (about 160 x 120 x 70 mm) along the scene's x, y, z, m.
pub const TOUCH_HALF_EXTENT_M: [f32; 3] = [0.080, 0.060, 0.035];
/// The pen's workspace without a body: scene metres per device metre, and its centre.
/// It reaches 0.8 x 0.6 x 0.35 m around (0, 0.6, 0): the cube scene.
pub const DEFAULT_WORKSPACE_SCALE: f32 = 5.0;
pub const DEFAULT_WORKSPACE_CENTRE: [f32; 3] = [0.0, 0.6, 0.0];
/// The largest workspace scale a model may carry (a 160 m scene across the Touch), and
/// the least (the Touch's reach shrunk to 1.6 mm: a pen that could not move).
pub const MAX_WORKSPACE_SCALE: f32 = 1000.0;
pub const MIN_WORKSPACE_SCALE: f32 = 0.01;

/// The pen's workspace for a scene whose body lies in `lo..hi`: the default mapping
/// (`DEFAULT_WORKSPACE_*`), grown where needed to reach the whole body with a tenth of
/// its size to spare, at one scale on every axis (the Touch's motion is not distorted).
/// `[centre x, y, z, scale]`. With the default alone the pen reached only the
/// mannequin's legs (y 0.3-0.9 m): its hands could not pinch a garment's shoulder.
pub fn workspace_covering(lo: [f32; 3], hi: [f32; 3]) -> [f32; 4] {
    let s = DEFAULT_WORKSPACE_SCALE;
    let c = DEFAULT_WORKSPACE_CENTRE;
    let mut a: [f32; 3] = std::array::from_fn(|i| c[i] - TOUCH_HALF_EXTENT_M[i] * s);
    let mut b: [f32; 3] = std::array::from_fn(|i| c[i] + TOUCH_HALF_EXTENT_M[i] * s);
    for i in 0..3 {
        let spare = 0.05 * (hi[i] - lo[i]);
        if lo[i].is_finite() && hi[i].is_finite() && lo[i] <= hi[i] {
            a[i] = a[i].min(lo[i] - spare);
            b[i] = b[i].max(hi[i] + spare);
        }
    }
    let scale = (0..3)
        .map(|i| (b[i] - a[i]) / (2.0 * TOUCH_HALF_EXTENT_M[i]))
        .fold(s, f32::max)
        .min(MAX_WORKSPACE_SCALE);
    [
        0.5 * (a[0] + b[0]),
        0.5 * (a[1] + b[1]),
        0.5 * (a[2] + b[2]),
        scale,
    ]
}

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
    /// The pen's workspace in this scene: `[centre x, y, z, scale]` (scene metres per
    /// device metre; `workspace_covering`), or all zero for the default mapping. The
    /// haptic loop maps the device into it.
    pub workspace: [f32; 4],
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
        let [cx, cy, cz, scale] = self.workspace;
        let default = self.workspace == [0.0; 4];
        let centre_ok = [cx, cy, cz].iter().all(|c| c.is_finite() && c.abs() <= 1e4);
        let real = (MIN_WORKSPACE_SCALE..=MAX_WORKSPACE_SCALE).contains(&scale) && centre_ok;
        if !(default || real) {
            return Err(format!(
                "workspace {:?}: its scale must be in [{MIN_WORKSPACE_SCALE}, {MAX_WORKSPACE_SCALE}] and its centre \
                 finite, within 10 km (or all zero: the default)",
                self.workspace
            ));
        }
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
