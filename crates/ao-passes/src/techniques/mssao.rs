//! `mssao`: multi-resolution screen-space ambient occlusion (Hoang & Low, "Efficient
//! screen-space approach to high-quality multi-scale ambient occlusion", The Visual Computer
//! 28(3), 2012). Equation and table numbers are the paper's; docs/techniques/mssao.md records
//! them with the errata followed here.
//!
//! The graph is the paper's pipeline (Table 1), levels l = 0 (finest, the paper's Res_1) to
//! n - 1 (coarsest):
//!
//! ```text
//! gbuffer (linear depth, octahedral face normals: "Storage" below)
//! mssao.downsample{l}, l = 1..n-1   2x2 depth-sorted median / second-nearest (Table 2)
//! mssao.ao{n-1}                     interleaved kernel, tuple (mean, sum, N)   (Eqs. 5-7, 10)
//! for l = n-2 down to 0:
//!   mssao.blur{l+1}                 3x3 blur of level l+1's tuple            (Table 4)
//!   mssao.ao{l}                     near AO + bilateral upsampling of the blurred level l+1
//!                                   (Fig. 9, Eqs. 8-9) + Eq. 10; at l = 0 the Poisson disk
//!                                   and Eq. 11, writing accessibility 1 - AO_final
//! [mssao.temporal.*]                optional temporal filter (Eqs. 12-14), see below
//! ```
//!
//! One downsample pass per level below the finest (level 0 is the g-buffer itself), one AO pass
//! per level, one blur per level above the finest; the 2x2 upsampling is fused into the next
//! finer AO pass (the spec's pass count, and one texture fewer per level than a separate
//! upsample pass would need). With n = 1 the single pass is `mssao.ao0` (Poisson disk, Eq. 11).
//!
//! # Radius
//! The paper's d_max (Eq. 7: the view-space distance beyond which an occluder contributes
//! nothing; 2 units in all of its tests) *is* the shared world-space radius R (`[ao] radius`):
//! the reference's obscurance mode uses exactly Eq. 7 with d_max = R, and its binary mode counts
//! hits within R, so MSSAO is compared against the same sphere of influence every other
//! technique uses. configs/mssao.toml sets `radius = 2.0`, the paper's d_max. d_threshold and
//! t_z are, as in the paper, in scene units: scale them with R when the scene's unit changes.
//!
//! # Errata followed, and choices where the paper is silent (also noted in the WGSL)
//! - Eq. 5 uses the 0-based level index (spec erratum): the finest level's radius is the full
//!   projected d_max, r_l = r_0 / 2^l; s / (2 tan(alpha/2)) is the viewport height times
//!   P\[1\]\[1\] / 2 (`pixels_per_unit`), so non-square viewports work.
//! - Eq. 6 sums without 1/N (spec erratum: Eq. 10 divides by N itself); samples below the
//!   hemisphere or beyond d_max still count in N (the paper's "no rejection").
//! - Coarse levels take the odd offsets (+-1, +-3, +-5) within R (4, 16 or 36 taps at odd R);
//!   ring k (the taps with max(|o.x|, |o.y|) = k) enters with a weight rising from 0 at
//!   R = k - 2 to 1 at R = k, counted in N as that fraction, so the kernel is the paper's at
//!   odd R (at r_max = 5 too) and moves continuously with R between (see "At every output
//!   size"). The finest level's 16-point Poisson disk is our own (Mitchell best-candidate),
//!   fixed and unrotated, scaled by R and rounded to texels; a point rounding onto the pixel
//!   itself is skipped (not counted in N).
//! - Off-screen taps are skipped (not counted); sky taps count as unoccluding samples.
//! - Downsampling keeps the median where the four sub-pixels lie within d_threshold of the
//!   median's plane (the plane through the mean of the middle two with their renormalised
//!   normal), else the second-nearest; Table 2 tests the depth range instead, which a plane
//!   seen at a grazing angle exceeds (see "At every output size"). Sky sorts last; odd sizes
//!   round up (`SizeClass::half_pow`) and clamp the 2x2 fetch at the border.
//! - Eq. 9's depth term in the upsampling weighs the coarse texel's distance from the fine
//!   texel's tangent plane, |n . (q - p)|, not the depth difference |z_q - z_p|: the two agree
//!   for a surface facing the camera, and along a wall seen at a grazing angle the depth
//!   difference of neighbouring coarse texels of the same wall is many units, which made
//!   Eq. 9 pick one coarse texel: faint blocks the size of a coarse texel.
//! - Blur and upsampling are normalised by their weight sums (the pseudo-code omits it); the
//!   blur is bilateral by default as the prose says (`bilateral_blur`), applied to all three
//!   channels. If every bilateral upsampling weight underflows, the bilinear weights are used.
//! - Tuple textures (max, sum, count, unused) are intermediates: Rgba16Float under
//!   `intermediate_format = "r16float"`, Rgba32Float under "r32float"
//!   (`ctx.intermediate_rgba_format`), written by the matching shader variants. In fp16 the max
//!   is in [0, 1]; sums and counts are at most 11 x 36 + 16 = 412 at r_max = 5 and
//!   11 x 100 + 16 = 1116 at the limits (12 levels, r_max = 8: rings up to 9), within 2^-11
//!   relative in fp16.
//!
//! # At every output size
//! On `columns` at 1280x720 the walls at the image's sides, mirror images of each other in the
//! reference (0.712 and 0.715), read 0.884 and 0.737 (0.075 apart at 640x360, the sign flipping
//! with the size). The cause was no left/right rule: with the camera on the mirror plane every
//! size is symmetric to 0.001. It was three rules that jump as a view moves, so two walls at
//! different distances (2.35 and 3.15 units here) land on different sides of a jump, and a
//! camera step of 0.1 units changed one wall by 0.15:
//! 1. the interleaved kernel took ring k only once R_l >= k: where R_l = r_0 / 2^l crosses 3 or
//!    5 texels the tap count jumps 4 -> 16 -> 36 and the level's mean with it, which Eq. 10's
//!    max passes to every finer level (the rings now fade in, above);
//! 2. Table 2's depth-range test calls a grazing plane a discontinuity at coarse levels, so
//!    whether a block is averaged or keeps one sub-pixel depended on the distance (the plane
//!    test, above);
//! 3. Eq. 9 on depth differences made a grazing wall's upsampling blocky (the tangent-plane
//!    distance, above).
//!
//! With all three, the walls agree within 0.014 at 640x360 and 1920x1080 and 0.023 at
//! 1280x720 (docs/results/output-sizes.md, "At every output size"); what remains moves with the
//! camera (+-0.04 over 0.4 units of sideways motion, gtao +-0.02): the arcade in front of the
//! aisle walls lands on different coarse taps, screen-space parallax no rule of the pyramid
//! removes. Against the obscurance reference, whose falloff is Eq. 7's, the MAE on `columns`
//! falls (0.0721 to 0.0649 at 1280x720); against the binary one it rises (0.120 to 0.139): the
//! jumps' dark patches had made the obscurance estimate look closer to binary AO.
//!
//! `levels = "auto"` sizes the pyramid to R at the view's closest geometry (at most the image's
//! diagonal, `ProjectedRadius::reach_needed_px`), up to 12 levels: r_max 2^11 = 10240 px, so R
//! is reached at every size up to 7680x4320.
//!
//! # Storage
//! Every level, the g-buffer's included, is linear depth (R32Float) and an octahedral normal
//! in one u32 (R32Uint, `GBufferChannel::NormalsOct`, shaders/common/normal_oct.wgsl): 8 bytes
//! a texel where an Rgba32Float position and an Rgba16Float normal took 24. A texel's position
//! is rebuilt from its depth at its centre, (c + 0.5) 2^l full-resolution pixels: exact at
//! level 0 (the g-buffer's positions lie on their pixel's centre ray); at coarser levels the
//! paper's mean position of two sub-pixels moves to the texel's centre (at most half a texel).
//! Peak texture bytes of the technique's plan at 1024x1024 fall from 45.1 MiB (1.9x ssao) to
//! the figures in docs/results/memory.md, at the MAE measured there.
//!
//! # Temporal filter (optional, off by default)
//! `temporal = true` appends the shared temporal building block (`blocks::temporal`, also
//! TSSAO's) in its fixed-blend mode: `mssao.temporal.reproject` (Eq. 12 through the camera, or
//! the g-buffer's motion where the scene moves; Eq. 13 with `temporal_epsilon`) and
//! `mssao.temporal.accumulate` (Eq. 14 with k = `temporal_k`, k = 0 where the test fails or
//! the point was off screen, Table 5), plus `mssao.temporal.zero_motion` on static scenes.
//! epsilon is not given by the paper; the default is the block's 0.03 (the spec: 0.01-0.05).
//! The blended value is next frame's AO_prev (an exponential moving average, spec §7).

