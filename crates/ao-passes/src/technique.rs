//! The `AoTechnique` plugin interface.
//!
//! A technique is a typed parameter struct (serde, defaults from the paper), one
//! [`ParamDesc`] per parameter (its allowed values and meaning), the g-buffer channels it reads,
//! and a build step that adds its passes to the graph and returns the accessibility texture
//! (R32Float, full output size, 1 = unoccluded). [`DynAoTechnique`] is the object-safe face the
//! registry holds; [`ConfiguredTechnique`] is a technique with its parameters parsed, once.
//! Every typed technique gets both for free.
//!
//! Invariant: a parameter table is parsed and validated once, by [`DynAoTechnique::configure`]
//! (or [`DynAoTechnique::check`]); everything asked of the configured technique afterwards
//! reads the typed parameters it holds.

use aograph_frame::{
    DeclaredInputs, FrameInput, GBufferChannel, GBufferChannels, GBufferTextures,
    SceneAcceleration, SceneBvh, SceneBvhInputs, SceneLighting, SceneTraceInputs,
    intermediate_shader,
};
use aograph_graph::{BufferHandle, GraphBuilder, SizeClass, TextureDesc, TextureHandle};
use serde::Deserialize;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::sync::Arc;

use crate::error::unknown_key;
use crate::error::{AoError, AoResult};
use crate::param::ParamDesc;
use crate::tracer::{RayTracer, TraceBackend, TracingSupport};

/// Format of every technique's accessibility output.
pub const ACCESSIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// What a technique's build step sees.
pub struct AoBuildContext<'a> {
    /// The frame graph the technique adds its passes and textures to.
    pub builder: &'a mut GraphBuilder,
    /// The g-buffer channels written this frame: those the technique's `channels()` asked
    /// for, except motion on a scene where nothing moves (read them with
    /// [`AoBuildContext::channel`]).
    pub gbuffer: GBufferTextures,
    /// The imported per-frame `View` uniform buffer (shaders/common/view.wgsl).
    pub view: BufferHandle,
    /// The shared world-space AO radius R.
    pub radius: f32,
    /// Format of intermediate AO textures (R32Float, or R16Float to save bandwidth). A pass
    /// writing one uses the shader [`AoBuildContext::shader`] names; multi-channel
    /// intermediates use [`AoBuildContext::intermediate_rgba_format`].
    pub intermediate_format: wgpu::TextureFormat,
    /// Name of the technique being built, for error messages.
    pub technique: &'static str,
    /// R projected to full-resolution pixels at the view's closest geometry, at most the
    /// image's diagonal (`aograph_scene::ProjectedRadius::reach_needed_px`), when the graph
    /// is built for a known view (for `levels = "auto"`; see [`crate::Levels`]). Filled in
    /// only for techniques whose [`ConfiguredTechnique::needs_radius_pixels`] says so.
    pub radius_pixels: Option<f32>,
    /// The frame inputs declared so far: the `View` block (declared by whoever builds the
    /// frame, `view` above) and those the build asks for ([`AoBuildContext::input`]); whoever
    /// runs the graph binds what is declared here, per plan, and builds nothing else.
    pub declared: DeclaredInputs,
    /// What the device the graph is built for offers ray tracing (`tracer = "auto"` resolves
    /// against it); the default has no ray queries.
    pub tracing: TracingSupport,
}

