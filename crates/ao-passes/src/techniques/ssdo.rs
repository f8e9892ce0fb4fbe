//! `ssdo`: screen-space directional occlusion with one indirect bounce (Ritschel, Grosch and
//! Seidel, "Approximating Dynamic Global Illumination in Image Space"; docs/techniques/ssdo.md). The
//! paper has no equation numbers; E1/E2/E3 below are the spec's labels.
//!
//! Passes, in the paper's order (§1.5):
//! 1. `ssdo.direct` (shaders/ao/ssdo/direct.wgsl): N samples `P + lambda_i omega_i` from one of
//!    16 interleaved sets ([`kernel`]), each back-projected and classified against the position
//!    buffer (§1.4); the direct radiance L_dir (E1) from the environment and the directional
//!    light, and the AO-equivalent accessibility, as rgb + a of one Rgba16Float texture.
//! 2. `ssdo.indirect` (indirect.wgsl, only with `bounce = true`): the same samples and verdicts;
//!    every blocker is a sender patch of area A_s = pi r_max^2 / N (E3) radiating the pass-1
//!    radiance of its pixel; L_ind by E2.
//! 3. `ssdo.blur_x`, `ssdo.blur_y` (blur_x.wgsl, blur_y.wgsl): the geometry-sensitive blur
//!    [Segovia et al. 2006] over the 4x4 interleave footprint, separable; blur_y writes the
//!    accessibility (R32Float, the main output) and the extra outputs `ssdo_direct` and
//!    `ssdo_indirect` (Rgba16Float, linear radiance; `aograph render` writes them as PNGs).
//!
//! Reads positions, normals, albedo and direct light: the only technique that needs colour, so
//! the g-buffer writes albedo and direct light only when SSDO is in the graph. The scene's light
//! and ambient come from the scene's lighting block (`aograph_frame::LightingUniforms`, a frame
//! input this technique declares with `AoBuildContext::scene_lighting`), which the app's
//! renderer fills from the scene: techniques stay independent of the scene crate.
//!
//! Invariants: accessibility in [0, 1], exactly 1 on sky; radiance finite and >= 0, zero on sky;
//! `ssdo_indirect` exactly zero with `bounce = false`; never NaN; every loop runs at most N.
//!
//! Where the paper is silent (choices, here and in the shaders):
//! - r_max is the shared R (`[ao] radius`); the paper leaves it to the user per scene.
//! - Environment L_in: by default constant, the scene's ambient (what shaded.png uses),
//!   optionally tilted by `sky_gradient`: L_in(w) = ambient * (1 + g * w.up); with a constant
//!   L_in the direct term is exactly albedo x L x A. `environment = "sky"` is the paper's case
//!   (an environment map, Fig. 3): the built-in procedural sky with a sun
//!   (`aograph_scene::SkyEnvironment`, filled into the lighting block by the renderer), colour
//!   varying with direction, integrated over the visible sample directions; its sun is a lobe
//!   of the sky, so the directional light's separate visibility vote is off. The radiance
//!   reference (`aograph_tracing::trace_radiance`) integrates the same sky.
//! - The directional light: the paper shades important lights with shadow maps, which aograph
//!   does not have. Here the sun is the g-buffer's unshadowed DirectLight (rho E max(0, n.l))
//!   times a per-sample-weighted visibility sum V_i w_i / sum w_i, w_i = max(0, omega_i.l)^k,
//!   k = `light_lobe`: the samples towards the light decide; 1 when none faces the light.
//! - E1's dw = 2 pi / N becomes pi / sum(cos theta_i) of the pixel's set (self-normalised): an
//!   unoccluded pixel under a constant environment gets exactly rho * L_in, and the small
//!   per-set bias does not print the 4x4 pattern. The accessibility uses the same weights,
//!   A = sum V_i cos theta_i / sum cos theta_i (unweighted by radiance).
//! - Visibility (§1.4): "its distance to the viewer decreases" is tested with both distances
//!   measured from the receiver's tangent plane along their own eye rays (the position read
//!   lies on its pixel centre's ray, up to half a pixel off the sample's; exact for planes, so
//!   grazing planes do not self-occlude; the plain test where that plane is edge-on), with a
//!   depth bias of `bias` * r_max. Off-screen, behind-camera and sky taps are visible. The
//!   border fade (§7.2, no parameters given): a blocker at Q weighs
//!   1 - smoothstep(fade_start * r_max, r_max, |Q - P|). Default 0.8, the top of the spec's
//!   suggested 0.5..0.8: every fade only removes occlusion the reference counts (a sample
//!   inside a solid within r_max means a hit within r_max), so on sphere-on-plane the MAE goes
//!   0.061 (0.5), 0.051 (0.8), 0.041 (1.0, a hard cut at r_max).
//! - Bounce (E2): the sender patch sits at Q, the position-buffer point of the blocker's pixel,
//!   with that pixel's normal and pass-1 radiance (unblurred, the paper's order); the cosines
//!   are clamped at 0, which drops back-facing senders and senders in the receiver's negative
//!   half-space; d = |Q - P| clamped below at `distance_clamp` (the paper's 1, in scene
//!   units: re-tune it when the scene is rescaled; while r_max <= clamp the 1/d^2 falloff is
//!   off and bleeding is weak in small scenes). `sender_area_scale` is the paper's manual
//!   colour-bleeding knob on A_s.
//! - Blur: separable, 5 taps per axis weighted [1/2, 1, 1, 1, 1/2] (every residue of the 4x4
//!   pattern weighs the same and the kernel is centred), times normal similarity (n.n_j)^8 and
//!   tangent-plane distance 1 - |n.(P_j - P)| / (0.1 r_max); sky taps excluded. The paper gives
//!   no kernel; it blurs once, at the end, so pass 2 reads the unblurred pass-1 radiance.
//! - Raw radiance and accessibility share one texture; it and the other intermediates (the
//!   raw indirect radiance, the horizontal blur's two outputs) follow `intermediate_format`:
//!   Rgba16Float under "r16float" (accessibility steps of 2^-11, far below the estimator's
//!   noise), Rgba32Float under "r32float", written by the matching shader variants. The
//!   outputs `ssdo_direct` and `ssdo_indirect` are Rgba16Float either way.

