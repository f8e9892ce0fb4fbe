//! `tssao`: temporal SSAO (Mattausch, Scherzer, Wimmer 2010; docs/techniques/tssao.md). A per-pixel AO
//! buffer (accessibility, sample count n_t, Halton index, depth) is reprojected into each new
//! frame; k new samples continue each pixel's Halton sequence and are blended in with weight
//! k / (n_t + k); pixels whose history is invalid restart, and unconverged pixels get more
//! samples and a convergence-aware spatial filter.
//!
//! Passes, in order:
//! - `tssao.zero_motion` (only when nothing in the scene moves, so the g-buffer has no motion
//!   channel: the shared temporal block's 1x1 stand-in);
//! - `tssao.reproject` (shared block `blocks::temporal`, shaders/blocks/temporal_reproject.wgsl):
//!   Eq. 3 reprojection (motion vectors for moving geometry, `view_to_prev_clip` for the
//!   camera), the disocclusion test Eq. 7, off-screen invalidation (§3.6.3), bilinear AO and
//!   nearest n_t / Halton index (§3.3.1);
//! - `tssao.sample` (shaders/ao/tssao/sample.wgsl): k = k1 while conv < c_spatial, else k2
//!   (§3.6.2), per-pixel pattern rotation while conv < c_rot (§3.6.4), the per-frame estimator
//!   Eq. 2 over the next k points of the pixel's sequence (Eq. 4), the neighbourhood test
//!   Eq. 8 with smooth invalidation (§3.6.1), the blend Eqs. 5-6; writes the AO buffer (the
//!   history);
//! - `tssao.filter` (shaders/ao/tssao/filter.wgsl): the convergence-aware spatial filter
//!   Eqs. 9-10 into the output; the AO buffer keeps the unfiltered values (spec §2 \[I\]).
//!
//! Reads linear depth, normals and (for scenes that move) motion. History validity comes from
//! the view block's `frame.y` and the executor clears invalid history, so a camera cut or a
//! resize restarts every pixel from n_t = 0 at its own starting index: the first frame after
//! either equals a first frame.
//!
//! Invariant: the output is accessibility in [0, 1], exactly 1 on sky, never NaN; each
//! per-pixel loop runs at most k1 x steps iterations (filter: F x F).
//!
//! Values the paper leaves open (spec §13), chosen here:
//! - Estimator (Eq. 2, C = V cos D): sample directions are cosine-distributed over the
//!   hemisphere (Halton bases 2 and 3, Malley's method), which folds the cosine into the
//!   sampling density, so C = V D. V(p, s_i), "s_i is not visible from p" (§3.1), is tested
//!   along the segment from p to s_i = p + R w_i at `steps` points t_j = R (j + 1 - u) / steps,
//!   the last at R itself, u the sample's third Halton coordinate (base 5): the accumulated
//!   samples integrate the whole segment, and an occluder anywhere before R leaves the end
//!   point behind a wall-like depth buffer. A point counts as blocked when the depth buffer
//!   lies in front of it and the surface seen there is within 2R of p (the paper's distance
//!   rejection, §4: samples it rejects count as visible). Off-screen and sky taps are
//!   unoccluding. This is the reference's definition (a ray hitting geometry within R)
//!   evaluated on the depth buffer. steps = 4: on `columns` (96x64) the converged MAE is 0.040,
//!   0.032, 0.027, 0.027 for 1, 2, 4, 8 steps.
//! - `visibility = "point"` is the paper's own test instead (§3.1, \[RGS09\]: "checking whether
//!   s_i is visible in the z-buffer"): one depth test per sample, at s_i = p + R (1 - u) w, a
//!   point placed uniformly along the sample's direction. An occluder at distance d then
//!   blocks with probability 1 - d/R, the "linear falloff" the paper says its equal weights
//!   amount to (§4), so against the binary reference it reads lighter than the march; it
//!   costs one depth load a sample instead of `steps`.
//! - `neighbourhood_test = false` drops Eq. 8 (the disocclusion test, Eq. 7, alone): the
//!   paper's Fig. 8 comparison, where contact shadows stay behind moving objects.
//! - Falloff D: `none` (D = 1, the reference's binary mode; the paper's Fig. 12 comparison
//!   with Mental Ray also weighted samples equally) or `quadratic` (1 - (t/R)^2 at the
//!   blocked point, the reference's obscurance mode). The paper's example exp() is not offered:
//!   the reference has no exp mode to be measured against.
//! - Self-occlusion: the segment starts 1.5 pixel footprints above p along the normal, which
//!   covers the half-texel depth slope of a plane at any view angle.
//! - Sample sequence: a precomputed table of L = 2048 Halton points (bases 2, 3, 5; spec
//!   §10.2: L >= n_max) already mapped to tangent-space directions. Each pixel's index starts
//!   at a per-pixel hash where it has no history at all (first frame, cut, resize, previously
//!   off screen: §3.3.1's per-pixel "starting index", so converged neighbours do not share one
//!   pattern), advances by k each frame, wraps modulo L, and runs on across a disocclusion
//!   (spec §10.2 \[I\]). Pattern rotation (§3.6.4) turns the pattern about the normal by a
//!   per-pixel angle and shifts the step jitter by a per-pixel offset.
//! - Eq. 7 epsilon: 0.03 (`depth_epsilon`, the middle of the spec's 0.01-0.05). Eq. 8
//!   epsilon: 0.02 R (`neighbour_epsilon`, the low end of the spec's 2-10% of R: occluders
//!   moving 3 cm per frame, like `dynamic`'s spinner, still trip it). The g-buffer's motion is
//!   3D (previous uv and previous linear depth, `GBufferChannel::Motion`), so the previous
//!   positions s_i^old, p_old of Eq. 8 and the previous depth of Eq. 7 are the surfaces' true
//!   ones, for motion along the view axis too; exact for static geometry (the test then never
//!   fires under camera motion, as in the paper). Eq. 8 runs only where the scene has motion vectors and the
//!   pixel's history is valid.
//! - Eq. 8 extended to the previous occupant (\[I\], for spec §12's noted gap: an occluder that
//!   left p's kernel is hit by no current sample): at each sample's previous position the AO
//!   buffer's depth tells what was there last frame; if that was moving geometry (history.w <
//!   0) at a depth that fails Eq. 7, the neighbourhood changed. So contact shadows do not trail
//!   behind moving objects for the n_max decay time.
//! - Smooth invalidation (§3.6.1): n_t := min(n_t, n_smooth) before Eq. 5 when only the
//!   neighbourhood test fails (n_smooth = 32, the tighter end of 32-64; 0 = full reset); a
//!   disocclusion or off-screen pixel resets to 0. k is chosen before the test (spec §14
//!   note), but a pixel whose test fails takes k1 samples in that frame already (§3.6.2's
//!   adaptive sampling applied one frame earlier).
//! - n_max = 500 (the paper's 500-1500; the spec's suggestion for dynamic content). Filter:
//!   Eq. 9 evaluated over the full F x F = 5 x 5 footprint (Table 1) in one pass rather than
//!   the paper's separable approximation: exact, and a single load for converged pixels;
//!   Gaussian on world distance with sigma = 0.5 R; Eq. 10's shrink s scales the half width
//!   (the tap at offset (i, j) weighs c(i) c(j), c(k) = clamp(s h + 0.5 - |k|, 0, 1)), so at
//!   s = 0 only the centre remains. conv is taken after this frame's update, so every non-sky
//!   pixel has conv > 0 and the filter's denominator is positive.
//! - Screen-radius cap as in `ssao`/`hbao`: R projects to at most `max_screen_radius` x height
//!   pixels (R shrinks to match); under one pixel the pixel is unoccluded.
//! - `intermediate_format` does not apply: the AO buffer is 32-bit RGBA as in the paper (§4:
//!   "Both the ambient occlusion buffer and the SSAO texture are 32-bit RGBA render targets")
//!   and the output is R32Float accessibility.
//! - Under camera motion the bilinear history fetch (§3.3) blurs a little more each frame; the
//!   n_max clamp bounds it as the paper says, but at small image sizes it is visible (the
//!   `dynamic` test reports it).

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{SizeClass, TextureDesc};
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use crate::blocks::temporal::{add_reprojection, ao_history};
use crate::error::{AoError, AoResult};
use crate::param::ParamDesc;
use crate::technique::{ACCESSIBILITY_FORMAT, AoBuildContext, AoOutput, AoTechnique};

