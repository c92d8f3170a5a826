//! The renderer: pipelines, the cloth's texture, the target, and one frame's draw.

use egui_wgpu::wgpu;
use wgpu::util::DeviceExt;

use super::blit::{Blit, ShowView, sampler_entry, texture_entry};
use super::gpu::{Buf, Uniforms, Vertex};
use super::scene::{self, Overlay};
use crate::camera::Camera;
use crate::store::Store;

const COLOUR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

pub struct View3d {
    textured: wgpu::RenderPipeline,
    coloured: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    uniforms: wgpu::Buffer,
    bind: wgpu::BindGroup,
    cloth_tex: wgpu::Texture,
    cloth_tex_size: (u32, u32),
    bind_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    cloth: Buf,
    /// The cloth's distinct (vertex, UV) pairs and the triangles over them, rebuilt when
    /// the topology changes: a grid cloth then shades each vertex once, not six times.
    cloth_keys: Vec<(u32, [f32; 2])>,
    cloth_index: Buf,
    cloth_topology: Option<(u64, u64, usize)>,
    body: Buf,
    body_version: u64,
    line_buf: Buf,
    marker: Buf,
    scratch: Vec<Vertex>,
    /// The cloth is drawn in the map's colours (untextured) this frame.
    mapped: bool,
    target: Option<(wgpu::Texture, wgpu::Texture, [u32; 2])>,
    blit: Blit,
}