pub mod kernel;

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::{BufferAccess, SizeClass, TextureDesc, TextureHandle};
use serde::{Deserialize, Serialize};

use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::technique::{
    AoBuildContext, AoOutput, AoTechnique, ExtraOutput, RadianceEnvironment, RadianceOutput,
};

/// The extra output `ssdo_direct`: direct radiance past the occlusion, linear RGB (Eq. 1).
pub const DIRECT_OUTPUT: ExtraOutput = ExtraOutput::new("ssdo_direct");
/// The extra output `ssdo_indirect`: one indirect bounce, linear RGB (Eq. 2).
pub const INDIRECT_OUTPUT: ExtraOutput = ExtraOutput::new("ssdo_indirect");
pub use kernel::MAX_SAMPLES;

/// Format of the radiance outputs (the intermediates follow `intermediate_format`).
pub const RADIANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Blur plane tolerance as a fraction of r_max.
const BLUR_PLANE_TOLERANCE: f32 = 0.1;

/// The `ssdo` technique (module docs): screen-space directional occlusion, direct radiance
/// and accessibility from N samples, optionally one indirect bounce; parameters
/// [`SsdoParams`].
pub struct Ssdo;

/// `[ao.ssdo]` parameters.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SsdoParams {
    /// N, samples per pixel (the paper: 8 and 16).
    pub samples: u32,
    /// One indirect bounce (E2).
    pub bounce: bool,
    /// Lower clamp of the sender distance d_i in E2, scene units (the paper: 1).
    pub distance_clamp: f32,
    /// Multiplier on the sender area A_s = pi r_max^2 / N (the paper's colour-bleeding knob).
    pub sender_area_scale: f32,
    /// Blockers fade out from this fraction of r_max to r_max (§7.2's smooth step).
    pub fade_start: f32,
    /// Depth bias of the visibility test, as a fraction of r_max.
    pub bias: f32,
    /// Exponent of the per-sample weight max(0, omega . l)^k of the directional light.
    pub light_lobe: f32,
    /// Sky gradient of the environment: L_in = ambient * (1 + g * omega.up).
    pub sky_gradient: f32,
    /// L_in: "ambient" (the scene's constant ambient, tilted by `sky_gradient`, plus the
    /// directional light's visibility vote) or "sky" (the built-in sky with its sun,
    /// `aograph_scene::SkyEnvironment`: coloured, directional shadows, paper Fig. 3).
    pub environment: String,
}

