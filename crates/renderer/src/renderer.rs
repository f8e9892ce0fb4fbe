//! Renders frames of a scene with an AO technique: owns the device, one executor and the
//! compiled frame graphs, writes the `View` block and the g-buffer clock each frame, and reads
//! outputs back. Camera cuts and resizes invalidate history through the executor.
//!
//! The technique and its parameters can change between frames ([`Renderer::set_ao`]): every
//! frame graph built is kept by its settings, so going back to settings seen before reuses the
//! same declaration and plan (no graph rebuilt, no pipeline or g-buffer upload), and the one
//! executor keeps each plan's state and shares pipelines and textures between them.

use std::sync::Arc;

use crate::gbuffer::{GBufferFrame, GBufferStates};
use aograph_ao_passes::{
    AoConfig, GraphSettings, IntermediateFormat, TechniqueRegistry, TracingSupport,
};
use aograph_frame::{
    FrameInput, InputBindings, LightingUniforms, SceneAcceleration, SceneBvh, SceneLighting,
    SkyColours, ViewBlock,
};
use aograph_graph::{
    CompileOptions, CompiledGraph, Executor, Extent, GpuContext, GraphBuilder, GraphCompiler,
    PassTimings, PlanKey, ShaderLibrary,
};
use aograph_scene::view_block::{ViewFrame, view_uniforms};
use aograph_scene::{Camera, Scene};
use aograph_tracing::gpu::{AsWork, GpuSceneBvh};

use crate::error::{RenderError, RenderResult};
use crate::frame_graph::{FrameGraph, FrameOutputs, build_frame_graph_with, build_gbuffer_graph};
use crate::scene_tracing::SceneTracing;

/// R16Float intermediates are written as r16float storage textures, which core WebGPU does not
/// guarantee: the device must offer them (through `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES`).
fn check_intermediate_format(gpu: &GpuContext, ao: &AoConfig) -> RenderResult<()> {
    let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING;
    if ao.intermediate_format == IntermediateFormat::R16Float
        && !gpu.supports(wgpu::TextureFormat::R16Float, usage)
    {
        return Err(RenderError::InvalidArgument {
            name: "[ao] intermediate_format".into(),
            value: "\"r16float\"".into(),
            allowed: format!(
                "\"r32float\" on this device, {}: it cannot write r16float storage textures",
                gpu.describe()
            ),
        });
    }
    Ok(())
}

/// How one-shot runs and benchmarks time passes: GPU timestamps on a GPU; CPU wall time per
/// pass (each pass submitted and waited for) on a software device or one without timestamps.
/// Lavapipe's timestamps do not bracket a compute pass's own work: a pass alone in its chain
/// reads ~0.03 ms for a kernel that takes 62 ms, and a dependent pass's interval takes in part
/// of its producer's time (docs/results/roofline.md). `AOGRAPH_TIMING=gpu|cpu|off` overrides.
/// A real-time front end sets its own mode (the viewer: timestamps, never waiting).
pub fn timing_mode(gpu: &GpuContext) -> RenderResult<aograph_graph::TimingMode> {
    use aograph_graph::TimingMode;
    let default = if gpu.has_timestamps() && !gpu.is_software() {
        TimingMode::GpuTimestamps
    } else {
        TimingMode::CpuWall
    };
    match std::env::var("AOGRAPH_TIMING").ok().as_deref() {
        None | Some("") => Ok(default),
        Some("gpu") => Ok(TimingMode::GpuTimestamps),
        Some("cpu") => Ok(TimingMode::CpuWall),
        Some("off") => Ok(TimingMode::Off),
        Some(other) => Err(RenderError::InvalidArgument {
            name: "AOGRAPH_TIMING".into(),
            value: other.into(),
            allowed: "gpu, cpu or off".into(),
        }),
    }
}

/// The lighting block of `scene`: its directional light, ambient and built-in sky.
fn lighting_of(scene: &Scene) -> LightingUniforms {
    let l = &scene.light;
    let sky = aograph_scene::SkyEnvironment::for_scene(scene);
    LightingUniforms::new(
        l.direction.into(),
        l.color.map(|c| c * l.intensity),
        scene.ambient,
    )
    .with_sky(SkyColours {
        zenith: sky.zenith.into(),
        horizon: sky.horizon.into(),
        ground: sky.ground.into(),
        sun_direction: sky.sun_direction.into(),
        sun_irradiance: sky.sun_irradiance.into(),
        sun_exponent: sky.sun_exponent,
    })
}

