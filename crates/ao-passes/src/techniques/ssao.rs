//! `ssao`: the classic sampled SSAO the MSSAO paper compares with (docs/techniques/mssao.md §9.1, the
//! Crytek/Blizzard baseline): N sample points in the normal-oriented hemisphere of radius R,
//! rotated per pixel by a 4x4 tile of 16 rotations, each counted as occluded when the depth
//! buffer lies in front of it, weighted by a smoothstep range check; then a 4x4 box blur that
//! removes the 4x4 rotation pattern (made centred: 5 taps weighted 1/2, 1, 1, 1, 1/2 per axis).
//!
//! Passes, in order: `ssao.ao` (raw accessibility, shaders/ao/ssao/ao.wgsl) and `ssao.blur`
//! (4x4 box, shaders/ao/ssao/blur.wgsl). Reads linear depth and normals.
//!
//! Invariant: the output is accessibility in [0, 1], exactly 1 on sky, never NaN; every
//! per-pixel loop runs at most [`MAX_SAMPLES`] iterations whatever R is.
//!
//! Implementation choices (the baseline papers leave them open; written down here):
//! - Kernel: directions cosine-distributed in the hemisphere (Halton bases 2 and 3, Malley's
//!   method) so the point count approximates the reference's cosine weighting; lengths
//!   `lerp(0.1, 1, t^2)`, t = (i + 0.5) / N, so more samples lie near the origin.
//! - Rotation noise: rotation k of the 4x4 tile is 2 pi (k + 1/2) / 16, k the pixel's Bayer
//!   index (`interleave_4x4`), so every 4x4 window holds all 16 rotations once and the blur
//!   averages them exactly. The frame is built by Gram-Schmidt of the rotation vector against n.
//! - Mirror covariance (a view mirrored left to right gives the mirrored image; tests/
//!   output_sizes.rs): mirroring maps rotation a to pi - a, which the half-step angles map onto
//!   the set (k -> 7 - k), and flips the frame's bitangent; so rotations with k mod 8 >= 4 use the
//!   kernel's mirror image (y negated), and k -> 7 - k swaps the two halves. The classic 4x4 box
//!   (offsets -2..1) is half a pixel off centre, so its image and its mirror differed by a
//!   pixel; the blur is the centred 5x5 with end taps at half weight, which gives each phase of
//!   the 4-pixel pattern the same total weight. (Before: block means 0.007 to 0.011 from the
//!   mirror image on `columns`; after: 0.001 to 0.003, within the noise bound.)
//! - Depth test: the classic test `z_scene < z_sample - bias` compares the sample with the depth
//!   at the centre of the pixel it lands in, which on grazing surfaces reads the receiver itself
//!   up to half a pixel closer and self-occludes. Both depths are therefore measured relative
//!   to the receiver's tangent plane along their own rays (identical to the classic test when
//!   the sample lies on a pixel centre, exact for planes); where that plane is edge-on the
//!   classic test is used. (With the plain test a plane seen 80 degrees off its normal came out
//!   as dark as 0.70 at 64x64; with this one it is 1.)
//! - Range check: weight `1 - smoothstep(R/2, R, |z_p - z_scene|)`: an occluder more than R
//!   away in depth contributes nothing.
//! - Bias is a fraction of R so it scales with the scene.
//! - Screen-radius cap: R projects to `R * pixels_per_unit(z)` pixels; it is capped at
//!   `max_screen_radius` times the image height (R shrinks to match), and a pixel whose radius
//!   is under one pixel has no neighbourhood to test and is unoccluded.
//! - The raw texture `ssao.raw` is an intermediate: it has `[ao] intermediate_format` and its
//!   writer is the matching variant of shaders/ao/ssao/ao.wgsl (`ctx.shader`); the blurred
//!   output is R32Float like every technique's.

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{SizeClass, TextureDesc};
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use super::depth_and_normals;
use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::spatial_options::SpatialOptions;
use crate::technique::{ACCESSIBILITY_FORMAT, AoBuildContext, AoOutput, AoTechnique};