const ENVIRONMENTS: [&str; 2] = ["ambient", "sky"];

impl Default for SsdoParams {
    fn default() -> Self {
        Self {
            samples: 8,
            bounce: true,
            distance_clamp: 1.0,
            sender_area_scale: 1.0,
            fade_start: 0.8,
            bias: 0.01,
            light_lobe: 4.0,
            sky_gradient: 0.0,
            environment: "ambient".into(),
        }
    }
}

impl SsdoParams {
    /// The `params` uniform for r_max = `radius`.
    pub fn uniform(&self, radius: f32) -> kernel::SsdoUniform {
        let n = self.samples.clamp(1, MAX_SAMPLES);
        let area = self.sender_area_scale * std::f32::consts::PI * radius * radius / n as f32; // E3
        kernel::SsdoUniform {
            r_max: radius,
            fade_start: self.fade_start * radius,
            bias: self.bias * radius,
            sender_area: area,
            distance_clamp: self.distance_clamp,
            light_lobe: self.light_lobe,
            sky_gradient: self.sky_gradient,
            blur_plane_tolerance: BLUR_PLANE_TOLERANCE * radius,
            sample_count: n,
            bounce: self.bounce as u32,
            sky: (self.environment == "sky") as u32,
            _pad0: 0,
            samples: kernel::sample_table(n),
        }
    }
}

