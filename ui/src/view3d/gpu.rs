//! What the renderer uploads: the vertex layout, the uniforms, growable buffers.

use egui_wgpu::wgpu;

/// One vertex of every draw: position, normal, UV, colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub pos: [f32; 3],
    pub nrm: [f32; 3],
    pub uv: [f32; 2],
    pub col: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Uniforms {
    pub(super) view_proj: [[f32; 4]; 4],
    pub(super) light_dir: [f32; 4],
    pub(super) eye: [f32; 4],
}

/// A growable GPU buffer (vertices or indices), with the count of its last upload.
pub(super) struct Buf {
    pub(super) buf: wgpu::Buffer,
    label: &'static str,
    usage: wgpu::BufferUsages,
    cap: u64,
    pub(super) len: u32,
}

impl Buf {
    pub(super) fn new(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
    ) -> Self {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        Self {
            buf: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 4096,
                usage,
                mapped_at_creation: false,
            }),
            label,
            usage,
            cap: 4096,
            len: 0,
        }
    }

    pub(super) fn vertices(device: &wgpu::Device, label: &'static str) -> Self {
        Self::new(device, label, wgpu::BufferUsages::VERTEX)
    }

    pub(super) fn upload<T: bytemuck::Pod>(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        v: &[T],
    ) {
        let bytes: &[u8] = bytemuck::cast_slice(v);
        if bytes.len() as u64 > self.cap {
            self.cap = (bytes.len() as u64).next_power_of_two();
            self.buf = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(self.label),
                size: self.cap,
                usage: self.usage,
                mapped_at_creation: false,
            });
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buf, 0, bytes);
        }
        self.len = v.len() as u32;
    }
}
