//! Execute phase: the executor runs compiled plans on a device, many plans side by side.
//!
//! Per frame: harvest finished timings (never waiting), take the plan's state (made once per
//! plan, its pipelines shared through the cache), bind its resources for this frame (pool,
//! imports, histories), record every kept pass, submit, and start the read-back of its
//! timestamps. Nothing in `execute` waits for the GPU, except in the opt-in
//! [`TimingMode::CpuWall`]. [`Executor::encode`] records the same frame into an application's
//! own command encoder instead, untimed and unsubmitted.
//!
//! Invariants: a plan's exported resources stay readable (with [`Executor::read_texture`],
//! naming the plan) until that plan executes again or is evicted, whatever other plans run in
//! between; a history is valid only when its plan wrote it in the immediately preceding frame
//! (see `history.rs`); steady-state frames of a cached plan allocate nothing on the heap in
//! the executor itself.

mod import_bindings;

use std::sync::Arc;
use std::time::Instant;

use crate::bind::{BindSources, bind_groups, bind_resources};
use crate::compile::CompiledGraph;
use crate::declaration::{ResourceOrigin, UniformHandle};
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::history::HistoryStore;
use crate::imports::ImportTable;
use crate::name_lookups::count_name_lookup;
use crate::pipeline::PipelineCache;
use crate::plan_state::{PlanState, PlanStates};
use crate::pool::{PoolKey, TexturePool};
use crate::readback::{TextureReadback, read_texture};
use crate::record::{RecordContext, record_pass};
use crate::resource::{Extent, TextureHandle};
use crate::sampler::SamplerCache;
use crate::shader::ShaderLibrary;
use crate::timing::{FrameId, PassTimings, TimestampRing, TimingMode, TimingSource};

/// Runs compiled plans on a device.
pub struct Executor {
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    pool: TexturePool,
    history: HistoryStore,
    imports: ImportTable,
    pipelines: PipelineCache,
    plans: PlanStates,
    /// One sampler per distinct `SamplerDesc` any plan has bound.
    samplers: SamplerCache,
    timing: TimingMode,
    ring: TimestampRing,
    /// A frame recorded into a caller's encoder with timestamps ([`Executor::encode`]): its
    /// read-back is mapped when the next frame begins, by which time the caller has submitted
    /// it (`encode`'s contract).
    unsubmitted: Option<(usize, FrameId, Arc<CompiledGraph>)>,
    /// CPU-wall milliseconds of the frame being recorded.
    pass_ms: Vec<f64>,
    /// Bind-group cache keys, reused every frame.
    scratch: Vec<u64>,
    /// Frames executed so far: the next frame's number.
    frames: u64,
}

impl Executor {
    /// An executor whose custom passes load shaders from `shaders`.
    pub fn with_shaders(gpu: Arc<GpuContext>, shaders: Arc<ShaderLibrary>) -> Self {
        let mut e = Self::new(gpu);
        e.shaders = shaders;
        e
    }

    /// An executor timing passes with GPU timestamps where the device has them, and not at
    /// all otherwise (see [`Executor::set_timing`]).
    pub fn new(gpu: Arc<GpuContext>) -> Self {
        let ring = TimestampRing::new(&gpu.queue, TimestampRing::DEFAULT_PENDING_FRAMES);
        let timing = if gpu.has_timestamps() {
            TimingMode::GpuTimestamps
        } else {
            TimingMode::Off
        };
        Self {
            gpu,
            shaders: Arc::new(ShaderLibrary::inline_only()),
            pool: TexturePool::default(),
            history: HistoryStore::default(),
            imports: ImportTable::default(),
            pipelines: PipelineCache::default(),
            plans: PlanStates::default(),
            samplers: SamplerCache::default(),
            timing,
            ring,
            unsubmitted: None,
            pass_ms: Vec::new(),
            scratch: Vec::new(),
            frames: 0,
        }
    }