impl AoTechnique for Ssdo {
    type Params = SsdoParams;
    const NAME: &'static str = "ssdo";
    fn description(&self) -> &'static str {
        "screen-space directional occlusion with one indirect bounce; radiance as extra outputs"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::int("samples", 4, MAX_SAMPLES)
                .doc("N, sample points per pixel (the paper uses 8 and 16)"),
            ParamDesc::flag("bounce").doc(
                "one indirect bounce from occluding sender patches (off: ssdo_indirect is zero)",
            ),
            ParamDesc::float("distance_clamp", 1e-4, 1e4).doc(
                "lower clamp of the sender distance in the form factor, scene units (the paper: 1)",
            ),
            ParamDesc::float("sender_area_scale", 0.0, 16.0)
                .doc("multiplier on the sender patch area pi R^2 / N: colour-bleeding strength"),
            ParamDesc::float("fade_start", 0.0, 1.0)
                .doc("blockers fade out between this fraction of R and R"),
            ParamDesc::float("bias", 0.0, 0.5)
                .doc("depth bias of the visibility test as a fraction of R"),
            ParamDesc::float("light_lobe", 1.0, 64.0).doc(
                "exponent of the per-sample weight of the directional light, max(0, w.l)^k",
            ),
            ParamDesc::float("sky_gradient", 0.0, 1.0)
                .doc("environment = ambient * (1 + g * up): 0 is the scene's constant ambient"),
            ParamDesc::choice("environment", &ENVIRONMENTS).doc(
                "L_in: the scene's ambient plus its directional light, or the built-in sky with its sun",
            ),
        ]
    }
    fn radiance(&self, p: &SsdoParams) -> Option<RadianceEnvironment> {
        Some(if p.environment == "sky" {
            RadianceEnvironment::Sky
        } else {
            RadianceEnvironment::Ambient
        })
    }
    fn channels(&self, _: &SsdoParams) -> GBufferChannels {
        GBufferChannels::of(&[
            GBufferChannel::Normals,
            GBufferChannel::Positions,
            GBufferChannel::Albedo,
            GBufferChannel::DirectLight,
        ])
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &SsdoParams) -> AoResult<AoOutput> {
        let positions = ctx.channel(GBufferChannel::Positions)?;
        let normals = ctx.channel(GBufferChannel::Normals)?;
        let albedo = ctx.channel(GBufferChannel::Albedo)?;
        let direct_light = ctx.channel(GBufferChannel::DirectLight)?;
        let lighting = ctx.scene_lighting();
        let uniform = p.uniform(ctx.radius);
        let radiance_texture = |ctx: &mut AoBuildContext<'_>, name: &str| {
            ctx.builder
                .create_texture(name, TextureDesc::new(RADIANCE_FORMAT, SizeClass::FULL))
        };
        let intermediate = |ctx: &mut AoBuildContext<'_>, name: &str| {
            let f = ctx.intermediate_rgba_format();
            ctx.builder
                .create_texture(name, TextureDesc::new(f, SizeClass::FULL))
        };

        // Pass 1: direct light with directional occlusion (E1) + accessibility in alpha.
        let raw_direct = intermediate(ctx, "ssdo.raw_direct");
        let shader = ctx.shader("ao/ssdo/direct.wgsl");
        let mut pass = ctx.builder.compute_pass("ssdo.direct", &shader, "main");
        pass.sample("positions", positions)
            .sample("normals", normals)
            .sample("albedo", albedo)
            .sample("direct_light", direct_light);
        pass.read_view(ctx.view)
            .read_buffer("lighting", BufferAccess::Uniform, lighting);
        pass.uniform_struct("params", &uniform);
        let raw_direct = pass.write_storage("radiance", raw_direct);
        pass.dispatch_over(raw_direct);

        // Pass 2: one indirect bounce (E2) from the pass-1 radiance of occluding patches.
        let raw_indirect: Option<TextureHandle> = if p.bounce {
            let raw = intermediate(ctx, "ssdo.raw_indirect");
            let shader = ctx.shader("ao/ssdo/indirect.wgsl");
            let mut pass = ctx.builder.compute_pass("ssdo.indirect", &shader, "main");
            pass.sample("positions", positions)
                .sample("normals", normals)
                .sample("albedo", albedo)
                .sample("radiance", raw_direct);
            pass.read_view(ctx.view);
            pass.uniform_struct("params", &uniform);
            let raw = pass.write_storage("indirect", raw);
            pass.dispatch_over(raw);
            Some(raw)
        } else {
            None
        };

        // Pass 3: the separable geometry-aware blur of all three. Without the bounce the
        // shaders write zero indirect light and never read `bounce`, which is bound to the
        // direct radiance only because every WGSL global must be bound.
        let direct_x = intermediate(ctx, "ssdo.direct_x");
        let indirect_x = intermediate(ctx, "ssdo.indirect_x");
        let shader = ctx.shader("ao/ssdo/blur_x.wgsl");
        let mut pass = ctx.builder.compute_pass("ssdo.blur_x", &shader, "main");
        pass.sample("positions", positions)
            .sample("normals", normals)
            .sample("radiance", raw_direct)
            .sample("bounce", raw_indirect.unwrap_or(raw_direct));
        pass.uniform_struct("params", &uniform);
        let direct_x = pass.write_storage("direct_x", direct_x);
        let indirect_x = pass.write_storage("indirect_x", indirect_x);
        pass.dispatch_over(direct_x);

        let ao = ctx.accessibility_texture("ssdo.accessibility");
        let direct_out = radiance_texture(ctx, "ssdo_direct");
        let indirect_out = radiance_texture(ctx, "ssdo_indirect");
        let mut pass = ctx
            .builder
            .compute_pass("ssdo.blur_y", "ao/ssdo/blur_y.wgsl", "main");
        pass.sample("positions", positions)
            .sample("normals", normals)
            .sample("radiance", direct_x)
            .sample("bounce", indirect_x);
        pass.uniform_struct("params", &uniform);
        let ao = pass.write_storage("ao", ao);
        let direct_out = pass.write_storage("ssdo_direct", direct_out);
        let indirect_out = pass.write_storage("ssdo_indirect", indirect_out);
        pass.dispatch_over(ao);
        Ok(AoOutput {
            accessibility: ao,
            radiance: Some(RadianceOutput {
                direct: direct_out,
                indirect: indirect_out,
            }),
            extra: vec![(DIRECT_OUTPUT, direct_out), (INDIRECT_OUTPUT, indirect_out)],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use aograph_frame::{GBufferTextures, VIEW_BUFFER, ViewUniforms};
    use aograph_graph::BufferDesc;
    use aograph_graph::{CompileOptions, GraphBuilder, compile};

    fn plan(params: &SsdoParams) -> (Vec<String>, Vec<String>) {
        let mut b = GraphBuilder::new();
        let view = b.import_buffer(
            VIEW_BUFFER,
            BufferDesc {
                size: std::mem::size_of::<ViewUniforms>() as u64,
            },
        );
        let mut g = GBufferTextures::default();
        for c in AoTechnique::channels(&Ssdo, params).iter() {
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
            technique: Ssdo::NAME,
            radius_pixels: None,
            declared: Default::default(),
            tracing: Default::default(),
        };
        let out = AoTechnique::build(&Ssdo, &mut ctx, params).unwrap();
        b.export(out.accessibility);
        out.extra.iter().for_each(|(_, h)| b.export(*h));
        let extra = out
            .extra
            .iter()
            .map(|(n, _)| n.name().to_string())
            .collect();
        let shaders = crate::shader_library().unwrap();
        let plan = compile(b.build(), &shaders, CompileOptions::default()).unwrap();
        (
            plan.pass_names().into_iter().map(String::from).collect(),
            extra,
        )
    }

    #[test]
    fn plan_is_direct_indirect_blur_and_bounce_off_drops_the_indirect_pass() {
        let (passes, extra) = plan(&SsdoParams::default());
        assert_eq!(
            passes,
            ["ssdo.direct", "ssdo.indirect", "ssdo.blur_x", "ssdo.blur_y"]
        );
        assert_eq!(extra, ["ssdo_direct", "ssdo_indirect"]);
        let (passes, extra) = plan(&SsdoParams {
            bounce: false,
            samples: 16,
            ..Default::default()
        });
        assert_eq!(passes, ["ssdo.direct", "ssdo.blur_x", "ssdo.blur_y"]);
        assert_eq!(
            extra,
            ["ssdo_direct", "ssdo_indirect"],
            "the indirect output exists (zero) without the bounce"
        );
    }

    #[test]
    fn reads_colour_and_direct_light() {
        let c = AoTechnique::channels(&Ssdo, &SsdoParams::default());
        assert_eq!(
            c.iter().collect::<Vec<_>>(),
            [
                GBufferChannel::Normals,
                GBufferChannel::Positions,
                GBufferChannel::Albedo,
                GBufferChannel::DirectLight
            ]
        );
    }

    #[test]
    fn uniform_carries_the_sender_area_and_the_sets() {
        let u = SsdoParams::default().uniform(2.0);
        assert!(
            (u.sender_area - std::f32::consts::PI * 4.0 / 8.0).abs() < 1e-6,
            "A_s = pi r^2 / N"
        );
        assert_eq!((u.sample_count, u.bounce, u.sky, u._pad0), (8, 1, 0, 0));
        assert!(u.samples[16 * 15 + 7] != [0.0; 4] && u.samples[16 * 15 + 8] == [0.0; 4]);
        assert_eq!(
            std::mem::size_of::<kernel::SsdoUniform>(),
            48 + 16 * 16 * 16
        );
    }
}