/// Largest sample count (size of the kernel array in the uniform block).
pub const MAX_SAMPLES: u32 = 64;

/// The `ssao` technique (module docs): the classic sampled SSAO, N points in the
/// normal-oriented hemisphere of radius R tested against the depth buffer, then a 4x4 box
/// blur; parameters [`SsaoParams`].
pub struct Ssao;

/// `[ao.ssao]` parameters.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct SsaoParams {
    /// Sample points per pixel.
    pub samples: u32,
    /// Depth bias, as a fraction of R.
    pub bias: f32,
    /// Cap of the projected radius, as a fraction of the image height.
    pub max_screen_radius: f32,
    /// `resolution` and the temporal option (crate::SpatialOptions).
    #[serde(flatten)]
    pub spatial: SpatialOptions,
}

impl Default for SsaoParams {
    fn default() -> Self {
        Self {
            samples: 16,
            bias: 0.025,
            max_screen_radius: 0.5,
            spatial: SpatialOptions::default(),
        }
    }
}

/// The `params` uniform of shaders/ao/ssao/ao.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct SsaoUniform {
    /// Sample count N.
    samples: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    /// R (world units).
    radius: f32,
    /// Depth bias (fraction of R).
    bias: f32,
    /// Cap of the projected radius (fraction of the image height).
    max_screen_radius: f32,
    _pad3: f32,
    /// Tangent-space sample offsets (z along the normal), in units of R.
    kernel: [[f32; 4]; MAX_SAMPLES as usize],
}

aograph_graph::uniform_layout!(SsaoUniform {
    samples,
    _pad0,
    _pad1,
    _pad2,
    radius,
    bias,
    max_screen_radius,
    _pad3,
    kernel
});

fn radical_inverse(mut i: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0 / base as f32, 0.0);
    let inv = f;
    while i > 0 {
        r += (i % base) as f32 * f;
        i /= base;
        f *= inv;
    }
    r
}

/// The hemisphere kernel: `n` points with z >= 0 and length in [0.1, 1], cosine-distributed
/// directions, denser near the origin.
pub fn hemisphere_kernel(n: u32) -> Vec<[f32; 3]> {
    (0..n)
        .map(|i| {
            // Halton point i + 1 (index 0 is the degenerate origin).
            let (u1, u2) = (radical_inverse(i + 1, 2), radical_inverse(i + 1, 3));
            let (r, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
            let dir = [r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt()];
            let t = (i as f32 + 0.5) / n as f32;
            let scale = 0.1 + 0.9 * t * t;
            dir.map(|c| c * scale)
        })
        .collect()
}

impl AoTechnique for Ssao {
    type Params = SsaoParams;
    const NAME: &'static str = "ssao";
    fn description(&self) -> &'static str {
        "classic SSAO: N points in the normal-oriented hemisphere, 4x4 rotation noise, 4x4 box blur"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::int("samples", 4, MAX_SAMPLES).doc("sample points per pixel"),
            ParamDesc::float("bias", 0.0, 0.5).doc(
                "depth bias as a fraction of R: a sample counts as occluded only this far behind the depth buffer",
            ),
            ParamDesc::float("max_screen_radius", 0.01, 2.0)
                .doc("cap of the projected radius R, as a fraction of the image height"),
        ]
        .into_iter()
        .chain(SpatialOptions::params())
        .collect()
    }
    fn reach_pixels(&self, p: &SsaoParams, height: u32, r: Option<f32>) -> Option<f32> {
        // The projected radius is capped at max_screen_radius x height (R shrinks to match).
        p.spatial
            .reach(height, r, |h, _| Some(p.max_screen_radius * h as f32))
    }
    fn channels(&self, p: &SsaoParams) -> GBufferChannels {
        p.spatial.channels(depth_and_normals())
    }
    fn is_temporal(&self, p: &SsaoParams) -> bool {
        p.spatial.is_temporal()
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &SsaoParams) -> AoResult<AoOutput> {
        // At the chosen resolution, then the optional running mean (crate::SpatialOptions).
        p.spatial
            .build(ctx, depth_and_normals(), |ctx| self.spatial(ctx, p))
    }
}