/// Largest k1 / k2 (new samples per pixel and frame).
pub const MAX_SAMPLES: u32 = 64;
/// Largest number of visibility steps per sample.
pub const MAX_STEPS: u32 = 8;
/// Largest spatial filter width (taps per axis).
pub const MAX_FILTER_WIDTH: u32 = 9;
/// Length L of the precomputed Halton table (a power of two); each pixel's index wraps
/// modulo L, so n_max is at most L (a pixel's window never overlaps itself).
pub const HALTON_LENGTH: u32 = 2048;

/// The sample pattern (the shader's `halton` table): Halton points 1..=L in bases 2, 3 and 5
/// (point 0, the origin, is skipped), (u1, u2) mapped to a cosine-distributed direction in
/// tangent space by Malley's method (xyz, z along the normal), u3 kept as the step jitter (w).
pub fn halton_table() -> Vec<[f32; 4]> {
    fn radical_inverse(mut i: u32, base: u32) -> f32 {
        let (inv, mut f, mut r) = (1.0 / base as f64, 1.0 / base as f64, 0.0f64);
        while i > 0 {
            r += (i % base) as f64 * f;
            i /= base;
            f *= inv;
        }
        r as f32
    }
    (1..=HALTON_LENGTH)
        .map(|i| {
            let (u1, u2, u3) = (
                radical_inverse(i, 2),
                radical_inverse(i, 3),
                radical_inverse(i, 5),
            );
            let (r, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
            [r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt(), u3]
        })
        .collect()
}

/// The `tssao` technique (module docs): temporal SSAO, each pixel's AO buffer reprojected
/// and continued with k new samples a frame; parameters [`TssaoParams`].
pub struct Tssao;

/// `[ao.tssao]` parameters (Table 1 of the paper where it gives them).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TssaoParams {
    /// New samples per frame while conv < c_spatial (k1, Table 1: 32).
    pub k1: u32,
    /// New samples per frame once converged (k2, Table 1: 8-16).
    pub k2: u32,
    /// Cap of the per-pixel sample count n_t (Table 1: 500-1500).
    pub n_max: u32,
    /// Convergence below which k1 samples are taken (Table 1: 0.3).
    pub c_spatial: f32,
    /// Convergence from which the per-pixel pattern rotation is off (Table 1: 0.5).
    pub c_rot: f32,
    /// Convergence from which the spatial filter is off (Table 1: 0.2, Eq. 10).
    pub c_adaptive: f32,
    /// Smooth invalidation: n_t is clamped to this when only Eq. 8 fails (§3.6.1: 32-64;
    /// 0 = reset to 0, the paper's unsmoothed invalidation).
    pub n_smooth: u32,
    /// Relative depth tolerance of the disocclusion test, Eq. 7 (not given by the paper).
    pub depth_epsilon: f32,
    /// Tolerance of the neighbourhood test, Eq. 8, as a fraction of R (not given).
    pub neighbour_epsilon: f32,
    /// Spatial filter taps per axis (Table 1: 5 x 5).
    pub filter_width: u32,
    /// Gaussian sigma of the filter's world-space distance term, as a fraction of R.
    pub filter_sigma: f32,
    /// Points tested along each sample's segment for V(p, s_i).
    pub steps: u32,
    /// Distance falloff D of Eq. 2: "none" (binary) or "quadratic" (1 - (t/R)^2).
    pub falloff: String,
    /// Cap of the projected radius, as a fraction of the image height.
    pub max_screen_radius: f32,
    /// V(p, s_i): "march" (`steps` points along the segment, the last at R) or "point" (the
    /// paper's single depth test at s_i, a point uniformly placed along the direction).
    pub visibility: String,
    /// The neighbourhood test, Eq. 8. Off: the disocclusion test alone (Fig. 8's left image,
    /// which shows what Eq. 8 prevents: contact shadows left behind by moving objects).
    pub neighbourhood_test: bool,
}

