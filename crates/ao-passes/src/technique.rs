//! The `AoTechnique` plugin interface.
//!
//! A technique is a typed parameter struct (serde, `deny_unknown_fields`, defaults from the
//! paper), a validation with allowed ranges, the g-buffer channels it reads, and a build step
//! that adds its passes to the graph and returns the accessibility texture (R32Float, full
//! output size, 1 = unoccluded). [`DynAoTechnique`] is the object-safe face the registry holds;
//! every typed technique gets it for free.

use aograph_frame::{GBufferChannel, GBufferChannels, GBufferTextures, intermediate_shader};
use aograph_graph::{BufferHandle, GraphBuilder, SizeClass, TextureDesc, TextureHandle};
use serde::Deserialize;
use serde::Serialize;
use serde::de::DeserializeOwned;

use crate::error::{AoError, AoResult};

/// One parameter of a technique, for listings, the viewer's controls and error messages.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    pub name: &'static str,
    pub default: String,
    pub allowed: String,
    pub doc: &'static str,
}

/// Format of every technique's accessibility output.
pub const ACCESSIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// What a technique's build step sees.
pub struct AoBuildContext<'a> {
    pub builder: &'a mut GraphBuilder,
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
    /// R projected to full-resolution pixels at the view's nearest geometry, when the graph
    /// is built for a known view (for `levels = "auto"`; see [`crate::Levels`]). Filled in
    /// only for techniques whose [`DynAoTechnique::needs_radius_pixels`] says so.
    pub radius_pixels: Option<f32>,
}

impl AoBuildContext<'_> {
    /// The g-buffer channel `c`, or an error naming the technique and the channel.
    pub fn channel(&self, c: GBufferChannel) -> AoResult<TextureHandle> {
        self.gbuffer.get(c).ok_or_else(|| AoError::MissingChannel {
            technique: self.technique.into(),
            channel: c.name().into(),
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
    /// Further named outputs (e.g. SSDO's radiance).
    pub extra: Vec<(String, TextureHandle)>,
}

impl AoOutput {
    pub fn new(accessibility: TextureHandle) -> Self {
        Self {
            accessibility,
            extra: Vec::new(),
        }
    }
}

/// A technique with a typed parameter struct.
pub trait AoTechnique: Send + Sync + 'static {
    type Params: Serialize + DeserializeOwned + Default + Clone + std::fmt::Debug;
    /// The registry name (`[ao] technique = "..."`).
    fn name(&self) -> &'static str;
    fn description(&self) -> &'static str;
    /// Every parameter with its allowed range and meaning (defaults come from `Params`).
    fn param_specs(&self) -> Vec<ParamSpec>;
    fn validate(&self, params: &Self::Params) -> AoResult<()>;
    /// The g-buffer channels the technique reads.
    fn channels(&self, params: &Self::Params) -> GBufferChannels;
    /// True when the technique keeps history between frames.
    fn is_temporal(&self, _params: &Self::Params) -> bool {
        false
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
    fn build(&self, ctx: &mut AoBuildContext<'_>, params: &Self::Params) -> AoResult<AoOutput>;
}

/// The object-safe face of a technique, taking parameters as a TOML table.
pub trait DynAoTechnique: Send + Sync {
    fn name(&self) -> &'static str;
    fn description(&self) -> &'static str;
    /// Parameters with defaults filled in from the parameter struct.
    fn parameters(&self) -> Vec<ParamSpec>;
    /// Parses and validates `params` (unknown keys and out-of-range values are errors).
    fn check(&self, params: &toml::Table) -> AoResult<()>;
    fn channels(&self, params: &toml::Table) -> AoResult<GBufferChannels>;
    fn is_temporal(&self, params: &toml::Table) -> AoResult<bool>;
    /// See [`AoTechnique::needs_radius_pixels`].
    fn needs_radius_pixels(&self, params: &toml::Table) -> AoResult<bool>;
    /// See [`AoTechnique::reach_pixels`].
    fn reach_pixels(
        &self,
        params: &toml::Table,
        height: u32,
        radius_pixels: Option<f32>,
    ) -> AoResult<Option<f32>>;
    fn build(&self, ctx: &mut AoBuildContext<'_>, params: &toml::Table) -> AoResult<AoOutput>;
}

fn parse<T: AoTechnique>(t: &T, params: &toml::Table) -> AoResult<T::Params> {
    let p: T::Params = T::Params::deserialize(toml::Value::Table(params.clone())).map_err(|e| {
        let allowed: Vec<&str> = t.param_specs().iter().map(|s| s.name).collect();
        AoError::Config(format!(
            "[ao.{}]: {} (parameters: {})",
            t.name(),
            e.to_string().trim(),
            allowed.join(", ")
        ))
    })?;
    t.validate(&p)?;
    Ok(p)
}

impl<T: AoTechnique> DynAoTechnique for T {
    fn name(&self) -> &'static str {
        AoTechnique::name(self)
    }
    fn description(&self) -> &'static str {
        AoTechnique::description(self)
    }
    fn parameters(&self) -> Vec<ParamSpec> {
        let defaults = toml::Value::try_from(T::Params::default()).ok();
        self.param_specs()
            .into_iter()
            .map(|mut s| {
                if let Some(v) = defaults.as_ref().and_then(|d| d.get(s.name)) {
                    // Parameters are f32: print the f32, not its widened f64 (0.03, not 0.0299999...).
                    s.default = match v {
                        toml::Value::Float(f) => format!("{:?}", *f as f32),
                        other => other.to_string(),
                    };
                }
                s
            })
            .collect()
    }
    fn check(&self, params: &toml::Table) -> AoResult<()> {
        parse(self, params).map(|_| ())
    }
    fn channels(&self, params: &toml::Table) -> AoResult<GBufferChannels> {
        Ok(AoTechnique::channels(self, &parse(self, params)?))
    }
    fn is_temporal(&self, params: &toml::Table) -> AoResult<bool> {
        Ok(AoTechnique::is_temporal(self, &parse(self, params)?))
    }
    fn needs_radius_pixels(&self, params: &toml::Table) -> AoResult<bool> {
        Ok(AoTechnique::needs_radius_pixels(
            self,
            &parse(self, params)?,
        ))
    }
    fn reach_pixels(
        &self,
        params: &toml::Table,
        height: u32,
        radius_pixels: Option<f32>,
    ) -> AoResult<Option<f32>> {
        Ok(AoTechnique::reach_pixels(
            self,
            &parse(self, params)?,
            height,
            radius_pixels,
        ))
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, params: &toml::Table) -> AoResult<AoOutput> {
        let p = parse(self, params)?;
        AoTechnique::build(self, ctx, &p)
    }
}

/// A `ParamSpec` with the default left for [`DynAoTechnique::parameters`] to fill.
pub fn spec(name: &'static str, allowed: &str, doc: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        default: String::new(),
        allowed: allowed.to_string(),
        doc,
    }
}