/// Passes a front end adds after the frame graph (the viewer's display pass), declared on the
/// same builder with the frame graph's handles.
pub type GraphExtension =
    Arc<dyn Fn(&mut GraphBuilder, &FrameGraph) -> RenderResult<()> + Send + Sync>;

/// Graphs kept for settings seen before (every technique and preset of a session, with room);
/// beyond that the kept ones are dropped and rebuilt when asked for again.
const MAX_BUILT_GRAPHS: usize = 32;

/// What a built graph was built for: the settings that decide it and the output size.
#[derive(Clone, Debug, PartialEq)]
struct SettingsKey {
    /// `None`: the g-buffer alone.
    settings: Option<GraphSettings>,
    output: Extent,
}

impl SettingsKey {
    fn of(ao: Option<&AoConfig>, output: Extent) -> Self {
        Self {
            settings: ao.map(AoConfig::graph_settings),
            output,
        }
    }
}

/// One scene, one technique at a time, frames on demand.
pub struct Renderer {
    /// The device frames render on.
    pub gpu: Arc<GpuContext>,
    /// The shader library the plan was compiled from (a reference g-buffer reuses it).
    pub shaders: Arc<ShaderLibrary>,
    /// The executor every plan runs on (timings, counters, read-backs).
    pub exec: Executor,
    /// The plan of the current settings.
    pub plan: Arc<CompiledGraph>,
    /// The frame graph of the current settings (its handles name what to read back).
    pub graph: FrameGraph,
    /// The scene rendered.
    pub scene: Arc<Scene>,
    /// The output size in pixels.
    pub output: Extent,
    /// The settings the current graph was built for (the defaults, unused, while the renderer
    /// draws the g-buffer alone: [`Renderer::gbuffer_only`]).
    pub ao: AoConfig,
    /// No technique runs: the frame is the g-buffer alone.
    gbuffer_only: bool,
    registry: TechniqueRegistry,
    outputs: FrameOutputs,
    options: CompileOptions,
    compiler: GraphCompiler,
    extension: Option<GraphExtension>,
    /// Graphs built before, with the settings and output size they were built for (see the
    /// module docs); at most [`MAX_BUILT_GRAPHS`], found by comparing settings.
    built: Vec<(SettingsKey, FrameGraph, Arc<CompiledGraph>)>,
    /// The settings key of `graph` and `plan`.
    current_key: SettingsKey,
    /// The g-buffer's GPU state, shared by every graph of the current scene.
    gbuffer: GBufferStates,
    view_buffer: wgpu::Buffer,
    /// The lighting block (SSDO's light, ambient and sky), rewritten with the scene.
    lighting_buffer: wgpu::Buffer,
    /// The scene's BVH and acceleration structures on the device, each built the first time
    /// a graph declares it (rtao) and moved to each frame's time.
    tracing: SceneTracing,
    /// The frame inputs the renderer supplies (the View block, the scene's lighting, its BVH
    /// or acceleration structures once built) and those an application binds
    /// ([`Renderer::bind_input`]).
    inputs: InputBindings,
    /// The plan whose frame inputs are bound (`None`: bind before the next frame).
    inputs_bound: Option<PlanKey>,
    frame_index: u32,
    prev: Option<(f32, Camera)>,
    cut: bool,
    time: f32,
}

impl Renderer {
    /// A renderer of `scene` with the technique of `ao` at `output` pixels, writing the
    /// read-backs `outputs` asks for; nothing renders until [`Renderer::render`].
    pub fn new(
        gpu: Arc<GpuContext>,
        shaders: Arc<ShaderLibrary>,
        registry: &TechniqueRegistry,
        scene: Arc<Scene>,
        ao: &AoConfig,
        outputs: FrameOutputs,
        output: Extent,
    ) -> RenderResult<Self> {
        Self::with_options(
            gpu,
            shaders,
            registry,
            scene,
            ao,
            outputs,
            output,
            CompileOptions::default(),
        )
    }

