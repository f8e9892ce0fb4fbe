//! Execute phase: binds a compiled plan to physical resources and records it on wgpu.
//!
//! Per frame: release last frame's textures to the pool and take the plan's physical textures
//! back (in the same order, so the same textures and cached bind groups come back), bind
//! imports and histories, then record every kept pass inside a debug group between two
//! timestamps, submit, and read the timestamps back on the next frame. Invariant: after
//! `execute`, exported and history resources stay readable until the next `execute`.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::Instant;

use crate::compile::CompiledGraph;
use crate::custom::{BoundTexture, PassContext};
use crate::declaration::{PassKind, ResourceKind, ResourceOrigin, UniformHandle};
use crate::error::{GraphError, GraphResult};
use crate::gpu::GpuContext;
use crate::history::HistoryStore;
use crate::pipeline::{PassPipeline, create_pipeline};
use crate::pool::{PoolKey, PooledTexture, TexturePool};
use crate::readback::{TextureReadback, read_texture};
use crate::resource::{Extent, TextureAccess, TextureHandle};
use crate::shader::{ShaderBindingKind, ShaderLibrary};
use crate::timing::{PassTimings, TimestampQueries, TimingSource};

/// GPU objects that belong to one plan: pipelines, uniform buffers, transient buffers and
/// cached bind groups.
struct PlanState {
    hash: u64,
    pipelines: Vec<Option<PassPipeline>>,
    uniforms: Vec<wgpu::Buffer>,
    buffers: Vec<Option<wgpu::Buffer>>,
    bind_groups: Vec<Option<CachedBindGroups>>,
}

/// A pass's bind groups and the texture serials (and mips) they were made for: reused while
/// the same physical textures come back.
type CachedBindGroups = (Vec<u64>, Vec<(u32, wgpu::BindGroup)>);

/// Runs compiled plans on a device.
pub struct Executor {
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    pool: TexturePool,
    history: HistoryStore,
    imports: HashMap<String, BoundTexture>,
    import_buffers: HashMap<String, wgpu::Buffer>,
    state: Option<PlanState>,
    linear: wgpu::Sampler,
    nearest: wgpu::Sampler,
    lent: Vec<PooledTexture>,
    frame: Vec<Option<BoundTexture>>,
    frame_buffers: Vec<Option<wgpu::Buffer>>,
    output: Extent,
    timestamps: Option<TimestampQueries>,
    force_cpu_timing: bool,
    pass_ms: Vec<f64>,
    timings: PassTimings,
    timed_plan: Option<Arc<CompiledGraph>>,
    scratch: Vec<u64>,
    frames: u64,
}

impl Executor {
    /// An executor whose custom passes load shaders from `shaders`.
    pub fn with_shaders(gpu: Arc<GpuContext>, shaders: Arc<ShaderLibrary>) -> Self {
        let mut e = Self::new(gpu);
        e.shaders = shaders;
        e
    }

