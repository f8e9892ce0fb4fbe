//! Recording one pass of a bound plan: a compute dispatch, a full-screen draw with its
//! attachments' operations (load or clear, blend, depth test, read-only depth), a copy, or a
//! custom pass's own commands.
//!
//! Invariant: recording reads only what `bind` prepared for this frame (`PlanState::textures`,
//! `frame_buffers`, `bind_groups`) and creates no GPU object.

use crate::attachment::{AttachmentOps, LoadOp};
use crate::compile::CompiledGraph;
use crate::custom::PassContext;
use crate::declaration::{Dispatch, PassKind};
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::pipeline::PassPipeline;
use crate::plan_state::PlanState;
use crate::resource::{Extent, TextureAccess};
use crate::shader::ShaderLibrary;
use crate::uses::TextureUse;

/// What recording a pass needs besides the plan's state.
pub(crate) struct RecordContext<'a> {
    pub gpu: &'a GpuContext,
    pub shaders: &'a ShaderLibrary,
    pub output: Extent,
}

/// Records the pass at position `pos` of `plan`'s order. `timestamps` (a query set and the
/// index of the pass's first query) asks a compute or full-screen pass to write its begin and
/// end timestamps itself (WebGPU's only timestamps); copies and custom passes write none.
pub(crate) fn record_pass(
    ctx: &RecordContext<'_>,
    state: &PlanState,
    plan: &CompiledGraph,
    pos: usize,
    encoder: &mut wgpu::CommandEncoder,
    timestamps: Option<(&wgpu::QuerySet, u32)>,
) -> GraphResult<()> {
    let p = plan.order[pos];
    let pass = &plan.decl.passes[p.0];
    let pipeline = state.pipelines[p.0].as_deref();
    let groups = state.bind_groups[p.0]
        .as_ref()
        .map(|(_, g)| g.as_slice())
        .unwrap_or(&[]);
    let view_of = |u: &TextureUse| {
        state.textures[u.resource()]
            .as_ref()
            .map(|t| t.view_of(u.mip.or(Some(0))))
    };
    match (&pass.kind, pipeline) {
        (
            PassKind::Compute { dispatch, .. },
            Some(PassPipeline::Compute {
                pipeline,
                workgroup,
                ..
            }),
        ) => {
            let counts = match dispatch {
                Some(Dispatch::Threads { size, mip }) => {
                    let e = size.resolve(ctx.output).mip(*mip);
                    [
                        e.width.div_ceil(workgroup[0].max(1)),
                        e.height.div_ceil(workgroup[1].max(1)),
                        1,
                    ]
                }
                Some(Dispatch::Workgroups(w)) => *w,
                None => [0, 0, 0],
            };
            let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&pass.name),
                timestamp_writes: timestamps.map(|(query_set, first)| {
                    wgpu::ComputePassTimestampWrites {
                        query_set,
                        beginning_of_pass_write_index: Some(first),
                        end_of_pass_write_index: Some(first + 1),
                    }
                }),
            });
            cp.set_pipeline(pipeline);
            for (g, bg) in groups {
                cp.set_bind_group(*g, bg, &[]);
            }
            cp.dispatch_workgroups(counts[0], counts[1], counts[2]);
        }
        (PassKind::Fullscreen { .. }, Some(PassPipeline::Render { pipeline, .. })) => {
            let mut color: [Option<wgpu::RenderPassColorAttachment>; 8] = Default::default();
            let mut n_color = 0;
            let mut depth = None;
            for u in &pass.textures {
                let Some(ops) = u.attachment else { continue };
                let view = view_of(u).ok_or_else(|| GraphError::MissingResource {
                    resource: plan.decl.resources[u.resource()].name.clone(),
                    message: format!("attachment of pass `{}` not bound", pass.name),
                })?;
                match ops {
                    AttachmentOps::Color { load, .. } => {
                        let slot =
                            color
                                .get_mut(n_color)
                                .ok_or_else(|| GraphError::InvalidPass {
                                    pass: pass.name.clone(),
                                    message: "more than 8 colour attachments".into(),
                                })?;
                        *slot = Some(wgpu::RenderPassColorAttachment {
                            view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: wgpu::Operations {
                                load: match load {
                                    LoadOp::Load => wgpu::LoadOp::Load,
                                    LoadOp::Clear(c) => wgpu::LoadOp::Clear(wgpu::Color {
                                        r: c[0] as f64,
                                        g: c[1] as f64,
                                        b: c[2] as f64,
                                        a: c[3] as f64,
                                    }),
                                },
                                store: wgpu::StoreOp::Store,
                            },
                        });
                        n_color += 1;
                    }
                    AttachmentOps::Depth {
                        load, read_only, ..
                    } if depth.is_none() => {
                        // A read-only attachment has no depth operations: wgpu neither
                        // loads-and-stores it as a write nor lets the pipeline write it.
                        let depth_ops = (!read_only).then_some(wgpu::Operations {
                            load: match load {
                                LoadOp::Load => wgpu::LoadOp::Load,
                                LoadOp::Clear(d) => wgpu::LoadOp::Clear(d),
                            },
                            store: wgpu::StoreOp::Store,
                        });
                        depth = Some(wgpu::RenderPassDepthStencilAttachment {
                            view,
                            depth_ops,
                            stencil_ops: None,
                        });
                    }
                    AttachmentOps::Depth { .. } => {
                        return Err(GraphError::InvalidPass {
                            pass: pass.name.clone(),
                            message: "more than one depth attachment".into(),
                        });
                    }
                }
            }
            let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&pass.name),
                color_attachments: &color[..n_color],
                depth_stencil_attachment: depth,
                timestamp_writes: timestamps.map(|(query_set, first)| {
                    wgpu::RenderPassTimestampWrites {
                        query_set,
                        beginning_of_pass_write_index: Some(first),
                        end_of_pass_write_index: Some(first + 1),
                    }
                }),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            rp.set_pipeline(pipeline);
            for (g, bg) in groups {
                rp.set_bind_group(*g, bg, &[]);
            }
            rp.draw(0..3, 0..1);
        }
        (PassKind::Copy, _) => {
            let find = |access| {
                pass.textures
                    .iter()
                    .find(|u| u.access == access)
                    .and_then(|u| state.textures[u.resource()].as_ref())
            };
            let (Some(src), Some(dst)) =
                (find(TextureAccess::CopySrc), find(TextureAccess::CopyDst))
            else {
                return Err(GraphError::InvalidPass {
                    pass: pass.name.clone(),
                    message: "a copy pass needs one copy source and one copy destination".into(),
                });
            };
            for mip in 0..src
                .texture
                .mip_level_count()
                .min(dst.texture.mip_level_count())
            {
                let e = src.extent.mip(mip);
                encoder.copy_texture_to_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: &src.texture,
                        mip_level: mip,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::TexelCopyTextureInfo {
                        texture: &dst.texture,
                        mip_level: mip,
                        origin: wgpu::Origin3d::ZERO,
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::Extent3d {
                        width: e.width,
                        height: e.height,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        (PassKind::Custom(custom), _) => {
            let mut pc = PassContext {
                device: &ctx.gpu.device,
                queue: &ctx.gpu.queue,
                encoder,
                output: ctx.output,
                pass_name: &pass.name,
                texture_uses: &pass.textures,
                buffer_uses: &pass.buffers,
                textures: &state.textures,
                buffers: &state.frame_buffers,
                shaders: ctx.shaders,
                features: ctx.gpu.features,
            };
            custom.record(&mut pc)?;
        }
        _ => {
            return Err(GraphError::InvalidPass {
                pass: pass.name.clone(),
                message: "no pipeline could be created for this pass".into(),
            });
        }
    }
    Ok(())
}
