//! The g-buffer's raster pass: uploads the scene's meshes once, the per-instance transforms
//! and skinned instances' joint palettes (now and at the previous frame) every frame, and draws
//! every instance into the requested colour targets plus depth. Skinned instances are drawn by
//! a second pipeline (`vs_skinned`, with the mesh's joints and weights as a second vertex
//! buffer), built only for a scene that has them. Depth is reversed (clear 0, test Greater) when the camera uses
//! an infinite reversed-Z projection: the frame's camera as the clock reports it
//! (`GBufferFrame::reversed_z`), else the scene's; one pipeline per depth test, built when
//! first needed, so a renderer may switch cameras between the two conventions.

use std::sync::{Arc, Mutex};

use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{
    BufferHandle, CustomPass, GraphError, GraphResult, PassContext, TextureHandle,
};
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

use super::GBufferClock;

mod second_layer;
use crate::camera::Projection;
use crate::model::Scene;
use crate::normal_transform::normal_matrix;
pub use second_layer::SecondLayerRaster;

const SHADER: &str = "scene/gbuffer.wgsl";

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct InstanceGpu {
    model: [[f32; 4]; 4],
    prev_model: [[f32; 4]; 4],
    /// WGSL `mat3x3<f32>`: three columns padded to 16 bytes each.
    normal_model: [[f32; 4]; 3],
    color: [f32; 4],
    /// A skinned instance's first entry in the joint palette (0 when rigid).
    palette_first: u32,
    /// A skinned instance's joint count (0 when rigid).
    joint_count: u32,
    /// Unused; pads the row to 16 bytes.
    pad0: u32,
    /// Unused; pads the row to 16 bytes.
    pad1: u32,
}

/// One joint's skinning matrix now and at the previous frame (WGSL `JointPalette`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct JointGpu {
    current: [[f32; 4]; 4],
    previous: [[f32; 4]; 4],
}

/// The skinned vertex buffer's element: JOINTS_0 widened to u32 and the normalised weights.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SkinVertexGpu {
    joints: [u32; 4],
    weights: [f32; 4],
}

