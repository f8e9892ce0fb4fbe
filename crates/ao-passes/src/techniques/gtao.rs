//! `gtao`: ground-truth AO (Jimenez, Wu, Pesce, Jarabo 2016) as Intel's XeGTAO computes it
//! (docs/techniques/gtao.md; its equation numbers G1-G6 are the spec's own, the paper's body was not
//! available to it). Cosine-weighted AO with the inner integral per slice in closed form.
//!
//! Passes, in order:
//! 1. `gtao.depth_level1..4`: XeGTAO's depth MIP prefilter, 5 levels with level 0 the
//!    g-buffer's linear depth (the shared block `blocks::depth_prefilter`, spec §4).
//! 2. `gtao.ao` (shaders/ao/gtao/ao.wgsl over ao/gtao/estimator.wgsl): S slices x T steps per side; horizon search with
//!    XeGTAO's falloff towards the tangent horizon (G3), the analytic inner integral (G5),
//!    weighted by the projected normal's length (G6); writes the raw accessibility and the
//!    depth-edge weights (`gtao.edges`, Rgba8Unorm, XeGTAO's 2-bit quantisation).
//! 3. `gtao.denoise1..N`: XeGTAO's edge-aware 3x3 denoiser, N = 1 to 3 (the shared block
//!    `blocks::edge_denoise`, spec §6); 0 skips it and `gtao.ao` writes the output.
//! 4. `gtao.multibounce`, only with `multibounce = true`.
//!
//! Invariant: the output is accessibility in [0, 1], exactly 1 on sky, never NaN; an open
//! plane at any tilt is exactly 1 under the default normalisation (tests/technique_gtao.rs).
//!
//! Constants (XeGTAO v1.30, spec §2-§3): radius multiplier 1.457, falloff range 0.615,
//! sample distribution power 2, thin-occluder compensation 0, final value power 2.2, depth
//! MIP sampling offset 3.30 (the code's, not the README's stale 3.15), projected-normal fudge
//! 0.05, the 0.03 visibility floor, the 1.3-pixel "too close" threshold and the small-radius
//! fade. Presets (slices x steps per side): low 1x2, medium 2x2, high 3x3 (default), ultra
//! 9x3 (spec §8).
//!
//! Choices where the spec leaves room, and why:
//! - Normalisation (G6). XeGTAO divides the slice sum by S. With few slices that makes an
//!   open but tilted plane read anywhere from 0.62 to 1.57 per pixel (one slice; 0.97 to 1.04
//!   at three), which the denoiser then has to average away and the clamp to 1 biases low.
//!   The default, `normalization = "unoccluded"`, divides instead by the same sum for an open
//!   hemisphere, Σ ‖n_p‖ (cos γ + γ sin γ), known per slice in closed form (spec §1.4): a
//!   ratio estimator, consistent as S grows (the open sum's mean is exactly S, spec §1.4), and
//!   exact wherever nothing occludes. A view along n (γ = 0) gives both the same answer, so the
//!   pit's cos² β holds under either. `"slice-count"` is XeGTAO's rule.
//! - acos is the precise one, not XeGTAO's fast_acos (0.009 rad error): aograph trades speed
//!   for accuracy. A side no sample raised keeps its exact tangent angle γ ± π/2.
//! - Samples within the g-buffer normals' rounding of the tangent plane are the plane itself
//!   (shaders/common/horizon.wgsl, as hbao), and sky and off-screen samples occlude nothing;
//!   XeGTAO has neither sky nor an off-screen rule (its sampler clamps).
//! - Noise: XeGTAO's R2 sequence over a 64 x 64 Hilbert index, computed in the shader; no
//!   temporal term (XeGTAO adds one only with TAA, which aograph does not run).
//! - The per-pixel estimate is clamped to [0, 1.5] before denoising (XeGTAO's UNORM range
//!   1.5) and to [0, 1] by the last pass.
//! - A MIP tap's point is rebuilt at its texel block's centre, where the block's mean depth
//!   belongs (ao.wgsl, `depth_tap`); at the tap pixel, on a slope, the mean lies up to half a
//!   texel's depth step in front of the surface and a plane occludes itself. A block holding
//!   sky is sky (blocks::depth_prefilter).
//! - Known bias, XeGTAO's own: taps are rounded to whole pixels, so they lie slightly off the
//!   slice plane, and the per-side maximum keeps the highest of them. Seen along the axis of a
//!   conical pit every wall point has the same elevation and the estimate is exact (cos² β to
//!   1e-4); seen 30 degrees off the axis, β = 20 degrees, 32 slices x 8 steps read 0.853 at
//!   65², 0.865 at 129², 0.874 at 257² against cos² β = 0.883: the bias shrinks with
//!   resolution and with fewer steps per side.
//!
//! - `layers = 2`: each tap's second-layer surface (the g-buffer's nearest surface 0.05 R
//!   behind the first, a second raster pass; Mara et al. 2016) is a horizon candidate too,
//!   under the same falloff: where the first layer lies in front of a gap, beyond R', the
//!   surface it hides can still raise the horizon (the deep g-buffer paper's AO keeps each
//!   tap's stronger layer). Only candidates are added, so the frame can only darken.
//!
//! Tests: closed forms (plane, pit) in tests/technique_gtao.rs; the estimator against a CPU
//! recomputation of every pixel in tests/gtao_golden.rs; the blocks in tests/blocks/.
//! Optional outputs: `bent_normals = true` runs ao/gtao/ao_bent.wgsl, the same estimator
//! (ao/gtao/estimator.wgsl) also writing XeGTAO's bent normal (Algorithm 2, spec §1.5) as
//! `gtao_bent_normals` (Rgba16Float, view-space xyz, raw accessibility in w);
//! `multibounce = true` adds `gtao.multibounce` (ao/gtao/multibounce.wgsl), GTAO's cubic fit
//! per channel from the albedo (spec §7), as `gtao_multibounce`. Neither enters the
//! comparison with the reference, which reads the accessibility.