mod passes;
#[cfg(test)]
mod tests;

use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::TextureHandle;
use serde::{Deserialize, Serialize};

use crate::blocks::temporal::{
    DEFAULT_EPSILON, TemporalAccumulation, TemporalMode, add_temporal, temporal_channels,
};
use crate::error::AoResult;
use crate::levels::Levels;
use crate::param::ParamDesc;
use crate::resolution::Resolution;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique};
use crate::temporal_option::PER_FRAME_OUTPUT;

use passes::{Level, MssaoUniform};

/// The `mssao` technique.
pub struct Mssao;

/// Most pyramid levels accepted.
pub const MAX_LEVELS: u32 = 12;
/// The paper's n (Sec. 4.2, all of its tests): `levels = "auto"` without a known view.
pub const PAPER_LEVELS: u32 = 4;

/// `[ao.mssao]`: every constant of the paper, with its value as the default.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MssaoParams {
    /// n, the number of resolutions (Sec. 4.2; 4 in all of the paper's tests), or `auto`: the
    /// fewest whose coarsest kernel reaches R at the view's nearest geometry (see
    /// [`MssaoParams::levels_for`]).
    pub levels: Levels,
    /// d_threshold (Table 2), scene units: a 2x2 block whose sub-pixels all lie within this of
    /// the median's plane is averaged (median), otherwise its second-nearest sub-pixel is kept
    /// (Table 2 tests the depth range; module docs, "At every output size").
    pub d_threshold: f32,
    /// r_max (Eq. 5): cap of the kernel radius in pixels of each level (5 = an 11x11 kernel).
    pub r_max: f32,
    /// t_n (Eq. 8): exponent of the normal weight of the bilateral filters.
    pub normal_power: f32,
    /// t_z (Eq. 9): exponent of the depth weight of the bilateral filters (scene units).
    pub depth_power: f32,
    /// Multiply the 3x3 blur's weights by Eqs. 8-9 (the paper's prose calls it bilateral;
    /// Table 4 lists only 1 / ((dx + 1)(dy + 1))).
    pub bilateral_blur: bool,
    /// How a level's blurred tuple reaches the next finer level (Sec. 4.5, Fig. 8): the
    /// paper's bilateral 2x2 upsampling, or the plain bilinear or nearest it compares with.
    pub upsampling: Upsampling,
    /// The optional temporal filter (Sec. 4.6, Eqs. 12-14). Off by default.
    pub temporal: bool,
    /// k (Eq. 14): weight of the reprojected history when the depth test passes.
    pub temporal_k: f32,
    /// epsilon (Eq. 13): relative depth tolerance of the reprojection test (not given by the
    /// paper; the spec suggests 0.01 to 0.05, the shared block's default is 0.03).
    pub temporal_epsilon: f32,
    /// The size the pyramid's finest level has (crate::Resolution): at half, the whole
    /// pipeline, its temporal filter included, runs on the half-size g-buffer.
    pub resolution: Resolution,
}

