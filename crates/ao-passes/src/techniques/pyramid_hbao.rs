//! `pyramid-hbao`: horizon-based AO marching a 3x3-average linear-depth pyramid (Astapov,
//! Frolov, Galaktionov, "Pyramid HBAO", GraphiCon 2021; spec docs/techniques/pyramid-hbao.md).
//!
//! Passes, in the paper's order (§3.3-3.5):
//! 1. `pyramid-hbao.depth_level1` .. `depth_level{L-1}`: the depth pyramid, K = 3, each level
//!    the mean of a 3x3 block, sizes rounded up (blocks::depth_pyramid, Average3x3), the block
//!    grid centred on the image (a texel more where its overhang would be odd) so that the
//!    pyramid of a mirrored view is the mirrored pyramid: the spec's grid from the top-left
//!    corner put `columns`' two walls at different phases of the coarse grid (0.024 apart at
//!    320x180; with the centred grid block means are 0.002-0.003 from the mirror image, were
//!    0.005-0.013). Cost: 2-10 % more AO-pass time (each level's edge texels found per pixel).
//! 2. `pyramid-hbao.ao`: per pixel, D = 8 directions; along each, `step_count` reads on each
//!    level 0..L-1, the step multiplied by K after each level; per direction the max of
//!    W(r) sin(alpha) (Eqs. 7, 8); AO = 1 - mean over directions (shaders/ao/pyramid_hbao/ao.wgsl).
//! 3. `pyramid-hbao.blur_x`, `pyramid-hbao.blur_y`: the separable Gaussian, sigma 1.5, 5 taps
//!    (blocks::gaussian_blur), with sky kept at 1 and sky taps left out.
//!
//! Reads linear depth and view-space normals; level 0 is the g-buffer's linear depth, which is
//! Eq. (6) applied to the hardware depth already (the spec's level 0 is the raw depth buffer
//! linearised on read: same values). Output: accessibility, 1 = unoccluded, sky exactly 1.
//!
//! Values the paper leaves open (\[NOT IN PAPER\] / \[IMPL\] in the spec), chosen here:
//! - R: the shared world radius `[ao] radius` (W(r) = max(0, 1 - r/R), Eq. 7).
//! - Initial step s0 = 1 full-resolution pixel (`initial_step`), the spec's suggested start:
//!   level 0 is then sampled at its texel spacing, and level l at one texel of level l.
//! - step_count S = 4 reads per level (the spec suggests 4-8): with L = 4 the march reaches
//!   s0 xi S (K^L - 1)/(K - 1) = 160 xi px (xi in [0.5, 1.5)), about R at 720p for the default
//!   scenes; before each level past the first the march stops if that level's first sample
//!   is off screen or its line of sight passes farther than R from P (both only grow along a
//!   direction), so a larger reach costs little where it is not needed. S is a pipeline
//!   constant (`STEP_COUNT`): the driver unrolls the march, and each S is its own pipeline.
//! - L = 4 levels by default (the paper tests 1-5; its Viking Room saturates at 4), 1 to 7:
//!   levels 6 and 7 (texels of 243 and 729 px) let `auto` reach R at 1920x1080 and 3840x2160.
//!   L counts level 0 (spec §2.4 \[IMPL\]): L = 1 marches the full-resolution depth only.
//! - xi_d in [0.5, 1.5) (spec §2.5 \[IMPL\]); directions theta_d = 2 pi (phi + (d + u_d)/D):
//!   stratified random; the per-pixel rotation phi is the R2 low-discrepancy dither (a
//!   blue-noise-like pattern computed in the shader) instead of a 32x32 blue-noise texture,
//!   u_d and xi_d hash the pixel modulo 32. The noise is not animated (deterministic frames).
//! - Tangent-angle bias `angle_bias` = 0 degrees (spec §6.3: off by default, faithful).
//! - Sky and far taps are unoccluding and left out of the pyramid means (spec §6.3); samples
//!   are rebuilt at the centre of their (coarse) texel, whose edge texels are exact centroids.
//!   A block mixing sky and geometry keeps its centre texel rather than the mean of its
//!   geometry (blocks::depth_pyramid), which would be rebuilt at the wrong place.
//! - Cost (lavapipe, 256x256, columns and sphere-on-plane, no blur on either side as in the
//!   paper's Table 1): L = 4 at 13 ms against HBAO 64x80 at 420-526 ms, 32-41x cheaper at a
//!   lower MAE (0.1029 against 0.1215, 0.0196 against 0.0198); 28-35x with both blurs. The
//!   march body has no branch: off-screen, sky and self samples are selected out. L is a
//!   pipeline constant as well (`LEVELS`): SIMD CPU drivers run a branch's body under a mask
//!   whatever the condition, so marches of levels the pyramid lacks must not be compiled in.
//! - The raw AO (when blurred) and the blur's horizontal pass are intermediates in
//!   `[ao] intermediate_format`, written by the matching shader variants.
//!
//! The estimator is the paper's: Eq. (2)'s elevation limit read as pi/2 (spec §1.2 erratum), so
//! Eq. (1) is uniform-weighted AO, estimated per direction by Eq. (8) with the elevation taken
//! from the tangent plane of the normal (spec §1.3: no separate tangent angle). Against the
//! binary, cosine-weighted reference it under-occludes: W(r) = 1 - r/R fades occluders the
//! reference counts fully, and a height field cannot see overhangs (measured on
//! sphere-on-plane, 128x96: MAE 0.045, mean signed error +0.043; a step W(r) = \[r < R\]
//! would give MAE 0.027, but that is not the paper's method).

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::SizeClass;
use serde::{Deserialize, Serialize};

