//! `vbao`: visibility-bitmask AO (Therrien, Levesque, Gilet 2023; specs/vbao.md, whose V1-V6
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
//! - Not yet: indirect light and the ambient fallback (V5), which need radiance inputs.

use crate::ParamSpec;
use aograph_frame::{GBufferChannel, GBufferChannels};
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use super::gtao::{GtaoPreset, MAX_SLICES, MAX_STEPS};
use super::slices::{SlicePasses, slice_passes};
use crate::blocks::EdgeDenoise;
use crate::error::{AoResult, check_param};
use crate::technique::{AoBuildContext, AoOutput, AoTechnique, spec};

/// Most sectors per slice: one u32 of bits.
pub const MAX_SECTORS: u32 = 32;
/// XeGTAO's falloff range, for the depth prefilter's weights only.
const PREFILTER_FALLOFF_RANGE: f32 = 0.615;

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
#[serde(deny_unknown_fields, default)]
pub struct VbaoParams {
    /// Slices x steps per side, as gtao's presets (bevy's levels).
    pub preset: GtaoPreset,
    pub slices: Option<u32>,
    pub steps: Option<u32>,
    /// Sectors N per slice.
    pub sectors: u32,
    /// T = thickness x R.
    pub thickness: f32,
    /// R' = R x this.
    pub radius_multiplier: f32,
    /// Drop taps farther than R' from the receiver.
    pub clip_to_radius: bool,
    pub weighting: SectorWeighting,
    pub rounding: SectorRounding,
    /// XeGTAO's sample distribution power.
    pub sample_distribution_power: f32,
    /// XeGTAO's depth MIP sampling offset.
    pub depth_mip_offset: f32,
    pub final_value_power: f32,
    pub denoise_passes: u32,
    pub blur_beta: f32,
}

impl Default for VbaoParams {
    fn default() -> Self {
        Self {
            preset: GtaoPreset::High,
            slices: None,
            steps: None,
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
        }
    }
}

impl VbaoParams {
    /// (slices, steps per side) in effect.
    pub fn counts(&self) -> (u32, u32) {
        let (s, t) = self.preset.counts();
        (self.slices.unwrap_or(s), self.steps.unwrap_or(t))
    }
}

/// The `params` uniform of shaders/ao/vbao/ao.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct VbaoUniform {
    /// S, T, unused, N
    counts: [u32; 4],
    /// R', T (view units), sample distribution power, depth MIP offset
    shape: [f32; 4],
    /// final power, cosine (1) or uniform (0), centre rounding (1) or ceil (0), clip (1)
    tail: [f32; 4],
}