    /// [`Renderer::new`] compiling with `options` (texture reuse on or off).
    #[allow(clippy::too_many_arguments)]
    pub fn with_options(
        gpu: Arc<GpuContext>,
        shaders: Arc<ShaderLibrary>,
        registry: &TechniqueRegistry,
        scene: Arc<Scene>,
        ao: &AoConfig,
        outputs: FrameOutputs,
        output: Extent,
        options: CompileOptions,
    ) -> RenderResult<Self> {
        Self::create(
            gpu,
            shaders,
            registry,
            scene,
            Some(ao),
            outputs,
            output,
            options,
        )
    }

    /// A renderer of `scene` that draws the g-buffer alone, no AO technique (what every
    /// reference starts its rays from): [`Renderer::read_ao`] is an error until
    /// [`Renderer::set_ao`] gives it a technique (a built-in one).
    pub fn gbuffer_only(
        gpu: Arc<GpuContext>,
        shaders: Arc<ShaderLibrary>,
        scene: Arc<Scene>,
        outputs: FrameOutputs,
        output: Extent,
    ) -> RenderResult<Self> {
        Self::create(
            gpu,
            shaders,
            &TechniqueRegistry::with_builtins(),
            scene,
            None,
            outputs,
            output,
            CompileOptions::default(),
        )
    }

    /// A renderer drawing `ao`'s technique, or the g-buffer alone when `ao` is `None`.
    #[allow(clippy::too_many_arguments)]
    fn create(
        gpu: Arc<GpuContext>,
        shaders: Arc<ShaderLibrary>,
        registry: &TechniqueRegistry,
        scene: Arc<Scene>,
        ao: Option<&AoConfig>,
        outputs: FrameOutputs,
        output: Extent,
        options: CompileOptions,
    ) -> RenderResult<Self> {
        crate::output_size::check_size("width", output.width)?;
        crate::output_size::check_size("height", output.height)?;
        if let Some(ao) = ao {
            check_intermediate_format(&gpu, ao)?;
        }
        let gbuffer = GBufferStates::default();
        let graph = match ao {
            Some(ao) => build_frame_graph_with(
                registry,
                scene.clone(),
                ao,
                outputs,
                output,
                &gbuffer,
                &TracingSupport::of(&gpu),
            )?,
            None => build_gbuffer_graph(scene.clone(), outputs, output, &gbuffer)?,
        };
        // Plans are checked against the device's limits and formats when they are built.
        let mut compiler = GraphCompiler::for_device(aograph_graph::DeviceProfile::of(&gpu));
        let plan = compiler.compile(graph.decl.clone(), &shaders, options)?;
        let mut exec = Executor::with_shaders(gpu.clone(), shaders.clone());
        exec.set_timing(timing_mode(&gpu)?)?;
        let view_buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("view"),
            size: std::mem::size_of::<aograph_frame::ViewUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // The scene's light, ambient and sky, for techniques that shade (SSDO); unused
        // otherwise.
        let lighting = lighting_of(&scene);
        let lighting_buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lighting"),
            size: std::mem::size_of::<LightingUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue
            .write_buffer(&lighting_buffer, 0, lighting.bytes());
        let mut inputs = InputBindings::default();
        inputs.set::<ViewBlock>(view_buffer.clone());
        inputs.set::<SceneLighting>(lighting_buffer.clone());
        let mut r = Self {
            gpu,
            shaders,
            exec,
            plan,
            graph,
            scene,
            output,
            ao: ao.cloned().unwrap_or_default(),
            gbuffer_only: ao.is_none(),
            registry: registry.clone(),
            outputs,
            options,
            compiler,
            extension: None,
            built: Vec::new(),
            current_key: SettingsKey::of(None, output),
            gbuffer,
            view_buffer,
            lighting_buffer,
            tracing: SceneTracing::default(),
            inputs,
            inputs_bound: None,
            frame_index: 0,
            prev: None,
            cut: false,
            time: 0.0,
        };
        r.current_key = r.settings_key();
        Ok(r)
    }

    /// Passes to add after the frame graph from now on (the current graph is rebuilt with
    /// them).
    pub fn set_extension(&mut self, extension: GraphExtension) -> RenderResult<()> {
        self.extension = Some(extension);
        self.built.clear();
        self.rebuild(true)
    }