use super::depth_and_normals;
use crate::blocks::{DepthReduction, GaussianBlur, depth_pyramid, gaussian_blur_with_intermediate};
use crate::error::AoResult;
use crate::levels::Levels;
use crate::param::ParamDesc;
use crate::spatial_options::SpatialOptions;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique};

/// Pyramid reduction factor K (spec §2.2).
const K: u32 = 3;
/// Most levels the AO shader binds (level 0 included).
pub const MAX_LEVELS: u32 = 7;
/// The paper's L where its Viking Room saturates: `levels = "auto"` without a known view.
pub const PAPER_LEVELS: u32 = 4;
/// The smallest step jitter xi (spec §2.5: xi in [0.5, 1.5)): the reach every direction has.
const MIN_JITTER: f32 = 0.5;

/// The `pyramid-hbao` technique (module docs): horizon-based AO marching a 3x3-average depth
/// pyramid, the march's step growing by K = 3 per level; parameters [`PyramidHbaoParams`].
pub struct PyramidHbao;

/// Parameters; defaults are the paper's values where it gives them (module docs for the rest).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct PyramidHbaoParams {
    /// Pyramid levels L, level 0 (full resolution) included, or `auto`: the fewest whose
    /// march reaches R at the view's nearest geometry ([`PyramidHbaoParams::levels_for`]).
    pub levels: Levels,
    /// Azimuth directions D (paper: 8).
    pub directions: u32,
    /// Reads per direction and pyramid level.
    pub step_count: u32,
    /// Initial step s0, full-resolution pixels.
    pub initial_step: f32,
    /// Tangent-angle bias in degrees (0 = the paper's estimator).
    pub angle_bias: f32,
    /// Run the Gaussian denoiser.
    pub blur: bool,
    /// Gaussian sigma in pixels (paper: 1.5).
    pub blur_sigma: f32,
    /// Gaussian taps per axis (paper: 5).
    pub blur_taps: u32,
    /// `resolution` and the temporal option (crate::SpatialOptions).
    #[serde(flatten)]
    pub spatial: SpatialOptions,
}

impl Default for PyramidHbaoParams {
    fn default() -> Self {
        Self {
            levels: Levels::Auto,
            directions: 8,
            step_count: 4,
            initial_step: 1.0,
            angle_bias: 0.0,
            blur: true,
            blur_sigma: 1.5,
            blur_taps: 5,
            spatial: SpatialOptions::default(),
        }
    }
}

/// The AO pass's constants (shaders/ao/pyramid_hbao/ao.wgsl, `Params`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct AoUniform {
    radius: f32,
    initial_step: f32,
    sin_bias: f32,
    factor: f32,
    directions: u32,
    _pad: [u32; 3],
}

aograph_graph::uniform_layout!(AoUniform {
    radius,
    initial_step,
    sin_bias,
    factor,
    directions,
    _pad
});

impl PyramidHbaoParams {
    /// The march's reach with L levels in full-resolution pixels, for the smallest jitter:
    /// s0 xi_min S (K^L - 1) / (K - 1), so every direction reaches it (module docs).
    pub fn reach(&self, levels: u32) -> f32 {
        let k = K as f32;
        self.initial_step * MIN_JITTER * self.step_count as f32 * (k.powi(levels as i32) - 1.0)
            / (k - 1.0)
    }

