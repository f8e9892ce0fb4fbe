//! The application side of examples/own_renderer.rs: a minimal forward renderer that knows
//! nothing of aograph's scenes or g-buffer. It loads a glTF's triangles into its own vertex
//! buffers, draws a depth pre-pass into its own reversed-Z Depth32Float buffer, and shades
//! with an AO texture it is handed. (tests/own_renderer.rs runs it too.)

use std::path::Path;

use glam::{Mat4, Vec3};

/// One vertex: world-space position and normal.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// Every triangle of a glTF's default scene, in world space.
pub struct Mesh {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
}

impl Mesh {
    /// The glTF at `path` (its buffers only: images are not needed to draw shapes).
    pub fn load(path: &Path) -> Result<Self, String> {
        let gltf = gltf::Gltf::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let buffers = gltf::import_buffers(&gltf.document, path.parent(), gltf.blob.clone())
            .map_err(|e| format!("{}: buffers: {e}", path.display()))?;
        let mut mesh = Mesh {
            vertices: Vec::new(),
            indices: Vec::new(),
        };
        let scene = gltf
            .document
            .default_scene()
            .or_else(|| gltf.document.scenes().next())
            .ok_or_else(|| format!("{}: no scene", path.display()))?;
        for node in scene.nodes() {
            mesh.add_node(&node, Mat4::IDENTITY, &buffers);
        }
        if mesh.indices.is_empty() {
            return Err(format!("{}: no triangles", path.display()));
        }
        Ok(mesh)
    }

    fn add_node(&mut self, node: &gltf::Node, parent: Mat4, buffers: &[gltf::buffer::Data]) {
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let normal_matrix = world.inverse().transpose();
        if let Some(m) = node.mesh() {
            for p in m.primitives() {
                if p.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let r = p.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let Some(positions) = r.read_positions() else {
                    continue;
                };
                let positions: Vec<Vec3> = positions.map(Vec3::from).collect();
                let normals: Vec<Vec3> = match r.read_normals() {
                    Some(n) => n.map(Vec3::from).collect(),
                    None => vec![Vec3::Y; positions.len()],
                };
                let base = self.vertices.len() as u32;
                for (p, n) in positions.iter().zip(&normals) {
                    self.vertices.push(Vertex {
                        position: world.transform_point3(*p).into(),
                        normal: normal_matrix
                            .transform_vector3(*n)
                            .normalize_or_zero()
                            .into(),
                    });
                }
                let flip = world.determinant() < 0.0;
                let idx: Vec<u32> = match r.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                for t in idx.chunks_exact(3) {
                    let t = if flip {
                        [t[0], t[2], t[1]]
                    } else {
                        [t[0], t[1], t[2]]
                    };
                    self.indices.extend(t.map(|i| base + i));
                }
            }
        }
        for child in node.children() {
            self.add_node(&child, world, buffers);
        }
    }

    /// Centre and radius of the bounding sphere of the vertices' box.
    pub fn bounds(&self) -> (Vec3, f32) {
        let (lo, hi) = self.vertices.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| {
                let p = Vec3::from(v.position);
                (lo.min(p), hi.max(p))
            },
        );
        (0.5 * (lo + hi), 0.5 * (hi - lo).length())
    }
}