impl AoBuildContext<'_> {
    /// The g-buffer channel `c`, or an error naming the technique and the channel.
    pub fn channel(&self, c: GBufferChannel) -> AoResult<TextureHandle> {
        self.gbuffer.get(c).ok_or_else(|| AoError::MissingChannel {
            technique: self.technique.into(),
            channel: c.name().into(),
        })
    }
    /// Frame input `I` (`aograph_frame::FrameInput`): declared the first time a build asks
    /// for it, its handles returned every time; whoever runs the graph binds it, per plan.
    pub fn input<I: FrameInput>(&mut self) -> I::Handles {
        self.declared.declare::<I>(self.builder)
    }
    /// The scene's lighting block (light, ambient, sky: `aograph_frame::LightingUniforms`),
    /// the frame input [`SceneLighting`].
    pub fn scene_lighting(&mut self) -> BufferHandle {
        self.input::<SceneLighting>()
    }
    /// The scene's two-level BVH (shaders/common/bvh.wgsl), the frame input [`SceneBvh`]:
    /// whoever runs the graph builds and binds it only when a build asked for it.
    pub fn scene_bvh(&mut self) -> SceneBvhInputs {
        self.input::<SceneBvh>()
    }
    /// The scene as the ray tracer `tracer` resolves to on this device (`tracer.rs`): the BVH
    /// buffers or the acceleration structures, declared as frame inputs (imported once) that
    /// whoever runs the graph builds and binds (`DeclaredInputs`). Hardware on a device
    /// without ray queries is a named error.
    pub fn scene_trace(&mut self, tracer: RayTracer) -> AoResult<SceneTraceInputs> {
        Ok(match tracer.resolve(&self.tracing, self.technique)? {
            TraceBackend::Compute => SceneTraceInputs::Compute(self.scene_bvh()),
            TraceBackend::Hardware => SceneTraceInputs::Hardware(self.input::<SceneAcceleration>()),
        })
    }
    /// A new full-size accessibility texture.
    pub fn accessibility_texture(&mut self, name: &str) -> TextureHandle {
        self.builder.create_texture(
            name,
            TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
        )
    }
    /// A new intermediate texture at `size` in the intermediate format.
    pub fn intermediate(&mut self, name: &str, size: SizeClass) -> TextureHandle {
        let f = self.intermediate_format;
        self.builder.create_texture(name, TextureDesc::new(f, size))
    }
    /// The four-channel float format at the intermediate precision (Rgba16Float under
    /// R16Float, Rgba32Float otherwise), for intermediates that carry more than accessibility.
    pub fn intermediate_rgba_format(&self) -> wgpu::TextureFormat {
        match self.intermediate_format {
            wgpu::TextureFormat::R16Float => wgpu::TextureFormat::Rgba16Float,
            _ => wgpu::TextureFormat::Rgba32Float,
        }
    }
    /// The shader `file` at the intermediate precision: `file?IntermediateStorage=f16` under
    /// R16Float, `file` itself under R32Float. The file declares its intermediate outputs'
    /// type on one line, `alias IntermediateStorage = texture_storage_2d<r32float, write>;`
    /// (or rgba32float), which the variant rewrites (`aograph_frame::intermediate_shader`).
    pub fn shader(&self, file: &str) -> String {
        intermediate_shader(file, self.intermediate_format)
    }
}

/// What a technique produces.
#[derive(Clone, Debug)]
pub struct AoOutput {
    /// Accessibility in [0, 1], 1 = unoccluded, full output size.
    pub accessibility: TextureHandle,
    /// Radiance, where the technique computes it ([`AoTechnique::radiance`]).
    pub radiance: Option<RadianceOutput>,
    /// Further outputs for inspection (e.g. gtao's bent normals), each under its key.
    pub extra: Vec<(ExtraOutput, TextureHandle)>,
}

/// The key of an extra output: declared once, as a constant beside the technique or block
/// that writes it (`techniques::gtao::BENT_NORMALS_OUTPUT`, [`crate::PER_FRAME_OUTPUT`]), and
/// passed by whoever reads it back (`Renderer::read_extra`). Its name is what files and
/// listings show.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ExtraOutput {
    name: &'static str,
}

impl ExtraOutput {
    /// The key of the extra output named `name` (snake_case, prefixed by the technique).
    pub const fn new(name: &'static str) -> Self {
        Self { name }
    }
    /// Its name, as files and listings show it.
    pub const fn name(self) -> &'static str {
        self.name
    }
}

impl std::fmt::Display for ExtraOutput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name)
    }
}

/// Linear RGB radiance a technique writes besides accessibility (Rgba16Float or Rgba32Float,
/// full size): the direct term and one indirect bounce.
#[derive(Clone, Copy, Debug)]
pub struct RadianceOutput {
    /// Direct radiance: the environment and the directional light reaching the surface past
    /// the technique's occlusion, reflected by the albedo (SSDO's L_dir).
    pub direct: TextureHandle,
    /// One indirect bounce from nearby surfaces (SSDO's L_ind); all zero when the technique
    /// computes no bounce.
    pub indirect: TextureHandle,
}

/// The light a technique's radiance is computed under.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RadianceEnvironment {
    /// The scene's constant ambient (and its directional light).
    Ambient,
    /// The built-in sky (`aograph_scene::SkyEnvironment`), which the radiance reference traces.
    Sky,
}

impl AoOutput {
    /// An output of `accessibility` alone: no radiance, no extra outputs.
    pub fn new(accessibility: TextureHandle) -> Self {
        Self {
            accessibility,
            radiance: None,
            extra: Vec::new(),
        }
    }
    /// The extra output under `key`, if the technique wrote one.
    pub fn extra(&self, key: ExtraOutput) -> Option<TextureHandle> {
        self.extra.iter().find(|(k, _)| *k == key).map(|(_, h)| *h)
    }
}