    /// The level count: fixed, or for `auto` the fewest in 1..=7 whose reach covers
    /// `radius_pixels` (the paper's 4 when the view is unknown).
    pub fn levels_for(&self, radius_pixels: Option<f32>) -> u32 {
        self.levels
            .resolve(radius_pixels, MAX_LEVELS, PAPER_LEVELS, |n| self.reach(n))
    }
}

impl AoTechnique for PyramidHbao {
    type Params = PyramidHbaoParams;
    const NAME: &'static str = "pyramid-hbao";
    fn description(&self) -> &'static str {
        "HBAO marching a 3x3-average linear-depth pyramid, one level coarser per step group (Astapov et al. 2021)"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::word_or_int("levels", "auto", 1, MAX_LEVELS).doc(
                "pyramid levels L, level 0 included; the reach grows 3x per level; auto: the fewest that reach R at the view's closest geometry (7 levels reach 2186 px: all of R up to 3840x2160)",
            ),
            ParamDesc::int("directions", 1, 32).doc("azimuth directions D (paper: 8)"),
            ParamDesc::int("step_count", 1, 16).doc("reads per direction and pyramid level"),
            ParamDesc::float("initial_step", 0.25, 16.0)
                .doc("initial step s0 in full-resolution pixels (x3 per level)"),
            ParamDesc::float("angle_bias", 0.0, 30.0)
                .doc("tangent-angle bias in degrees (0 = the paper's estimator)"),
            ParamDesc::flag("blur").doc("run the separable Gaussian denoiser"),
            ParamDesc::float("blur_sigma", 0.1, 8.0).doc("Gaussian sigma in pixels (paper: 1.5)"),
            ParamDesc::odd("blur_taps", 1, 31).doc("Gaussian taps per axis (paper: 5)"),
        ]
        .into_iter()
        .chain(SpatialOptions::params())
        .collect()
    }
    fn channels(&self, p: &PyramidHbaoParams) -> GBufferChannels {
        p.spatial.channels(depth_and_normals())
    }
    fn is_temporal(&self, p: &PyramidHbaoParams) -> bool {
        p.spatial.is_temporal()
    }
    fn needs_radius_pixels(&self, p: &PyramidHbaoParams) -> bool {
        p.levels == Levels::Auto
    }
    fn reach_pixels(
        &self,
        p: &PyramidHbaoParams,
        _: u32,
        radius_pixels: Option<f32>,
    ) -> Option<f32> {
        p.spatial
            .reach(0, radius_pixels, |_, r| Some(p.reach(p.levels_for(r))))
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &PyramidHbaoParams) -> AoResult<AoOutput> {
        // At the chosen resolution; 4. optional: the running mean over frames
        // (crate::SpatialOptions).
        p.spatial
            .build(ctx, depth_and_normals(), |ctx| self.spatial(ctx, p))
    }
}