impl Default for TssaoParams {
    fn default() -> Self {
        Self {
            k1: 32,
            k2: 8,
            n_max: 500,
            c_spatial: 0.3,
            c_rot: 0.5,
            c_adaptive: 0.2,
            n_smooth: 32,
            depth_epsilon: 0.03,
            neighbour_epsilon: 0.02,
            filter_width: 5,
            filter_sigma: 0.5,
            steps: 4,
            falloff: "none".into(),
            max_screen_radius: 0.5,
            visibility: "march".into(),
            neighbourhood_test: true,
        }
    }
}

const VISIBILITY: [&str; 2] = ["march", "point"];

const FALLOFFS: [&str; 2] = ["none", "quadratic"];

/// The `params` uniform of shaders/ao/tssao/sample.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SampleUniform {
    /// Samples per frame k1 (unconverged).
    k1: u32,
    /// Samples per frame k2 (converged).
    k2: u32,
    /// Steps per sample.
    steps: u32,
    /// Visibility: 0 march, 1 point.
    visibility: u32,
    /// n_t clamp on a smooth invalidation (n_smooth).
    n_smooth: u32,
    /// Falloff: 0 none, 1 quadratic.
    falloff: u32,
    /// Halton sequence length L.
    halton_length: u32,
    _pad0: u32,
    /// Convergence below which k1 samples are taken (c_spatial).
    c_spatial: f32,
    /// Convergence from which the pattern rotation is off (c_rot).
    c_rot: f32,
    /// Cap of the sample count n_t (n_max).
    n_max: f32,
    /// R (world units).
    radius: f32,
    /// Eq. 7 epsilon (relative).
    depth_epsilon: f32,
    /// Eq. 8 epsilon (world units).
    neighbour_epsilon: f32,
    /// Cap of the projected radius (fraction of the image height).
    max_screen_radius: f32,
    _pad1: f32,
}