    pub fn new(gpu: Arc<GpuContext>) -> Self {
        let sampler = |filter| {
            gpu.device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("aograph sampler"),
                mag_filter: filter,
                min_filter: filter,
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                ..Default::default()
            })
        };
        let (linear, nearest) = (
            sampler(wgpu::FilterMode::Linear),
            sampler(wgpu::FilterMode::Nearest),
        );
        Self {
            gpu,
            shaders: Arc::new(ShaderLibrary::inline_only()),
            pool: TexturePool::default(),
            history: HistoryStore::default(),
            imports: HashMap::new(),
            import_buffers: HashMap::new(),
            state: None,
            linear,
            nearest,
            lent: Vec::new(),
            frame: Vec::new(),
            frame_buffers: Vec::new(),
            output: Extent::new(1, 1),
            timestamps: None,
            force_cpu_timing: false,
            pass_ms: Vec::new(),
            timings: PassTimings::default(),
            timed_plan: None,
            scratch: Vec::new(),
            frames: 0,
        }
    }

    pub fn gpu(&self) -> &Arc<GpuContext> {
        &self.gpu
    }
    /// Measure CPU wall time per pass (submit and wait per pass) even where timestamps exist.
    pub fn force_cpu_timing(&mut self, on: bool) {
        self.force_cpu_timing = on;
    }
    /// Which timing source the next frame will use.
    pub fn timing_source(&self) -> TimingSource {
        if self.gpu.has_timestamps() && !self.force_cpu_timing {
            TimingSource::GpuTimestamps
        } else {
            TimingSource::CpuWall
        }
    }
    /// Provides the texture behind imported resource `name`.
    pub fn import_texture(&mut self, name: &str, texture: wgpu::Texture) {
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let mip_views: Arc<[wgpu::TextureView]> = (0..texture.mip_level_count())
            .map(|m| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: m,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let extent = Extent::new(texture.width(), texture.height());
        let serial = self.pool.next_serial();
        self.imports.insert(
            name.to_string(),
            BoundTexture {
                texture,
                view,
                mip_views,
                extent,
                serial,
            },
        );
    }
    /// Provides the buffer behind imported buffer `name`.
    pub fn import_buffer(&mut self, name: &str, buffer: wgpu::Buffer) {
        self.import_buffers.insert(name.to_string(), buffer);
    }
    /// Invalidates every history: the next frame reads zeros with `valid == false` (a cut).
    pub fn reset_history(&mut self) {
        self.history.reset();
    }
    /// Whether history `name` will hold a valid previous value in the next frame of `plan` at
    /// output size `output` (false on the first frame, after a resize or format change, after
    /// a reset).
    pub fn history_valid(&self, plan: &CompiledGraph, name: &str, output: Extent) -> bool {
        let Some(r) = plan.decl.resources.iter().find(
            |r| matches!(&r.origin, ResourceOrigin::HistoryCurrent { history } if history == name),
        ) else {
            return false;
        };
        let Some(desc) = r.texture_desc() else {
            return false;
        };
        let key = PoolKey {
            format: desc.format,
            extent: desc.size.resolve(output),
            mip_levels: desc.mip_levels,
            usage: wgpu::TextureUsages::empty(),
        };
        self.history.is_valid(name, &key)
    }
    /// Whether every history of `plan` will be valid in its next frame at `output` (what a
    /// technique with one history writes into the view block's `frame.y`).
    pub fn all_history_valid(&self, plan: &CompiledGraph, output: Extent) -> bool {
        plan.decl.resources.iter().all(|r| match &r.origin {
            ResourceOrigin::HistoryCurrent { history } => self.history_valid(plan, history, output),
            _ => true,
        })
    }
    /// Textures the pool holds (lent to the current frame or free). History and imported
    /// textures are not counted.
    pub fn pool_texture_count(&self) -> usize {
        self.pool.texture_count()
    }
    /// Textures the pool has created since the executor was made.
    pub fn pool_created_count(&self) -> u64 {
        self.pool.created_count()
    }
    /// Textures the executor holds in all: pool plus history.
    pub fn texture_count(&self) -> usize {
        self.pool.texture_count() + self.history.texture_count()
    }

    /// Sets the contents of a uniform block of `plan`; takes effect at the next `execute`.
    pub fn write_uniform(
        &mut self,
        plan: &CompiledGraph,
        handle: UniformHandle,
        bytes: &[u8],
    ) -> GraphResult<()> {
        self.ensure_state(plan)?;
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
        if let Some(state) = &self.state {
            self.gpu
                .queue
                .write_buffer(&state.uniforms[handle.0], 0, bytes);
        }
        Ok(())
    }

    fn ensure_state(&mut self, plan: &CompiledGraph) -> GraphResult<()> {
        if self.state.as_ref().is_some_and(|s| s.hash == plan.hash) {
            return Ok(());
        }
        let device = &self.gpu.device;
        let decl = &plan.decl;
        // A format the device cannot use as declared (e.g. r16float storage without the
        // adapter's format features) is an error naming the texture, not a validation error.
        for slot in &plan.physical {
            if !self.gpu.supports(slot.desc.format, slot.usage) {
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
                    device: self.gpu.describe(),
                });
            }
        }
        let mut pipelines = Vec::with_capacity(decl.passes.len());
        for (i, pass) in decl.passes.iter().enumerate() {
            pipelines.push(
                plan.shaders[i]
                    .as_ref()
                    .and_then(|info| create_pipeline(device, self.gpu.features, decl, pass, info)),
            );
        }
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
                self.gpu.queue.write_buffer(&b, 0, &u.initial);
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
        let errors = self.gpu.take_errors();
        if !errors.is_empty() {
            return Err(GraphError::Gpu(errors.join("; ")));
        }
        self.state = Some(PlanState {
            hash: plan.hash,
            pipelines,
            uniforms,
            buffers,
            bind_groups: (0..decl.passes.len()).map(|_| None).collect(),
        });
        Ok(())
    }

    /// Binds every used resource of `plan` to a physical texture or buffer for this frame.
    fn bind_resources(
        &mut self,
        plan: &CompiledGraph,
        output: Extent,
        encoder: &mut wgpu::CommandEncoder,
    ) -> GraphResult<()> {
        let device = &self.gpu.device;
        let decl = &plan.decl;
        while let Some(t) = self.lent.pop() {
            self.pool.release(t);
        }
        let max_dim = device.limits().max_texture_dimension_2d;
        for slot in &plan.physical {
            let extent = slot.desc.size.resolve(output);
            if extent.width > max_dim || extent.height > max_dim {
                return Err(GraphError::InvalidParameter {
                    owner: "graph".into(),
                    name: "output size".into(),
                    value: output.to_string(),
                    allowed: format!("at most {max_dim} pixels a side on this device"),
                });
            }
            self.lent.push(self.pool.acquire(
                device,
                PoolKey {
                    format: slot.desc.format,
                    extent,
                    mip_levels: slot.desc.mip_levels,
                    usage: slot.usage,
                },
            ));
        }
        // Released last-slot-first above, so each slot pops the texture it had last frame and
        // cached bind groups stay valid.
        self.frame.clear();
        self.frame.resize(decl.resources.len(), None);
        self.frame_buffers.clear();
        self.frame_buffers.resize(decl.resources.len(), None);
        for (r, res) in decl.resources.iter().enumerate() {
            if plan.lifetimes[r].is_none() {
                continue;
            }
            let desc = match &res.kind {
                ResourceKind::Texture(d) => *d,
                ResourceKind::Buffer(_) => {
                    self.frame_buffers[r] = match res.origin {
                        ResourceOrigin::Imported => {
                            Some(self.import_buffers.get(&res.name).cloned().ok_or_else(|| {
                                GraphError::MissingResource {
                                    resource: res.name.clone(),
                                    message:
                                        "imported buffer not provided; call Executor::import_buffer"
                                            .into(),
                                }
                            })?)
                        }
                        _ => self.state.as_ref().and_then(|s| s.buffers[r].clone()),
                    };
                    continue;
                }
            };
            let extent = desc.size.resolve(output);
            self.frame[r] = Some(match &res.origin {
                ResourceOrigin::Transient => match plan.slot_of[r] {
                    Some(s) => self.lent[s].bound.clone(),
                    None => continue,
                },
                ResourceOrigin::Imported => {
                    let t =
                        self.imports
                            .get(&res.name)
                            .ok_or_else(|| GraphError::MissingResource {
                                resource: res.name.clone(),
                                message:
                                    "imported texture not provided; call Executor::import_texture"
                                        .into(),
                            })?;
                    if t.texture.format() != desc.format {
                        return Err(GraphError::FormatMismatch {
                            pass: "import".into(),
                            resource: res.name.clone(),
                            expected: format!("{:?}", desc.format),
                            found: t.texture.format(),
                        });
                    }
                    if t.extent != extent {
                        return Err(GraphError::SizeMismatch {
                            pass: "import".into(),
                            resource: res.name.clone(),
                            expected: extent.to_string(),
                            found: t.extent.to_string(),
                        });
                    }
                    t.clone()
                }
                ResourceOrigin::HistoryPrevious { history }
                | ResourceOrigin::HistoryCurrent { history } => {
                    let usage = history_usage(plan, history);
                    let key = PoolKey {
                        format: desc.format,
                        extent,
                        mip_levels: desc.mip_levels,
                        usage,
                    };
                    let pool = &mut self.pool;
                    let (pair, valid) = self
                        .history
                        .prepare(device, history, key, &mut || pool.next_serial());
                    let previous = &pair.textures[1 - pair.current].bound;
                    if matches!(res.origin, ResourceOrigin::HistoryPrevious { .. }) {
                        if !valid {
                            clear_texture(&self.gpu, encoder, &previous.texture);
                        }
                        previous.clone()
                    } else {
                        pair.textures[pair.current].bound.clone()
                    }
                }
            });
        }
        Ok(())
    }

    /// Builds (or reuses) the bind groups of every kept pass for this frame's textures.
    fn bind_groups(&mut self, plan: &CompiledGraph) -> GraphResult<()> {
        let Some(state) = self.state.as_mut() else {
            return Ok(());
        };
        let decl = &plan.decl;
        for p in &plan.order {
            let (Some(pipeline), Some(info)) = (&state.pipelines[p.0], &plan.shaders[p.0]) else {
                continue;
            };
            let pass = &decl.passes[p.0];
            self.scratch.clear();
            for b in &info.bindings {
                let serial = match b.kind {
                    ShaderBindingKind::SampledTexture { .. }
                    | ShaderBindingKind::StorageTexture { .. } => pass
                        .textures
                        .iter()
                        .find(|u| u.binding.as_deref() == Some(b.name.as_str()))
                        .and_then(|u| {
                            self.frame[u.resource()]
                                .as_ref()
                                .map(|t| t.serial * 64 + u.mip.unwrap_or(63) as u64)
                        })
                        .unwrap_or(0),
                    _ => 0,
                };
                self.scratch.push(serial);
            }
            if state.bind_groups[p.0]
                .as_ref()
                .is_some_and(|(k, _)| *k == self.scratch)
            {
                continue;
            }
            let mut groups = Vec::new();
            for (g, layout) in pipeline.groups() {
                let mut entries = Vec::new();
                for b in info.bindings.iter().filter(|b| b.group == *g) {
                    let missing = || GraphError::MissingResource {
                        resource: b.name.clone(),
                        message: format!("pass `{}` has nothing bound to it this frame", pass.name),
                    };
                    let resource = match &b.kind {
                        ShaderBindingKind::Sampler { linear } => {
                            wgpu::BindingResource::Sampler(if *linear {
                                &self.linear
                            } else {
                                &self.nearest
                            })
                        }
                        ShaderBindingKind::SampledTexture { .. }
                        | ShaderBindingKind::StorageTexture { .. } => {
                            let u = pass
                                .textures
                                .iter()
                                .find(|u| u.binding.as_deref() == Some(b.name.as_str()))
                                .ok_or_else(missing)?;
                            let t = self.frame[u.resource()].as_ref().ok_or_else(missing)?;
                            let storage =
                                matches!(b.kind, ShaderBindingKind::StorageTexture { .. });
                            wgpu::BindingResource::TextureView(t.view_of(if storage {
                                u.mip.or(Some(0))
                            } else {
                                u.mip
                            }))
                        }
                        ShaderBindingKind::Uniform { .. }
                        | ShaderBindingKind::StorageBuffer { .. } => {
                            if let Some(h) = pass
                                .uniforms
                                .iter()
                                .find(|h| decl.uniforms[h.0].binding == b.name)
                            {
                                state.uniforms[h.0].as_entire_binding()
                            } else {
                                let u = pass
                                    .buffers
                                    .iter()
                                    .find(|u| u.binding.as_deref() == Some(b.name.as_str()))
                                    .ok_or_else(missing)?;
                                let h = u.read.or(u.written).ok_or_else(missing)?;
                                self.frame_buffers[h.id as usize]
                                    .as_ref()
                                    .ok_or_else(missing)?
                                    .as_entire_binding()
                            }
                        }
                    };
                    entries.push(wgpu::BindGroupEntry {
                        binding: b.binding,
                        resource,
                    });
                }
                groups.push((
                    *g,
                    self.gpu
                        .device
                        .create_bind_group(&wgpu::BindGroupDescriptor {
                            label: Some(&pass.name),
                            layout,
                            entries: &entries,
                        }),
                ));
            }
            state.bind_groups[p.0] = Some((self.scratch.clone(), groups));
        }
        Ok(())
    }

    /// Runs one frame of `plan` at output size `output`.
    pub fn execute(&mut self, plan: &Arc<CompiledGraph>, output: Extent) -> GraphResult<()> {
        if output.width == 0 || output.height == 0 {
            return Err(GraphError::InvalidParameter {
                owner: "graph".into(),
                name: "output size".into(),
                value: output.to_string(),
                allowed: "width and height of at least 1 pixel".into(),
            });
        }
        self.collect_timings()?;
        self.ensure_state(plan)?;
        self.output = output;
        let device = self.gpu.device.clone();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("aograph frame"),
        });
        self.bind_resources(plan, output, &mut encoder)?;
        self.bind_groups(plan)?;
        let n = plan.order.len() as u32;
        self.pass_ms.clear();
        self.pass_ms.resize(n as usize, 0.0);
        let gpu_timing = self.timing_source() == TimingSource::GpuTimestamps;
        if gpu_timing && !self.timestamps.as_ref().is_some_and(|t| t.fits(n)) {
            self.timestamps = Some(TimestampQueries::new(&device, &self.gpu.queue, n));
        }
        for (pos, p) in plan.order.iter().enumerate() {
            let name = &plan.decl.passes[p.0].name;
            let started = Instant::now();
            // Debug groups only where the driver survives them (see `GpuContext::debug_groups`).
            let outer_group = self.gpu.debug_groups();
            if outer_group {
                encoder.push_debug_group(name);
            }
            if let (true, Some(ts)) = (gpu_timing, &self.timestamps) {
                encoder.write_timestamp(ts.set(), 2 * pos as u32);
            }
            self.record_pass(plan, pos, &mut encoder)?;
            if let (true, Some(ts)) = (gpu_timing, &self.timestamps) {
                encoder.write_timestamp(ts.set(), 2 * pos as u32 + 1);
            }
            if outer_group {
                encoder.pop_debug_group();
            }
            if !gpu_timing {
                let done = std::mem::replace(
                    &mut encoder,
                    device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("aograph frame"),
                    }),
                );
                self.gpu.queue.submit([done.finish()]);
                self.gpu.wait_idle()?;
                self.pass_ms[pos] = started.elapsed().as_secs_f64() * 1000.0;
            }
        }
        if let (true, Some(ts)) = (gpu_timing, self.timestamps.as_mut()) {
            ts.resolve(&mut encoder, n);
        }
        self.gpu.queue.submit([encoder.finish()]);
        if let (true, Some(ts)) = (gpu_timing, self.timestamps.as_mut()) {
            ts.start_map();
        }
        if self
            .timed_plan
            .as_ref()
            .is_none_or(|t| !Arc::ptr_eq(t, plan))
        {
            self.timed_plan = Some(plan.clone());
            self.timings.passes = plan
                .order
                .iter()
                .map(|p| (plan.decl.passes[p.0].name.clone(), 0.0))
                .collect();
        }
        if !gpu_timing {
            self.timings.source = Some(TimingSource::CpuWall);
            for (slot, ms) in self.timings.passes.iter_mut().zip(&self.pass_ms) {
                slot.1 = *ms;
            }
        }
        let written = plan.decl.resources.iter().filter_map(|r| match &r.origin {
            ResourceOrigin::HistoryCurrent { history } if r.latest_version() > 0 => {
                Some(history.as_str())
            }
            _ => None,
        });
        self.history.end_frame(written);
        self.pool.end_frame();
        self.frames += 1;
        let errors = self.gpu.take_errors();
        if !errors.is_empty() {
            return Err(GraphError::Gpu(errors.join("; ")));
        }
        Ok(())
    }

    fn record_pass(
        &self,
        plan: &CompiledGraph,
        pos: usize,
        encoder: &mut wgpu::CommandEncoder,
    ) -> GraphResult<()> {
        let p = plan.order[pos];
        let pass = &plan.decl.passes[p.0];
        let state = self.state.as_ref();
        let pipeline = state.and_then(|s| s.pipelines[p.0].as_ref());
        let groups = state
            .and_then(|s| s.bind_groups[p.0].as_ref())
            .map(|(_, g)| g.as_slice())
            .unwrap_or(&[]);
        let view_of = |u: &crate::TextureUse| {
            self.frame[u.resource()]
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
                    Some(crate::Dispatch::Threads { size, mip }) => {
                        let e = size.resolve(self.output).mip(*mip);
                        [
                            e.width.div_ceil(workgroup[0].max(1)),
                            e.height.div_ceil(workgroup[1].max(1)),
                            1,
                        ]
                    }
                    Some(crate::Dispatch::Workgroups(w)) => *w,
                    None => [0, 0, 0],
                };
                let mut cp = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(&pass.name),
                    timestamp_writes: None,
                });
                cp.set_pipeline(pipeline);
                for (g, bg) in groups {
                    cp.set_bind_group(*g, bg, &[]);
                }
                cp.dispatch_workgroups(counts[0], counts[1], counts[2]);
            }
            (PassKind::Fullscreen { .. }, Some(PassPipeline::Render { pipeline, .. })) => {
                let mut color = Vec::new();
                for u in pass
                    .textures
                    .iter()
                    .filter(|u| u.access == TextureAccess::ColorAttachment)
                {
                    let view = view_of(u).ok_or_else(|| GraphError::MissingResource {
                        resource: format!("#{}", u.resource()),
                        message: "colour attachment not bound".into(),
                    })?;
                    let load = if u.read.is_some() {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT)
                    };
                    color.push(Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load,
                            store: wgpu::StoreOp::Store,
                        },
                    }));
                }
                let depth = pass
                    .textures
                    .iter()
                    .find(|u| {
                        matches!(
                            u.access,
                            TextureAccess::DepthAttachment | TextureAccess::DepthRead
                        )
                    })
                    .and_then(|u| {
                        let load = if u.read.is_some() {
                            wgpu::LoadOp::Load
                        } else {
                            wgpu::LoadOp::Clear(1.0)
                        };
                        view_of(u).map(|view| wgpu::RenderPassDepthStencilAttachment {
                            view,
                            depth_ops: Some(wgpu::Operations {
                                load,
                                store: wgpu::StoreOp::Store,
                            }),
                            stencil_ops: None,
                        })
                    });
                let mut rp = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(&pass.name),
                    color_attachments: &color,
                    depth_stencil_attachment: depth,
                    timestamp_writes: None,
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
                let src = pass
                    .textures
                    .iter()
                    .find(|u| u.access == TextureAccess::CopySrc)
                    .and_then(|u| self.frame[u.resource()].as_ref());
                let dst = pass
                    .textures
                    .iter()
                    .find(|u| u.access == TextureAccess::CopyDst)
                    .and_then(|u| self.frame[u.resource()].as_ref());
                let (Some(src), Some(dst)) = (src, dst) else {
                    return Err(GraphError::InvalidPass {
                        pass: pass.name.clone(),
                        message: "a copy pass needs one copy source and one copy destination"
                            .into(),
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
                let mut ctx = PassContext {
                    device: &self.gpu.device,
                    queue: &self.gpu.queue,
                    encoder,
                    output: self.output,
                    pass,
                    textures: &self.frame,
                    buffers: &self.frame_buffers,
                    shaders: &self.shaders,
                    features: self.gpu.features,
                };
                custom.record(&mut ctx)?;
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

    /// Reads the timestamps of the frame in flight into the timing table.
    fn collect_timings(&mut self) -> GraphResult<()> {
        if let Some(ts) = self.timestamps.as_mut() {
            if ts.collect(&self.gpu.device, &mut self.pass_ms)? {
                self.timings.source = Some(TimingSource::GpuTimestamps);
                for (slot, ms) in self.timings.passes.iter_mut().zip(&self.pass_ms) {
                    slot.1 = *ms;
                }
            }
        }
        Ok(())
    }

    /// Per-pass milliseconds of the last executed frame (waits for its timestamps).
    pub fn timings(&mut self) -> GraphResult<&PassTimings> {
        self.collect_timings()?;
        Ok(&self.timings)
    }

    /// Reads an exported or history texture of the last frame back to the CPU (mip 0).
    pub fn read_texture(
        &self,
        plan: &CompiledGraph,
        handle: TextureHandle,
    ) -> GraphResult<TextureReadback> {
        self.read_texture_mip(plan, handle, 0)
    }

    /// Reads one mip level of an exported or history texture of the last frame.
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
            return Err(GraphError::MissingResource { resource: res.name.clone(), message: "only exported, imported and history textures can be read back; call GraphBuilder::export on it".into() });
        }
        let t = self.frame.get(r).and_then(Option::as_ref).ok_or_else(|| {
            GraphError::MissingResource {
                resource: res.name.clone(),
                message: "not produced by the last frame (was it culled, or has no frame run?)"
                    .into(),
            }
        })?;
        read_texture(&self.gpu.device, &self.gpu.queue, &t.texture, mip)
    }
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

/// Usage of a history's textures: everything its two halves are used for, plus copies.
fn history_usage(plan: &CompiledGraph, history: &str) -> wgpu::TextureUsages {
    plan.decl
        .resources
        .iter()
        .enumerate()
        .filter(|(_, r)| matches!(&r.origin, ResourceOrigin::HistoryPrevious { history: h } | ResourceOrigin::HistoryCurrent { history: h } if h == history))
        .fold(wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::TEXTURE_BINDING, |acc, (i, _)| acc | plan.usage[i])
}
