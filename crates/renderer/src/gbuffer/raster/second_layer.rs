//! The g-buffer's second raster pass (`gbuffer.second_layer`): the scene drawn again with the
//! first pass's uploaded meshes and instance rows, keeping per pixel the nearest surface at
//! least Δ behind the first layer (`fs_second_layer` in shaders/scene/gbuffer.wgsl).
//!
//! Invariant: it runs after `gbuffer` in the same frame (it samples that pass's linear depth),
//! so the shared GPU state exists and holds this frame's instance rows.

use aograph_frame::GBufferChannel;
use aograph_graph::{CustomPass, GraphError, GraphResult, PassContext, TextureHandle};

use super::{
    GpuState, PipelineShape, RasterSource, depth_attachment, draw_instances, ensure_pipelines,
    raster_pipeline,
};
use aograph_scene::model::Scene;

/// What `gbuffer.second_layer` adds to the shared state: the first layer's linear depth as
/// group 1, and pipelines writing one R32Float target with `fs_second_layer`.
pub(super) struct SecondLayerGpu {
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// [skinned][reversed], as `GpuState::pipelines`.
    pipelines: [[Option<wgpu::RenderPipeline>; 2]; 2],
    /// The bind group of the first layer's view it was made for.
    bind_group: Option<(wgpu::TextureView, wgpu::BindGroup)>,
}

/// The custom pass behind the g-buffer's second layer (`gbuffer.second_layer`, declared by
/// `add_gbuffer_shared` when `GBufferChannel::SecondLayerDepth` is asked for). It runs after
/// `gbuffer` in the same frame and draws with that pass's uploaded meshes and this frame's
/// instance rows; `fs_second_layer` discards every fragment less than Δ behind the first
/// layer's linear depth, so the depth test keeps the nearest surface at least Δ behind.
pub struct SecondLayerRaster {
    source: RasterSource,
    first_layer: TextureHandle,
    target: TextureHandle,
    depth: TextureHandle,
}

impl SecondLayerRaster {
    pub(in crate::gbuffer) fn new(
        source: RasterSource,
        first_layer: TextureHandle,
        target: TextureHandle,
        depth: TextureHandle,
    ) -> Self {
        Self {
            source,
            first_layer,
            target,
            depth,
        }
    }

    fn create(device: &wgpu::Device, state: &GpuState) -> SecondLayerGpu {
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gbuffer.second_layer"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("gbuffer.second_layer"),
            bind_group_layouts: &[Some(&state.layout), Some(&layout)],
            immediate_size: 0,
        });
        SecondLayerGpu {
            layout,
            pipeline_layout,
            pipelines: Default::default(),
            bind_group: None,
        }
    }
}

impl CustomPass for SecondLayerRaster {
    fn kind_name(&self) -> &str {
        "gbuffer second layer raster"
    }
    fn cache_key(&self) -> u64 {
        let s = &*self.source.scene as *const Scene as u64;
        s ^ ((self.source.reversed_z() as u64) << 62)
            ^ ((self.source.channels.depth_format as u64) << 60)
            ^ u64::from(self.source.channels.second_layer_separation().to_bits())
    }
    fn record(&self, ctx: &mut PassContext<'_>) -> GraphResult<()> {
        let mut guard = self.source.state.lock().map_err(|_| {
            GraphError::Internal("the g-buffer's state was poisoned by an earlier panic")
        })?;
        let Some(state) = guard.as_mut() else {
            return Err(GraphError::Internal(
                "the g-buffer's second layer ran before its first layer",
            ));
        };
        let frame = self.source.clock.get();
        let reversed = frame.reversed_z.unwrap_or_else(|| self.source.reversed_z());
        let mut layer = match state.second_layer.take() {
            Some(layer) => layer,
            None => Self::create(ctx.device, state),
        };
        let separation = f64::from(self.source.channels.second_layer_separation());
        let targets = [Some(wgpu::ColorTargetState {
            format: GBufferChannel::SecondLayerDepth.format(),
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let shape = PipelineShape {
            layout: &layer.pipeline_layout,
            fragment: "fs_second_layer",
            targets: &targets,
            constants: &[("SECOND_LAYER_SEPARATION", separation)],
        };
        ensure_pipelines(&mut layer.pipelines, state, reversed, |skinned| {
            raster_pipeline(
                ctx.device,
                state,
                self.source.channels,
                &shape,
                skinned,
                reversed,
            )
        });
        let first = ctx.view(self.first_layer)?.clone();
        if layer.bind_group.as_ref().is_none_or(|(v, _)| *v != first) {
            let bg = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("gbuffer.second_layer"),
                layout: &layer.layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&first),
                }],
            });
            layer.bind_group = Some((first, bg));
        }
        // The view block is the one the first pass bound (same buffer, same frame).
        let _ = ctx.buffer(self.source.view)?;
        let target = ctx.view(self.target)?.clone();
        let depth_view = ctx.view(self.depth)?.clone();
        {
            let mut rp = ctx.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("gbuffer.second_layer"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(depth_attachment(
                    &depth_view,
                    reversed,
                    wgpu::StoreOp::Discard,
                )),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if let Some((_, bg)) = &state.bind_group {
                rp.set_bind_group(0, bg, &[]);
            }
            if let Some((_, bg)) = &layer.bind_group {
                rp.set_bind_group(1, bg, &[]);
            }
            draw_instances(
                &mut rp,
                &self.source.scene,
                state,
                &layer.pipelines,
                reversed,
            );
        }
        state.second_layer = Some(layer);
        Ok(())
    }
}
