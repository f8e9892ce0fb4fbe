//! [`AmbientOcclusion`]: aograph's techniques on an application's own device, recording into
//! its own command encoder. Declare (adapters for the inputs given, the technique, the output
//! pass), compile, execute, as aograph's own renderer does; only the g-buffer is the
//! application's.
//!
//! Invariants: `encode` never submits or waits; a plan is built once per (settings, input
//! layout, output format) and kept, so switching technique or parameters back and forth, or
//! alternating layouts, creates no pipeline after each plan's first frame (the executor shares
//! pipelines between plans); choosing the plan for a frame compares `Copy` values and allocates
//! nothing.

use std::collections::HashMap;
use std::sync::Arc;

use aograph_ao_passes::{
    AoBuildContext, AoConfig, ConfiguredTechnique, GraphSettings, TechniqueRegistry, TracingSupport,
};
use aograph_frame::{
    DeclaredInputs, FrameInput, InputBindings, ViewBlock, ViewMatrices, ViewUniforms,
};
use aograph_graph::{
    CompileOptions, CompiledGraph, Executor, Extent, GpuContext, GraphBuilder, GraphCompiler,
    ShaderLibrary, ShaderMount,
};
use glam::Mat4;

use crate::adapters::{
    DEPTH_IMPORT, MOTION_IMPORT, NORMALS_IMPORT, OUTPUT_IMPORT, VIEWPORT_BYTES, VIEWPORT_IMPORT,
    declare_inputs, declare_output,
};
use crate::error::{EmbedError, EmbedResult};
use crate::inputs::{AoInputs, InputLayout};
use crate::output::{AoOutputFormat, AoOutputView, OUTPUT_USAGE};
use crate::projection::DepthConvention;
use crate::settings::{check_inputs, parse_config, resolve};

/// Plans kept for settings and layouts seen before; beyond that they are dropped and rebuilt
/// when asked for again (a window dragged through many sizes builds one per size).
const MAX_PLANS: usize = 32;

/// Which plan a frame runs: the settings, the inputs' shape and the output format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PlanKey {
    /// Technique, parameters, radius and precision: the index of their [`GraphSettings`] in
    /// `AmbientOcclusion::seen_settings` (found once per `set_config` or `prepare`).
    settings: usize,
    layout: InputLayout,
    output: AoOutputFormat,
}

/// An engine keeps `AmbientOcclusion` in its render world and may prepare plans on another
/// thread: it must stay `Send + Sync` (checked when this crate compiles).
const _: () = {
    const fn send_and_sync<T: Send + Sync>() {}
    send_and_sync::<AmbientOcclusion>();
};

/// One technique at a time on an application's frames. See the crate docs for an example.
pub struct AmbientOcclusion {
    gpu: Arc<GpuContext>,
    shaders: Arc<ShaderLibrary>,
    registry: TechniqueRegistry,
    config: AoConfig,
    technique: Arc<dyn ConfiguredTechnique>,
    radius: f32,
    settings: usize,
    /// The settings plans were built for, indexed by [`PlanKey::settings`]; cleared with
    /// `plans`.
    seen_settings: Vec<GraphSettings>,
    output_format: AoOutputFormat,
    exec: Executor,
    compiler: GraphCompiler,
    plans: HashMap<PlanKey, (Arc<CompiledGraph>, DeclaredInputs)>,
    /// The frame inputs supplied: the View block, and those the application binds
    /// ([`AmbientOcclusion::bind_input`]).
    inputs: InputBindings,
    current: Option<(PlanKey, Arc<CompiledGraph>)>,
    view_buffer: wgpu::Buffer,
    /// The viewport's corner (`adapters::VIEWPORT_IMPORT`), and what it holds now.
    viewport_buffer: wgpu::Buffer,
    viewport_corner: Option<[u32; 2]>,
    /// The textures imported last, so an unchanged texture is not rebound.
    bound: [Option<wgpu::Texture>; 4],
    /// aograph's own output texture, when the application passes none.
    owned_output: Option<AoOutputView>,
    prev_view_proj: Option<Mat4>,
    prev_time: f32,
    frame_index: u32,
}

impl AmbientOcclusion {
    /// AO on the application's `device` (made from `adapter`) and `queue`, with the technique
    /// and parameters of `config` (`[ao]`: `technique`, `radius` in the view matrix's units,
    /// `[ao.<technique>]` tables). Builds nothing on the GPU until the first frame.
    pub fn new(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        config: &AoConfig,
    ) -> EmbedResult<Self> {
        Self::with_registry(
            adapter,
            device,
            queue,
            config,
            TechniqueRegistry::with_builtins(),
            [],
        )
    }