    /// The device context the executor records and submits on.
    pub fn gpu(&self) -> &Arc<GpuContext> {
        &self.gpu
    }
    /// How passes are timed from the next frame on. `GpuTimestamps` on a device without
    /// timestamp queries is an error naming the alternatives.
    pub fn set_timing(&mut self, mode: TimingMode) -> GraphResult<()> {
        if mode == TimingMode::GpuTimestamps && !self.gpu.has_timestamps() {
            return Err(GraphError::InvalidParameter {
                owner: "executor".into(),
                name: "timing".into(),
                value: "GpuTimestamps".into(),
                allowed: format!(
                    "Off or CpuWall on this device ({}), which has no timestamp queries",
                    self.gpu.describe()
                ),
            });
        }
        self.timing = mode;
        Ok(())
    }
    /// How many frames may wait for their timestamps at once (default 3, at least 1); a
    /// frame executed while all are waiting goes untimed ([`Executor::dropped_timings`]).
    /// Discards timings not yet harvested.
    pub fn set_pending_timing_frames(&mut self, frames: usize) {
        self.ring = TimestampRing::new(&self.gpu.queue, frames);
        self.unsubmitted = None;
    }
    /// How passes are timed now (see [`Executor::set_timing`]).
    pub fn timing(&self) -> TimingMode {
        self.timing
    }
    /// Where the next frame's milliseconds will come from (`None` with timing off).
    pub fn timing_source(&self) -> Option<TimingSource> {
        match self.timing {
            TimingMode::Off => None,
            TimingMode::GpuTimestamps => Some(TimingSource::GpuTimestamps),
            TimingMode::CpuWall => Some(TimingSource::CpuWall),
        }
    }
    /// Invalidates every history: the next frame reads zeros with `valid == false` (a cut).
    pub fn reset_history(&mut self) {
        self.history.reset();
    }
    fn history_key(plan: &CompiledGraph, slot: usize, output: Extent) -> Option<PoolKey> {
        let desc = plan.decl.resources[plan.histories[slot].current].texture_desc()?;
        Some(PoolKey {
            format: desc.format,
            extent: desc.size.resolve(output),
            mip_levels: desc.mip_levels,
            usage: wgpu::TextureUsages::empty(),
        })
    }
    /// Whether history `name` will hold a valid previous value in the next frame of `plan` at
    /// output size `output`: false on the plan's first frame, after a resize or format change,
    /// after a reset, and when another plan ran since this plan's last frame.
    /// (A query by name, for tests and tools; a frame uses [`Executor::all_history_valid`].)
    pub fn history_valid(&self, plan: &CompiledGraph, name: &str, output: Extent) -> bool {
        plan.histories
            .iter()
            .position(|h| {
                count_name_lookup();
                h.name == name
            })
            .is_some_and(|slot| self.history_slot_valid(plan, slot, output))
    }
    fn history_slot_valid(&self, plan: &CompiledGraph, slot: usize, output: Extent) -> bool {
        Self::history_key(plan, slot, output)
            .is_some_and(|key| self.history.is_valid(plan.key(), slot, &key, self.frames))
    }
    /// Whether every history of `plan` will be valid in its next frame at `output` (what a
    /// technique with one history writes into the view block's `frame.y`).
    pub fn all_history_valid(&self, plan: &CompiledGraph, output: Extent) -> bool {
        (0..plan.histories.len()).all(|slot| self.history_slot_valid(plan, slot, output))
    }
    /// Textures the pool holds (lent to frames, retained by plans, or free). History and
    /// imported textures are not counted.
    pub fn pool_texture_count(&self) -> usize {
        self.pool.texture_count() - self.history.texture_count()
    }
    /// Textures the pool has created since the executor was made (histories included).
    pub fn pool_created_count(&self) -> u64 {
        self.pool.created_count()
    }
    /// Textures the executor holds in all: pool plus history.
    pub fn texture_count(&self) -> usize {
        self.pool.texture_count()
    }
    /// Pipelines created since the executor was made (a cache hit creates none).
    pub fn pipeline_created_count(&self) -> u64 {
        self.pipelines.created()
    }
    /// Pipelines held in the cache now.
    pub fn pipeline_count(&self) -> usize {
        self.pipelines.len()
    }
    /// Samplers the executor has created: one per distinct [`SamplerDesc`] its plans bind,
    /// however many plans and frames bind it.
    ///
    /// [`SamplerDesc`]: crate::SamplerDesc
    pub fn sampler_count(&self) -> usize {
        self.samplers.len()
    }
    /// Plans whose state the executor holds now.
    pub fn plan_count(&self) -> usize {
        self.plans.len()
    }
    /// The number the next executed frame will get.
    pub fn next_frame(&self) -> FrameId {
        FrameId(self.frames)
    }