/// The upsampling of Fig. 8 (shaders/common/mssao.wgsl, `mssao_upsample`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Upsampling {
    /// The coarse texel the fine texel lies in.
    Nearest,
    /// The four nearest coarse texels, weights 9/16, 3/16, 3/16, 1/16.
    Bilinear,
    /// The bilinear weights times Eq. 8 (normals) and Eq. 9 (depths): the paper's.
    #[default]
    Bilateral,
}

impl Upsampling {
    /// The shader's code for it (`MssaoParams.upsampling`).
    pub fn code(self) -> u32 {
        match self {
            Self::Nearest => 0,
            Self::Bilinear => 1,
            Self::Bilateral => 2,
        }
    }
}

impl Default for MssaoParams {
    fn default() -> Self {
        Self {
            levels: Levels::Auto,
            d_threshold: 1.0,
            r_max: 5.0,
            normal_power: 8.0,
            depth_power: 16.0,
            bilateral_blur: true,
            upsampling: Upsampling::Bilateral,
            temporal: false,
            temporal_k: 0.5,
            temporal_epsilon: DEFAULT_EPSILON,
            resolution: Resolution::Full,
        }
    }
}

impl MssaoParams {
    /// The reach of n levels in full-resolution pixels: the coarsest level's kernel radius is
    /// capped at r_max of its own pixels (Eq. 5), 2^(n-1) full-resolution pixels each.
    pub fn reach(&self, levels: u32) -> f32 {
        self.r_max * 2f32.powi(levels as i32 - 1)
    }