    /// As [`AmbientOcclusion::new`], with the `[ao]` section given as TOML text (the same
    /// keys as aograph's config files: `technique = "gtao"`, `radius = 0.5`, `[gtao]` ...).
    pub fn from_toml(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        toml_text: &str,
    ) -> EmbedResult<Self> {
        let registry = TechniqueRegistry::with_builtins();
        let config = parse_config(toml_text, &registry)?;
        Self::with_registry(adapter, device, queue, &config, registry, [])
    }

    /// As [`AmbientOcclusion::new`], choosing among the techniques of `registry` (the
    /// built-ins and the application's own), whose WGSL `mounts` bring beside aograph's (a
    /// user technique's `ShaderMount::new("my-app").with_files(..)`; its files may include
    /// aograph's, `common/view.wgsl` say). A mount giving a file aograph already has is an
    /// error naming both.
    pub fn with_registry(
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        config: &AoConfig,
        registry: TechniqueRegistry,
        mounts: impl IntoIterator<Item = ShaderMount>,
    ) -> EmbedResult<Self> {
        let gpu = Arc::new(GpuContext::from_device(
            adapter.clone(),
            device.clone(),
            queue.clone(),
        ));
        let shaders = crate::shader_mount::shader_library()?;
        for mount in mounts {
            shaders.mount(mount)?;
        }
        let shaders: Arc<ShaderLibrary> = Arc::new(shaders);
        let mut exec = Executor::with_shaders(gpu.clone(), shaders.clone());
        exec.set_timing(aograph_graph::TimingMode::Off)?;
        let view_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("aograph view"),
            size: std::mem::size_of::<ViewUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut inputs = InputBindings::default();
        inputs.set::<ViewBlock>(view_buffer.clone());
        let (technique, radius, settings) = resolve(&gpu, &registry, config, &inputs)?;
        let viewport_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("aograph viewport"),
            size: VIEWPORT_BYTES,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        exec.import_buffer(VIEWPORT_IMPORT, viewport_buffer.clone());
        // Every plan is checked against the application's device when it is built.
        let compiler = GraphCompiler::for_device(aograph_graph::DeviceProfile::of(&gpu));
        Ok(Self {
            gpu,
            shaders,
            registry,
            inputs,
            config: config.clone(),
            technique,
            radius,
            settings: 0,
            seen_settings: vec![settings],
            output_format: AoOutputFormat::default(),
            exec,
            compiler,
            plans: HashMap::new(),
            current: None,
            view_buffer,
            viewport_buffer,
            viewport_corner: None,
            bound: Default::default(),
            owned_output: None,
            prev_view_proj: None,
            prev_time: 0.0,
            frame_index: 0,
        })
    }

    /// Supplies `resources` for the frame input `I` (an application's own, for a technique
    /// that reads it: docs/guide/writing-a-technique.md), bound to every plan that declares it,
    /// kept ones included. Bind it before choosing such a technique: `set_config` refuses a
    /// technique reading an input nothing supplies.
    pub fn bind_input<I: FrameInput>(&mut self, resources: I::Resources) -> EmbedResult<()>
    where
        I::Resources: Sized + Send + Sync,
    {
        self.inputs.set::<I>(resources);
        for (plan, declared) in self.plans.values() {
            self.inputs.bind(&mut self.exec, plan, declared)?;
        }
        Ok(())
    }

    /// Switches technique or parameters from the next frame on. Settings seen before come back
    /// with the plan they were built with: nothing is compiled or created. On an error the
    /// current settings stay.
    pub fn set_config(&mut self, config: &AoConfig) -> EmbedResult<()> {
        let (technique, radius, settings) =
            resolve(&self.gpu, &self.registry, config, &self.inputs)?;
        self.config = config.clone();
        self.technique = technique;
        self.radius = radius;
        self.settings = self.settings_index(settings);
        Ok(())
    }

    /// [`AmbientOcclusion::set_config`] from `[ao]` TOML text.
    pub fn set_config_toml(&mut self, toml_text: &str) -> EmbedResult<()> {
        let config = parse_config(toml_text, &self.registry)?;
        self.set_config(&config)
    }