    /// Sets the contents of a uniform block of `plan`; takes effect at the plan's next frame.
    pub fn write_uniform(
        &mut self,
        plan: &CompiledGraph,
        handle: UniformHandle,
        bytes: &[u8],
    ) -> GraphResult<()> {
        let decl = plan
            .decl
            .uniforms
            .get(handle.0)
            .ok_or_else(|| GraphError::MissingResource {
                resource: format!("uniform #{}", handle.0),
                message: "not declared in this plan".into(),
            })?;
        if decl.initial.len() != bytes.len() {
            return Err(GraphError::InvalidParameter {
                owner: plan.decl.passes[decl.pass.0].name.clone(),
                name: decl.binding.clone(),
                value: format!("{} bytes", bytes.len()),
                allowed: format!("exactly {} bytes, as declared", decl.initial.len()),
            });
        }
        let queue = self.gpu.queue.clone();
        let state = self.ensure_state(plan)?;
        queue.write_buffer(&state.uniforms[handle.0], 0, bytes);
        Ok(())
    }

    /// The state of `plan`, made on its first use; its uniforms follow `plan`'s declaration.
    fn ensure_state(&mut self, plan: &CompiledGraph) -> GraphResult<&mut PlanState> {
        let key = plan.key();
        if self.plans.get(key).is_none() {
            let state = PlanState::new(&self.gpu, &mut self.pipelines, &mut self.samplers, plan)?;
            self.plans.insert(key, state, &mut self.pool);
        }
        let state = self.plans.get_mut(key).ok_or(GraphError::Internal(
            "a plan's state vanished between its lookup and its use",
        ))?;
        state.adopt(&self.gpu.queue, plan);
        Ok(state)
    }

    /// Makes `plan`'s state ahead of its first frame: every pass's pipeline (shared with other
    /// plans where the key matches) and sampler, so the frame that first runs it creates none.
    /// Textures are still taken from the pool at that frame (they depend on its size).
    pub fn prepare(&mut self, plan: &CompiledGraph) -> GraphResult<()> {
        self.ensure_state(plan).map(|_| ())
    }

