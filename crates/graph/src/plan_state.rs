//! Per-plan GPU state in the executor: pipelines (shared through the pipeline cache), samplers
//! (shared through the sampler cache), uniform and transient buffers, cached bind groups, and the physical textures a plan holds between
//! its frames. Many plans live side by side, keyed by [`PlanKey`], so switching between
//! techniques rebuilds nothing.
//!
//! Invariants:
//! - The uniform buffers hold the contents of `decl`, the last declaration executed with this
//!   plan's structure (or what `Executor::write_uniform` wrote since): a declaration with new
//!   uniform contents is written once, when it first executes.
//! - Between two frames of a plan, it holds only the physical textures of its exported
//!   resources (so `Executor::read_texture` reads what *this* plan wrote, whatever ran since);
//!   all its other textures are back in the pool for any plan to use.
//! - At most [`PlanStates::CAPACITY`] plans are kept; the least recently executed is evicted
//!   and its textures return to the pool.

use std::collections::HashMap;
use std::sync::Arc;

use crate::compile::{CompiledGraph, PlanKey};
use crate::custom::BoundTexture;
use crate::declaration::{GraphDecl, ResourceKind, ResourceOrigin};
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::imports::ImportSlots;
use crate::pipeline::{PassPipeline, PipelineCache, pipeline_key};
use crate::pool::{PooledTexture, TexturePool};
use crate::sampler::SamplerCache;

/// A pass's bind groups and the texture serials (and mips) they were made for: reused while
/// the same physical textures come back.
pub(crate) type CachedBindGroups = (Vec<u64>, Vec<(u32, wgpu::BindGroup)>);

/// GPU objects that belong to one plan.
pub(crate) struct PlanState {
    /// The declaration whose uniform contents the buffers hold.
    pub decl: Arc<GraphDecl>,
    /// Per pass (declaration order).
    pub pipelines: Vec<Option<Arc<PassPipeline>>>,
    /// Per uniform block.
    pub uniforms: Vec<wgpu::Buffer>,
    /// Per entry of `CompiledGraph::samplers`: its sampler, from the executor's cache.
    pub samplers: Vec<wgpu::Sampler>,
    /// Per resource: the graph-owned buffer of a used transient buffer.
    pub buffers: Vec<Option<wgpu::Buffer>>,
    /// Per pass.
    pub bind_groups: Vec<Option<CachedBindGroups>>,
    /// Per physical slot: the texture lent to the frame being recorded, or retained since the
    /// plan's last frame (exported slots only).
    pub slots: Vec<Option<PooledTexture>>,
    /// Per physical slot: the serial it had last time (asked for again, so bind groups hold).
    pub serials: Vec<u64>,
    /// Per physical slot: holds an exported resource, kept until the plan's next frame.
    pub retain: Vec<bool>,
    /// Per resource: the texture bound in this plan's last frame.
    pub textures: Vec<Option<BoundTexture>>,
    /// Per resource: the buffer bound in this plan's last frame.
    pub frame_buffers: Vec<Option<wgpu::Buffer>>,
    /// Per resource: the acceleration structure bound in this plan's last frame.
    pub frame_acceleration_structures: Vec<Option<Arc<wgpu::Tlas>>>,
    /// The last frame this plan executed.
    pub last_frame: Option<u64>,
    /// Its imported resources resolved to the executor's import names, once.
    pub import_slots: ImportSlots,
}