/// The WGSL layout of a 3x3 matrix: columns padded to vec4.
fn padded_mat3(m: glam::Mat3) -> [[f32; 4]; 3] {
    [m.x_axis, m.y_axis, m.z_axis].map(|c| c.extend(0.0).to_array())
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LightGpu {
    /// World-space direction the light travels (unit).
    direction: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pad0: f32,
    /// Linear RGB colour times intensity.
    color: [f32; 3],
    /// Unused; pads the row to 16 bytes.
    pad1: f32,
}

struct MeshGpu {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// Joints and weights per vertex, for a mesh with skin weights.
    skin: Option<wgpu::Buffer>,
}

pub(super) struct GpuState {
    meshes: Vec<MeshGpu>,
    instances: wgpu::Buffer,
    light: wgpu::Buffer,
    /// Every skinned instance's joint palette (at least one entry, so it can always be bound).
    palette: wgpu::Buffer,
    /// Per instance, its first palette entry when it is drawn skinned.
    palette_offsets: Vec<Option<u32>>,
    palette_staging: Vec<JointGpu>,
    /// Rigid (`vs`) and skinned (`vs_skinned`) pipelines, each with depth test Less (index 0)
    /// and Greater (reversed Z, index 1), built on first use.
    pipelines: [[Option<wgpu::RenderPipeline>; 2]; 2],
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    color_targets: Vec<Option<wgpu::ColorTargetState>>,
    layout: wgpu::BindGroupLayout,
    bind_group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    staging: Vec<InstanceGpu>,
    /// The second layer's pipelines and bindings, made on its first frame.
    second_layer: Option<second_layer::SecondLayerGpu>,
}

/// A g-buffer node's GPU state, made on its first frame.
type SharedState = Arc<Mutex<Option<GpuState>>>;

/// G-buffer GPU states by scene and channels (see `add_gbuffer_shared`). Each entry keeps its
/// scene alive, so the scene's address cannot be reused by another scene while it is a key.
#[derive(Clone, Default)]
pub struct GBufferStates(Arc<Mutex<Vec<StateEntry>>>);

/// One shared state and what it was made for.
type StateEntry = (Arc<Scene>, GBufferChannels, SharedState);

impl GBufferStates {
    pub(super) fn state(&self, scene: &Arc<Scene>, channels: GBufferChannels) -> SharedState {
        let Ok(mut list) = self.0.lock() else {
            return SharedState::default();
        };
        if let Some((_, _, s)) = list
            .iter()
            .find(|(sc, ch, _)| Arc::ptr_eq(sc, scene) && *ch == channels)
        {
            return s.clone();
        }
        let s = SharedState::default();
        list.push((scene.clone(), channels, s.clone()));
        s
    }
}

/// The custom pass behind `add_gbuffer`.
pub struct GBufferRaster {
    source: RasterSource,
    targets: Vec<(GBufferChannel, TextureHandle)>,
    depth: TextureHandle,
}

/// What both raster passes of a g-buffer node draw and share: the scene, the channel set, the
/// view block, the frame's clock and the GPU state (uploaded meshes, instance rows).
#[derive(Clone)]
pub(super) struct RasterSource {
    pub(super) scene: Arc<Scene>,
    pub(super) channels: GBufferChannels,
    pub(super) view: BufferHandle,
    pub(super) clock: GBufferClock,
    pub(super) state: SharedState,
}

impl RasterSource {
    /// Whether the scene's own camera rasterises with reversed Z (an infinite reversed-Z
    /// perspective), the depth test both layers use unless the frame says otherwise.
    fn reversed_z(&self) -> bool {
        matches!(
            self.scene.camera.projection,
            Projection::Perspective {
                reversed_z_infinite: true,
                ..
            }
        )
    }
}

impl GBufferRaster {
    pub(super) fn new(
        source: RasterSource,
        targets: Vec<(GBufferChannel, TextureHandle)>,
        depth: TextureHandle,
    ) -> Self {
        Self {
            source,
            targets,
            depth,
        }
    }

    fn create_state(&self, ctx: &PassContext<'_>) -> GraphResult<GpuState> {
        let device = ctx.device;
        let info = ctx.shaders().load(SHADER)?;
        let entries =
            info.layout_entries(wgpu::ShaderStages::VERTEX_FRAGMENT, ctx.features(), |_| {
                None
            });
        let group0 = entries
            .into_iter()
            .find(|(g, _)| *g == 0)
            .map(|(_, e)| e)
            .unwrap_or_default();
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer"),
            entries: &group0,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gbuffer"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(SHADER),
            source: wgpu::ShaderSource::Wgsl(info.source.as_str().into()),
        });
        // Locations 0..6 in the shader's order; unrequested channels get no target.
        let order = [
            GBufferChannel::LinearDepth,
            GBufferChannel::Normals,
            GBufferChannel::Positions,
            GBufferChannel::Albedo,
            GBufferChannel::DirectLight,
            GBufferChannel::Motion,
            GBufferChannel::NormalsOct,
        ];
        let targets: Vec<Option<wgpu::ColorTargetState>> = order
            .iter()
            .map(|c| {
                self.targets
                    .iter()
                    .any(|(t, _)| t == c)
                    .then(|| wgpu::ColorTargetState {
                        format: c.format(),
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })
            })
            .collect();
        let meshes = self.upload_meshes(device);
        let mut palette_offsets = Vec::with_capacity(self.source.scene.instances.len());
        let mut joints = 0u32;
        for inst in &self.source.scene.instances {
            let skin =
                (self.source.scene.meshes.get(inst.mesh)).and_then(|mesh| inst.skin_for(mesh));
            palette_offsets.push(skin.map(|skin| {
                let first = joints;
                joints += skin.joints.len() as u32;
                first
            }));
        }
        let palette = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("gbuffer joint palette"),
            size: (joints.max(1) as usize * std::mem::size_of::<JointGpu>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let n = self.source.scene.instances.len().max(1);
        let instances = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("gbuffer instances"),
            size: (n * std::mem::size_of::<InstanceGpu>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let l = &self.source.scene.light;
        let dir = l.direction.try_normalize().unwrap_or(glam::Vec3::NEG_Y);
        let light = LightGpu {
            direction: [dir.x, dir.y, dir.z],
            pad0: 0.0,
            color: [
                l.color[0] * l.intensity,
                l.color[1] * l.intensity,
                l.color[2] * l.intensity,
            ],
            pad1: 0.0,
        };
        let light = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("gbuffer light"),
            contents: bytemuck::bytes_of(&light),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        Ok(GpuState {
            meshes,
            instances,
            light,
            palette,
            palette_offsets,
            palette_staging: Vec::with_capacity(joints as usize),
            pipelines: Default::default(),
            module,
            pipeline_layout,
            color_targets: targets,
            layout,
            bind_group: None,
            staging: Vec::with_capacity(n),
            second_layer: None,
        })
    }

    fn create_pipeline(
        &self,
        device: &wgpu::Device,
        state: &GpuState,
        skinned: bool,
        reversed: bool,
    ) -> wgpu::RenderPipeline {
        let fragment = if self.source.channels.face_normals {
            "fs_face"
        } else {
            "fs_smooth"
        };
        let shape = PipelineShape {
            layout: &state.pipeline_layout,
            fragment,
            targets: &state.color_targets,
            constants: &[],
        };
        raster_pipeline(
            device,
            state,
            self.source.channels,
            &shape,
            skinned,
            reversed,
        )
    }
}

/// What differs between the first layer's pipelines and the second's.
struct PipelineShape<'a> {
    layout: &'a wgpu::PipelineLayout,
    fragment: &'a str,
    targets: &'a [Option<wgpu::ColorTargetState>],
    constants: &'a [(&'a str, f64)],
}