use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{SizeClass, TextureDesc};
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use super::depth_and_normals;
use super::slices::{DepthLayers, SliceExtra, SlicePasses, slice_passes};
use crate::blocks::EdgeDenoise;
use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::spatial_options::SpatialOptions;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique, ExtraOutput};

/// The extra output `gtao_bent_normals` (`bent_normals = true`): view-space bent normal xyz,
/// raw accessibility w (XeGTAO Algorithm 2), Rgba16Float.
pub const BENT_NORMALS_OUTPUT: ExtraOutput = ExtraOutput::new("gtao_bent_normals");
/// The extra output `gtao_multibounce` (`multibounce = true`): GTAO's multi-bounce fit per
/// colour channel, Rgba16Float.
pub const MULTIBOUNCE_OUTPUT: ExtraOutput = ExtraOutput::new("gtao_multibounce");

pub use super::slices::{GtaoPreset, MAX_SLICES, MAX_STEPS, SliceCounts};

/// The `gtao` technique (module docs): ground-truth AO as XeGTAO computes it, S slices x T
/// steps per side with the cosine-weighted slice integral in closed form; parameters
/// [`GtaoParams`].
pub struct Gtao;

/// How the slice sum becomes accessibility (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Normalization {
    /// Divided by the same sum for an open hemisphere (exact on open surfaces).
    #[default]
    Unoccluded,
    /// Divided by the slice count (XeGTAO).
    SliceCount,
}

/// `[ao.gtao]` parameters (XeGTAO's names and defaults, spec §3).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct GtaoParams {
    /// preset, slices, steps (shared with vbao).
    #[serde(flatten)]
    pub counts: SliceCounts,
    /// R' = R x this (XeGTAO's auto-tuned 1.457).
    pub radius_multiplier: f32,
    /// Falloff range F, a fraction of R' (0.615).
    pub falloff_range: f32,
    /// Sample distribution power p (2).
    pub sample_distribution_power: f32,
    /// Thin-occluder compensation (0; useful up to 0.7).
    pub thin_occluder_compensation: f32,
    /// Final value power (2.2).
    pub final_value_power: f32,
    /// Depth MIP sampling offset (3.30).
    pub depth_mip_offset: f32,
    /// ‖n_p‖ <- mix(‖n_p‖, 1, this) (0.05).
    pub normal_fudge: f32,
    /// What the slice sum is divided by (G6): its open-hemisphere value (`"unoccluded"`,
    /// exact on open surfaces) or the slice count S (`"slice-count"`, XeGTAO's rule).
    pub normalization: Normalization,
    /// Edge-aware denoise passes, 0 to 3 (1).
    pub denoise_passes: u32,
    /// The denoiser's centre weight on its last pass (1.2).
    pub blur_beta: f32,
    /// Also output bent normals (`gtao_bent_normals`, spec §1.5).
    pub bent_normals: bool,
    /// Also output the multi-bounce fit from the albedo (`gtao_multibounce`, spec §7).
    pub multibounce: bool,
    /// `resolution` and the temporal option (crate::SpatialOptions).
    #[serde(flatten)]
    pub spatial: SpatialOptions,
    /// `layers`: 1, or 2 with the g-buffer's second depth layer (crate module docs).
    #[serde(flatten)]
    pub depth_layers: DepthLayers,
}

