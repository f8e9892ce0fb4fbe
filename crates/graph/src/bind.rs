//! Binding a plan's resources for one frame: physical textures from the pool (the same ones
//! as last time where they are free, so cached bind groups stay valid), imports, histories
//! and buffers; then the bind groups of every kept pass, from the binding slots compile
//! resolved, rebuilt only when a bound texture or buffer changed.
//!
//! Invariant: after `bind_resources`, `state.textures[r]` (`state.frame_buffers[r]`) holds
//! the texture (buffer) of every resource the plan uses this frame, and nothing else.

use crate::binding_slots::{BindingSlot, BindingSource};
use crate::compile::CompiledGraph;
use crate::declaration::{ResourceKind, ResourceOrigin};
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::history::HistoryStore;
use crate::imports::ImportTable;
use crate::plan_state::PlanState;
use crate::pool::{PoolKey, TexturePool};
use crate::resource::Extent;

/// The executor's shared resources a frame binds from.
pub(crate) struct BindSources<'a> {
    pub gpu: &'a GpuContext,
    pub pool: &'a mut TexturePool,
    pub history: &'a mut HistoryStore,
    pub imports: &'a ImportTable,
    pub frame: u64,
}

/// Binds every used resource of `plan` to a physical texture or buffer for this frame,
/// clearing invalid history textures with `encoder`.
pub(crate) fn bind_resources(
    state: &mut PlanState,
    plan: &CompiledGraph,
    output: Extent,
    src: &mut BindSources<'_>,
    encoder: &mut wgpu::CommandEncoder,
) -> GraphResult<()> {
    let device = &src.gpu.device;
    let decl = &plan.decl;
    let max_dim = device.limits().max_texture_dimension_2d;
    // Retained textures of the last frame go back first, so each slot can take its own again.
    state.release_slots(src.pool, true);
    for (s, slot) in plan.physical.iter().enumerate() {
        let extent = slot.desc.size.resolve(output);
        if extent.width > max_dim || extent.height > max_dim {
            return Err(GraphError::InvalidParameter {
                owner: "graph".into(),
                name: "output size".into(),
                value: output.to_string(),
                allowed: format!("at most {max_dim} pixels a side on this device"),
            });
        }
        let key = PoolKey {
            format: slot.desc.format,
            extent,
            mip_levels: slot.desc.mip_levels,
            usage: slot.usage,
        };
        let t = src.pool.acquire(device, key, state.serials[s]);
        state.serials[s] = t.bound.serial;
        state.slots[s] = Some(t);
    }
    // Import names resolve once per plan (again only after a new name was imported).
    src.imports.resolve(plan, &mut state.import_slots);
    state.textures.fill(None);
    state.frame_buffers.fill(None);
    state.frame_acceleration_structures.fill(None);
    for (r, res) in decl.resources.iter().enumerate() {
        if plan.lifetimes[r].is_none() {
            continue;
        }
        let desc = match &res.kind {
            ResourceKind::Texture(d) => *d,
            ResourceKind::AccelerationStructure => {
                // Imported only (the builder offers no other origin).
                state.frame_acceleration_structures[r] = Some(
                    src.imports
                        .acceleration_structure(plan.key(), &state.import_slots, r as u32, res)?
                        .clone(),
                );
                continue;
            }
            ResourceKind::Buffer(_) => {
                state.frame_buffers[r] = match res.origin {
                    ResourceOrigin::Imported => Some(
                        src.imports
                            .buffer(plan.key(), &state.import_slots, r as u32, res)?
                            .clone(),
                    ),
                    _ => state.buffers[r].clone(),
                };
                continue;
            }
        };
        let extent = desc.size.resolve(output);
        state.textures[r] = Some(match &res.origin {
            ResourceOrigin::Transient => {
                match plan.slot_of[r].and_then(|s| state.slots[s].as_ref()) {
                    Some(t) => t.bound.clone(),
                    None => continue,
                }
            }
            ResourceOrigin::Imported => src
                .imports
                .texture(
                    plan.key(),
                    &state.import_slots,
                    r as u32,
                    res,
                    &desc,
                    extent,
                    plan.usage[r],
                )?
                .clone(),
            ResourceOrigin::HistoryPrevious { .. } | ResourceOrigin::HistoryCurrent { .. } => {
                let slot = plan.history_of[r].ok_or(GraphError::Internal(
                    "a history resource without the slot compile gives every history",
                ))?;
                let key = PoolKey {
                    format: desc.format,
                    extent,
                    mip_levels: desc.mip_levels,
                    usage: plan.histories[slot].usage,
                };
                let (pair, valid) =
                    src.history
                        .prepare(device, src.pool, plan.key(), slot, key, src.frame);
                if matches!(res.origin, ResourceOrigin::HistoryPrevious { .. }) {
                    if !valid {
                        clear_texture(src.gpu, encoder, &pair.previous().bound.texture);
                    }
                    pair.previous().bound.clone()
                } else {
                    pair.current().bound.clone()
                }
            }
        });
    }
    Ok(())
}