fn cloth_texture(device: &wgpu::Device, w: u32, h: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("saiho cloth texture"),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

impl View3d {
    pub fn new(device: &wgpu::Device) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("saiho view3d"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("saiho view3d"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                texture_entry(1),
                sampler_entry(2),
            ],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("saiho view3d"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
        let pipeline = |fs: &str, topology: wgpu::PrimitiveTopology| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(fs),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some(if topology == wgpu::PrimitiveTopology::LineList {
                        "vs_line"
                    } else {
                        "vs"
                    }),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attrs,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(fs),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: COLOUR,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let textured = pipeline("fs_textured", wgpu::PrimitiveTopology::TriangleList);
        let coloured = pipeline("fs_colour", wgpu::PrimitiveTopology::TriangleList);
        let lines = pipeline("fs_flat", wgpu::PrimitiveTopology::LineList);
        let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("saiho uniforms"),
            contents: bytemuck::bytes_of(&Uniforms {
                view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
                light_dir: [0.3, 1.0, 0.5, 0.0],
                eye: [0.0; 4],
            }),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("saiho cloth"),
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let cloth_tex = cloth_texture(device, 1024, 1024);
        let bind = Self::bind_group(device, &bind_layout, &uniforms, &cloth_tex, &sampler);
        Self {
            textured,
            coloured,
            lines,
            uniforms,
            bind,
            cloth_tex,
            cloth_tex_size: (1024, 1024),
            bind_layout,
            sampler,
            cloth: Buf::vertices(device, "saiho cloth"),
            cloth_keys: Vec::new(),
            cloth_index: Buf::new(device, "saiho cloth indices", wgpu::BufferUsages::INDEX),
            cloth_topology: None,
            body: Buf::vertices(device, "saiho body"),
            body_version: u64::MAX,
            line_buf: Buf::vertices(device, "saiho lines"),
            marker: Buf::vertices(device, "saiho markers"),
            scratch: Vec::new(),
            mapped: false,
            target: None,
            blit: Blit::new(device),
        }
    }

    fn bind_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        uniforms: &wgpu::Buffer,
        tex: &wgpu::Texture,
        sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        let view = tex.create_view(&Default::default());
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("saiho view3d"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(sampler),
                },
            ],
        })
    }

    fn upload_texture(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, store: &mut Store) {
        let t = &mut store.texture;
        let (w, h) = (t.width as u32, t.height as u32);
        if (w, h) != self.cloth_tex_size {
            self.cloth_tex = cloth_texture(device, w, h);
            self.cloth_tex_size = (w, h);
            self.bind = Self::bind_group(
                device,
                &self.bind_layout,
                &self.uniforms,
                &self.cloth_tex,
                &self.sampler,
            );
            t.dirty = vec![[0, 0, t.width, t.height]];
        }
        for [x0, y0, rw, rh] in std::mem::take(&mut t.dirty) {
            if rw == 0 || rh == 0 || x0 + rw > t.width || y0 + rh > t.height {
                continue;
            }
            let mut rows = Vec::with_capacity(4 * rw * rh);
            for r in 0..rh {
                let s = 4 * ((y0 + r) * t.width + x0);
                rows.extend_from_slice(&t.rgba[s..s + 4 * rw]);
            }
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.cloth_tex,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: x0 as u32,
                        y: y0 as u32,
                        z: 0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                &rows,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(4 * rw as u32),
                    rows_per_image: Some(rh as u32),
                },
                wgpu::Extent3d {
                    width: rw as u32,
                    height: rh as u32,
                    depth_or_array_layers: 1,
                },
            );
        }
    }

    fn ensure_target(&mut self, device: &wgpu::Device, size: [u32; 2]) {
        if self.target.as_ref().is_some_and(|t| t.2 == size) {
            return;
        }
        let make = |format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("saiho view3d target"),
                size: wgpu::Extent3d {
                    width: size[0],
                    height: size[1],
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let colour = make(
            COLOUR,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = make(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let view = colour.create_view(&Default::default());
        self.blit.group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("saiho view3d blit"),
            layout: &self.blit.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.blit.sampler),
                },
            ],
        }));
        self.target = Some((colour, depth, size));
    }

    /// Renders the scene at `size` pixels into the view's own texture; show it with
    /// [`Self::paint_callback`].
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        store: &mut Store,
        camera: &Camera,
        overlay: &Overlay,
        size: [u32; 2],
    ) {
        let size = [size[0].clamp(16, 4096), size[1].clamp(16, 4096)];
        self.ensure_target(device, size);
        self.upload_texture(device, queue, store);
        let aspect = size[0] as f32 / size[1] as f32;
        let eye = camera.eye();
        queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&Uniforms {
                view_proj: camera.view_proj(aspect).to_cols_array_2d(),
                light_dir: [0.35, 1.0, 0.55, 0.0],
                eye: [eye.x, eye.y, eye.z, 1.0],
            }),
        );
        let key = store
            .mesh
            .as_ref()
            .map(|m| (store.mesh_generation, m.topology, m.corners.len()));
        if key != self.cloth_topology {
            let index = scene::cloth_keys(store.mesh.as_ref(), &mut self.cloth_keys);
            self.cloth_index.upload(device, queue, &index);
            self.cloth_topology = key;
        }
        scene::cloth_vertices(&self.cloth_keys, store, &mut self.scratch);
        self.mapped = store.stretch.is_some();
        self.cloth.upload(device, queue, &self.scratch);
        if self.body_version != store.body_version {
            scene::body_vertices(store, &mut self.scratch);
            self.body.upload(device, queue, &self.scratch);
            self.body_version = store.body_version;
        }
        scene::lines(store, overlay, eye, &mut self.scratch);
        self.line_buf.upload(device, queue, &self.scratch);
        scene::markers(store, overlay, eye, &mut self.scratch);
        self.marker.upload(device, queue, &self.scratch);
        self.draw(device, queue);
    }

    /// Draws the uploaded scene into the view's target.
    fn draw(&self, device: &wgpu::Device, queue: &wgpu::Queue) {
        let Some((colour, depth, _)) = self.target.as_ref() else {
            return;
        };
        let cview = colour.create_view(&Default::default());
        let dview = depth.create_view(&Default::default());
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("saiho view3d"),
        });
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("saiho view3d"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &cview,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.13,
                            g: 0.14,
                            b: 0.16,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &dview,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.bind, &[]);
            if self.cloth.len > 0 && self.cloth_index.len > 0 {
                pass.set_pipeline(if self.mapped {
                    &self.coloured
                } else {
                    &self.textured
                });
                pass.set_vertex_buffer(0, self.cloth.buf.slice(..));
                pass.set_index_buffer(self.cloth_index.buf.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.cloth_index.len, 0, 0..1);
            }
            for (pipe, buf) in [
                (&self.coloured, &self.body),
                (&self.coloured, &self.marker),
                (&self.lines, &self.line_buf),
            ] {
                if buf.len > 0 {
                    pass.set_pipeline(pipe);
                    pass.set_vertex_buffer(0, buf.buf.slice(..));
                    pass.draw(0..buf.len, 0..1);
                }
            }
        }
        queue.submit([enc.finish()]);
    }

    /// A paint callback that draws the last rendered view over `rect` of a pass whose
    /// colour target has `format` (None before the first render).
    pub fn paint_callback(
        &mut self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
        rect: egui::Rect,
    ) -> Option<egui::PaintCallback> {
        let group = self.blit.group.clone()?;
        let pipeline = self.blit.pipeline(device, format);
        Some(egui_wgpu::Callback::new_paint_callback(
            rect,
            ShowView { pipeline, group },
        ))
    }
}