/// A g-buffer raster pipeline: the scene's vertex layout (rigid or skinned), no culling (two-
/// sided surfaces), depth test Less or Greater (reversed Z) with writes, `shape`'s fragment.
fn raster_pipeline(
    device: &wgpu::Device,
    state: &GpuState,
    channels: GBufferChannels,
    shape: &PipelineShape<'_>,
    skinned: bool,
    reversed: bool,
) -> wgpu::RenderPipeline {
    PIPELINES_CREATED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let module = &state.module;
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: 24,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
    };
    let skin_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<SkinVertexGpu>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![2 => Uint32x4, 3 => Float32x4],
    };
    let buffers = [Some(vertex_layout), Some(skin_layout)];
    let buffers = if skinned { &buffers[..] } else { &buffers[..1] };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("gbuffer"),
        layout: Some(shape.layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(if skinned { "vs_skinned" } else { "vs" }),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: channels.depth_format.format(),
            depth_write_enabled: Some(true),
            depth_compare: Some(if reversed {
                wgpu::CompareFunction::Greater
            } else {
                wgpu::CompareFunction::Less
            }),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(shape.fragment),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: shape.constants,
                ..Default::default()
            },
            targets: shape.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl GBufferRaster {
    fn upload_meshes(&self, device: &wgpu::Device) -> Vec<MeshGpu> {
        self.source
            .scene
            .meshes
            .iter()
            .map(|m| {
                let verts: Vec<[f32; 6]> = m
                    .positions
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        // No normals: zero, so the fragment uses the geometric normal.
                        let n = m.normals.get(i).copied().unwrap_or(glam::Vec3::ZERO);
                        [p.x, p.y, p.z, n.x, n.y, n.z]
                    })
                    .collect();
                let indices: Vec<u32> = m
                    .indices
                    .iter()
                    .copied()
                    .filter(|&i| (i as usize) < m.positions.len())
                    .collect();
                let indices = if indices.len() == m.indices.len() {
                    indices
                } else {
                    Vec::new()
                };
                MeshGpu {
                    vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("mesh vertices"),
                        contents: bytemuck::cast_slice(if verts.is_empty() {
                            &[[0f32; 6]]
                        } else {
                            verts.as_slice()
                        }),
                        usage: wgpu::BufferUsages::VERTEX,
                    }),
                    indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("mesh indices"),
                        contents: bytemuck::cast_slice(if indices.is_empty() {
                            &[0u32]
                        } else {
                            indices.as_slice()
                        }),
                        usage: wgpu::BufferUsages::INDEX,
                    }),
                    index_count: (indices.len() / 3 * 3) as u32,
                    // Exactly the meshes `Instance::skin_for` skins (palette offsets below).
                    skin: (!m.skin_weights.is_empty() && m.skin_weights.len() == m.positions.len())
                        .then(|| {
                            let skin: Vec<SkinVertexGpu> = m
                                .skin_weights
                                .iter()
                                .map(|w| SkinVertexGpu {
                                    joints: w.joints.map(u32::from),
                                    weights: w.weights,
                                })
                                .collect();
                            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                                label: Some("mesh joints and weights"),
                                contents: bytemuck::cast_slice(&skin),
                                usage: wgpu::BufferUsages::VERTEX,
                            })
                        }),
                }
            })
            .collect()
    }
}