impl AoTechnique for Vbao {
    type Params = VbaoParams;
    fn name(&self) -> &'static str {
        "vbao"
    }
    fn description(&self) -> &'static str {
        "visibility-bitmask AO: GTAO's slices with 32 sectors per slice, samples of constant thickness, uniform or cosine sector weights"
    }
    fn param_specs(&self) -> Vec<ParamSpec> {
        vec![
            spec(
                "preset",
                "\"low\", \"medium\", \"high\" or \"ultra\"",
                "slices x steps per side: 1x2, 2x2, 3x3, 9x3 (bevy's levels)",
            ),
            ParamSpec {
                default: "the preset's".into(),
                ..spec(
                    "slices",
                    &format!("1 to {MAX_SLICES}"),
                    "slices S per pixel",
                )
            },
            ParamSpec {
                default: "the preset's".into(),
                ..spec(
                    "steps",
                    &format!("1 to {MAX_STEPS}"),
                    "steps T per side of a slice",
                )
            },
            spec(
                "sectors",
                &format!("1 to {MAX_SECTORS}"),
                "sectors N per slice (the paper's 32)",
            ),
            spec(
                "thickness",
                "0.01 to 100",
                "every sample is a surface this many R thick along the view ray",
            ),
            spec("radius_multiplier", "0.3 to 3", "R' = R x this"),
            spec(
                "clip_to_radius",
                "true or false",
                "drop samples farther than R' from the receiver (the reference's hard radius)",
            ),
            spec(
                "weighting",
                "\"uniform\" or \"cosine\"",
                "a set sector hides 1/N (the blog) or its share of the cosine-weighted hemisphere",
            ),
            spec(
                "rounding",
                "\"centre\" or \"ceil\"",
                "an interval sets the sectors whose centre it holds, or every sector it touches (the blog's code)",
            ),
            spec(
                "sample_distribution_power",
                "1 to 3",
                "step s = ((j + jitter) / T)^p (XeGTAO)",
            ),
            spec(
                "depth_mip_offset",
                "2 to 6",
                "a tap at d pixels reads depth MIP log2(d) - this",
            ),
            spec("final_value_power", "0.5 to 5", "accessibility^p"),
            spec(
                "denoise_passes",
                "0 to 3",
                "edge-aware 3x3 passes (0: none)",
            ),
            spec(
                "blur_beta",
                "0.01 to 10000",
                "the denoiser's centre weight on its last pass",
            ),
        ]
    }
    fn validate(&self, p: &VbaoParams) -> AoResult<()> {
        let (slices, steps) = p.counts();
        check_param("vbao", "slices", slices, 1, MAX_SLICES)?;
        check_param("vbao", "steps", steps, 1, MAX_STEPS)?;
        check_param("vbao", "sectors", p.sectors, 1, MAX_SECTORS)?;
        check_param("vbao", "thickness", p.thickness, 0.01, 100.0)?;
        check_param("vbao", "radius_multiplier", p.radius_multiplier, 0.3, 3.0)?;
        check_param(
            "vbao",
            "sample_distribution_power",
            p.sample_distribution_power,
            1.0,
            3.0,
        )?;
        check_param("vbao", "depth_mip_offset", p.depth_mip_offset, 2.0, 6.0)?;
        check_param("vbao", "final_value_power", p.final_value_power, 0.5, 5.0)?;
        check_param("vbao", "denoise_passes", p.denoise_passes, 0, 3)?;
        check_param("vbao", "blur_beta", p.blur_beta, 0.01, 1e4)
    }
    fn channels(&self, _: &VbaoParams) -> GBufferChannels {
        GBufferChannels::of(&[GBufferChannel::LinearDepth, GBufferChannel::Normals])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &VbaoParams) -> AoResult<AoOutput> {
        let effect_radius = ctx.radius * p.radius_multiplier;
        let (slices, steps) = p.counts();
        let uniform = VbaoUniform {
            counts: [slices, steps, 0, p.sectors],
            shape: [
                effect_radius,
                p.thickness * ctx.radius,
                p.sample_distribution_power,
                p.depth_mip_offset,
            ],
            tail: [
                p.final_value_power,
                (p.weighting == SectorWeighting::Cosine) as u32 as f32,
                (p.rounding == SectorRounding::Centre) as u32 as f32,
                p.clip_to_radius as u32 as f32,
            ],
        };
        slice_passes(
            ctx,
            &SlicePasses {
                prefix: "vbao",
                shader: "ao/vbao/ao.wgsl",
                uniform: bytemuck::bytes_of(&uniform),
                loads_per_pixel: 6.0 + 2.0 * (slices * steps) as f32,
                effect_radius,
                falloff_range: PREFILTER_FALLOFF_RANGE,
                denoise: EdgeDenoise {
                    passes: p.denoise_passes,
                    blur_beta: p.blur_beta,
                },
                extra_output: None,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AoError, DynAoTechnique};

    #[test]
    fn out_of_range_parameters_name_the_range() {
        for (key, value, range) in [
            ("sectors", "0", "1 to 32"),
            ("sectors", "33", "1 to 32"),
            ("thickness", "0", "0.01 to 100"),
            ("thickness", "-1", "0.01 to 100"),
            ("radius_multiplier", "9", "0.3 to 3"),
            ("slices", "40", "1 to 32"),
            ("denoise_passes", "5", "0 to 3"),
        ] {
            let e = Vbao
                .check(&format!("{key} = {value}").parse().unwrap())
                .unwrap_err();
            assert!(
                matches!(e, AoError::InvalidParameter { .. }),
                "{key} = {value}: {e}"
            );
            let msg = e.to_string();
            assert!(msg.contains(key) && msg.contains(range), "{msg}");
        }
        for (key, value, names) in [
            ("weighting", "\"cos\"", ["uniform", "cosine"]),
            ("rounding", "\"floor\"", ["centre", "ceil"]),
        ] {
            let e = Vbao
                .check(&format!("{key} = {value}").parse().unwrap())
                .unwrap_err()
                .to_string();
            assert!(e.contains(names[0]) && e.contains(names[1]), "{e}");
        }
    }

    #[test]
    fn every_parameter_has_a_spec_and_default() {
        let specs = DynAoTechnique::parameters(&Vbao);
        let defaults = toml::Value::try_from(VbaoParams::default()).unwrap();
        for key in defaults.as_table().unwrap().keys() {
            assert!(specs.iter().any(|s| s.name == key), "{key} has no spec");
        }
        assert_eq!(specs.len(), 14);
        assert!(specs.iter().all(|s| !s.default.is_empty()), "{specs:?}");
    }

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
