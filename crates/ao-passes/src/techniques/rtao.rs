//! `rtao`: ray-traced ambient occlusion against the scene's real geometry (its two-level BVH,
//! `aograph_tracing::gpu`), not the depth buffer: what lies behind the first surface,
//! off screen and behind the camera occludes as it does in the reference. The estimator is the
//! reference's own (shaders/common/ao_rays.wgsl mirrors crates/scene/src/reference): N
//! cosine-weighted rays per pixel from the g-buffer point offset along its normal, the pixel's
//! scrambled 2D Sobol sequence, binary occlusion within R or obscurance
//! 1 - min(1, (d/R)^2); A = 1 - mean.
//!
//! Passes, in order:
//! 1. `rtao.trace` (shaders/ao/rtao/trace.wgsl): N rays per pixel; frame f traces rays
//!    [f N, (f + 1) N) of each pixel's sequence (`sequence = "per-frame"`), so frames the
//!    temporal block averages continue one low-discrepancy sequence; also writes XeGTAO's
//!    depth-edge weights for the edge denoiser and, in `rtao_changed.g`, the nearest hit of
//!    the pixel's rays over R for the history denoiser.
//! 2. `rtao.temporal.*` (`blocks::temporal::add_temporal`, [`TemporalMode::Average`]): a running
//!    mean over up to `temporal_frames` frames, reprojected through the g-buffer's motion,
//!    reset where the disocclusion test fails, and held to `moving_frames` frames where a ray
//!    hit moving geometry or the pixel's own surface moves (`blocks::temporal::ChangeMask`,
//!    the ray-traced counterpart of TSSAO's Eq. 8: AO cast by a walking character changes
//!    every frame, and a 64-frame mean would lag it; on CesiumMan walking the mean over 64
//!    frames read MAE 0.0384, over 4 frames 0.0275, at 2 rays). `temporal = false` skips it.
//! 3. The spatial filter, `denoiser`:
//!    - `history` (default): `rtao.history_fix` then `rtao.atrous1..K`
//!      (`blocks::history_denoise`): the history fix for pixels with fewer than 4 frames, then
//!      variance-guided a-trous iterations whose radius follows the pixel's history length
//!      (1 / (1 + k (n - 1))) and its nearest hit (the trace writes it), so a new pixel is
//!      blurred widely and a converged one over about a pixel at the 64-frame cap;
//!    - `edge`, and `history` when `temporal = false`: `rtao.denoise1..N`
//!      (`blocks::edge_denoise`), XeGTAO's edge-aware 3x3 filter, N = `denoise_passes` (0
//!      skips it);
//!    - `none`: no spatial filter.
//!
//! Known answers (tests/technique_rtao.rs): with 256 rays, no temporal and no denoise, each
//! pixel is the reference's estimate from the same rays (within 4 standard errors of the CPU
//! reference); 1 ray per frame accumulated over 64 still frames matches a 64-ray reference.
//! `rays` goes to 256 so one frame can match the 256-ray reference exactly; real-time use is
//! 1 to 8 with temporal accumulation.
//!
//! Extra outputs: `rtao_changed` (Rgba8Unorm, r = 1 where a ray hit moving geometry this frame,
//! g = the nearest hit over R) unless the trace pass is the last; `rtao_guide` (Rgba16Float:
//! variance, radius in pixels, frames of history, nearest hit over R) with the history
//! denoiser.
//!
//! Backends (`tracer`, crate::RayTracer): the trace pass's shader is written once against
//! shaders/common/scene_trace.wgsl; on `compute` it traverses the scene's BVH in the compute
//! shader, on `hardware` its `RayTracer=hardware` variant asks ray queries of the scene's
//! acceleration structures (one BLAS per mesh, a TLAS over the instances, any-hit early exit
//! with t_max = R). `auto` picks hardware where the device has ray queries. Both trace the same
//! rays (tests/technique_rtao.rs checks them against each other and the reference).
//!
//! Invariant: the output is accessibility in [0, 1], exactly 1 on sky, never NaN; the scene is
//! a frame input this technique declares ([`AoBuildContext::scene_trace`]: the BVH or the
//! acceleration structures): a graph without rtao builds and uploads neither.