impl PlanState {
    /// Creates the state of `plan`: checks its formats on this device, takes its pipelines
    /// and samplers from the caches (creating what is missing) and makes its buffers.
    pub fn new(
        gpu: &GpuContext,
        pipelines: &mut PipelineCache,
        samplers: &mut SamplerCache,
        plan: &CompiledGraph,
    ) -> GraphResult<Self> {
        let device = &gpu.device;
        let decl = &plan.decl;
        // A format the device cannot use as declared (e.g. r16float storage without the
        // adapter's format features) is an error naming the texture, not a validation error.
        for slot in &plan.physical {
            if !gpu.supports(slot.desc.format, slot.usage) {
                let resource = slot
                    .resources
                    .iter()
                    .map(|r| decl.resources[*r].name.as_str())
                    .collect::<Vec<_>>()
                    .join("`, `");
                return Err(GraphError::UnsupportedFormat {
                    resource,
                    format: slot.desc.format,
                    usage: format!("{:?}", slot.usage),
                    device: gpu.describe(),
                });
            }
        }
        let pipelines = decl
            .passes
            .iter()
            .enumerate()
            .map(|(i, pass)| {
                let info = plan.shaders[i].as_ref()?;
                let slots = &plan.binding_slots[i];
                let key = pipeline_key(gpu.features, decl, pass, info, slots, &plan.samplers)?;
                Some(pipelines.get(device, &key, info, &pass.name))
            })
            .collect();
        let samplers = plan
            .samplers
            .iter()
            .map(|d| samplers.get(device, *d))
            .collect();
        let uniforms = decl
            .uniforms
            .iter()
            .map(|u| {
                let size = (u.initial.len() as u64).max(16).next_multiple_of(16);
                let b = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&u.binding),
                    size,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                gpu.queue.write_buffer(&b, 0, &u.initial);
                b
            })
            .collect();
        let buffers = decl
            .resources
            .iter()
            .enumerate()
            .map(|(r, res)| match (&res.kind, &res.origin) {
                (ResourceKind::Buffer(d), ResourceOrigin::Transient)
                    if plan.lifetimes[r].is_some() =>
                {
                    let usage = decl
                        .passes
                        .iter()
                        .flat_map(|p| p.buffers.iter())
                        .filter(|u| u.read.or(u.written).is_some_and(|h| h.id as usize == r))
                        .fold(wgpu::BufferUsages::COPY_SRC, |acc, u| {
                            acc | u.access.usage()
                        });
                    Some(device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(&res.name),
                        size: d.size.max(4),
                        usage,
                        mapped_at_creation: false,
                    }))
                }
                _ => None,
            })
            .collect();
        let errors = gpu.take_errors();
        if !errors.is_empty() {
            return Err(GraphError::Device {
                during: "creating a plan's textures and buffers",
                message: errors.join("; "),
            });
        }
        let retain = plan
            .physical
            .iter()
            .map(|s| s.resources.iter().any(|r| decl.resources[*r].exported))
            .collect();
        let n = decl.resources.len();
        Ok(Self {
            decl: decl.clone(),
            pipelines,
            uniforms,
            samplers,
            buffers,
            bind_groups: (0..decl.passes.len()).map(|_| None).collect(),
            slots: (0..plan.physical.len()).map(|_| None).collect(),
            serials: vec![0; plan.physical.len()],
            retain,
            textures: vec![None; n],
            frame_buffers: vec![None; n],
            frame_acceleration_structures: vec![None; n],
            last_frame: None,
            import_slots: ImportSlots::default(),
        })
    }

    /// Takes `plan`'s declaration as current: when it is another declaration than the one
    /// the buffers hold (same structure, maybe other parameter values), its uniform contents
    /// are written.
    pub fn adopt(&mut self, queue: &wgpu::Queue, plan: &CompiledGraph) {
        if Arc::ptr_eq(&self.decl, &plan.decl) {
            return;
        }
        for (buffer, u) in self.uniforms.iter().zip(&plan.decl.uniforms) {
            queue.write_buffer(buffer, 0, &u.initial);
        }
        self.decl = plan.decl.clone();
    }

    /// Returns the textures of every slot (`all`) or of the slots not retained to the pool.
    pub fn release_slots(&mut self, pool: &mut TexturePool, all: bool) {
        for (s, slot) in self.slots.iter_mut().enumerate() {
            if all || !self.retain[s] {
                if let Some(t) = slot.take() {
                    pool.release(t);
                }
            }
        }
    }
}

/// The executor's plan states, bounded (see the module invariants).
#[derive(Default)]
pub(crate) struct PlanStates {
    plans: HashMap<PlanKey, PlanState>,
}

impl PlanStates {
    /// Plans kept at once: every technique and preset a session alternates between, with room.
    pub const CAPACITY: usize = 16;

    pub fn get(&self, key: PlanKey) -> Option<&PlanState> {
        self.plans.get(&key)
    }
    pub fn get_mut(&mut self, key: PlanKey) -> Option<&mut PlanState> {
        self.plans.get_mut(&key)
    }
    /// Inserts a new state, first evicting the least recently executed plan when full.
    pub fn insert(&mut self, key: PlanKey, state: PlanState, pool: &mut TexturePool) {
        if self.plans.len() >= Self::CAPACITY {
            let oldest = self
                .plans
                .iter()
                .min_by_key(|(_, s)| s.last_frame.map_or(0, |f| f + 1))
                .map(|(k, _)| *k);
            if let Some(mut evicted) = oldest.and_then(|k| self.plans.remove(&k)) {
                evicted.release_slots(pool, true);
            }
        }
        self.plans.insert(key, state);
    }
    pub fn len(&self) -> usize {
        self.plans.len()
    }
}