    /// Switches to the technique and parameters of `ao` from the next frame on. Settings seen
    /// before (same technique, parameters, radius, precision and size) come back as they were
    /// built: same declaration, same plan, nothing created.
    pub fn set_ao(&mut self, ao: &AoConfig) -> RenderResult<()> {
        check_intermediate_format(&self.gpu, ao)?;
        ao.validate(&self.registry)?;
        let old = std::mem::replace(&mut self.ao, ao.clone());
        let was_gbuffer_only = std::mem::replace(&mut self.gbuffer_only, false);
        if let Err(e) = self.rebuild(false) {
            self.ao = old;
            self.gbuffer_only = was_gbuffer_only;
            return Err(e);
        }
        Ok(())
    }

    /// The key of the current settings in `built`.
    fn settings_key(&self) -> SettingsKey {
        SettingsKey::of((!self.gbuffer_only).then_some(&self.ao), self.output)
    }

    /// Makes the graph for the current settings current: the one built before, or a new one
    /// (`force`: always new, e.g. after the extension changed).
    fn rebuild(&mut self, force: bool) -> RenderResult<()> {
        let key = self.settings_key();
        if !force && key == self.current_key {
            return Ok(());
        }
        let cached = if force {
            None
        } else {
            (self.built.iter().position(|(k, _, _)| *k == key)).map(|i| self.built.swap_remove(i))
        };
        let (graph, plan) = match cached {
            Some((_, graph, plan)) => (graph, plan),
            None => {
                let mut graph = if self.gbuffer_only {
                    build_gbuffer_graph(
                        self.scene.clone(),
                        self.outputs,
                        self.output,
                        &self.gbuffer,
                    )?
                } else {
                    build_frame_graph_with(
                        &self.registry,
                        self.scene.clone(),
                        &self.ao,
                        self.outputs,
                        self.output,
                        &self.gbuffer,
                        &TracingSupport::of(&self.gpu),
                    )?
                };
                if let Some(ext) = &self.extension {
                    let mut b = GraphBuilder::from_decl(graph.decl.clone());
                    ext(&mut b, &graph)?;
                    graph.decl = b.build();
                }
                let plan =
                    self.compiler
                        .compile(graph.decl.clone(), &self.shaders, self.options)?;
                (graph, plan)
            }
        };
        let old_graph = std::mem::replace(&mut self.graph, graph);
        let old_plan = std::mem::replace(&mut self.plan, plan);
        let old_key = std::mem::replace(&mut self.current_key, key);
        if !force {
            // Bounded: a window being resized builds a graph per size on the way.
            if self.built.len() >= MAX_BUILT_GRAPHS {
                self.built.clear();
            }
            self.built.push((old_key, old_graph, old_plan));
        }
        Ok(())
    }

    /// Renders `scene` with `ao` from the next frame on (a camera cut: no history carries over).
    /// On an error the renderer keeps its scene.
    pub fn set_scene(&mut self, scene: Arc<Scene>, ao: &AoConfig) -> RenderResult<()> {
        check_intermediate_format(&self.gpu, ao)?;
        ao.validate(&self.registry)?;
        let old_scene = std::mem::replace(&mut self.scene, scene);
        let old_ao = std::mem::replace(&mut self.ao, ao.clone());
        let old_gbuffer = std::mem::take(&mut self.gbuffer);
        let was_gbuffer_only = std::mem::replace(&mut self.gbuffer_only, false);
        if let Err(e) = self.rebuild(true) {
            self.scene = old_scene;
            self.ao = old_ao;
            self.gbuffer = old_gbuffer;
            self.gbuffer_only = was_gbuffer_only;
            return Err(e);
        }
        self.built.clear();
        self.tracing = SceneTracing::default();
        // The old scene's BVH and acceleration structures are released with the bindings
        // that held them; the next frame binds the current plan's inputs again.
        self.exec.clear_plan_bindings();
        self.inputs.remove::<SceneBvh>();
        self.inputs.remove::<SceneAcceleration>();
        self.inputs_bound = None;
        self.gpu
            .queue
            .write_buffer(&self.lighting_buffer, 0, lighting_of(&self.scene).bytes());
        self.cut();
        Ok(())
    }

    /// The scene's BVH, once a graph that traces rays has rendered a frame.
    pub fn scene_bvh(&self) -> Option<&GpuSceneBvh> {
        self.tracing.bvh.as_ref()
    }

    /// What the last frame did to the scene's acceleration structures (builds of BLAS and
    /// TLAS), once a graph tracing on the hardware backend has rendered a frame.
    pub fn acceleration_work(&self) -> Option<AsWork> {
        self.tracing.acceleration_work()
    }

