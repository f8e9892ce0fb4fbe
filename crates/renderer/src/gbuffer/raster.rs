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
use wgpu::util::DeviceExt;

use super::GBufferClock;

mod draw;
mod gpu_rows;
mod second_layer;
use aograph_scene::camera::Projection;
use aograph_scene::model::Scene;
use aograph_scene::normal_transform::normal_matrix;
pub use draw::raster_pipelines_created;
use draw::{PipelineShape, depth_attachment, draw_instances, ensure_pipelines, raster_pipeline};
use gpu_rows::{InstanceGpu, JointGpu, LightGpu, MeshGpu, padded_mat3, upload_meshes};
pub use second_layer::SecondLayerRaster;

const SHADER: &str = "scene/gbuffer.wgsl";

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
        let meshes = upload_meshes(&self.source.scene, device);
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
        let mut guard = self.source.state.lock().map_err(|_| {
            GraphError::Internal("the g-buffer's state was poisoned by an earlier panic")
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
        let mut pipelines = std::mem::take(&mut state.pipelines);
        ensure_pipelines(&mut pipelines, state, reversed, |skinned| {
            self.create_pipeline(ctx.device, state, skinned, reversed)
        });
        state.pipelines = pipelines;
        let mut rp = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &color,
            depth_stencil_attachment: Some(depth_attachment(
                &depth_view,
                reversed,
                wgpu::StoreOp::Store,
            )),
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
