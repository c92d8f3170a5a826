//! cloth-ui: the egui/eframe design studio. It shows what cloth-sim and haptic-loop
//! publish (the `Link` fills the `Store`) and sends commands and the mouse-driven pen back.
//! The 3D view renders with wgpu into its own texture (`view3d`), so the app and the
//! egui_kittest tests draw the same way.

pub mod app;
pub mod camera;
pub mod link;
pub mod store;
pub mod view3d;