impl Default for GtaoParams {
    fn default() -> Self {
        Self {
            counts: SliceCounts::default(),
            radius_multiplier: 1.457,
            falloff_range: 0.615,
            sample_distribution_power: 2.0,
            thin_occluder_compensation: 0.0,
            final_value_power: 2.2,
            depth_mip_offset: 3.30,
            normal_fudge: 0.05,
            normalization: Normalization::Unoccluded,
            denoise_passes: 1,
            blur_beta: 1.2,
            bent_normals: false,
            multibounce: false,
            spatial: SpatialOptions::default(),
            depth_layers: DepthLayers::default(),
        }
    }
}

impl GtaoParams {
    /// (slices, steps per side) in effect: the overrides, else the preset's.
    pub fn counts(&self) -> (u32, u32) {
        self.counts.counts()
    }
}

/// The `params` uniform of shaders/ao/gtao/ao.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct GtaoUniform {
    /// Slices S.
    slices: u32,
    /// Steps T per side.
    steps: u32,
    /// 1: this pass is the output; 0: a denoiser follows.
    is_output: u32,
    /// Normalisation: 0 slice count, 1 unoccluded.
    normalization: u32,
    /// R' = R x radius multiplier (view units).
    effect_radius: f32,
    /// Falloff range F (fraction of R').
    falloff_range: f32,
    /// Sample distribution power.
    sample_distribution_power: f32,
    /// Thin-occluder compensation.
    thin_occluder_compensation: f32,
    /// Final value power.
    final_value_power: f32,
    /// Depth MIP sampling offset.
    depth_mip_offset: f32,
    /// Projected-normal fudge.
    normal_fudge: f32,
    _pad0: f32,
}

aograph_graph::uniform_layout!(GtaoUniform {
    slices,
    steps,
    is_output,
    normalization,
    effect_radius,
    falloff_range,
    sample_distribution_power,
    thin_occluder_compensation,
    final_value_power,
    depth_mip_offset,
    normal_fudge,
    _pad0
});

