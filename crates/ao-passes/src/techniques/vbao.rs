//! `vbao`: visibility-bitmask AO (Therrien, Levesque, Gilet 2023; docs/techniques/vbao.md, whose V1-V6
//! numbers the shader cites). GTAO's slices with the two horizons replaced by a 32-bit mask of
//! sectors, and every depth sample a surface of constant thickness T, so light passes behind
//! thin occluders.
//!
//! Passes, in order (the same blocks as gtao, `slices::slice_passes`):
//! 1. `vbao.depth_level1..4`: XeGTAO's depth MIP prefilter (spec §2: bevy's placement), with
//!    XeGTAO's falloff range 0.615 for its weights (the prefilter's own rule; VBAO itself has no
//!    falloff).
//! 2. `vbao.ao` (shaders/ao/vbao/ao.wgsl): S slices x T steps per side at XeGTAO's sample
//!    positions and noise; per tap the arc between its front and its back (V1), mapped to
//!    sector coordinates with the angle normalised by π (V2, the bug bevy shipped until
//!    #25334), the covered sectors set (V3), and accessibility from the unset ones (V4, or V6).
//! 3. `vbao.denoise1..N`: the edge-aware denoiser block, N = 1 to 3 (0: none).
//!
//! Invariant: the output is accessibility in [0, 1], exactly 1 on sky and on an open plane at
//! any tilt (no tap is above the tangent plane, so no sector is set), never NaN.
//!
//! Choices, and why:
//! - Sectors: 32 (the paper's, the blog's and SSRT3's; bevy's 2 x steps is its own, spec §10).
//! - Weighting: `"uniform"` (the default, the blog's and the paper's rule: v = 1 -
//!   popcount / N) or `"cosine"` (V6: each set sector hides its exact share of GTAO's
//!   cosine-weighted measure, so it converges to the reference's measure).
//! - Rounding: `"centre"` (the default): a sector is set when its centre lies in the interval,
//!   which is unbiased; `"ceil"` (the blog's shipped code) sets every sector the interval
//!   touches, adding about half a sector per interval (spec §9-§10).
//! - Thickness is a multiple of R (`thickness = 0.5` is bevy's 0.25 view units at its R of
//!   0.5), so a scene in centimetres keeps its thickness; T = thickness x R.
//! - Radius multiplier 1 and taps farther than R' from the receiver dropped (`clip_to_radius`):
//!   the reference's rays stop at R, and XeGTAO's 1.457 was tuned for a falloff VBAO lacks
//!   (spec §9-§10: bevy's default reaches 1.46 R).
//! - Final power 1 (SSRT3's AOIntensity default; bevy applies none), then bevy's 0.03 floor.
//! - Taps within the g-buffer normals' rounding of the tangent plane set nothing
//!   (common/horizon.wgsl), as gtao and hbao; precise acos for θ and γ alike (spec §10).
//! - `layers = 2` reads the g-buffer's second depth layer (the nearest surface 0.05 R behind
//!   the first; Mara et al. 2016): a tap's back is the second layer's front under it, its real
//!   thickness where the surface is a closed solid (a plate with the floor far behind it reads
//!   as solid down to the floor), and the second layer's own surface sets its arc of thickness
//!   T; where no second layer lies behind a tap, T as before. The g-buffer then draws a second
//!   raster pass (R32Float + a depth buffer: 8 bytes a pixel). Not at `resolution = "half"`.
//! - Not yet: indirect light and the ambient fallback (V5), which need radiance inputs.

use aograph_frame::{GBufferChannel, GBufferChannels};
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use super::depth_and_normals;
use super::slices::{DepthLayers, SliceCounts, SlicePasses, slice_passes};
use crate::blocks::EdgeDenoise;
use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::spatial_options::SpatialOptions;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique};

/// Most sectors per slice: one u32 of bits.
pub const MAX_SECTORS: u32 = 32;
/// XeGTAO's falloff range, for the depth prefilter's weights only.
const PREFILTER_FALLOFF_RANGE: f32 = 0.615;

/// The `vbao` technique (module docs): visibility-bitmask AO, GTAO's slices with a 32-bit
/// sector mask and samples of constant thickness; parameters [`VbaoParams`].
pub struct Vbao;