aograph_graph::uniform_layout!(SampleUniform {
    k1,
    k2,
    steps,
    visibility,
    n_smooth,
    falloff,
    halton_length,
    _pad0,
    c_spatial,
    c_rot,
    n_max,
    radius,
    depth_epsilon,
    neighbour_epsilon,
    max_screen_radius,
    _pad1
});

/// The `params` uniform of shaders/ao/tssao/filter.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct FilterUniform {
    /// Half width h = (F - 1) / 2.
    half_width: i32,
    _pad0: i32,
    _pad1: i32,
    _pad2: i32,
    /// Gaussian sigma (world units).
    sigma: f32,
    /// Convergence from which the filter is off (c_adaptive).
    c_adaptive: f32,
    /// Cap of the sample count n_t (n_max).
    n_max: f32,
    _pad3: f32,
}

aograph_graph::uniform_layout!(FilterUniform {
    half_width,
    _pad0,
    _pad1,
    _pad2,
    sigma,
    c_adaptive,
    n_max,
    _pad3
});

impl AoTechnique for Tssao {
    type Params = TssaoParams;
    const NAME: &'static str = "tssao";
    fn description(&self) -> &'static str {
        "temporal SSAO: reprojected per-pixel AO buffer, k new Halton samples per frame, invalidation, convergence-aware filter"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::int("k1", 1, MAX_SAMPLES)
                .doc("new samples per frame while convergence < c_spatial (paper: 32)"),
            ParamDesc::int("k2", 1, MAX_SAMPLES)
                .doc("new samples per frame once converged (paper: 8 to 16)"),
            ParamDesc::int("n_max", 1, HALTON_LENGTH)
                .doc("cap of the per-pixel sample count n_t (paper: 500 to 1500)"),
            ParamDesc::float("c_spatial", 0.0, 1.0)
                .doc("convergence below which k1 samples are taken (paper: 0.3)"),
            ParamDesc::float("c_rot", 0.0, 1.0)
                .doc("convergence from which the per-pixel pattern rotation is off (paper: 0.5)"),
            ParamDesc::float("c_adaptive", 0.001, 1.0)
                .doc("convergence from which the spatial filter is off (paper: 0.2)"),
            ParamDesc::int("n_smooth", 0, HALTON_LENGTH).doc(
                "n_t is clamped to this (at most n_max) when only the neighbourhood test fails (paper: 32 to 64; 0 = reset)",
            ),
            ParamDesc::float_above("depth_epsilon", 0.0, 1.0)
                .doc("relative depth tolerance of the disocclusion test, Eq. 7"),
            ParamDesc::float_above("neighbour_epsilon", 0.0, 1.0)
                .doc("tolerance of the neighbourhood test, Eq. 8, as a fraction of R"),
            ParamDesc::odd("filter_width", 1, MAX_FILTER_WIDTH)
                .doc("spatial filter taps per axis (paper: 5)"),
            ParamDesc::float("filter_sigma", 0.01, 10.0)
                .doc("sigma of the filter's world-space Gaussian, as a fraction of R"),
            ParamDesc::int("steps", 1, MAX_STEPS)
                .doc("points tested along each sample's segment for the visibility V"),
            ParamDesc::choice("falloff", &FALLOFFS)
                .doc("distance falloff D of Eq. 2: none (binary) or 1 - (t/R)^2"),
            ParamDesc::float("max_screen_radius", 0.01, 2.0)
                .doc("cap of the projected radius R, as a fraction of the image height"),
            ParamDesc::choice("visibility", &VISIBILITY).doc(
                "V(p, s_i): march (steps points up to R) or point (the paper's single depth test)",
            ),
            ParamDesc::flag("neighbourhood_test").doc(
                "the neighbourhood test, Eq. 8 (false: disocclusion test only, the paper's Fig. 8)",
            ),
        ]
    }
    fn validate(&self, p: &TssaoParams) -> AoResult<()> {
        if p.n_smooth > p.n_max {
            return Err(AoError::ParameterRule {
                technique: Self::NAME.into(),
                rule: format!(
                    "n_smooth = {} exceeds n_max = {}: allowed 0 to n_max",
                    p.n_smooth, p.n_max
                ),
            });
        }
        Ok(())
    }
    fn reach_pixels(&self, p: &TssaoParams, height: u32, _: Option<f32>) -> Option<f32> {
        // The projected radius is capped at max_screen_radius x height (R shrinks to match).
        Some(p.max_screen_radius * height as f32)
    }
    fn channels(&self, _: &TssaoParams) -> GBufferChannels {
        // Motion is dropped by the g-buffer for scenes where nothing moves.
        GBufferChannels::of(&[
            GBufferChannel::LinearDepth,
            GBufferChannel::Normals,
            GBufferChannel::Motion,
        ])
    }
    fn is_temporal(&self, _: &TssaoParams) -> bool {
        true
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &TssaoParams) -> AoResult<AoOutput> {
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let normals = ctx.channel(GBufferChannel::Normals)?;
        let falloff = FALLOFFS.iter().position(|f| *f == p.falloff).unwrap_or(0) as u32;
        let visibility = VISIBILITY
            .iter()
            .position(|v| *v == p.visibility)
            .unwrap_or(0) as u32;

        // The AO buffer and its reprojection (shared temporal block: Eqs. 3 and 7).
        let history = ao_history(ctx.builder, Self::NAME);
        let r = add_reprojection(
            ctx.builder,
            Self::NAME,
            history.previous,
            &ctx.gbuffer,
            ctx.view,
            p.depth_epsilon,
        )?;

        // k new samples, Eq. 8, Eqs. 5-6: writes the AO buffer.
        let uniform = SampleUniform {
            k1: p.k1,
            k2: p.k2,
            steps: p.steps,
            visibility,
            n_smooth: p.n_smooth,
            falloff,
            halton_length: HALTON_LENGTH,
            _pad0: 0,
            c_spatial: p.c_spatial,
            c_rot: p.c_rot,
            n_max: p.n_max as f32,
            radius: ctx.radius,
            depth_epsilon: p.depth_epsilon,
            neighbour_epsilon: p.neighbour_epsilon * ctx.radius,
            max_screen_radius: p.max_screen_radius,
            _pad1: 0.0,
        };
        // Without Eq. 8 (or without motion, where it always holds) the test is compiled out.
        let entry = if r.has_motion && p.neighbourhood_test {
            "main_dynamic"
        } else {
            "main"
        };
        let mut pass = ctx
            .builder
            .compute_pass("tssao.sample", "ao/tssao/sample.wgsl", entry);
        pass.sample("reprojected", r.reprojected)
            .sample("previous", history.previous);
        pass.sample("depth", depth)
            .sample("normals", normals)
            .sample("motion", r.motion);
        pass.read_view(ctx.view);
        pass.uniform_struct("params", &uniform);
        pass.uniform("halton", bytemuck::cast_slice(&halton_table()));
        let buffer = pass.write_storage("ao_buffer", history.current);
        pass.dispatch_over(buffer);

        // Eqs. 9-10 into the output; the AO buffer keeps the unfiltered values.
        let out = ctx.builder.create_texture(
            "tssao.filtered",
            TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
        );
        let mut pass = ctx
            .builder
            .compute_pass("tssao.filter", "ao/tssao/filter.wgsl", "main");
        pass.sample("ao_buffer", buffer).sample("depth", depth);
        pass.read_view(ctx.view);
        let filter = FilterUniform {
            half_width: (p.filter_width / 2) as i32,
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
            sigma: p.filter_sigma * ctx.radius,
            c_adaptive: p.c_adaptive,
            n_max: p.n_max as f32,
            _pad3: 0.0,
        };
        pass.uniform_struct("params", &filter);
        let out = pass.write_storage("dst", out);
        pass.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DynAoTechnique;
    use aograph_frame::{GBufferTextures, VIEW_BUFFER, ViewUniforms};
    use aograph_graph::{BufferDesc, CompileOptions, GraphBuilder, compile};

    fn plan_names(with_motion: bool) -> Vec<String> {
        let mut b = GraphBuilder::new();
        let view = b.import_buffer(
            VIEW_BUFFER,
            BufferDesc {
                size: std::mem::size_of::<ViewUniforms>() as u64,
            },
        );
        let mut g = GBufferTextures::default();
        let channels = AoTechnique::channels(&Tssao, &TssaoParams::default());
        for c in channels
            .iter()
            .filter(|c| with_motion || *c != GBufferChannel::Motion)
        {
            g.set(
                c,
                b.import_texture(c.name(), TextureDesc::new(c.format(), SizeClass::FULL)),
            );
        }
        let mut ctx = AoBuildContext {
            builder: &mut b,
            gbuffer: g,
            view,
            radius: 1.0,
            intermediate_format: wgpu::TextureFormat::R32Float,
            technique: Tssao::NAME,
            radius_pixels: None,
            declared: Default::default(),
            tracing: Default::default(),
        };
        let out = AoTechnique::build(&Tssao, &mut ctx, &TssaoParams::default()).unwrap();
        b.export(out.accessibility);
        let shaders = crate::shader_library().unwrap();
        let plan = compile(b.build(), &shaders, CompileOptions::default()).unwrap();
        plan.pass_names().into_iter().map(String::from).collect()
    }

    #[test]
    fn plan_is_reproject_sample_filter() {
        assert_eq!(
            plan_names(true),
            ["tssao.reproject", "tssao.sample", "tssao.filter"]
        );
        assert_eq!(
            plan_names(false),
            [
                "tssao.zero_motion",
                "tssao.reproject",
                "tssao.sample",
                "tssao.filter"
            ]
        );
    }

    #[test]
    fn is_temporal_and_reads_depth_normals_motion() {
        assert!(AoTechnique::is_temporal(&Tssao, &TssaoParams::default()));
        let c = AoTechnique::channels(&Tssao, &TssaoParams::default());
        assert_eq!(
            c.iter().collect::<Vec<_>>(),
            [
                GBufferChannel::LinearDepth,
                GBufferChannel::Normals,
                GBufferChannel::Motion
            ]
        );
    }

    #[test]
    fn n_smooth_is_at_most_n_max() {
        let t = |text: &str| Tssao.check(&text.parse().unwrap());
        assert!(
            t("n_smooth = 500").is_ok(),
            "n_smooth = n_max (500) is allowed"
        );
        let e = t("n_smooth = 501").unwrap_err();
        assert!(matches!(e, AoError::ParameterRule { .. }), "{e}");
        assert!(
            e.to_string().contains("n_smooth = 501 exceeds n_max = 500"),
            "{e}"
        );
        assert!(t("n_max = 1500\nn_smooth = 1000").is_ok());
    }

    #[test]
    fn halton_table_is_a_cosine_distributed_pattern_the_shader_declares() {
        let t = halton_table();
        assert_eq!(t.len(), HALTON_LENGTH as usize);
        assert!(
            HALTON_LENGTH.is_power_of_two(),
            "the shader wraps indices with a mask"
        );
        for p in &t {
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!(
                (len - 1.0).abs() < 1e-5 && p[2] >= 0.0 && (0.0..1.0).contains(&p[3]),
                "{p:?}"
            );
        }
        // Cosine-distributed: E[cos theta] = 2/3 over the hemisphere.
        let mean_cos = t.iter().map(|p| p[2] as f64).sum::<f64>() / t.len() as f64;
        assert!((mean_cos - 2.0 / 3.0).abs() < 0.01, "{mean_cos}");
        let shader = crate::shader_mount()
            .source("ao/tssao/sample.wgsl")
            .expect("embedded")
            .to_string();
        assert!(
            shader.contains(&format!("array<vec4<f32>, {HALTON_LENGTH}>")),
            "sample.wgsl's table length must be HALTON_LENGTH"
        );
    }

    #[test]
    fn paper_defaults() {
        let p = TssaoParams::default();
        assert_eq!(
            (p.k1, p.k2, p.n_max, p.n_smooth, p.filter_width),
            (32, 8, 500, 32, 5)
        );
        assert_eq!((p.c_spatial, p.c_rot, p.c_adaptive), (0.3, 0.5, 0.2));
    }
}