impl AoTechnique for Gtao {
    type Params = GtaoParams;
    const NAME: &'static str = "gtao";
    fn description(&self) -> &'static str {
        "ground-truth AO (XeGTAO): S slices x T steps, analytic cosine-weighted slice integral, depth MIP prefilter, edge-aware denoiser"
    }
    fn params(&self) -> Vec<ParamDesc> {
        let mut d = SliceCounts::params();
        d.extend([
            ParamDesc::float("radius_multiplier", 0.3, 3.0)
                .doc("R' = R x this (XeGTAO's auto-tuned 1.457)"),
            ParamDesc::float("falloff_range", 0.01, 1.0)
                .doc("share of R' over which a sample's weight falls to 0 (XeGTAO: 0.615)"),
            ParamDesc::float("sample_distribution_power", 1.0, 3.0)
                .doc("step s = ((j + jitter) / T)^p: p > 1 packs taps near the centre"),
            ParamDesc::float("thin_occluder_compensation", 0.0, 0.7)
                .doc("stretches the falloff distance along view z, so thin occluders fade sooner"),
            ParamDesc::float("final_value_power", 0.5, 5.0)
                .doc("accessibility^p after the slice average (XeGTAO's fit: 2.2)"),
            ParamDesc::float("depth_mip_offset", 2.0, 6.0)
                .doc("a tap at d pixels reads depth MIP log2(d) - this: a speed knob"),
            ParamDesc::float("normal_fudge", 0.0, 1.0)
                .doc("|n_p| <- mix(|n_p|, 1, this) against over-darkening on slopes (0.05)"),
            ParamDesc::choice("normalization", &["unoccluded", "slice-count"]).doc(
                "divide the slice sum by its open-hemisphere value (exact on open surfaces) or by S (XeGTAO)",
            ),
            ParamDesc::int("denoise_passes", 0, 3)
                .doc("edge-aware 3x3 passes: 1 sharp, 2 medium, 3 soft (0: none)"),
            ParamDesc::float("blur_beta", 0.01, 1e4)
                .doc("the denoiser's centre weight on its last pass"),
            ParamDesc::flag("bent_normals").doc(
                "also output gtao_bent_normals: view-space bent normal xyz, raw accessibility w (XeGTAO Algorithm 2; about +25% on a GPU)",
            ),
            ParamDesc::flag("multibounce").doc(
                "also output gtao_multibounce: max(A, ((a A + b) A + c) A) per channel from the albedo (GTAO's fit); the reference comparison uses A",
            ),
        ]);
        d.push(DepthLayers::param());
        d.extend(SpatialOptions::params());
        d
    }
    fn validate(&self, p: &GtaoParams) -> AoResult<()> {
        p.depth_layers.validate(Self::NAME, p.spatial.resolution)
    }
    fn channels(&self, p: &GtaoParams) -> GBufferChannels {
        // The multi-bounce fit reads the albedo at the output size, after the slices.
        let slices = p.depth_layers.channels(depth_and_normals());
        let c = if p.multibounce {
            slices.with(GBufferChannel::Albedo)
        } else {
            slices
        };
        p.spatial.channels(c)
    }
    fn dropping_channel(&self, p: &GtaoParams, channel: GBufferChannel) -> Option<&'static str> {
        if p.multibounce && channel == GBufferChannel::Albedo {
            return Some("multibounce = false (the multi-bounce fit needs the surface colour)");
        }
        p.depth_layers.dropping(channel)
    }
    fn is_temporal(&self, p: &GtaoParams) -> bool {
        p.spatial.is_temporal()
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &GtaoParams) -> AoResult<AoOutput> {
        // §4 prefilter, §1-§3 slices (ao/gtao/ao.wgsl), §6 denoiser: `slice_passes`.
        let effect_radius = ctx.radius * p.radius_multiplier;

        let (slices, steps) = p.counts();
        let uniform = GtaoUniform {
            slices,
            steps,
            is_output: (p.denoise_passes == 0) as u32,
            normalization: (p.normalization == Normalization::Unoccluded) as u32,
            effect_radius,
            falloff_range: p.falloff_range,
            sample_distribution_power: p.sample_distribution_power,
            thin_occluder_compensation: p.thin_occluder_compensation,
            final_value_power: p.final_value_power,
            depth_mip_offset: p.depth_mip_offset,
            normal_fudge: p.normal_fudge,
            _pad0: 0.0,
        };
        let slices = SlicePasses {
            prefix: "gtao",
            shader: if p.bent_normals {
                "ao/gtao/ao_bent.wgsl"
            } else {
                "ao/gtao/ao.wgsl"
            },
            uniform: &uniform,
            loads_per_pixel: 6.0 + 2.0 * (slices * steps) as f32,
            effect_radius,
            falloff_range: p.falloff_range,
            denoise: EdgeDenoise {
                passes: p.denoise_passes,
                blur_beta: p.blur_beta,
            },
            extra_output: p.bent_normals.then_some(SliceExtra {
                binding: "bent",
                output: BENT_NORMALS_OUTPUT,
                format: wgpu::TextureFormat::Rgba16Float,
            }),
            accumulation: p.spatial.accumulation,
            layers: p.depth_layers,
        };
        // At the chosen resolution, then the optional running mean over frames
        // (crate::SpatialOptions), before the multi-bounce fit reads the accessibility.
        let mut out = p
            .spatial
            .build(ctx, depth_and_normals(), |ctx| slice_passes(ctx, &slices))?;
        // §7: the multi-bounce fit, an extra output for shading.
        if p.multibounce {
            let albedo = ctx.channel(GBufferChannel::Albedo)?;
            let dst = ctx.builder.create_texture(
                "gtao.multibounce",
                TextureDesc::new(wgpu::TextureFormat::Rgba16Float, SizeClass::FULL),
            );
            let mut pass =
                ctx.builder
                    .compute_pass("gtao.multibounce", "ao/gtao/multibounce.wgsl", "main");
            pass.sample("accessibility", out.accessibility)
                .sample("albedo", albedo);
            let dst = pass.write_storage("dst", dst);
            pass.dispatch_over(dst);
            out.extra.push((MULTIBOUNCE_OUTPUT, dst));
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TechniqueRegistry;
    use crate::contract::plan_pass_names;

    fn plan_names(params: &str) -> Vec<String> {
        let shaders = crate::shader_library().unwrap();
        let gtao = TechniqueRegistry::with_builtins()
            .get(Gtao::NAME)
            .unwrap()
            .clone();
        plan_pass_names(&gtao, params, &shaders).unwrap()
    }

    #[test]
    fn plan_is_prefilter_then_slices_then_denoiser() {
        let levels = [
            "gtao.depth_level1",
            "gtao.depth_level2",
            "gtao.depth_level3",
        ];
        let mut want: Vec<&str> = levels.to_vec();
        want.extend(["gtao.depth_level4", "gtao.ao", "gtao.denoise1"]);
        assert_eq!(plan_names(""), want);
        want.pop();
        assert_eq!(plan_names("denoise_passes = 0"), want);
        want.extend(["gtao.denoise1", "gtao.denoise2", "gtao.denoise3"]);
        assert_eq!(plan_names("denoise_passes = 3"), want);
    }

    #[test]
    fn presets_are_xegtaos_and_keys_override_them() {
        let parse = |t: &str| -> GtaoParams { toml::from_str(t).unwrap() };
        for (preset, counts) in [
            ("low", (1, 2)),
            ("medium", (2, 2)),
            ("high", (3, 3)),
            ("ultra", (9, 3)),
        ] {
            assert_eq!(parse(&format!("preset = \"{preset}\"")).counts(), counts);
        }
        assert_eq!(parse("").counts(), (3, 3));
        assert_eq!(parse("preset = \"ultra\"\nsteps = 6").counts(), (9, 6));
    }
}