/// Builds (or reuses) the bind groups of every kept pass for this frame's textures, walking
/// the plan's binding slots (resolved at compile: no name is compared here). In steady state,
/// when every pass gets the textures of its last frame back, nothing is allocated.
pub(crate) fn bind_groups(
    state: &mut PlanState,
    plan: &CompiledGraph,
    gpu: &GpuContext,
    scratch: &mut Vec<u64>,
) -> GraphResult<()> {
    let decl = &plan.decl;
    for p in &plan.order {
        let Some(pipeline) = &state.pipelines[p.0] else {
            continue;
        };
        let pass = &decl.passes[p.0];
        let slots = &plan.binding_slots[p.0];
        scratch.clear();
        for slot in slots {
            let key = match slot.source {
                // A buffer slot keys on the buffer's identity: an imported buffer may be
                // replaced between frames (a new scene's BVH under the same name).
                BindingSource::Buffer { resource, .. } => state.frame_buffers[resource]
                    .as_ref()
                    .map_or(0, buffer_identity),
                // Likewise an acceleration structure (a new scene's TLAS).
                BindingSource::AccelerationStructure { resource, .. } => state
                    .frame_acceleration_structures[resource]
                    .as_deref()
                    .map_or(0, buffer_identity),
                _ => slot
                    .source
                    .texture_resource()
                    .and_then(|r| state.textures[r].as_ref())
                    .map_or(0, |t| t.serial),
            };
            scratch.push(key);
        }
        if state.bind_groups[p.0]
            .as_ref()
            .is_some_and(|(k, _)| k == scratch)
        {
            continue;
        }
        let mut groups = Vec::new();
        for (g, layout) in pipeline.groups() {
            let mut entries = Vec::new();
            for slot in slots.iter().filter(|s| s.group == *g) {
                entries.push(wgpu::BindGroupEntry {
                    binding: slot.binding,
                    resource: slot_resource(state, plan, p.index(), slot)?,
                });
            }
            groups.push((
                *g,
                gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&pass.name),
                    layout,
                    entries: &entries,
                }),
            ));
        }
        state.bind_groups[p.0] = Some((scratch.clone(), groups));
    }
    Ok(())
}

/// A hash of a buffer's (or acceleration structure's) identity (wgpu orders and hashes both by
/// their id); no allocation.
fn buffer_identity(buffer: &impl std::hash::Hash) -> u64 {
    use std::hash::Hasher;
    let mut h = std::collections::hash_map::DefaultHasher::new();
    buffer.hash(&mut h);
    // Never 0, which stands for "nothing bound".
    h.finish() | 1
}

/// What `slot` of pass `p` binds this frame.
fn slot_resource<'s>(
    state: &'s PlanState,
    plan: &CompiledGraph,
    p: usize,
    slot: &BindingSlot,
) -> GraphResult<wgpu::BindingResource<'s>> {
    let missing = |resource: usize| GraphError::MissingResource {
        resource: plan.decl.resources[resource].name.clone(),
        message: format!(
            "pass `{}` binds it at @group({}) @binding({}) but nothing is bound to it this frame",
            plan.decl.passes[p].name, slot.group, slot.binding
        ),
    };
    let texture = |resource: usize| {
        state.textures[resource]
            .as_ref()
            .ok_or_else(|| missing(resource))
    };
    Ok(match slot.source {
        BindingSource::SampledTexture { resource, mip, .. } => {
            wgpu::BindingResource::TextureView(texture(resource)?.view_of(mip))
        }
        BindingSource::StorageTexture { resource, mip, .. } => {
            wgpu::BindingResource::TextureView(texture(resource)?.view_of(Some(mip)))
        }
        BindingSource::Uniform(h) => state.uniforms[h.0].as_entire_binding(),
        BindingSource::Buffer { resource, .. } => state.frame_buffers[resource]
            .as_ref()
            .ok_or_else(|| missing(resource))?
            .as_entire_binding(),
        BindingSource::AccelerationStructure { resource, .. } => {
            wgpu::BindingResource::AccelerationStructure(
                state.frame_acceleration_structures[resource]
                    .as_deref()
                    .ok_or_else(|| missing(resource))?,
            )
        }
        BindingSource::Sampler { sampler } => {
            wgpu::BindingResource::Sampler(&state.samplers[sampler])
        }
    })
}

/// Zeroes a texture: with `clear_texture` where the device has it, else by uploading zeros
/// (only on frames where a history is invalid, so the upload is rare).
fn clear_texture(gpu: &GpuContext, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture) {
    if gpu.features.contains(wgpu::Features::CLEAR_TEXTURE) {
        encoder.clear_texture(texture, &wgpu::ImageSubresourceRange::default());
        return;
    }
    for mip in 0..texture.mip_level_count() {
        let e = Extent::new(texture.width(), texture.height()).mip(mip);
        let row = e.width * crate::resource::texel_bytes(texture.format()) as u32;
        let zeros = vec![0u8; (row * e.height) as usize];
        gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: mip,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &zeros,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(e.height),
            },
            wgpu::Extent3d {
                width: e.width,
                height: e.height,
                depth_or_array_layers: 1,
            },
        );
    }
}