/// How set sectors become occlusion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SectorWeighting {
    /// Every sector counts 1 / N (V4).
    #[default]
    Uniform,
    /// Each sector counts its share of the cosine-weighted hemisphere (V6).
    Cosine,
}

/// Which sectors an interval sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SectorRounding {
    /// Those whose centre it contains.
    #[default]
    Centre,
    /// Every one it touches (the blog's code).
    Ceil,
}

/// `[ao.vbao]` parameters.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct VbaoParams {
    /// Slices x steps per side, as gtao's presets (bevy's levels): preset, slices, steps.
    #[serde(flatten)]
    pub counts: SliceCounts,
    /// Sectors N per slice.
    pub sectors: u32,
    /// T = thickness x R.
    pub thickness: f32,
    /// R' = R x this.
    pub radius_multiplier: f32,
    /// Drop taps farther than R' from the receiver.
    pub clip_to_radius: bool,
    /// What a set sector hides: 1/N (`"uniform"`, V4) or its share of the cosine-weighted
    /// hemisphere (`"cosine"`, V6, which converges to the reference's measure).
    pub weighting: SectorWeighting,
    /// Which sectors a tap's interval sets: those whose centre it holds (`"centre"`, unbiased)
    /// or every one it touches (`"ceil"`, the blog's code: about half a sector more).
    pub rounding: SectorRounding,
    /// XeGTAO's sample distribution power.
    pub sample_distribution_power: f32,
    /// XeGTAO's depth MIP sampling offset.
    pub depth_mip_offset: f32,
    /// Accessibility^p after the slice average (1: SSRT3's default; bevy applies none).
    pub final_value_power: f32,
    /// Edge-aware 3x3 denoise passes, 0 to 3 (0: none).
    pub denoise_passes: u32,
    /// The denoiser's centre weight on its last pass (1.2).
    pub blur_beta: f32,
    /// `resolution` and the temporal option (crate::SpatialOptions).
    #[serde(flatten)]
    pub spatial: SpatialOptions,
    /// `layers`: 1, or 2 with the g-buffer's second depth layer (crate module docs).
    #[serde(flatten)]
    pub depth_layers: DepthLayers,
}

impl Default for VbaoParams {
    fn default() -> Self {
        Self {
            counts: SliceCounts::default(),
            sectors: MAX_SECTORS,
            thickness: 0.5,
            radius_multiplier: 1.0,
            clip_to_radius: true,
            weighting: SectorWeighting::Uniform,
            rounding: SectorRounding::Centre,
            sample_distribution_power: 2.0,
            depth_mip_offset: 3.30,
            final_value_power: 1.0,
            denoise_passes: 1,
            blur_beta: 1.2,
            spatial: SpatialOptions::default(),
            depth_layers: DepthLayers::default(),
        }
    }
}

impl VbaoParams {
    /// (slices, steps per side) in effect.
    pub fn counts(&self) -> (u32, u32) {
        self.counts.counts()
    }
}

/// The `params` uniform of shaders/ao/vbao/ao.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct VbaoUniform {
    /// Slices S.
    slices: u32,
    /// Steps T per side.
    steps: u32,
    _pad0: u32,
    /// Sectors N.
    sectors: u32,
    /// R' (view units).
    effect_radius: f32,
    /// Thickness T (view units).
    thickness: f32,
    /// Sample distribution power.
    sample_distribution_power: f32,
    /// Depth MIP sampling offset.
    depth_mip_offset: f32,
    /// Final value power.
    final_value_power: f32,
    /// Weighting: 1.0 cosine, 0.0 uniform.
    cosine_weighting: f32,
    /// Sector rounding: 1.0 centre, 0.0 ceil.
    centre_rounding: f32,
    /// 1.0: taps farther than R' are dropped.
    clip_to_radius: f32,
}

aograph_graph::uniform_layout!(VbaoUniform {
    slices,
    steps,
    _pad0,
    sectors,
    effect_radius,
    thickness,
    sample_distribution_power,
    depth_mip_offset,
    final_value_power,
    cosine_weighting,
    centre_rounding,
    clip_to_radius
});

