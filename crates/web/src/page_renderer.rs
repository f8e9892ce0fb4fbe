//! The page's own renderer: a pre-pass into its Depth32Float depth (reversed Z for a
//! perspective camera) and
//! Rgba16Float world-space normals (shaders/web/prepass.wgsl), and a full-screen shading pass
//! into the canvas that multiplies aograph's AO into the ambient light
//! (shaders/web/shade.wgsl). It knows nothing of aograph's g-buffer.
//!
//! Invariant: the depth and normal textures are the output's size and are what aograph-embed
//! reads; the shading pass reads them and the AO texel for texel, so all three share a size.

use aograph_graph::plain_texture;
use glam::{Mat4, Vec3};

use crate::scene_mesh::{SceneMesh, Vertex};
use crate::shader_source;

/// The depth format the page renders and aograph reads.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The normals' format: xyz signed, world space.
pub const NORMALS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// A texture of `size` the page can shade into instead of a canvas and read back: Rgba8Unorm,
/// `RENDER_ATTACHMENT | COPY_SRC` (the native example, the tests, and the page's copy-out
/// mode).
pub fn offscreen_target(device: &wgpu::Device, size: (u32, u32)) -> wgpu::Texture {
    plain_texture(
        device,
        "page frame",
        size,
        OFFSCREEN_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    )
}

/// The format of [`offscreen_target`].
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The page's pipelines, buffers and pre-pass targets.
pub struct PageRenderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// Depth32Float, reversed Z (near = 1, cleared to 0) or standard Z (cleared to 1):
    /// aograph's depth input.
    pub depth: wgpu::Texture,
    /// World-space normals, xyz signed (w = 1 where something was drawn, 0 for the sky).
    pub normals: wgpu::Texture,
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    prepass: wgpu::RenderPipeline,
    shade: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    vertex_count: u32,
    camera: wgpu::Buffer,
    /// Made once: the targets' views and the pre-pass's bind group (only the camera).
    depth_view: wgpu::TextureView,
    normals_view: wgpu::TextureView,
    prepass_bind: wgpu::BindGroup,
    /// The depth the pre-pass clears to: 0 with reversed Z, 1 with standard Z.
    clear_depth: f32,
}

impl PageRenderer {
    /// The renderer of `mesh` at `width` x `height`, shading into `target_format`, its depth
    /// in reversed Z (nearer is greater) when `reversed_z`, for the projection it is given.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &SceneMesh,
        (width, height): (u32, u32),
        target_format: wgpu::TextureFormat,
        reversed_z: bool,
    ) -> Self {
        use wgpu::util::DeviceExt;
        // TEXTURE_BINDING: aograph and the shading pass read them.
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let texture = |label, format| plain_texture(device, label, (width, height), format, usage);
        let depth = texture("page depth", DEPTH_FORMAT);
        let normals = texture("page normals", NORMALS_FORMAT);
        let module = |path: &str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(path),
                source: wgpu::ShaderSource::Wgsl(shader_source(path).into()),
            })
        };
        let prepass_module = module("web/prepass.wgsl");
        let shade_module = module("web/shade.wgsl");
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        };
        let prepass = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("page pre-pass"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &prepass_module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[Some(vertex_layout)],
            },
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(if reversed_z {
                    wgpu::CompareFunction::Greater
                } else {
                    wgpu::CompareFunction::Less
                }),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &prepass_module,
                entry_point: Some("fs_normals"),
                compilation_options: Default::default(),
                targets: &[Some(NORMALS_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let shade = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("page shading"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &shade_module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &shade_module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(target_format.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("page vertices"),
            contents: bytemuck::cast_slice(&mesh.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let camera = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("page camera"),
            size: 96,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let prepass_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("page pre-pass"),
            layout: &prepass.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: camera.as_entire_binding(),
            }],
        });
        Self {
            device: device.clone(),
            queue: queue.clone(),
            depth_view: depth.create_view(&Default::default()),
            normals_view: normals.create_view(&Default::default()),
            prepass_bind,
            depth,
            normals,
            width,
            height,
            prepass,
            shade,
            vertices,
            vertex_count: mesh.vertices.len() as u32,
            camera,
            clear_depth: if reversed_z { 0.0 } else { 1.0 },
        }
    }

    /// Writes the camera block: `view_proj`, the sun's direction and the display mode (AO
    /// only when `ao_only`).
    pub fn set_camera(&self, view_proj: Mat4, light_dir: Vec3, ao_only: bool) {
        let mut block = [0f32; 24];
        block[..16].copy_from_slice(&view_proj.to_cols_array());
        block[16..19].copy_from_slice(&light_dir.normalize_or_zero().to_array());
        block[20] = if ao_only { 1.0 } else { 0.0 };
        self.queue
            .write_buffer(&self.camera, 0, bytemuck::cast_slice(&block));
    }

    /// The pre-pass: depth (cleared to the far value) and world normals (cleared to 0).
    pub fn prepass(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("page pre-pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.normals_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(self.clear_depth),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&self.prepass);
        pass.set_bind_group(0, &self.prepass_bind, &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.draw(0..self.vertex_count, 0..1);
    }

    /// Shading into `target` (the canvas, or an offscreen texture of the target format),
    /// with `ao` (aograph's output, the renderer's size).
    pub fn shade(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        ao: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        // Made per frame: the AO view changes with the technique's output.
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("page shading"),
            layout: &self.shade.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.camera.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&self.normals_view),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(ao),
                },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("page shading"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            ..Default::default()
        });
        pass.set_pipeline(&self.shade);
        pass.set_bind_group(0, &bind, &[]);
        pass.draw(0..3, 0..1);
    }
}