    /// The settings in use.
    pub fn config(&self) -> &AoConfig {
        &self.config
    }

    /// The format of the texture [`AmbientOcclusion::encode`] writes (R8Unorm by default).
    pub fn set_output_format(&mut self, format: AoOutputFormat) {
        self.output_format = format;
    }

    /// Marks a camera cut: the next frame starts with no history (as `camera_cut` does).
    pub fn cut(&mut self) {
        self.prev_view_proj = None;
        self.exec.reset_history();
    }

    /// Records one frame into `encoder` and returns the texture holding its AO, owned by
    /// aograph (made or remade when the size or output format changes). Submits nothing:
    /// submit `encoder` before the next `encode`.
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &AoInputs<'_>,
    ) -> EmbedResult<AoOutputView> {
        let (w, h) = match inputs.viewport {
            Some(v) => (v.width, v.height),
            None => (
                inputs.depth.texture().width(),
                inputs.depth.texture().height(),
            ),
        };
        let format = self.output_format.wgpu();
        let fits = self.owned_output.as_ref().is_some_and(|o| {
            (o.texture.width(), o.texture.height(), o.texture.format()) == (w, h, format)
        });
        if !fits {
            let texture = self.gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("aograph ao"),
                size: wgpu::Extent3d {
                    width: w.max(1),
                    height: h.max(1),
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: OUTPUT_USAGE
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            self.owned_output = Some(AoOutputView { texture, view });
        }
        let out = self
            .owned_output
            .clone()
            .ok_or(aograph_graph::GraphError::Internal(
                "the output texture vanished after it was made",
            ))?;
        self.encode_into(encoder, inputs, &out.texture)?;
        Ok(out)
    }

    /// Records one frame into `encoder`, writing the AO into the application's `target`
    /// (R8Unorm, R16Float or R32Float, with `RENDER_ATTACHMENT` usage, the output's size: the
    /// viewport's, else the depth's).
    pub fn encode_into(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &AoInputs<'_>,
        target: &wgpu::Texture,
    ) -> EmbedResult<()> {
        let layout = InputLayout::of(inputs)?;
        let output = AoOutputFormat::of(target.format()).ok_or(EmbedError::InputFormat {
            input: "the output texture",
            found: target.format(),
            allowed: "R8Unorm, R16Float or R32Float",
        })?;
        if (target.width(), target.height()) != (layout.width, layout.height) {
            return Err(EmbedError::InputSize {
                input: "the output texture",
                found: format!("{}x{}", target.width(), target.height()),
                expected: format!("{}x{}", layout.width, layout.height),
            });
        }
        if layout.width == 0 || layout.height == 0 {
            return Err(EmbedError::InvalidSetting {
                name: "depth texture size".into(),
                value: format!("{}x{}", layout.width, layout.height),
                allowed: "at least 1x1".into(),
            });
        }
        let convention = DepthConvention::of(inputs.projection)?;
        if !inputs.view.is_finite() {
            return Err(EmbedError::InvalidSetting {
                name: "view matrix".into(),
                value: "non-finite entries".into(),
                allowed: "a finite world-to-view matrix".into(),
            });
        }
        let plan = self.plan_for(layout, output)?;
        let size = Extent::new(layout.width, layout.height);

        self.bind(0, DEPTH_IMPORT, inputs.depth.texture());
        if let Some(n) = inputs.normals {
            self.bind(1, NORMALS_IMPORT, n.texture);
        }
        if let Some(m) = inputs.motion {
            self.bind(2, MOTION_IMPORT, m.texture);
        }
        self.bind(3, OUTPUT_IMPORT, target);

        if inputs.camera_cut {
            self.cut();
        }
        let corner = inputs.viewport.map_or([0, 0], |v| [v.x, v.y]);
        if self.viewport_corner != Some(corner) {
            let bytes: Vec<u8> = [corner[0], corner[1], 0, 0]
                .iter()
                .flat_map(|c| c.to_le_bytes())
                .collect();
            self.gpu
                .queue
                .write_buffer(&self.viewport_buffer, 0, &bytes);
            self.viewport_corner = Some(corner);
        }
        let view_proj = inputs.projection * inputs.view;
        let history_valid =
            self.prev_view_proj.is_some() && self.exec.all_history_valid(&plan, size);
        let view = ViewUniforms::from_matrices(&ViewMatrices {
            view: inputs.view,
            proj: inputs.projection,
            prev_view_proj: self.prev_view_proj.unwrap_or(view_proj),
            near: convention.near,
            far: convention.far,
            reversed_z: convention.reversed_z,
            orthographic: convention.orthographic,
            width: layout.width,
            height: layout.height,
            frame_index: self.frame_index,
            history_valid,
            camera_cut: self.prev_view_proj.is_none(),
            time: inputs.time,
            dt: if self.prev_view_proj.is_some() {
                inputs.time - self.prev_time
            } else {
                0.0
            },
        });
        self.gpu
            .queue
            .write_buffer(&self.view_buffer, 0, view.bytes());
        self.exec.encode(&plan, size, encoder)?;
        self.prev_view_proj = Some(view_proj);
        self.prev_time = inputs.time;
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(())
    }

    /// Builds, ahead of the frame that needs it, the plan for `config` on frames shaped like
    /// `layout` (`InputLayout::of` a frame's inputs, or written out) writing `output`, and
    /// creates its pipelines: the first frame with those settings and that layout then
    /// compiles nothing and creates no pipeline. The current settings do not change (call
    /// [`AmbientOcclusion::set_config`] when the switch is due). `AmbientOcclusion` is `Send +
    /// Sync`, so this can run on a loading thread, or behind a lock on a worker, between frames.
    pub fn prepare(
        &mut self,
        config: &AoConfig,
        layout: InputLayout,
        output: AoOutputFormat,
    ) -> EmbedResult<()> {
        let (technique, radius, settings) =
            resolve(&self.gpu, &self.registry, config, &self.inputs)?;
        let key = PlanKey {
            settings: self.settings_index(settings),
            layout,
            output,
        };
        let plan = self.kept_or_built(key, technique, radius, config.intermediate_format.wgpu())?;
        self.exec.prepare(&plan)?;
        Ok(())
    }

    /// Whether the plan for `config` on frames shaped like `layout` writing `output` is built
    /// and kept (by [`AmbientOcclusion::prepare`] or an earlier frame), so that switching to
    /// it creates no pipeline. Plans can be dropped again when more than a bounded number of
    /// settings and layouts have been seen; this answers for now.
    pub fn is_prepared(
        &self,
        config: &AoConfig,
        layout: InputLayout,
        output: AoOutputFormat,
    ) -> bool {
        let settings = config.graph_settings();
        self.seen_settings
            .iter()
            .position(|s| *s == settings)
            .is_some_and(|settings| {
                self.plans.contains_key(&PlanKey {
                    settings,
                    layout,
                    output,
                })
            })
    }

    /// Compute pipelines and render pipelines created so far (a switch back to settings seen
    /// before adds none).
    pub fn pipelines_created(&self) -> u64 {
        self.exec.pipeline_created_count()
    }

    /// Plans built so far and kept.
    pub fn plan_count(&self) -> usize {
        self.plans.len()
    }

    /// The frame graph's executor, for its counters and timings.
    pub fn executor(&self) -> &Executor {
        &self.exec
    }

    /// Times every pass of the frames encoded from now on: `TimingMode::GpuTimestamps` on a
    /// device with `TIMESTAMP_QUERY` (between commands with `TIMESTAMP_QUERY_INSIDE_ENCODERS`,
    /// at each pass's own boundaries otherwise, as on WebGPU), or `Off` (the default).
    /// `CpuWall` waits for the GPU after every pass: for one-shot tools only.
    pub fn set_timing(&mut self, mode: aograph_graph::TimingMode) -> EmbedResult<()> {
        Ok(self.exec.set_timing(mode)?)
    }

    /// The newest per-pass milliseconds that have arrived (GPU timestamps arrive a few frames
    /// after their frame, which `frame` names), without waiting; empty with timing off.
    pub fn latest_timings(&mut self) -> EmbedResult<&aograph_graph::PassTimings> {
        Ok(self.exec.latest_timings()?)
    }

    /// The compiled plan the last frame ran, if any (its passes, for inspection and tests).
    pub fn current_plan(&self) -> Option<&Arc<CompiledGraph>> {
        self.current.as_ref().map(|(_, p)| p)
    }

    /// Imports `texture` under `name` unless it is the one bound already.
    fn bind(&mut self, slot: usize, name: &str, texture: &wgpu::Texture) {
        if self.bound[slot].as_ref() != Some(texture) {
            self.exec.import_texture(name, texture.clone());
            self.bound[slot] = Some(texture.clone());
        }
    }

    /// The plan for this frame: the current one when nothing changed (no allocation), a kept
    /// one, or a new one.
    fn plan_for(
        &mut self,
        layout: InputLayout,
        output: AoOutputFormat,
    ) -> EmbedResult<Arc<CompiledGraph>> {
        if let Some((key, plan)) = &self.current
            && key.layout == layout
            && key.output == output
            && key.settings == self.settings
        {
            return Ok(plan.clone());
        }
        let key = PlanKey {
            settings: self.settings,
            layout,
            output,
        };
        let plan = self.kept_or_built(
            key,
            self.technique.clone(),
            self.radius,
            self.config.intermediate_format.wgpu(),
        )?;
        self.current = Some((key, plan.clone()));
        Ok(plan)
    }

    /// The index of `settings` among those seen, added when new. The list is bounded with the
    /// plans: when it reaches [`MAX_PLANS`], both start again from the current settings.
    fn settings_index(&mut self, settings: GraphSettings) -> usize {
        if let Some(i) = self.seen_settings.iter().position(|s| *s == settings) {
            return i;
        }
        if self.seen_settings.len() >= MAX_PLANS {
            let current = self.seen_settings[self.settings].clone();
            self.seen_settings = vec![current];
            self.settings = 0;
            self.plans.clear();
            self.current = None;
        }
        self.seen_settings.push(settings);
        self.seen_settings.len() - 1
    }

    /// The plan kept under `key`, or one built now for `technique` at `radius` (intermediates
    /// in `intermediate`) and kept, the kept ones dropped first when there are [`MAX_PLANS`].
    fn kept_or_built(
        &mut self,
        key: PlanKey,
        technique: Arc<dyn ConfiguredTechnique>,
        radius: f32,
        intermediate: wgpu::TextureFormat,
    ) -> EmbedResult<Arc<CompiledGraph>> {
        if let Some((plan, _)) = self.plans.get(&key) {
            return Ok(plan.clone());
        }
        let (plan, declared) =
            self.build_plan(technique, radius, intermediate, &key.layout, key.output)?;
        self.inputs.bind(&mut self.exec, &plan, &declared)?;
        if self.plans.len() >= MAX_PLANS {
            // The current plan stays: frames keep running it, and `bind_input` rebinds the
            // kept plans' inputs.
            let current = self.current.as_ref().map(|(k, _)| *k);
            self.plans.retain(|k, _| Some(*k) == current);
        }
        self.plans.insert(key, (plan.clone(), declared));
        Ok(plan)
    }

    /// Declares and compiles the frame of `technique` at `radius`, its intermediates in
    /// `intermediate`: adapters, technique, output pass.
    fn build_plan(
        &mut self,
        technique: Arc<dyn ConfiguredTechnique>,
        radius: f32,
        intermediate: wgpu::TextureFormat,
        layout: &InputLayout,
        output: AoOutputFormat,
    ) -> EmbedResult<(Arc<CompiledGraph>, DeclaredInputs)> {
        // Channels and frame inputs were checked when the settings were resolved.
        let wanted = technique.channels();
        let mut b = GraphBuilder::new();
        let mut declared = DeclaredInputs::default();
        let view = declared.declare::<ViewBlock>(&mut b);
        let gbuffer = declare_inputs(&mut b, layout, wanted, view);
        // `levels = "auto"` reaches R projected at the view's closest geometry, which an
        // application's frame does not tell before it is drawn: the image's diagonal bounds it
        // (aograph_scene::ProjectedRadius::reach_needed_px caps there too).
        let diagonal = (layout.width as f32).hypot(layout.height as f32);
        let mut ctx = AoBuildContext {
            builder: &mut b,
            gbuffer,
            view,
            radius,
            intermediate_format: intermediate,
            technique: technique.name(),
            radius_pixels: technique.needs_radius_pixels().then_some(diagonal),
            declared,
            tracing: TracingSupport::of(&self.gpu),
        };
        let out = technique.build(&mut ctx)?;
        let declared = ctx.declared;
        // Checked at `set_config` on the technique's plan without a layout; this layout's
        // plan is checked too.
        check_inputs(&self.registry, technique.name(), &declared, &self.inputs)?;
        declare_output(&mut b, out.accessibility, output.wgpu());
        let plan = self
            .compiler
            .compile(b.build(), &self.shaders, CompileOptions::default())?;
        Ok((plan, declared))
    }
}