/// A technique with a typed parameter struct.
pub trait AoTechnique: Send + Sync + 'static {
    /// The typed parameters, deserialised from `[ao.<NAME>]`: one field (or flattened group)
    /// per key of [`AoTechnique::params`], and `Default` holds the paper's values.
    type Params: Serialize + DeserializeOwned + Default + Clone + std::fmt::Debug + Send + Sync;
    /// The registry name (`[ao] technique = "..."`), stated once.
    const NAME: &'static str;
    /// One line saying what the technique is, for the `aograph techniques` listing.
    fn description(&self) -> &'static str;
    /// One description per parameter, in listing order (defaults come from `Params`).
    fn params(&self) -> Vec<ParamDesc>;
    /// Rules across parameters, after each value passed its own description (e.g. "n_smooth at
    /// most n_max"); report them as [`AoError::ParameterRule`].
    fn validate(&self, _params: &Self::Params) -> AoResult<()> {
        Ok(())
    }
    /// The g-buffer channels the technique reads.
    fn channels(&self, params: &Self::Params) -> GBufferChannels;
    /// The parameter setting that drops these parameters' need for `channel`, with why it is
    /// read (`multibounce = false (the multi-bounce fit needs the surface colour)`), for the
    /// error of a frame that cannot supply it (an application's depth buffer has no second
    /// layer, say); `None` when no setting does.
    fn dropping_channel(
        &self,
        _params: &Self::Params,
        _channel: GBufferChannel,
    ) -> Option<&'static str> {
        None
    }
    /// True when the technique keeps history between frames.
    fn is_temporal(&self, _params: &Self::Params) -> bool {
        false
    }
    /// True for the cost floor other techniques are compared with (reports show each
    /// technique's cost above it).
    fn is_baseline(&self) -> bool {
        false
    }
    /// The light of [`AoOutput::radiance`] when the build writes it (radiance under the sky
    /// is scored against the radiance reference); `None` for accessibility only.
    fn radiance(&self, _params: &Self::Params) -> Option<RadianceEnvironment> {
        None
    }
    /// True when the build needs [`AoBuildContext::radius_pixels`] (an automatic level count).
    fn needs_radius_pixels(&self, _params: &Self::Params) -> bool {
        false
    }
    /// How far from a pixel, in full-resolution pixels of an image `height` tall, the
    /// technique samples at most; `None` when it reaches R wherever R projects (it samples R in
    /// view space, uncapped). `radius_pixels` is what [`AoBuildContext::radius_pixels`] would
    /// hold, for automatic level counts.
    fn reach_pixels(
        &self,
        _params: &Self::Params,
        _height: u32,
        _radius_pixels: Option<f32>,
    ) -> Option<f32> {
        None
    }
    /// Adds the technique's passes to `ctx.builder` (named `<NAME>.<pass>`) and returns its
    /// output: accessibility in [0, 1], 1 = unoccluded and exactly 1 on sky, R32Float at the
    /// full output size ([`AoBuildContext::accessibility_texture`]).
    fn build(&self, ctx: &mut AoBuildContext<'_>, params: &Self::Params) -> AoResult<AoOutput>;
}

