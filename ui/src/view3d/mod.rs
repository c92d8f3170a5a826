//! The 3D view, rendered with wgpu into a colour + depth texture of our own and shown in
//! egui's pass by a paint callback ([`View3d::paint_callback`]), so the same code draws in
//! the app and in egui_kittest (whose pass has no depth attachment).
//!
//! Inside: `gpu` (vertex layout, uniforms, buffers) and `scene` (what is drawn, as vertex
//! lists) <- `renderer` (pipelines, texture, target, the draw); `blit` shows the result.

mod blit;
mod gpu;
mod renderer;
mod scene;

pub use gpu::Vertex;
pub use renderer::View3d;
pub use scene::{
    BORDER_COLOUR, HIGHLIGHT, Overlay, PIN_COLOUR, SEWN_COLOUR, pin_head, seam_colour,
};
