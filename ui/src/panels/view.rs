//! The 3D view: the cloth, the body, the pen and the seams rendered with wgpu into the
//! view's own texture (`view3d`), the hover text, and banners over the view when
//! something is wrong. Mouse input on it is `input`'s.

use crate::camera::{Camera, Hit};
use crate::store::Store;
use crate::view3d::{Overlay, View3d};

/// A drag in the 3D view.
pub struct Drag {
    /// Depth of the grabbed point along the view, to keep it in its view plane.
    pub depth: f32,
    /// The pen is held (pointer button 1 down).
    pub pen: bool,
}

/// A dart being dragged on the cloth in the 3D view (Dart ticked): its point and the last
/// place the drag crossed on the same piece, in the design's pattern plane (m), that
/// piece (`Mesh::piece_of`), and the line drawn meanwhile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DartDrag {
    pub from: [f32; 2],
    pub last: [f32; 2],
    pub piece: Option<u32>,
    /// Where it began and the last place the mouse was on the cloth, in 3D: the line
    /// the view draws while the dart is dragged.
    pub start: [f32; 3],
    pub now: [f32; 3],
}

/// The view's renderer and what the mouse is doing in it.
#[derive(Default)]
pub struct ViewPanel {
    renderer: Option<View3d>,
    pub error: Option<String>,
    /// Where the view was drawn last frame (points).
    pub rect: Option<egui::Rect>,
    /// The view's resolution factor in use.
    pub render_scale: Option<f32>,
    /// The renderer draws on the CPU (llvmpipe, lavapipe): known after the first frame.
    pub software: Option<bool>,
    /// The cloth under the mouse.
    pub last_hit: Option<Hit>,
    /// A drag in progress.
    pub drag: Option<Drag>,
    /// A scissors or brush stroke begun beside the cloth: where the mouse was last seen
    /// off it (view pixels from the view's corner), until the stroke meets the cloth.
    pub stroke_from: Option<glam::Vec2>,
    /// A dart being dragged on the cloth.
    pub dart: Option<DartDrag>,
}

impl ViewPanel {
    /// Allocates the view, renders the scene into it (at `scale` of the window's pixels,
    /// default 1 on a GPU and 0.5 on a software rasteriser), and returns its response.
    pub fn draw(
        &mut self,
        ui: &mut egui::Ui,
        frame: &eframe::Frame,
        store: &mut Store,
        camera: &Camera,
        overlay: &Overlay,
        scale: Option<f32>,
    ) -> egui::Response {
        let size = ui.available_size();
        let resp = ui.allocate_response(size, egui::Sense::click_and_drag());
        match frame.wgpu_render_state() {
            Some(rs) => {
                let software = *self.software.get_or_insert_with(|| {
                    rs.adapter.get_info().device_type == egui_wgpu::wgpu::DeviceType::Cpu
                });
                let scale = *self
                    .render_scale
                    .get_or_insert_with(|| scale.unwrap_or(if software { 0.5 } else { 1.0 }));
                let ppp = ui.ctx().pixels_per_point() * scale.clamp(0.1, 2.0);
                let px = [
                    (size.x * ppp).round().max(16.0) as u32,
                    (size.y * ppp).round().max(16.0) as u32,
                ];
                let view = self.renderer.get_or_insert_with(|| View3d::new(&rs.device));
                view.render(&rs.device, &rs.queue, store, camera, overlay, px);
                if let Some(cb) = view.paint_callback(&rs.device, rs.target_format, resp.rect) {
                    ui.painter().add(cb);
                }
            }
            None => {
                self.error = Some("no wgpu renderer: the 3D view needs wgpu".into());
            }
        }
        resp
    }

    /// A banner over the top of the view.
    pub fn banner(ui: &mut egui::Ui, rect: egui::Rect, text: String) {
        ui.put(
            egui::Rect::from_min_size(
                rect.min + egui::vec2(12.0, 12.0),
                egui::vec2(rect.width() - 24.0, 28.0),
            ),
            egui::Label::new(
                egui::RichText::new(text)
                    .color(egui::Color32::from_rgb(255, 210, 120))
                    .size(15.0),
            ),
        );
    }
}