use aograph_frame::ReadsView;
use aograph_frame::{GBufferChannel, GBufferChannels};
use aograph_graph::SizeClass;
use bytemuck::{Pod, Zeroable};
use serde::{Deserialize, Serialize};

use crate::blocks::history_denoise::{self, HistoryDenoise, HistoryDenoiseInputs, history_denoise};
use crate::blocks::temporal::{
    ChangeMask, DEFAULT_EPSILON, TemporalAccumulation, TemporalMode, add_temporal_with_changes,
    temporal_channels,
};
use crate::blocks::{EdgeDenoise, edge_denoise};
use crate::error::AoResult;
use crate::param::ParamDesc;
use crate::resolution::Resolution;
use crate::technique::{AoBuildContext, AoOutput, AoTechnique, ExtraOutput};

/// The extra output `rtao_changed`: r, 1 where a ray hit moving geometry this frame;
/// g, the nearest hit over R (the history denoiser's radius guide).
pub const CHANGED_OUTPUT: ExtraOutput = ExtraOutput::new("rtao_changed");
/// The extra output `rtao_guide` (`denoiser = "history"`): the history denoiser's variance,
/// radius, history length and hit (`blocks::history_denoise`).
pub const GUIDE_OUTPUT: ExtraOutput = ExtraOutput::new("rtao_guide");
use crate::temporal_option::PER_FRAME_OUTPUT;
use crate::tracer::RayTracer;

/// Most rays per pixel and frame (one frame of the 256-ray reference).
pub const MAX_RAYS: u32 = 256;
/// Most frames the temporal block averages.
pub const MAX_TEMPORAL_FRAMES: u32 = 1024;

/// The `rtao` technique (module docs): N cosine-weighted rays per pixel traced against the
/// scene's BVH, accumulated over frames and denoised; parameters [`RtaoParams`].
pub struct Rtao;

/// `[ao.rtao]` parameters.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RtaoParams {
    /// Rays per pixel and frame.
    pub rays: u32,
    /// Temporal accumulation (a running mean over `temporal_frames` frames).
    pub temporal: bool,
    /// Cap of the running mean's frame count (TSSAO Eq. 6's n_max).
    pub temporal_frames: u32,
    /// The cap where a ray hit moving geometry or the surface itself moves.
    pub moving_frames: u32,
    /// The spatial filter after accumulation: "history" (`blocks::history_denoise`, which
    /// narrows as each pixel's history grows), "edge" (XeGTAO's fixed 3x3 filter,
    /// `denoise_passes` times) or "none". Without `temporal` there is no history: "history"
    /// runs the edge filter.
    pub denoiser: String,
    /// Edge-aware denoise passes (0 to 3) where the edge denoiser runs.
    pub denoise_passes: u32,
    /// The history denoiser's a-trous iterations (0 to 5; 0: the history fix alone).
    pub spatial_iterations: u32,
    /// The history denoiser's radius in pixels on a new pixel.
    pub spatial_radius: f32,
    /// k of the history denoiser's radius shrink 1 / (1 + k (n - 1)) over n frames of history.
    pub spatial_shrink: f32,
    /// "per-frame": each frame continues the pixel's ray sequence (the reference's rays);
    /// "fixed": the same rays every frame; "blue-noise": the frame's Sobol point shifted by
    /// the pixel's blue-noise offset.
    pub sequence: String,
    /// "binary" or "obscurance" (the reference's modes).
    pub mode: String,
    /// The size the rays are traced at (crate::Resolution): at half, the rays, the running
    /// mean and the denoiser run on the half-size g-buffer.
    pub resolution: Resolution,
    /// The GPU ray tracer's backend (crate::RayTracer): compute, hardware, or auto.
    pub tracer: RayTracer,
}

