//! What the slice-based techniques (`gtao`, `vbao`) share on the Rust side, as
//! shaders/common/slices.wgsl does in WGSL: their pass sequence. XeGTAO's depth MIP prefilter
//! (`<prefix>.depth_level1..4`, docs/techniques/gtao.md §4), the technique's AO pass over the 5 MIP
//! levels and the normals (`<prefix>.ao`: raw accessibility, the denoiser's edges, and an
//! optional extra output), then the edge-aware denoiser (`<prefix>.denoise1..N`, §6).
//! Invariant: the AO pass's bindings are slices.wgsl's plus `params` (1), `ao` (8), `edges`
//! (9) and the extra output's; the returned accessibility is R32Float at full size.

use aograph_frame::GBufferChannel;
use aograph_frame::ReadsView;
use aograph_graph::{SizeClass, TextureDesc, UniformLayout};
use serde::{Deserialize, Serialize};

use crate::blocks::{EdgeDenoise, depth_prefilter, edge_denoise};
use crate::error::{AoError, AoResult};
use crate::param::ParamDesc;
use crate::resolution::Resolution;
use crate::technique::{AoBuildContext, AoOutput, ExtraOutput};
use crate::temporal_option::TemporalOption;
use aograph_frame::GBufferChannels;

/// Depth MIP levels, level 0 included (XeGTAO: 5).
pub const DEPTH_MIP_LEVELS: u32 = 5;

/// Largest slice count S.
pub const MAX_SLICES: u32 = 32;
/// Largest step count T per side of a slice.
pub const MAX_STEPS: u32 = 32;

/// XeGTAO's quality presets (docs/techniques/gtao.md §8).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GtaoPreset {
    /// 1 slice x 2 steps per side.
    Low,
    /// 2 x 2.
    Medium,
    /// 3 x 3, XeGTAO's default.
    #[default]
    High,
    /// 9 x 3.
    Ultra,
}

impl GtaoPreset {
    /// The serde names, in order.
    pub const NAMES: &'static [&'static str] = &["low", "medium", "high", "ultra"];
    /// (slices, steps per side).
    pub fn counts(self) -> (u32, u32) {
        match self {
            GtaoPreset::Low => (1, 2),
            GtaoPreset::Medium => (2, 2),
            GtaoPreset::High => (3, 3),
            GtaoPreset::Ultra => (9, 3),
        }
    }
}

/// The parameter set the slice techniques share, flattened into each one's table: a preset
/// and two overrides of its counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SliceCounts {
    /// XeGTAO's quality preset: slices x steps per side, 1x2, 2x2, 3x3 (default) or 9x3.
    pub preset: GtaoPreset,
    /// Overrides the preset's slice count.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slices: Option<u32>,
    /// Overrides the preset's steps per side.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps: Option<u32>,
}

impl SliceCounts {
    /// (slices, steps per side) in effect: the overrides, else the preset's.
    pub fn counts(&self) -> (u32, u32) {
        let (s, t) = self.preset.counts();
        (self.slices.unwrap_or(s), self.steps.unwrap_or(t))
    }
    /// The descriptions of `preset`, `slices` and `steps`.
    pub fn params() -> Vec<ParamDesc> {
        vec![
            ParamDesc::choice("preset", GtaoPreset::NAMES).doc(
                "slices x steps per side: 1x2, 2x2, 3x3, 9x3 (XeGTAO's presets, bevy's levels)",
            ),
            ParamDesc::int("slices", 1, MAX_SLICES)
                .unset("the preset's")
                .doc("slices S per pixel"),
            ParamDesc::int("steps", 1, MAX_STEPS)
                .unset("the preset's")
                .doc("steps T per side of a slice"),
        ]
    }
}

/// Δ of the second depth layer, in units of R: the nearest surface at least 0.05 R behind the
/// first (the separation the two-layer ceiling of `aograph_scene::reference::ceilings` uses,
/// so the techniques read the layer the ceiling measured; Mara et al. 2016 §2 leave Δ to the
/// scene).
pub const SECOND_LAYER_SEPARATION: f32 = 0.05;

/// `layers = 1 | 2` of the slice techniques (gtao, vbao): with 2 they also read the g-buffer's
/// second depth layer (`GBufferChannel::SecondLayerDepth`, Mara, McGuire, Nowrouzezahrai,
/// Luebke 2016), which the g-buffer then draws in a second raster pass; each technique's docs
/// say what it does with it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DepthLayers {
    /// 1 (the depth buffer alone) or 2 (and the second layer).
    pub layers: u32,
}

impl Default for DepthLayers {
    fn default() -> Self {
        Self { layers: 1 }
    }
}

impl DepthLayers {
    /// Whether the second layer is read.
    pub fn two(&self) -> bool {
        self.layers == 2
    }
    /// The parameter's description.
    pub fn param() -> ParamDesc {
        ParamDesc::int("layers", 1, 2).doc(
            "depth layers read: 1, or 2 with the second layer (the nearest surface 0.05 R behind the first, drawn in a second g-buffer pass)",
        )
    }
    /// The setting that drops the need for `channel`: `layers = 1` for the second layer when
    /// two are read ([`crate::AoTechnique::dropping_channel`]).
    pub fn dropping(&self, channel: GBufferChannel) -> Option<&'static str> {
        (self.two() && channel == GBufferChannel::SecondLayerDepth).then_some(
            "layers = 1 (the second depth layer is drawn by aograph's own g-buffer; a depth \
             buffer holds one)",
        )
    }
    /// `channels` with the second layer when two are read.
    pub fn channels(&self, channels: GBufferChannels) -> GBufferChannels {
        if self.two() {
            channels.with_second_layer(SECOND_LAYER_SEPARATION)
        } else {
            channels
        }
    }
    /// The rule across parameters: the half-resolution g-buffer has no second layer.
    pub fn validate(&self, technique: &str, resolution: Resolution) -> AoResult<()> {
        if self.two() && resolution != Resolution::Full {
            return Err(AoError::ParameterRule {
                technique: technique.into(),
                rule: "layers = 2 needs resolution = \"full\": the half-resolution g-buffer \
                       has no second layer"
                    .into(),
            });
        }
        Ok(())
    }
}