    /// Marks a camera cut: the next frame starts with no history.
    pub fn cut(&mut self) {
        self.cut = true;
        self.prev = None;
        self.exec.reset_history();
    }

    /// Changes the output size (history is invalidated by the executor). The graph is the one
    /// for these settings at this size (automatic level counts depend on it).
    pub fn resize(&mut self, output: Extent) -> RenderResult<()> {
        crate::output_size::check_size("width", output.width)?;
        crate::output_size::check_size("height", output.height)?;
        let old = std::mem::replace(&mut self.output, output);
        if let Err(e) = self.rebuild(false) {
            self.output = old;
            return Err(e);
        }
        Ok(())
    }

    /// Supplies `resources` for the frame input `I` (an application's own, for a technique
    /// that reads it: docs/guide/writing-a-technique.md), bound to every plan that declares it
    /// from the next frame on.
    pub fn bind_input<I: FrameInput>(&mut self, resources: I::Resources)
    where
        I::Resources: Sized + Send + Sync,
    {
        self.inputs.set::<I>(resources);
        self.inputs_bound = None;
    }

    /// Binds the frame inputs the current plan declared; an input nothing supplies is an error
    /// naming it.
    fn bind_inputs(&mut self) -> RenderResult<()> {
        let declared = &self.graph.declared;
        if let Some(input) = self.inputs.missing(declared) {
            return Err(RenderError::InvalidArgument {
                name: "frame input".into(),
                value: format!("{input}, which technique `{}` reads", self.ao.technique),
                allowed: "the inputs the renderer supplies (the View block, the scene's \
                          lighting, BVH and acceleration structures) and those bound with \
                          Renderer::bind_input"
                    .into(),
            });
        }
        self.inputs.bind(&mut self.exec, &self.plan, declared)?;
        self.inputs_bound = Some(self.plan.key());
        Ok(())
    }

    /// Renders the frame at scene time `time` (seconds).
    pub fn render(&mut self, time: f32) -> RenderResult<()> {
        let camera = self.scene.camera_at(time);
        self.render_with_camera(time, camera)
    }

    /// Renders the frame at `time` seen from `camera` (overriding the scene's camera path).
    pub fn render_with_camera(&mut self, time: f32, camera: Camera) -> RenderResult<()> {
        let (prev_time, prev_camera) = self.prev.unwrap_or((time, camera));
        let history_valid = self.exec.all_history_valid(&self.plan, self.output);
        let view = view_uniforms(&ViewFrame {
            camera,
            prev_camera,
            output: self.output,
            frame_index: self.frame_index,
            history_valid: history_valid && !self.cut,
            camera_cut: self.cut,
            time,
            dt: time - prev_time,
        });
        self.gpu
            .queue
            .write_buffer(&self.view_buffer, 0, view.bytes());
        let reversed_z = matches!(
            camera.projection,
            aograph_scene::Projection::Perspective {
                reversed_z_infinite: true,
                ..
            }
        );
        self.graph.clock.set(GBufferFrame {
            time,
            prev_time,
            reversed_z: Some(reversed_z),
        });
        let built = (self.tracing).update(&self.gpu, &self.scene, &self.graph.declared, time)?;
        if built {
            self.tracing.supply(&mut self.inputs);
        }
        if built || self.inputs_bound != Some(self.plan.key()) {
            self.bind_inputs()?;
        }
        self.exec.execute(&self.plan, self.output)?;
        self.prev = Some((time, camera));
        self.cut = false;
        self.time = time;
        self.frame_index = self.frame_index.wrapping_add(1);
        Ok(())
    }

    /// Per-pass times of the last frame. Waits for the GPU to finish it: for one-shot runs and
    /// benchmarks (a real-time loop reads `exec.latest_timings()`, which never waits).
    pub fn timings(&mut self) -> RenderResult<PassTimings> {
        Ok(self.exec.wait_timings()?.clone())
    }

    /// Scene time of the last rendered frame.
    pub fn time(&self) -> f32 {
        self.time
    }

    /// The camera of the last rendered frame.
    pub fn camera(&self) -> Camera {
        self.prev
            .map(|(_, c)| c)
            .unwrap_or_else(|| self.scene.camera_at(self.time))
    }
}