/// A technique with its parameters parsed and validated: what a frame graph asks of it.
pub trait ConfiguredTechnique: Send + Sync {
    /// The registry name ([`AoTechnique::NAME`]).
    fn name(&self) -> &'static str;
    /// The parameters in effect, defaults included, as a table (for labels and saving).
    fn params_table(&self) -> toml::Table;
    /// The g-buffer channels these parameters read: what the g-buffer must write
    /// ([`AoTechnique::channels`]).
    fn channels(&self) -> GBufferChannels;
    /// The setting that drops these parameters' need for `channel`
    /// ([`AoTechnique::dropping_channel`]).
    fn dropping_channel(&self, channel: GBufferChannel) -> Option<&'static str>;
    /// True when these parameters keep history between frames, so frames are not independent
    /// ([`AoTechnique::is_temporal`]).
    fn is_temporal(&self) -> bool;
    /// True for the cost floor, `none` ([`AoTechnique::is_baseline`]).
    fn is_baseline(&self) -> bool;
    /// See [`AoTechnique::radiance`].
    fn radiance(&self) -> Option<RadianceEnvironment>;
    /// True when [`ConfiguredTechnique::build`] needs [`AoBuildContext::radius_pixels`] filled
    /// in (`levels = "auto"`); see [`AoTechnique::needs_radius_pixels`].
    fn needs_radius_pixels(&self) -> bool;
    /// The farthest the technique samples from a pixel, in full-resolution pixels of an image
    /// `height` tall; `None` when it reaches R wherever R projects
    /// ([`AoTechnique::reach_pixels`]).
    fn reach_pixels(&self, height: u32, radius_pixels: Option<f32>) -> Option<f32>;
    /// Adds the technique's passes with these parameters, `ctx.technique` set to its name
    /// ([`AoTechnique::build`]).
    fn build(&self, ctx: &mut AoBuildContext<'_>) -> AoResult<AoOutput>;
}

/// The object-safe face of a technique, taking parameters as a TOML table.
pub trait DynAoTechnique: Send + Sync {
    /// The registry name ([`AoTechnique::NAME`]).
    fn name(&self) -> &'static str;
    /// One line saying what the technique is ([`AoTechnique::description`]).
    fn description(&self) -> &'static str;
    /// Parameter descriptions with their defaults filled in from the parameter struct.
    fn parameters(&self) -> Vec<ParamDesc>;
    /// `Params::default()` as a table (unset overrides absent).
    fn default_params(&self) -> toml::Table;
    /// See [`AoTechnique::is_baseline`].
    fn is_baseline(&self) -> bool;
    /// Parses and validates `params` (unknown keys and out-of-range values are errors).
    fn check(&self, params: &toml::Table) -> AoResult<()>;
    /// Parses and validates `params` once, into a technique that holds them.
    fn configure(self: Arc<Self>, params: &toml::Table) -> AoResult<Arc<dyn ConfiguredTechnique>>;
}

/// Parses `table` against `t`'s descriptions: unknown keys (with the nearest suggested), each
/// value against its description, then the struct and the cross-field rules.
fn parse<T: AoTechnique>(t: &T, table: &toml::Table) -> AoResult<T::Params> {
    let descs = t.params();
    for (key, value) in table {
        let Some(desc) = descs.iter().find(|d| d.name == key) else {
            let names: Vec<&str> = descs.iter().map(|d| d.name).collect();
            let section = format!("ao.{}", T::NAME);
            return Err(AoError::Config(if names.is_empty() {
                format!("[{section}] takes no parameters; remove `{key}`")
            } else {
                unknown_key(&section, key, &names)
            }));
        };
        desc.check(value)
            .map_err(|allowed| AoError::InvalidParameter {
                technique: T::NAME.into(),
                name: key.clone(),
                value: match value {
                    toml::Value::Float(f) => f.to_string(),
                    v => v.to_string(),
                },
                allowed,
            })?;
    }
    let p = T::Params::deserialize(toml::Value::Table(table.clone()))
        .map_err(|e| AoError::Config(format!("[ao.{}]: {}", T::NAME, e.to_string().trim())))?;
    t.validate(&p)?;
    Ok(p)
}

/// A technique and its parsed parameters.
struct Configured<T: AoTechnique> {
    technique: Arc<T>,
    params: T::Params,
}

impl<T: AoTechnique> ConfiguredTechnique for Configured<T> {
    fn name(&self) -> &'static str {
        T::NAME
    }
    fn params_table(&self) -> toml::Table {
        match toml::Value::try_from(&self.params) {
            Ok(toml::Value::Table(t)) => t,
            _ => toml::Table::new(),
        }
    }
    fn channels(&self) -> GBufferChannels {
        self.technique.channels(&self.params)
    }
    fn dropping_channel(&self, channel: GBufferChannel) -> Option<&'static str> {
        self.technique.dropping_channel(&self.params, channel)
    }
    fn is_temporal(&self) -> bool {
        self.technique.is_temporal(&self.params)
    }
    fn is_baseline(&self) -> bool {
        self.technique.is_baseline()
    }
    fn radiance(&self) -> Option<RadianceEnvironment> {
        self.technique.radiance(&self.params)
    }
    fn needs_radius_pixels(&self) -> bool {
        self.technique.needs_radius_pixels(&self.params)
    }
    fn reach_pixels(&self, height: u32, radius_pixels: Option<f32>) -> Option<f32> {
        self.technique
            .reach_pixels(&self.params, height, radius_pixels)
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>) -> AoResult<AoOutput> {
        ctx.technique = T::NAME;
        self.technique.build(ctx, &self.params)
    }
}

impl<T: AoTechnique> DynAoTechnique for T {
    fn name(&self) -> &'static str {
        T::NAME
    }
    fn description(&self) -> &'static str {
        AoTechnique::description(self)
    }
    fn parameters(&self) -> Vec<ParamDesc> {
        let defaults = self.default_params();
        self.params()
            .into_iter()
            .map(|mut d| {
                d.default = defaults.get(d.name).cloned();
                d
            })
            .collect()
    }
    fn default_params(&self) -> toml::Table {
        match toml::Value::try_from(T::Params::default()) {
            Ok(toml::Value::Table(t)) => t,
            _ => toml::Table::new(),
        }
    }
    fn is_baseline(&self) -> bool {
        AoTechnique::is_baseline(self)
    }
    fn check(&self, params: &toml::Table) -> AoResult<()> {
        parse(self, params).map(|_| ())
    }
    fn configure(self: Arc<Self>, params: &toml::Table) -> AoResult<Arc<dyn ConfiguredTechnique>> {
        let params = parse(self.as_ref(), params)?;
        Ok(Arc::new(Configured {
            technique: self,
            params,
        }))
    }
}