/// A further storage output of a slice technique's AO pass.
pub(crate) struct SliceExtra {
    /// The shader's binding name.
    pub binding: &'static str,
    /// Its key in [`AoOutput::extra`].
    pub output: ExtraOutput,
    pub format: wgpu::TextureFormat,
}

/// What a slice-based technique (gtao, vbao) hands to [`slice_passes`].
pub(crate) struct SlicePasses<'a, U: UniformLayout> {
    pub prefix: &'static str,
    /// The AO pass's shader: its bindings are shaders/common/slices.wgsl's plus `params` (1),
    /// `ao` (8) and `edges` (9).
    pub shader: &'static str,
    /// Its `params` uniform (checked against the shader's struct at compile).
    pub uniform: &'a U,
    /// R' (view units) and the falloff range, for the depth prefilter's weights.
    pub effect_radius: f32,
    pub falloff_range: f32,
    /// The denoiser (0 passes: the AO pass writes the output).
    pub denoise: EdgeDenoise,
    /// A further texture the AO pass writes (gtao's bent normals).
    pub extra_output: Option<SliceExtra>,
    /// Texel loads of the AO pass per pixel (for the bench's roofline): the centre's depth,
    /// normal and four edge neighbours, and two depth taps per step and slice.
    pub loads_per_pixel: f32,
    /// The technique's temporal option: its noise follows the frame when it accumulates.
    pub accumulation: TemporalOption,
    /// Depth layers read (`layers = 2`: the second layer too, binding 11, `SECOND_LAYER`).
    pub layers: DepthLayers,
}

/// The passes every slice-based technique runs: `<prefix>.depth_level1..4` (XeGTAO's depth
/// MIP prefilter, §4), `<prefix>.ao` (the technique's estimator over 5 MIP levels and the
/// normals; writes the raw accessibility and the edges), then `<prefix>.denoise1..N` (§6).
pub(crate) fn slice_passes(
    ctx: &mut AoBuildContext<'_>,
    s: &SlicePasses<'_, impl UniformLayout>,
) -> AoResult<AoOutput> {
    let depth = ctx.channel(GBufferChannel::LinearDepth)?;
    let normals = ctx.channel(GBufferChannel::Normals)?;
    // One-layer plans bind the first layer in the second's place and never read it.
    let second_layer = if s.layers.two() {
        Some(ctx.channel(GBufferChannel::SecondLayerDepth)?)
    } else {
        None
    };
    let mips = depth_prefilter(
        ctx.builder,
        s.prefix,
        depth,
        DEPTH_MIP_LEVELS,
        s.effect_radius,
        s.falloff_range,
    )?;
    let last = s.denoise.passes == 0;
    let (raw, shader) = if last {
        (
            ctx.accessibility_texture(&format!("{}.accessibility", s.prefix)),
            s.shader.to_string(),
        )
    } else {
        (
            ctx.intermediate(&format!("{}.raw", s.prefix), SizeClass::FULL),
            ctx.shader(s.shader),
        )
    };
    let edges = ctx.builder.create_texture(
        &format!("{}.edges", s.prefix),
        TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
    );
    let extra = s.extra_output.as_ref().map(|e| {
        let t = ctx.builder.create_texture(
            &format!("{}.{}", s.prefix, e.binding),
            TextureDesc::new(e.format, SizeClass::FULL),
        );
        (e.output, t, e.binding)
    });
    let mut pass = ctx
        .builder
        .compute_pass(&format!("{}.ao", s.prefix), &shader, "main");
    pass.read_view(ctx.view);
    pass.uniform_struct("params", s.uniform);
    for (l, binding) in ["depth0", "depth1", "depth2", "depth3", "depth4"]
        .iter()
        .enumerate()
    {
        pass.sample(binding, mips.level(l));
    }
    pass.sample("normals", normals)
        .loads_per_invocation(s.loads_per_pixel);
    pass.sample("second_layer", second_layer.unwrap_or(mips.level(0)));
    if s.layers.two() {
        pass.constant("SECOND_LAYER", 1.0);
    }
    s.accumulation.vary_noise(&mut pass);
    let raw = pass.write_storage("ao", raw);
    let edges = pass.write_storage("edges", edges);
    let mut extras = Vec::new();
    if let Some((name, t, binding)) = extra {
        extras.push((name, pass.write_storage(binding, t)));
    }
    pass.dispatch_over(raw);
    if last {
        return Ok(AoOutput {
            accessibility: raw,
            radiance: None,
            extra: extras,
        });
    }
    let out = edge_denoise(
        ctx.builder,
        s.prefix,
        raw,
        edges,
        depth,
        &s.denoise,
        ctx.intermediate_format,
    )?;
    Ok(AoOutput {
        accessibility: out,
        radiance: None,
        extra: extras,
    })
}