/// Raster pipelines every g-buffer node of the process has created (a front end adds them to
/// the executor's count: a g-buffer pass builds its own pipelines, on its first frame).
static PIPELINES_CREATED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Raster pipelines every g-buffer node of this process has created so far (a front end adds
/// them to the executor's pipeline count: a g-buffer pass builds its own, on its first frame).
pub fn raster_pipelines_created() -> u64 {
    PIPELINES_CREATED.load(std::sync::atomic::Ordering::Relaxed)
}

impl CustomPass for GBufferRaster {
    fn kind_name(&self) -> &str {
        "gbuffer raster"
    }
    fn cache_key(&self) -> u64 {
        // The plan depends on which scene is drawn and how.
        let s = &*self.source.scene as *const Scene as u64;
        s ^ ((self.source.channels.face_normals as u64) << 63)
            ^ ((self.source.reversed_z() as u64) << 62)
            ^ ((self.source.channels.depth_format as u64) << 60)
    }
    fn record(&self, ctx: &mut PassContext<'_>) -> GraphResult<()> {
        let mut guard =
            self.source.state.lock().map_err(|_| {
                GraphError::Gpu("g-buffer state poisoned by an earlier panic".into())
            })?;
        if guard.is_none() {
            *guard = Some(self.create_state(ctx)?);
        }
        let Some(state) = guard.as_mut() else {
            return Ok(());
        };
        let frame = self.source.clock.get();
        state.staging.clear();
        state.palette_staging.clear();
        for (inst, offset) in self
            .source
            .scene
            .instances
            .iter()
            .zip(&state.palette_offsets)
        {
            let color = self
                .source
                .scene
                .materials
                .get(
                    self.source
                        .scene
                        .meshes
                        .get(inst.mesh)
                        .map(|m| m.material)
                        .unwrap_or(0),
                )
                .map(|m| m.base_color)
                .unwrap_or([0.8, 0.8, 0.8, 1.0]);
            let model = inst.transform_at(frame.time);
            let (mut palette_first, mut joint_count) = (0, 0);
            if let (Some(first), Some(s)) = (offset, &inst.skin) {
                let (now, before) = (s.palette(frame.time), s.palette(frame.prev_time));
                state
                    .palette_staging
                    .extend(now.iter().zip(&before).map(|(c, p)| JointGpu {
                        current: c.to_cols_array_2d(),
                        previous: p.to_cols_array_2d(),
                    }));
                (palette_first, joint_count) = (*first, now.len() as u32);
            }
            state.staging.push(InstanceGpu {
                model: model.to_cols_array_2d(),
                prev_model: inst.transform_at(frame.prev_time).to_cols_array_2d(),
                normal_model: padded_mat3(normal_matrix(model)),
                color,
                palette_first,
                joint_count,
                pad0: 0,
                pad1: 0,
            });
        }
        if !state.staging.is_empty() {
            ctx.queue
                .write_buffer(&state.instances, 0, bytemuck::cast_slice(&state.staging));
        }
        if !state.palette_staging.is_empty() {
            ctx.queue.write_buffer(
                &state.palette,
                0,
                bytemuck::cast_slice(&state.palette_staging),
            );
        }
        let view_buffer = ctx.buffer(self.source.view)?.clone();
        if state
            .bind_group
            .as_ref()
            .is_none_or(|(b, _)| *b != view_buffer)
        {
            let bg = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("gbuffer"),
                layout: &state.layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: view_buffer.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: state.instances.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: state.light.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: state.palette.as_entire_binding(),
                    },
                ],
            });
            state.bind_group = Some((view_buffer, bg));
        }
        let order = [
            GBufferChannel::LinearDepth,
            GBufferChannel::Normals,
            GBufferChannel::Positions,
            GBufferChannel::Albedo,
            GBufferChannel::DirectLight,
            GBufferChannel::Motion,
            GBufferChannel::NormalsOct,
        ];
        let mut views = Vec::with_capacity(order.len());
        for c in order {
            views.push(match self.targets.iter().find(|(t, _)| *t == c) {
                Some((_, h)) => Some(ctx.view(*h)?.clone()),
                None => None,
            });
        }
        let color: Vec<Option<wgpu::RenderPassColorAttachment>> = views
            .iter()
            .map(|v| {
                v.as_ref().map(|view| wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let depth_view = ctx.view(self.depth)?.clone();
        let reversed = frame.reversed_z.unwrap_or_else(|| self.source.reversed_z());
        for skinned in [false, true] {
            if draws(state, skinned)
                && state.pipelines[skinned as usize][reversed as usize].is_none()
            {
                let pipeline = self.create_pipeline(ctx.device, state, skinned, reversed);
                state.pipelines[skinned as usize][reversed as usize] = Some(pipeline);
            }
        }
        let clear_depth = if reversed { 0.0 } else { 1.0 };
        let mut rp = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &color,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(clear_depth),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some((_, bg)) = &state.bind_group {
            rp.set_bind_group(0, bg, &[]);
        }
        draw_instances(
            &mut rp,
            &self.source.scene,
            state,
            &state.pipelines,
            reversed,
        );
        Ok(())
    }
}

/// Whether some instance is drawn by the skinned (`true`) or the rigid pipeline.
fn draws(state: &GpuState, skinned: bool) -> bool {
    if skinned {
        state.palette_offsets.iter().any(Option::is_some)
    } else {
        state.palette_offsets.iter().any(Option::is_none)
    }
}

/// Draws every instance of `scene` (uploaded in `state`) with `pipelines[skinned][reversed]`;
/// instance `i` is drawn as instance index `i`, which selects its row of transforms.
fn draw_instances(
    rp: &mut wgpu::RenderPass<'_>,
    scene: &Scene,
    state: &GpuState,
    pipelines: &[[Option<wgpu::RenderPipeline>; 2]; 2],
    reversed: bool,
) {
    let mut bound = None;
    for (i, (inst, offset)) in (scene.instances.iter())
        .zip(&state.palette_offsets)
        .enumerate()
    {
        let Some(mesh) = state.meshes.get(inst.mesh) else {
            continue;
        };
        if mesh.index_count == 0 {
            continue;
        }
        let skin = offset.and(mesh.skin.as_ref());
        let skinned = skin.is_some();
        if bound != Some(skinned) {
            if let Some(pipeline) = &pipelines[skinned as usize][reversed as usize] {
                rp.set_pipeline(pipeline);
            }
            bound = Some(skinned);
        }
        if let Some(skin) = skin {
            rp.set_vertex_buffer(1, skin.slice(..));
        }
        rp.set_vertex_buffer(0, mesh.vertices.slice(..));
        rp.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        rp.draw_indexed(0..mesh.index_count, 0, i as u32..i as u32 + 1);
    }
}