impl Default for RtaoParams {
    fn default() -> Self {
        Self {
            rays: 2,
            temporal: true,
            temporal_frames: 64,
            moving_frames: 4,
            denoiser: "history".into(),
            denoise_passes: 1,
            spatial_iterations: HistoryDenoise::default().iterations,
            spatial_radius: HistoryDenoise::default().base_radius,
            spatial_shrink: HistoryDenoise::default().shrink,
            sequence: "per-frame".into(),
            mode: "binary".into(),
            resolution: Resolution::Full,
            tracer: RayTracer::Auto,
        }
    }
}

/// The `params` uniform of shaders/ao/rtao/trace.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct RtaoUniform {
    rays: u32,
    mode: u32,
    sequence: u32,
    _pad0: u32,
    radius: f32,
    _pad1: [f32; 3],
}

aograph_graph::uniform_layout!(RtaoUniform {
    rays,
    mode,
    sequence,
    _pad0,
    radius,
    _pad1
});

const SEQUENCES: &[&str] = &["per-frame", "fixed", "blue-noise"];
const DENOISERS: &[&str] = &["history", "edge", "none"];
const MODES: &[&str] = &["binary", "obscurance"];

impl AoTechnique for Rtao {
    type Params = RtaoParams;
    const NAME: &'static str = "rtao";
    fn description(&self) -> &'static str {
        "ray-traced AO against the scene's BVH: the reference's rays, N per pixel, temporal accumulation, a denoiser that follows each pixel's history"
    }
    fn params(&self) -> Vec<ParamDesc> {
        vec![
            ParamDesc::int("rays", 1, MAX_RAYS).doc(
                "rays per pixel and frame (1 to 8 with temporal accumulation in real time; 256 = one frame of the reference)",
            ),
            ParamDesc::flag("temporal").doc("accumulate frames (a running mean, reprojected)"),
            ParamDesc::int("temporal_frames", 1, MAX_TEMPORAL_FRAMES)
                .doc("most frames the running mean holds"),
            ParamDesc::int("moving_frames", 1, MAX_TEMPORAL_FRAMES).doc(
                "most frames the mean holds where a ray hit moving geometry or the surface moves",
            ),
            ParamDesc::choice("denoiser", DENOISERS).doc(
                "history: wide on new pixels, narrowing as the history converges (SVGF's variance-guided a-trous, REBLUR's radius and history fix); edge: XeGTAO's fixed 3x3 filter (also what history runs with temporal = false); none: no spatial filter",
            ),
            ParamDesc::int("denoise_passes", 0, 3)
                .doc("edge denoiser: 3x3 passes after accumulation (0: none)"),
            ParamDesc::int("spatial_iterations", 0, history_denoise::MAX_ITERATIONS)
                .doc("history denoiser: a-trous iterations at tap spacing 1, 2, 4, ... (0: the history fix alone)"),
            ParamDesc::float_above("spatial_radius", 0.0, 256.0)
                .doc("history denoiser: radius in pixels on a pixel with one frame of history"),
            ParamDesc::float("spatial_shrink", 0.0, 1000.0)
                .doc("history denoiser: k of the radius' 1 / (1 + k (n - 1)) shrink over n frames"),
            ParamDesc::choice("sequence", SEQUENCES)
                .doc("per-frame: each frame continues the pixel's scrambled Sobol sequence (the reference's rays); fixed: the same rays every frame; blue-noise: every pixel the frame's Sobol point shifted by its own blue-noise dither offset, so the error left at 1 ray a pixel is high-frequency"),
            ParamDesc::choice("mode", MODES)
                .doc("binary: a hit within R occludes; obscurance: a hit at d occludes by 1 - (d/R)^2"),
            Resolution::param(),
            RayTracer::param(),
        ]
    }
    fn channels(&self, p: &RtaoParams) -> GBufferChannels {
        p.resolution.channels(Self::spatial_channels(p))
    }
    fn is_temporal(&self, p: &RtaoParams) -> bool {
        p.temporal
    }
    fn build(&self, ctx: &mut AoBuildContext<'_>, p: &RtaoParams) -> AoResult<AoOutput> {
        p.resolution
            .build(ctx, Self::spatial_channels(p), |ctx| self.traced(ctx, p))
    }
}