    /// Runs one frame of `plan` at output size `output` and returns its number, which its
    /// timings carry when they arrive. Returns without waiting for the GPU.
    pub fn execute(&mut self, plan: &Arc<CompiledGraph>, output: Extent) -> GraphResult<FrameId> {
        let frame = self.begin_frame(plan, output)?;
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("aograph frame"),
            });
        let timing = self.timing;
        let slot = self.record_frame(plan, output, frame, &mut encoder, timing)?;
        let n = plan.order.len() as u32;
        if let Some(s) = slot {
            self.ring.resolve(&mut encoder, s, n);
        }
        self.gpu.queue.submit([encoder.finish()]);
        match (slot, timing) {
            (Some(s), _) => self.ring.submitted(s, frame, plan),
            (None, TimingMode::CpuWall) => self.ring.record_cpu(frame, plan, &self.pass_ms),
            _ => {}
        }
        self.end_frame(plan, frame)
    }

    /// Records one frame of `plan` at output size `output` into the caller's `encoder`, for an
    /// application that owns its frame's command buffer (the embedding API): nothing is
    /// submitted and nothing waits. Uniforms and imports written for this frame go through the
    /// queue, so submit `encoder` before the next `encode` or `execute`. With
    /// `TimingMode::GpuTimestamps` the frame is timed: its timestamps are resolved into
    /// `encoder` and read back once the next frame has begun (so they arrive one frame later
    /// than `execute`'s); `CpuWall`, which must submit between passes, leaves it untimed.
    pub fn encode(
        &mut self,
        plan: &Arc<CompiledGraph>,
        output: Extent,
        encoder: &mut wgpu::CommandEncoder,
    ) -> GraphResult<FrameId> {
        let frame = self.begin_frame(plan, output)?;
        let timing = match self.timing {
            TimingMode::GpuTimestamps => TimingMode::GpuTimestamps,
            _ => TimingMode::Off,
        };
        let slot = self.record_frame(plan, output, frame, encoder, timing)?;
        if let Some(s) = slot {
            self.ring.resolve(encoder, s, plan.order.len() as u32);
            self.unsubmitted = Some((s, frame, plan.clone()));
        }
        self.end_frame(plan, frame)
    }

    /// Checks the size, harvests finished timings (no wait) and makes the plan's state.
    fn begin_frame(&mut self, plan: &Arc<CompiledGraph>, output: Extent) -> GraphResult<FrameId> {
        if output.width == 0 || output.height == 0 {
            return Err(GraphError::InvalidParameter {
                owner: "graph".into(),
                name: "output size".into(),
                value: output.to_string(),
                allowed: "width and height of at least 1 pixel".into(),
            });
        }
        // The previous `encode`'s frame has been submitted by now: read its timestamps back.
        if let Some((slot, frame, plan)) = self.unsubmitted.take() {
            self.ring.submitted(slot, frame, &plan);
        }
        // Run whatever map callbacks are due (no wait), then take finished timings.
        if self.timing == TimingMode::GpuTimestamps {
            let _ = self.gpu.device.poll(wgpu::PollType::Poll);
            self.ring.harvest()?;
        }
        self.ensure_state(plan)?;
        Ok(FrameId(self.frames))
    }

    /// Binds the plan's resources for `frame` and records every kept pass into `encoder`,
    /// timed as `timing` says; returns the timestamp slot to resolve, if any. On an error the
    /// frame's slots are released and nothing is left half-bound.
    fn record_frame(
        &mut self,
        plan: &Arc<CompiledGraph>,
        output: Extent,
        frame: FrameId,
        encoder: &mut wgpu::CommandEncoder,
        timing: TimingMode,
    ) -> GraphResult<Option<usize>> {
        let device = self.gpu.device.clone();
        let Self {
            gpu,
            shaders,
            pool,
            history,
            imports,
            plans,
            ring,
            pass_ms,
            scratch,
            ..
        } = self;
        let key = plan.key();
        let state = plans.get_mut(key).ok_or(GraphError::Internal(
            "a plan's state vanished between its lookup and its use",
        ))?;
        let mut sources = BindSources {
            gpu,
            pool,
            history,
            imports,
            frame: frame.0,
        };
        bind_resources(state, plan, output, &mut sources, encoder)?;
        bind_groups(state, plan, gpu, scratch)?;

        let n = plan.order.len() as u32;
        let slot = match timing {
            TimingMode::GpuTimestamps => ring.begin(&device, n),
            _ => None,
        };
        pass_ms.clear();
        let ctx = RecordContext {
            gpu,
            shaders,
            output,
        };
        // Debug groups only where the driver survives them (see `GpuContext::debug_groups`).
        let debug_groups = gpu.debug_groups();
        let inside_encoders = gpu
            .features
            .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS);
        let recorded = (|| -> GraphResult<()> {
            for pos in 0..plan.order.len() {
                // Read only in CPU wall-time mode (std's clock does not exist on wasm32, where
                // that mode cannot wait for the GPU anyway).
                let started = (timing == TimingMode::CpuWall).then(Instant::now);
                if debug_groups {
                    encoder.push_debug_group(&plan.decl.passes[plan.order[pos].0].name);
                }
                // Timestamps between commands where the device has them; otherwise (WebGPU)
                // at the boundaries of the pass itself, which copies and custom passes lack.
                let in_pass = match slot {
                    Some(s) if !inside_encoders => Some((ring.query_set(s), 2 * pos as u32)),
                    _ => None,
                };
                if let (Some(s), true) = (slot, inside_encoders) {
                    encoder.write_timestamp(ring.query_set(s), 2 * pos as u32);
                }
                record_pass(&ctx, state, plan, pos, encoder, in_pass)?;
                if let (Some(s), true) = (slot, inside_encoders) {
                    encoder.write_timestamp(ring.query_set(s), 2 * pos as u32 + 1);
                }
                if debug_groups {
                    encoder.pop_debug_group();
                }
                if timing == TimingMode::CpuWall {
                    let done = std::mem::replace(
                        encoder,
                        device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                            label: Some("aograph frame"),
                        }),
                    );
                    gpu.queue.submit([done.finish()]);
                    gpu.wait_idle()?;
                    let ms = started.map_or(0.0, |s| s.elapsed().as_secs_f64() * 1000.0);
                    pass_ms.push(ms);
                }
            }
            Ok(())
        })();
        if let Err(e) = recorded {
            if let Some(s) = slot {
                ring.abandon(s);
            }
            state.release_slots(pool, false);
            return Err(e);
        }
        Ok(slot)
    }

    /// Retires a recorded frame: histories swap, textures not retained go back to the pool,
    /// and validation errors raised meanwhile become the frame's error.
    fn end_frame(&mut self, plan: &Arc<CompiledGraph>, frame: FrameId) -> GraphResult<FrameId> {
        let key = plan.key();
        let written =
            (plan.histories.iter().enumerate()).filter_map(|(s, h)| h.written.then_some(s));
        self.history.end_frame(key, written, frame.0);
        let state = self.plans.get_mut(key).ok_or(GraphError::Internal(
            "a plan's state vanished between its lookup and its use",
        ))?;
        state.release_slots(&mut self.pool, false);
        state.last_frame = Some(frame.0);
        self.history.evict_idle(&mut self.pool, frame.0);
        self.pool.end_frame();
        self.frames += 1;
        let errors = self.gpu.take_errors();
        if !errors.is_empty() {
            return Err(GraphError::Device {
                during: "executing a frame",
                message: errors.join("; "),
            });
        }
        Ok(frame)
    }

    /// The newest frame's per-pass milliseconds that have arrived, without waiting: with GPU
    /// timestamps, a frame's timings arrive a few frames after it was executed (their `frame`
    /// says which); empty before the first arrives or with timing off.
    pub fn latest_timings(&mut self) -> GraphResult<&PassTimings> {
        if self.timing == TimingMode::GpuTimestamps {
            let _ = self.gpu.device.poll(wgpu::PollType::Poll);
            self.ring.harvest()?;
        }
        Ok(self.ring.latest())
    }

    /// Waits until the timings of every frame executed so far have arrived (or were dropped)
    /// and returns the newest. This blocks on the GPU: for benchmarks and one-shot tools, not
    /// for a real-time loop (use [`Executor::latest_timings`] there).
    pub fn wait_timings(&mut self) -> GraphResult<&PassTimings> {
        if self.frames > 0 && self.timing == TimingMode::GpuTimestamps {
            self.ring
                .wait_for(&self.gpu.device, FrameId(self.frames - 1))?;
        }
        Ok(self.ring.latest())
    }

    /// Frames whose timings were not recorded because every pending slot was still waiting
    /// for the GPU (the executor drops timings rather than stall).
    pub fn dropped_timings(&self) -> u64 {
        self.ring.dropped()
    }
    /// Frames whose timings are on their way.
    pub fn pending_timings(&self) -> usize {
        self.ring.pending()
    }

    /// Reads an exported, imported or history texture of `plan`'s last frame back to the CPU
    /// (mip 0). Blocks until the GPU has written it.
    pub fn read_texture(
        &self,
        plan: &CompiledGraph,
        handle: TextureHandle,
    ) -> GraphResult<TextureReadback> {
        self.read_texture_mip(plan, handle, 0)
    }

    /// Reads one mip level of an exported, imported or history texture of `plan`'s last frame.
    pub fn read_texture_mip(
        &self,
        plan: &CompiledGraph,
        handle: TextureHandle,
        mip: u32,
    ) -> GraphResult<TextureReadback> {
        let r = handle.id as usize;
        let res = plan
            .decl
            .resources
            .get(r)
            .ok_or_else(|| GraphError::MissingResource {
                resource: format!("{handle:?}"),
                message: "not a resource of this plan".into(),
            })?;
        let readable = res.exported || !matches!(res.origin, ResourceOrigin::Transient);
        if !readable {
            return Err(GraphError::MissingResource {
                resource: res.name.clone(),
                message: "only exported, imported and history textures can be read back; call \
                          GraphBuilder::export on it"
                    .into(),
            });
        }
        let not_run = || GraphError::MissingResource {
            resource: res.name.clone(),
            message: "this plan has not executed on this executor (or was evicted since)".into(),
        };
        let state = self.plans.get(plan.key()).ok_or_else(not_run)?;
        let last = state.last_frame.ok_or_else(not_run)?;
        if let Some(slot) = plan.history_of[r] {
            if !self.history.holds_frame(plan.key(), slot, last) {
                return Err(GraphError::MissingResource {
                    resource: res.name.clone(),
                    message: "the history was evicted or rebound since this plan's last frame"
                        .into(),
                });
            }
        }
        let t = state
            .textures
            .get(r)
            .and_then(Option::as_ref)
            .ok_or_else(|| GraphError::MissingResource {
                resource: res.name.clone(),
                message: "not produced by the plan's last frame (was it culled?)".into(),
            })?;
        read_texture(&self.gpu.device, &self.gpu.queue, &t.texture, mip)
    }
}