impl Ssao {
    /// The classic passes: the estimator, then the 5x5 tile blur.
    fn spatial(&self, ctx: &mut AoBuildContext<'_>, p: &SsaoParams) -> AoResult<AoOutput> {
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let normals = ctx.channel(GBufferChannel::Normals)?;
        let mut uniform = SsaoUniform {
            samples: p.samples,
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
            radius: ctx.radius,
            bias: p.bias,
            max_screen_radius: p.max_screen_radius,
            _pad3: 0.0,
            kernel: [[0.0; 4]; MAX_SAMPLES as usize],
        };
        for (k, s) in uniform.kernel.iter_mut().zip(hemisphere_kernel(p.samples)) {
            *k = [s[0], s[1], s[2], 0.0];
        }

        // Pass 1: occlusion of the N rotated hemisphere points, at the intermediate precision.
        let raw = ctx.intermediate("ssao.raw", SizeClass::FULL);
        let shader = ctx.shader("ao/ssao/ao.wgsl");
        let mut pass = ctx.builder.compute_pass("ssao.ao", &shader, "main");
        pass.sample("depth", depth).sample("normals", normals);
        // The centre's depth and normal, one depth tap per sample.
        pass.loads_per_invocation(2.0 + p.samples as f32);
        pass.read_view(ctx.view);
        pass.uniform_struct("params", &uniform);
        p.spatial.vary_noise(&mut pass);
        let raw = pass.write_storage("ao", raw);
        pass.dispatch_over(raw);

        // Pass 2: 4x4 box blur over the rotation tile.
        let out = ctx.builder.create_texture(
            "ssao.accessibility",
            TextureDesc::new(ACCESSIBILITY_FORMAT, SizeClass::FULL),
        );
        let mut pass = ctx
            .builder
            .compute_pass("ssao.blur", "ao/ssao/blur.wgsl", "main");
        pass.sample("raw", raw).sample("depth", depth);
        // The centre's depth, then depth and AO over the 4x4 tile.
        pass.loads_per_invocation(1.0 + 16.0 * 2.0);
        let out = pass.write_storage("ao", out);
        pass.dispatch_over(out);
        Ok(AoOutput::new(out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TechniqueRegistry;
    use crate::contract::plan_pass_names;

    #[test]
    fn plan_is_ao_then_blur() {
        let shaders = crate::shader_library().unwrap();
        let ssao = TechniqueRegistry::with_builtins()
            .get(Ssao::NAME)
            .unwrap()
            .clone();
        for params in ["", "samples = 64"] {
            assert_eq!(
                plan_pass_names(&ssao, params, &shaders).unwrap(),
                ["ssao.ao", "ssao.blur"]
            );
        }
    }

    #[test]
    fn reads_depth_and_normals_only() {
        let c = AoTechnique::channels(&Ssao, &SsaoParams::default());
        assert_eq!(
            c.iter().collect::<Vec<_>>(),
            [GBufferChannel::LinearDepth, GBufferChannel::Normals]
        );
    }

    #[test]
    fn kernel_lies_in_the_hemisphere_and_is_denser_near_the_origin() {
        for n in [4, 16, MAX_SAMPLES] {
            let k = hemisphere_kernel(n);
            assert_eq!(k.len(), n as usize);
            let lengths: Vec<f32> = k
                .iter()
                .map(|s| (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt())
                .collect();
            assert!(
                k.iter()
                    .all(|s| s[2] >= 0.0 && s.iter().all(|c| c.is_finite()))
            );
            assert!(
                lengths.iter().all(|l| (0.099..=1.0).contains(l)),
                "{lengths:?}"
            );
            let inner = lengths.iter().filter(|l| **l < 0.55).count();
            assert!(
                inner * 2 > n as usize,
                "more than half the points within half the radius: {inner}/{n}"
            );
        }
    }
}