impl Rtao {
    /// What the rays, the running mean and the denoiser read.
    fn spatial_channels(p: &RtaoParams) -> GBufferChannels {
        // The reference's hemisphere is the geometric normal's: face normals.
        let trace = GBufferChannels::of(&[GBufferChannel::Positions, GBufferChannel::LinearDepth])
            .with_face_normals();
        if p.temporal {
            trace.union(temporal_channels())
        } else {
            trace
        }
    }

    /// The passes: rays, running mean, denoise.
    fn traced(&self, ctx: &mut AoBuildContext<'_>, p: &RtaoParams) -> AoResult<AoOutput> {
        let positions = ctx.channel(GBufferChannel::Positions)?;
        let normals = ctx.channel(GBufferChannel::Normals)?;
        let depth = ctx.channel(GBufferChannel::LinearDepth)?;
        let scene = ctx.scene_trace(p.tracer)?;
        let uniform = RtaoUniform {
            rays: p.rays,
            mode: (p.mode == "obscurance") as u32,
            sequence: match p.sequence.as_str() {
                "fixed" => 0,
                "blue-noise" => 2,
                _ => 1,
            },
            _pad0: 0,
            radius: ctx.radius,
            _pad1: [0.0; 3],
        };
        let history_denoiser = p.temporal && p.denoiser == "history";
        let edge_passes = match p.denoiser.as_str() {
            "none" => 0,
            _ if history_denoiser => 0,
            _ => p.denoise_passes,
        };
        let last = !p.temporal && edge_passes == 0;

        // Pass 1: the rays. The raw texture is the output itself when nothing follows.
        let raw = if last {
            ctx.accessibility_texture("rtao.accessibility")
        } else {
            ctx.intermediate("rtao.raw", SizeClass::FULL)
        };
        let edges = ctx.builder.create_texture(
            "rtao.edges",
            aograph_graph::TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
        );
        let changed = ctx.builder.create_texture(
            "rtao.changed",
            aograph_graph::TextureDesc::new(wgpu::TextureFormat::Rgba8Unorm, SizeClass::FULL),
        );
        let file = "ao/rtao/trace.wgsl";
        let shader = scene.shader(&if last {
            file.to_string()
        } else {
            ctx.shader(file)
        });
        let mut pass = ctx.builder.compute_pass("rtao.trace", &shader, "main");
        pass.read_view(ctx.view);
        pass.uniform_struct("params", &uniform);
        pass.sample("positions", positions)
            .sample("normals", normals)
            .sample("depth", depth);
        scene.bind(&mut pass);
        // Point, normal, five depths for the edges; each ray's traversal reads far more (its
        // nodes and triangles), which this count of texture loads cannot state.
        pass.loads_per_invocation(7.0);
        let raw = pass.write_storage("ao", raw);
        let edges = pass.write_storage("edges", edges);
        let changed = pass.write_storage("changed", changed);
        pass.dispatch_over(raw);
        if last {
            return Ok(AoOutput::new(raw));
        }

        // Pass 2: the running mean over frames.
        let mut out = raw;
        let mut history = None;
        if p.temporal {
            let t = add_temporal_with_changes(
                ctx.builder,
                "rtao.temporal",
                raw,
                Some(ChangeMask {
                    mask: changed,
                    n_max: p.moving_frames.min(p.temporal_frames),
                }),
                &ctx.gbuffer,
                ctx.view,
                &TemporalAccumulation {
                    epsilon: DEFAULT_EPSILON,
                    n_max: p.temporal_frames,
                    mode: TemporalMode::Average,
                },
            )?;
            out = t.accumulated;
            history = Some(t.history.current);
        }

        // Pass 3: the spatial filter of the accumulated value.
        let mut guide = None;
        if let (true, Some(history)) = (history_denoiser, history) {
            let d = history_denoise(
                ctx.builder,
                "rtao",
                &HistoryDenoiseInputs {
                    accumulated: out,
                    history,
                    depth,
                    normals,
                    hits: Some(changed),
                    view: ctx.view,
                },
                &HistoryDenoise {
                    iterations: p.spatial_iterations,
                    base_radius: p.spatial_radius,
                    shrink: p.spatial_shrink,
                    fix_stride: HistoryDenoise::fix_stride_for(p.spatial_radius),
                    ..HistoryDenoise::default()
                },
            )?;
            out = d.accessibility;
            guide = Some(d.guide);
        } else if edge_passes > 0 {
            out = edge_denoise(
                ctx.builder,
                "rtao",
                out,
                edges,
                depth,
                &EdgeDenoise {
                    passes: edge_passes,
                    ..EdgeDenoise::default()
                },
                ctx.intermediate_format,
            )?;
        }
        let mut output = AoOutput::new(out);
        // Where this frame's rays hit moving geometry (r = 1): the pixels whose history is
        // held to `moving_frames`, for inspection.
        output.extra.push((CHANGED_OUTPUT, changed));
        if let Some(guide) = guide {
            // The history denoiser's guide: variance, radius in pixels, frames of history,
            // nearest hit over R.
            output.extra.push((GUIDE_OUTPUT, guide));
        }
        if p.temporal {
            // This frame's own rays, before the running mean (as the shared temporal option
            // outputs it), so the mean can be checked against its frames.
            output.extra.push((PER_FRAME_OUTPUT, raw));
        }
        Ok(output)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TechniqueRegistry;
    use crate::contract::plan_pass_names;

    fn rtao() -> std::sync::Arc<dyn crate::technique::DynAoTechnique> {
        TechniqueRegistry::with_builtins()
            .get(Rtao::NAME)
            .unwrap()
            .clone()
    }

    #[test]
    fn plan_is_trace_then_temporal_then_denoise_and_each_can_be_left_out() {
        let shaders = crate::shader_library().unwrap();
        let names = |params: &str| plan_pass_names(&rtao(), params, &shaders).unwrap();
        let all = names("");
        assert_eq!(all.first().map(String::as_str), Some("rtao.trace"));
        assert!(
            all.iter().any(|n| n == "rtao.temporal.accumulate"),
            "{all:?}"
        );
        assert_eq!(all.last().map(String::as_str), Some("rtao.atrous3"));
        assert!(all.iter().any(|n| n == "rtao.history_fix"), "{all:?}");
        assert_eq!(
            names("denoiser = \"edge\"").last().map(String::as_str),
            Some("rtao.denoise1")
        );
        assert_eq!(
            names("denoiser = \"none\"").last().map(String::as_str),
            Some("rtao.temporal.accumulate")
        );
        assert_eq!(
            names("temporal = false\ndenoise_passes = 0"),
            ["rtao.trace"]
        );
        assert_eq!(
            names("temporal = false\ndenoise_passes = 2"),
            ["rtao.trace", "rtao.denoise1", "rtao.denoise2"]
        );
    }

    #[test]
    fn rays_outside_one_to_256_are_refused_naming_the_range() {
        let e = rtao()
            .check(&toml::from_str("rays = 0").unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("rays") && e.contains("256"), "{e}");
        assert!(rtao().check(&toml::from_str("rays = 256").unwrap()).is_ok());
        let e = rtao()
            .check(&toml::from_str("sequence = \"halton\"").unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("per-frame") && e.contains("blue-noise"), "{e}");
    }
}