    /// The level count: fixed, or for `auto` the fewest in 1..=12 whose reach covers
    /// `radius_pixels` (the paper's 4 when the view is unknown).
    pub fn levels_for(&self, radius_pixels: Option<f32>) -> u32 {
        self.levels
            .resolve(radius_pixels, MAX_LEVELS, PAPER_LEVELS, |n| self.reach(n))
    }
}

impl AoTechnique for Mssao {
    type Params = MssaoParams;
    const NAME: &'static str = "mssao";
    fn description(&self) -> &'static str {
        "multi-resolution SSAO: g-buffer pyramid, small kernels per level, bilateral upsampling, max/average combine (Hoang & Low 2012)"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::word_or_int("levels", "auto", 1, MAX_LEVELS).doc(
                "number of resolutions n, each half the previous (Sec. 4.2); auto: the fewest whose reach r_max 2^(n-1) px covers R at the view's closest geometry (12 levels reach 10240 px: all of R up to 7680x4320)",
            ),
            ParamDesc::float("d_threshold", 0.0, 1000.0).doc(
                "spread of a 2x2 block about the median's plane (scene units) above which downsampling keeps the second-nearest sub-pixel instead of the median (Table 2's threshold; Table 2 tests the depth range)",
            ),
            ParamDesc::float("r_max", 1.0, 8.0)
                .doc("kernel radius cap in pixels of each level (Eq. 5)"),
            ParamDesc::float("normal_power", 0.0, 64.0)
                .doc("t_n, exponent of the normal weight (Eq. 8)"),
            ParamDesc::float("depth_power", 0.0, 64.0)
                .doc("t_z, exponent of the depth weight 1 / (1 + |dz|) (Eq. 9)"),
            ParamDesc::flag("bilateral_blur")
                .doc("weigh the 3x3 blur by Eqs. 8-9 as well (Sec. 4.5)"),
            ParamDesc::choice("upsampling", &["bilateral", "bilinear", "nearest"]).doc(
                "how a coarse level's tuple reaches the finer one (Sec. 4.5, Fig. 8): bilinear weights times Eqs. 8-9 (the paper's), bilinear alone, or the enclosing coarse texel",
            ),
            ParamDesc::flag("temporal").doc(
                "temporal filter: reprojection, depth test and fixed blend (Eqs. 12-14, Table 5)",
            ),
            ParamDesc::float("temporal_k", 0.0, 0.99)
                .doc("k, history weight when the reprojection test passes (Eq. 14)"),
            ParamDesc::float("temporal_epsilon", 0.0001, 1.0).doc(
                "relative depth tolerance |1 - z / z_prev| of the reprojection test (Eq. 13 in TSSAO Eq. 7's form, the shared block's; the paper's |1 - z_prev / z| differs only within about epsilon^2)",
            ),
            Resolution::param(),
        ]
    }
    fn channels(&self, p: &MssaoParams) -> GBufferChannels {
        p.resolution.channels(Self::spatial_channels(p))
    }
    fn is_temporal(&self, p: &MssaoParams) -> bool {
        p.temporal
    }
    fn needs_radius_pixels(&self, p: &MssaoParams) -> bool {
        p.levels == Levels::Auto
    }
    fn reach_pixels(&self, p: &MssaoParams, _: u32, radius_pixels: Option<f32>) -> Option<f32> {
        p.resolution
            .reach(0, radius_pixels, |_, r| Some(p.reach(p.levels_for(r))))
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &MssaoParams) -> AoResult<AoOutput> {
        self.validate(p)?;
        p.resolution.build(ctx, Self::spatial_channels(p), |ctx| {
            self.paper_pipeline(ctx, p)
        })
    }
}

