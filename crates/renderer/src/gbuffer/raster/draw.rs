//! What both g-buffer layers draw with: the raster pipeline (rigid or skinned vertex layout,
//! either depth test), built on first use, and the draw of every instance.
//!
//! Invariant: instance `i` is drawn as instance index `i`, which selects its row of the
//! instance buffer in both layers.

use aograph_frame::GBufferChannels;

use super::GpuState;
use super::gpu_rows::SkinVertexGpu;
use aograph_scene::model::Scene;

/// What differs between the first layer's pipelines and the second's.
pub(super) struct PipelineShape<'a> {
    pub(super) layout: &'a wgpu::PipelineLayout,
    pub(super) fragment: &'a str,
    pub(super) targets: &'a [Option<wgpu::ColorTargetState>],
    pub(super) constants: &'a [(&'a str, f64)],
}

/// A g-buffer raster pipeline: the scene's vertex layout (rigid or skinned), no culling (two-
/// sided surfaces), depth test Less or Greater (reversed Z) with writes, `shape`'s fragment.
pub(super) fn raster_pipeline(
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

/// Raster pipelines every g-buffer node of the process has created (a front end adds them to
/// the executor's count: a g-buffer pass builds its own pipelines, on its first frame).
static PIPELINES_CREATED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Raster pipelines every g-buffer node of this process has created so far (a front end adds
/// them to the executor's pipeline count: a g-buffer pass builds its own, on its first frame).
pub fn raster_pipelines_created() -> u64 {
    PIPELINES_CREATED.load(std::sync::atomic::Ordering::Relaxed)
}

/// Whether some instance is drawn by the skinned (`true`) or the rigid pipeline.
pub(super) fn draws(state: &GpuState, skinned: bool) -> bool {
    if skinned {
        state.palette_offsets.iter().any(Option::is_some)
    } else {
        state.palette_offsets.iter().any(Option::is_none)
    }
}

/// Draws every instance of `scene` (uploaded in `state`) with `pipelines[skinned][reversed]`;
/// instance `i` is drawn as instance index `i`, which selects its row of transforms.
pub(super) fn draw_instances(
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

/// Builds each pipeline of `pipelines[skinned][reversed]` the scene draws with and lacks, with
/// `make(skinned)`: the rigid one where some instance is rigid, the skinned one where some is
/// skinned.
pub(super) fn ensure_pipelines(
    pipelines: &mut [[Option<wgpu::RenderPipeline>; 2]; 2],
    state: &GpuState,
    reversed: bool,
    mut make: impl FnMut(bool) -> wgpu::RenderPipeline,
) {
    for skinned in [false, true] {
        let slot = &mut pipelines[skinned as usize][reversed as usize];
        if draws(state, skinned) && slot.is_none() {
            *slot = Some(make(skinned));
        }
    }
}

/// The depth attachment both layers draw with: cleared to the far value of the depth test
/// (0 for reversed Z, else 1).
pub(super) fn depth_attachment(
    view: &wgpu::TextureView,
    reversed: bool,
    store: wgpu::StoreOp,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(if reversed { 0.0 } else { 1.0 }),
            store,
        }),
        stencil_ops: None,
    }
}