/// The application's renderer: its own pipelines, buffers and depth buffer.
pub struct OwnRenderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// Reversed Z (near = 1, cleared to 0), Depth32Float, readable by aograph.
    pub depth: wgpu::Texture,
    /// What the application shows: RGBA8, sRGB-encoded by its shader.
    pub color: wgpu::Texture,
    pub width: u32,
    pub height: u32,
    prepass: wgpu::RenderPipeline,
    shade: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    camera: wgpu::Buffer,
    centre: Vec3,
    radius: f32,
}

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl OwnRenderer {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &Mesh,
        width: u32,
        height: u32,
    ) -> Self {
        use wgpu::util::DeviceExt;
        let texture = |label, format, usage| {
            aograph_graph::plain_texture(device, label, (width, height), format, usage)
        };
        let depth = texture(
            "own depth",
            DEPTH_FORMAT,
            // TEXTURE_BINDING: aograph reads it; COPY_SRC: tests read it back.
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        let color = texture(
            "own colour",
            COLOR_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("own renderer"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/own_renderer.wgsl").into()),
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
        };
        let pipeline = |label, depth_compare, depth_write, fragment: Option<&str>| {
            let targets = [Some(wgpu::ColorTargetState::from(COLOR_FORMAT))];
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                // Layouts from the shader: the pre-pass binds only the camera.
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout.clone())],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(depth_compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: fragment.map(|entry| wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        // Reversed Z: nearer is greater.
        let prepass = pipeline(
            "own depth pre-pass",
            wgpu::CompareFunction::Greater,
            true,
            None,
        );
        let shade = pipeline(
            "own shading",
            wgpu::CompareFunction::GreaterEqual,
            false,
            Some("fs_shade"),
        );
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("own vertices"),
            contents: bytemuck::cast_slice(&mesh.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("own indices"),
            contents: bytemuck::cast_slice(&mesh.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let camera = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("own camera"),
            size: 80,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (centre, radius) = mesh.bounds();
        Self {
            device: device.clone(),
            queue: queue.clone(),
            depth,
            color,
            prepass,
            shade,
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
            camera,
            centre,
            radius,
            width,
            height,
        }
    }

    /// The camera at time `t`: orbiting the mesh, looking at its centre, reversed-Z infinite
    /// perspective (view, projection).
    pub fn camera(&self, t: f32) -> (Mat4, Mat4) {
        let angle = 0.7 + 0.35 * t;
        let eye = self.centre + self.radius * Vec3::new(1.6 * angle.cos(), 0.9, 1.6 * angle.sin());
        let view = Mat4::look_at_rh(eye, self.centre, Vec3::Y);
        let aspect = self.width as f32 / self.height as f32;
        let proj =
            Mat4::perspective_infinite_reverse_rh(50f32.to_radians(), aspect, 0.01 * self.radius);
        (view, proj)
    }

    /// A length in the mesh's units for AO: a fifth of its bounding radius.
    pub fn ao_radius(&self) -> f32 {
        0.2 * self.radius
    }

    fn bind_group(
        &self,
        pipeline: &wgpu::RenderPipeline,
        ao: Option<&wgpu::TextureView>,
    ) -> wgpu::BindGroup {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: 0,
            resource: self.camera.as_entire_binding(),
        }];
        if let Some(ao) = ao {
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(ao),
            });
        }
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("own renderer"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        })
    }

    /// Writes the camera block for this frame.
    pub fn set_camera(&self, view: Mat4, proj: Mat4) {
        let light = Vec3::new(-0.4, -1.0, -0.3).normalize();
        let mut block = [0f32; 20];
        block[..16].copy_from_slice(&(proj * view).to_cols_array());
        block[16..19].copy_from_slice(&light.to_array());
        self.queue
            .write_buffer(&self.camera, 0, bytemuck::cast_slice(&block));
    }

    /// The depth pre-pass: only depth, reversed Z.
    pub fn depth_prepass(&self, encoder: &mut wgpu::CommandEncoder) {
        let depth = self.depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("own depth pre-pass"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&self.prepass);
        pass.set_bind_group(0, &self.bind_group(&self.prepass, None), &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }

    /// Shading: albedo * (ambient * AO + direct), against the pre-pass's depth.
    pub fn shade(&self, encoder: &mut wgpu::CommandEncoder, ao: &wgpu::TextureView) {
        let color = self.color.create_view(&Default::default());
        let depth = self.depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("own shading"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: 0.55,
                        g: 0.65,
                        b: 0.8,
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&self.shade);
        pass.set_bind_group(0, &self.bind_group(&self.shade, Some(ao)), &[]);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
    }
}
