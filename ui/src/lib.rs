//! cloth-ui: the egui/eframe design studio. It shows what cloth-sim and haptic-loop
//! publish (the `Link` fills the `Store`) and sends commands and the mouse-driven pen back.
//! The 3D view renders with wgpu into its own texture (`view3d`), so the app and the
//! egui_kittest tests draw the same way.
//!
//! - `app`: the frame (take in, lay out, apply) and what it applies;
//! - `panels`: each panel its own struct, returning `action::Action`s;
//! - `input`: the keyboard and the mouse in the 3D view, apart from drawing;
//! - `link`: the iceoryx2 ports and the checks of what arrives; `store`: what arrived;
//! - `camera`, `view3d`: the orbit camera, picking, and the wgpu renderer;
//! - `tools`: the tool table; `stretch`: the maps the view can colour the cloth by (the
//!   threads' stretch, the ease), and `fit`: the tape measure at the bust, waist and hips,
//!   both of which `mapper` keeps current.

pub mod action;
pub mod app;
pub mod camera;
pub mod fit;
pub mod input;
pub mod link;
pub mod mapper;
pub mod panels;
pub mod store;
pub mod stretch;
pub mod tools;
pub mod view3d;