impl PyramidHbao {
    /// The paper's passes: pyramid, march, Gaussian.
    fn spatial(&self, ctx: &mut AoBuildContext<'_>, p: &PyramidHbaoParams) -> AoResult<AoOutput> {
        let levels = p.levels_for(ctx.radius_pixels);
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let normals = ctx.channel(GBufferChannel::Normals)?;
        // 1. Depth pyramid, K = 3, 3x3 mean (§3.3).
        let pyramid = depth_pyramid(
            ctx.builder,
            Self::NAME,
            depth,
            DepthReduction::Average3x3,
            levels,
        )?;
        debug_assert_eq!(pyramid.factor(), K);
        // 2. AO at the output resolution (§3.4; no upsampling, §3).
        let target = if p.blur {
            ctx.intermediate("pyramid-hbao.ao", SizeClass::FULL)
        } else {
            ctx.accessibility_texture("pyramid-hbao.ao")
        };
        let uniform = AoUniform {
            radius: ctx.radius,
            initial_step: p.initial_step,
            sin_bias: p.angle_bias.to_radians().sin(),
            factor: K as f32,
            directions: p.directions,
            _pad: [0; 3],
        };
        // The raw AO is an intermediate when blurred: its writer is the matching shader variant.
        let shader = if p.blur {
            ctx.shader("ao/pyramid_hbao/ao.wgsl")
        } else {
            "ao/pyramid_hbao/ao.wgsl".to_string()
        };
        let mut pass = ctx.builder.compute_pass("pyramid-hbao.ao", &shader, "main");
        pass.sample("depth", depth);
        for l in 1..MAX_LEVELS as usize {
            // Slots past L - 1 get the coarsest level; the shader never reads them.
            pass.sample(&format!("depth{l}"), pyramid.level(l));
        }
        pass.sample("normals", normals);
        // The centre's depth and normal, step_count taps per direction and level.
        pass.loads_per_invocation(2.0 + (p.directions * p.step_count * levels) as f32);
        pass.read_view(ctx.view);
        pass.uniform_struct("params", &uniform);
        // The march's length and level count are compiled in: the driver unrolls the march and
        // drops the levels the pyramid lacks (shader, `STEP_COUNT`, `LEVELS`).
        pass.constant("STEP_COUNT", p.step_count as f64);
        pass.constant("LEVELS", levels as f64);
        p.spatial.vary_noise(&mut pass);
        let raw = pass.write_storage("ao", target);
        pass.dispatch_over(raw);
        if !p.blur {
            return Ok(AoOutput::new(raw));
        }
        // 3. Separable Gaussian, sigma 1.5, 5 taps (§3.5, §4).
        let blur = GaussianBlur {
            sigma: p.blur_sigma,
            taps: p.blur_taps,
            depth_sigma: None,
        };
        Ok(AoOutput::new(gaussian_blur_with_intermediate(
            ctx.builder,
            Self::NAME,
            raw,
            Some(depth),
            &blur,
            ctx.intermediate_format,
        )?))
    }
}

#[cfg(test)]
mod tests {
    use aograph_graph::ShaderLibrary;

    use super::*;
    use crate::TechniqueRegistry;
    use crate::contract::{compile_plan, plan_pass_names};

    fn shaders() -> ShaderLibrary {
        crate::shader_library().unwrap()
    }

    /// The kept pass names of the technique with `params`.
    fn plan(params: &str) -> AoResult<Vec<String>> {
        let t = TechniqueRegistry::with_builtins()
            .get(PyramidHbao::NAME)?
            .clone();
        plan_pass_names(&t, params, &shaders())
    }

    #[test]
    fn plan_has_the_spec_passes_for_every_level_count() {
        for l in 1..=MAX_LEVELS {
            let mut want: Vec<String> = (1..l)
                .map(|i| format!("pyramid-hbao.depth_level{i}"))
                .collect();
            want.extend(
                [
                    "pyramid-hbao.ao",
                    "pyramid-hbao.blur_x",
                    "pyramid-hbao.blur_y",
                ]
                .map(String::from),
            );
            assert_eq!(plan(&format!("levels = {l}")).unwrap(), want, "L = {l}");
        }
        assert_eq!(plan("").unwrap().len(), 3 + 3, "default L = 4");
        assert_eq!(
            plan("levels = 2\nblur = false").unwrap(),
            ["pyramid-hbao.depth_level1", "pyramid-hbao.ao"]
        );
    }

    #[test]
    fn r16float_intermediates_use_the_half_shader_variants() {
        let t = TechniqueRegistry::with_builtins()
            .get(PyramidHbao::NAME)
            .unwrap()
            .clone()
            .configure(&toml::Table::new())
            .unwrap();
        let plan = compile_plan(t.as_ref(), &shaders(), wgpu::TextureFormat::R16Float).unwrap();
        let shader_of = |pass: &str| match &plan
            .decl
            .passes
            .iter()
            .find(|p| p.name == pass)
            .unwrap()
            .kind
        {
            aograph_graph::PassKind::Compute { shader, .. } => shader.clone(),
            _ => unreachable!(),
        };
        assert_eq!(
            shader_of("pyramid-hbao.ao"),
            "ao/pyramid_hbao/ao.wgsl?IntermediateStorage=f16"
        );
        assert_eq!(
            shader_of("pyramid-hbao.blur_x"),
            "blocks/gaussian_blur_depth.wgsl?IntermediateStorage=f16"
        );
        assert_eq!(
            shader_of("pyramid-hbao.blur_y"),
            "blocks/gaussian_blur_depth.wgsl"
        );
    }

    #[test]
    fn reads_depth_and_normals() {
        let c = AoTechnique::channels(&PyramidHbao, &PyramidHbaoParams::default());
        assert_eq!(
            c.iter().collect::<Vec<_>>(),
            [GBufferChannel::LinearDepth, GBufferChannel::Normals]
        );
    }
}