impl Mssao {
    /// What the paper's pipeline reads.
    fn spatial_channels(p: &MssaoParams) -> GBufferChannels {
        // Sec. 4.1: view-space positions and true face normals (interpolated vertex normals
        // self-occlude on coarse meshes); positions are rebuilt from linear depth, normals read
        // in the compact encoding (module docs, "Storage").
        let spatial =
            GBufferChannels::of(&[GBufferChannel::LinearDepth]).with_compact_face_normals();
        // The temporal block reads linear depth (Eq. 13) and motion where the scene moves.
        if p.temporal {
            spatial.union(temporal_channels())
        } else {
            spatial
        }
    }

    /// Table 1's passes, levels 0 to n - 1, and the optional temporal filter.
    fn paper_pipeline(&self, ctx: &mut AoBuildContext<'_>, p: &MssaoParams) -> AoResult<AoOutput> {
        let radius = ctx.radius;
        let levels = p.levels_for(ctx.radius_pixels);
        let uniform = |level: u32| MssaoUniform::new(p, radius, level);
        let finest = Level {
            depth: ctx.channel(GBufferChannel::LinearDepth)?,
            normals: ctx.channel(GBufferChannel::NormalsOct)?,
        };
        // Table 2: the g-buffer pyramid.
        let mut pyramid = vec![finest];
        for l in 1..levels {
            let next = passes::downsample(ctx, l, pyramid[l as usize - 1], &uniform(l));
            pyramid.push(next);
        }
        // Tables 3-4, coarsest to finest; `blurred` is the previous (coarser) level's filtered
        // tuple.
        let mut blurred: Option<TextureHandle> = None;
        for l in (1..levels).rev() {
            let g = pyramid[l as usize];
            let far = blurred.map(|b| (b, pyramid[l as usize + 1]));
            let tuple = passes::ao_level(ctx, l, g, far, &uniform(l));
            blurred = Some(passes::blur(ctx, l, tuple, g, &uniform(l)));
        }
        let far = blurred.map(|b| (b, pyramid[1]));
        let accessibility = passes::ao_finest(ctx, pyramid[0], far, &uniform(0));
        if !p.temporal {
            return Ok(AoOutput::new(accessibility));
        }
        // Sec. 4.6, Table 5: reprojection, Eq. 13's test and Eq. 14's blend.
        let filter = TemporalAccumulation {
            epsilon: p.temporal_epsilon,
            n_max: 1,
            mode: TemporalMode::FixedBlend(p.temporal_k),
        };
        let t = add_temporal(
            ctx.builder,
            "mssao.temporal",
            accessibility,
            &ctx.gbuffer,
            ctx.view,
            &filter,
        )?;
        let mut out = AoOutput::new(t.accumulated);
        // This frame's own Eq. 11 output, before Eq. 14's blend (as the shared temporal
        // option outputs it).
        out.extra.push((PER_FRAME_OUTPUT, accessibility));
        Ok(out)
    }
}