impl AoTechnique for Vbao {
    type Params = VbaoParams;
    const NAME: &'static str = "vbao";
    fn description(&self) -> &'static str {
        "visibility-bitmask AO: GTAO's slices with 32 sectors per slice, samples of constant thickness, uniform or cosine sector weights"
    }
    fn params(&self) -> Vec<ParamDesc> {
        let mut d = SliceCounts::params();
        d.extend([
            ParamDesc::int("sectors", 1, MAX_SECTORS).doc("sectors N per slice (the paper's 32)"),
            ParamDesc::float("thickness", 0.01, 100.0)
                .doc("every sample is a surface this many R thick along the view ray"),
            ParamDesc::float("radius_multiplier", 0.3, 3.0).doc("R' = R x this"),
            ParamDesc::flag("clip_to_radius").doc(
                "drop samples farther than R' from the receiver (the reference's hard radius)",
            ),
            ParamDesc::choice("weighting", &["uniform", "cosine"]).doc(
                "a set sector hides 1/N (the blog) or its share of the cosine-weighted hemisphere",
            ),
            ParamDesc::choice("rounding", &["centre", "ceil"]).doc(
                "an interval sets the sectors whose centre it holds, or every sector it touches (the blog's code)",
            ),
            ParamDesc::float("sample_distribution_power", 1.0, 3.0)
                .doc("step s = ((j + jitter) / T)^p (XeGTAO)"),
            ParamDesc::float("depth_mip_offset", 2.0, 6.0)
                .doc("a tap at d pixels reads depth MIP log2(d) - this"),
            ParamDesc::float("final_value_power", 0.5, 5.0).doc("accessibility^p"),
            ParamDesc::int("denoise_passes", 0, 3).doc("edge-aware 3x3 passes (0: none)"),
            ParamDesc::float("blur_beta", 0.01, 1e4)
                .doc("the denoiser's centre weight on its last pass"),
        ]);
        d.push(DepthLayers::param());
        d.extend(SpatialOptions::params());
        d
    }
    fn validate(&self, p: &VbaoParams) -> AoResult<()> {
        p.depth_layers.validate(Self::NAME, p.spatial.resolution)
    }
    fn channels(&self, p: &VbaoParams) -> GBufferChannels {
        p.spatial
            .channels(p.depth_layers.channels(depth_and_normals()))
    }
    fn dropping_channel(&self, p: &VbaoParams, channel: GBufferChannel) -> Option<&'static str> {
        p.depth_layers.dropping(channel)
    }
    fn is_temporal(&self, p: &VbaoParams) -> bool {
        p.spatial.is_temporal()
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &VbaoParams) -> AoResult<AoOutput> {
        let effect_radius = ctx.radius * p.radius_multiplier;
        let (slices, steps) = p.counts();
        let uniform = VbaoUniform {
            slices,
            steps,
            _pad0: 0,
            sectors: p.sectors,
            effect_radius,
            thickness: p.thickness * ctx.radius,
            sample_distribution_power: p.sample_distribution_power,
            depth_mip_offset: p.depth_mip_offset,
            final_value_power: p.final_value_power,
            cosine_weighting: (p.weighting == SectorWeighting::Cosine) as u32 as f32,
            centre_rounding: (p.rounding == SectorRounding::Centre) as u32 as f32,
            clip_to_radius: p.clip_to_radius as u32 as f32,
        };
        let slices = SlicePasses {
            prefix: "vbao",
            shader: "ao/vbao/ao.wgsl",
            uniform: &uniform,
            loads_per_pixel: 6.0 + 2.0 * (slices * steps) as f32,
            effect_radius,
            falloff_range: PREFILTER_FALLOFF_RANGE,
            denoise: EdgeDenoise {
                passes: p.denoise_passes,
                blur_beta: p.blur_beta,
            },
            extra_output: None,
            accumulation: p.spatial.accumulation,
            layers: p.depth_layers,
        };
        // At the chosen resolution, then the optional running mean (crate::SpatialOptions).
        p.spatial
            .build(ctx, depth_and_normals(), |ctx| slice_passes(ctx, &slices))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_frame::GBufferChannel;

    #[test]
    fn reads_depth_and_normals_and_shares_gtaos_presets() {
        let p: VbaoParams = toml::from_str("preset = \"ultra\"").unwrap();
        assert_eq!(p.counts(), (9, 3));
        let c = AoTechnique::channels(&Vbao, &p);
        assert_eq!(
            c.iter().collect::<Vec<_>>(),
            [GBufferChannel::LinearDepth, GBufferChannel::Normals]
        );
    }
}
