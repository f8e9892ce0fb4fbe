//! One bench run: a technique with one parameter set on one scene, timed over N frames after
//! M warm-up frames and compared with the scene's reference.
//!
//! Decisions (see also the module docs of `bench`):
//! - Every frame is the scene at time 0 from its own camera (a still frame), so the reference
//!   traced once per scene is the reference of every frame, and flicker measures the
//!   technique's own frame-to-frame instability (animated noise, temporal convergence).
//! - The reference comes from a g-buffer of its own (`frame_reference`): points, the
//!   configured normals (geometric by default) and linear depth, so every technique in a run is
//!   scored against one reference whatever normals it reads. The technique's renderer asks for
//!   nothing but accessibility, so its plan, timings and texture bytes are exactly what the
//!   technique costs in an application (no extra g-buffer channels for measuring).
//! - Times: "total" is the sum of the technique's passes (every pass but the g-buffer, which
//!   every technique shares); "frame" adds the g-buffer. Both are per-frame sums whose median
//!   and spread are taken over the N measured frames.
//! - Metrics are taken on the last frame (temporal techniques have converged most by then).

use std::collections::BTreeMap;
use std::sync::Arc;

use aograph_ao_passes::{AoConfig, RadianceEnvironment, Radius, RadiusSetting, TechniqueRegistry};
use aograph_graph::{Extent, GpuContext, ShaderLibrary, TimingSource, pass_costs, texture_bytes};
use aograph_scene::{ProjectedRadius, ReferenceMode, ReferenceNormals, projected_radius};
use serde::{Deserialize, Serialize};

use crate::metrics::{
    FlickerMeter, MetricOptions, Metrics, RadianceScores, compare, radiance_scores,
};
use crate::roofline::{DevicePeaks, PassRoofline, passes_under};
pub use crate::stats::PassTime;
use crate::stats::Spread;
use crate::sweep::ParamSet;
use aograph_app_config::error::{AppError, AppResult};
use aograph_app_config::prepared_scene::PreparedScene;
use aograph_renderer::frame_graph::FrameOutputs;
use aograph_renderer::frame_reference::{
    FrameView, ReferenceSettings, radiance_reference, reference_surfaces, trace_surfaces,
};
use aograph_renderer::pass_owner::{PassOwner, PassOwners};
use aograph_renderer::renderer::Renderer;

/// One frame's scores, counted from the reset (frame 1 has no history).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergencePoint {
    /// Frames since the reset, from 1.
    pub frame: u32,
    /// Mean absolute error against the reference (non-sky pixels).
    pub mae: f64,
    /// SSIM against the reference.
    pub ssim: f64,
    /// MAE in the depth-edge band; `None` when the view has no depth edge.
    pub edge_mae: Option<f64>,
}

/// The run-wide settings.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchSettings {
    /// Output width in pixels; the reference is traced at the same size.
    pub width: u32,
    /// Output height in pixels; the reference is traced at the same size.
    pub height: u32,
    /// Measured frames.
    pub frames: u32,
    /// Frames rendered and discarded first.
    pub warmup: u32,
    /// The shared radius: `auto` (per scene: its size / 9; per interior view: what it sees),
    /// `auto-view` or world units.
    pub radius: RadiusSetting,
    /// Reference rays per pixel.
    pub rays: u32,
    /// Reference mode: binary (a hit within R occludes) or obscurance (weighted 1 - (d/R)^2).
    pub mode: ReferenceMode,
    /// Reference hemisphere: geometric (face) or shading (interpolated) normals.
    pub normals: ReferenceNormals,
    /// Reference tracer: auto (the GPU on hardware), cpu or gpu.
    pub tracer: aograph_scene::ReferenceTracer,
    /// Metric knobs (edge band, edge jump, SSIM window and constants).
    pub metrics: MetricOptions,
    /// Score every measured frame, not only the last (`bench --convergence N`, which also
    /// renders no warm-up, so the first measured frame is the first since a reset).
    pub score_every_frame: bool,
}

impl BenchSettings {
    /// The output size, `width` x `height`.
    pub fn extent(&self) -> Extent {
        Extent::new(self.width, self.height)
    }

    /// How the reference is traced with radius `radius`.
    pub fn reference(&self, radius: f32) -> ReferenceSettings {
        ReferenceSettings {
            radius,
            rays: self.rays,
            mode: self.mode,
            normals: self.normals,
            tracer: self.tracer,
        }
    }
}

/// What every run on one device shares.
pub struct BenchContext {
    /// The device every renderer, reference tracer and peak measurement of the bench runs on.
    pub gpu: Arc<GpuContext>,
    /// The shader library every renderer compiles from, shared so it is loaded once.
    pub shaders: Arc<ShaderLibrary>,
    /// The techniques the bench's parameter sets can name.
    pub registry: TechniqueRegistry,
    /// The device's peaks, measured at the start of the run, when the run reports a roofline.
    pub peaks: Option<DevicePeaks>,
}

/// "gpu-timestamps" or "cpu-wall".
pub fn timing_source_name(s: Option<TimingSource>) -> &'static str {
    match s {
        Some(TimingSource::GpuTimestamps) => "gpu-timestamps",
        Some(TimingSource::CpuWall) => "cpu-wall",
        None => "none",
    }
}

/// A scene seen from one view, with the reference of its still frame and the frame's linear
/// depth.
pub struct SceneReference {
    /// The scene's label as rows report it: the procedural name or the glTF path as given.
    pub label: String,
    /// The view's name ("default": the scene's own camera).
    pub view: String,
    /// The scene with the view's camera, and the radius in use.
    pub prepared: PreparedScene,
    /// The reference's accessibility per pixel, row-major, 0..1 (1 = unoccluded).
    pub accessibility: Vec<f32>,
    /// Linear view depth per pixel from the reference's own g-buffer, row-major (0 = sky).
    pub depth: Vec<f32>,
    /// `depth > 0` per pixel: the non-sky pixels every metric is taken over.
    pub valid: Vec<bool>,
    /// The size the reference was traced at (the runs' output size).
    pub extent: Extent,
    /// Mean reference accessibility over geometry pixels (1 when nothing is occluded: then R
    /// reaches nothing in this view and the measurement says little).
    pub mean_accessibility: f32,
    /// R projected to pixels in this view (`None` when it sees no geometry).
    pub projected: Option<ProjectedRadius>,
    /// The view's two ceilings against the reference (what the g-buffer's surfaces and what the
    /// seen triangles would give).
    pub ceilings: CeilingScores,
}

/// How close a screen-space technique could come at best in one view: the reference re-traced
/// against less geometry (`aograph_scene::reference::ceilings`), scored against the reference
/// with the bench's metrics over the same pixels. A technique's error splits into unseen
/// geometry (1 - the seen ceiling), the thickness and connectivity of what it sees (seen - g-buffer
/// ceiling) and its estimator (g-buffer ceiling - technique); a thickness heuristic can beat the
/// g-buffer ceiling.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CeilingScores {
    /// MAE of ceiling (a), the g-buffer's surfaces (a mesh through neighbouring pixels' points,
    /// broken at depth jumps over 10 %), against the reference; 0..1.
    #[serde(with = "crate::metrics::nonfinite")]
    pub gbuffer_mae: f64,
    /// SSIM of ceiling (a) against the reference (1 = identical).
    #[serde(with = "crate::metrics::nonfinite")]
    pub gbuffer_ssim: f64,
    /// MAE of ceiling (b), the scene's triangles some pixel sees (2 x 2 samples a pixel).
    #[serde(with = "crate::metrics::nonfinite")]
    pub seen_mae: f64,
    /// SSIM of ceiling (b) against the reference.
    #[serde(with = "crate::metrics::nonfinite")]
    pub seen_ssim: f64,
    /// MAE of ceiling (a) with a guard band (the g-buffer over a field a quarter of the image's
    /// height wider on every side): what rendering one would gain.
    #[serde(with = "crate::metrics::nonfinite", default = "f64_nan")]
    pub guard_mae: f64,
    /// SSIM of ceiling (a) with a guard band.
    #[serde(with = "crate::metrics::nonfinite", default = "f64_nan")]
    pub guard_ssim: f64,
    /// MAE of ceiling (a) with a second depth layer (the next surface at least 0.05 R behind
    /// the first): what a two-layer g-buffer could give at best.
    #[serde(with = "crate::metrics::nonfinite", default = "f64_nan")]
    pub two_layer_mae: f64,
    /// SSIM of ceiling (a) with a second depth layer.
    #[serde(with = "crate::metrics::nonfinite", default = "f64_nan")]
    pub two_layer_ssim: f64,
}

fn f64_nan() -> f64 {
    f64::NAN
}

/// Traces the reference of `prepared` (a scene through a view; from the disk cache when it is
/// there).
pub fn scene_reference(
    ctx: &BenchContext,
    label: &str,
    prepared: PreparedScene,
    s: &BenchSettings,
) -> AppResult<SceneReference> {
    let scene = prepared.scene.clone();
    let view = FrameView {
        camera: scene.camera_at(0.0),
        scene: scene.clone(),
        time: 0.0,
        extent: s.extent(),
    };
    let (surfaces, depth) =
        reference_surfaces(ctx.gpu.clone(), ctx.shaders.clone(), &view, s.normals)?;
    let image = trace_surfaces(
        &ctx.gpu,
        &scene,
        0.0,
        &surfaces,
        &s.reference(prepared.radius.get()),
        false,
    )?;
    let valid: Vec<bool> = depth.iter().map(|d| *d > 0.0).collect();
    let (sum, n) = image
        .accessibility
        .iter()
        .zip(&valid)
        .filter(|(_, v)| **v)
        .fold((0.0f64, 0usize), |(s, n), (a, _)| {
            (s + f64::from(*a), n + 1)
        });
    let projected = projected_radius(
        &scene,
        &view.camera,
        s.width,
        s.height,
        prepared.radius.get(),
    );
    let c = aograph_renderer::frame_reference::trace_ceilings(
        &scene,
        &view.camera,
        0.0,
        &surfaces,
        &s.reference(prepared.radius.get()),
    )?;
    let score = |ceiling: &[f32]| {
        compare(
            ceiling,
            &image.accessibility,
            &depth,
            s.width,
            s.height,
            &s.metrics,
        )
    };
    let (a, b, guard) = (
        score(&c.gbuffer_surfaces.accessibility)?,
        score(&c.seen_triangles.accessibility)?,
        score(&c.guard_band.accessibility)?,
    );
    let two = score(&c.two_layers.accessibility)?;
    let ceilings = CeilingScores {
        gbuffer_mae: a.mae,
        gbuffer_ssim: a.ssim,
        seen_mae: b.mae,
        seen_ssim: b.ssim,
        guard_mae: guard.mae,
        guard_ssim: guard.ssim,
        two_layer_mae: two.mae,
        two_layer_ssim: two.ssim,
    };
    Ok(SceneReference {
        label: label.to_string(),
        view: prepared.view.clone(),
        prepared,
        accessibility: image.accessibility,
        depth,
        valid,
        extent: s.extent(),
        mean_accessibility: if n > 0 { (sum / n as f64) as f32 } else { 1.0 },
        projected,
        ceilings,
    })
}

/// Times of N frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameTimes {
    /// Where the times come from: `gpu-timestamps`, `cpu-wall` or `none` (see
    /// [`timing_source_name`]).
    pub timing_source: String,
    /// The technique's passes.
    pub total_ms: Spread,
    /// Every pass, g-buffer included.
    pub frame_ms: Spread,
    /// Per pass, in execution order.
    pub passes: Vec<PassTime>,
}

/// Per-frame pass times gathered into [`FrameTimes`].
#[derive(Default)]
pub struct FrameTimeSamples {
    per_pass: Vec<(String, Vec<f64>)>,
    totals: Vec<f64>,
    frame_totals: Vec<f64>,
    source: Option<TimingSource>,
}

impl FrameTimeSamples {
    /// Adds one measured frame; `owners` says which passes are the technique's.
    pub fn push(&mut self, t: &aograph_graph::PassTimings, owners: &PassOwners) {
        self.source = t.source.or(self.source);
        let total = owners.total_ms(t, PassOwner::Technique);
        for (name, ms) in &t.passes {
            match self.per_pass.iter_mut().find(|(n, _)| n == name) {
                Some((_, v)) => v.push(*ms),
                None => self.per_pass.push((name.clone(), vec![*ms])),
            }
        }
        self.totals.push(total);
        self.frame_totals.push(t.total_ms());
    }

    /// Median and spread of every measured frame.
    pub fn finish(self) -> FrameTimes {
        FrameTimes {
            timing_source: timing_source_name(self.source).into(),
            total_ms: Spread::of(&self.totals),
            frame_ms: Spread::of(&self.frame_totals),
            passes: self
                .per_pass
                .into_iter()
                .map(|(name, v)| PassTime {
                    name,
                    ms: Spread::of(&v),
                })
                .collect(),
        }
    }
}

/// Renders `warmup` + `frames` still frames, calling `tick` after each and `measured` after
/// each measured one, and summarises the measured frames' timings.
pub fn time_frames(
    r: &mut Renderer,
    warmup: u32,
    frames: u32,
    tick: &mut dyn FnMut(),
    measured: &mut dyn FnMut(&Renderer) -> AppResult<()>,
) -> AppResult<FrameTimes> {
    let mut samples = FrameTimeSamples::default();
    for f in 0..warmup + frames {
        r.render(0.0)?;
        let t = r.timings()?;
        if f >= warmup {
            samples.push(&t, &r.graph.owners);
            measured(r)?;
        }
        tick();
    }
    Ok(samples.finish())
}

/// One row of the results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The scene's label: the procedural name or the glTF path as given.
    pub scene: String,
    /// The view (`--views`): "default" is the scene's own camera.
    #[serde(default = "default_view")]
    pub view: String,
    /// The technique's registry name (e.g. `hbao`, `none`).
    pub technique: String,
    /// The technique is the cost floor the others are compared with (`none`): reports show
    /// the others' MAE against it.
    #[serde(default)]
    pub baseline: bool,
    /// `ParamSet::label`: "directions=8 steps=10" or "defaults".
    pub label: String,
    /// The parameter set's values by name (empty: the technique's defaults).
    pub params: BTreeMap<String, toml::Value>,
    /// Output width in pixels (the reference's too).
    pub width: u32,
    /// Output height in pixels (the reference's too).
    pub height: u32,
    /// The AO radius R in scene units, as resolved for this scene (shared by the technique and
    /// the reference).
    pub radius: f32,
    /// R in pixels that a kernel must reach to sample all of R everywhere in the view: R
    /// projected at the closest depth the probe rays hit, capped at the image's diagonal
    /// (`ProjectedRadius::reach_needed_px`); `None` when the view shows no geometry.
    #[serde(default)]
    pub radius_px: Option<f32>,
    /// How far the technique samples, in pixels (`reach_pixels`); `None` for the baseline or
    /// a technique that samples R in view space, uncapped.
    #[serde(default)]
    pub reach_px: Option<f32>,
    /// Mean reference accessibility over the view's geometry pixels.
    #[serde(default)]
    pub reference_mean: Option<f32>,
    /// Reference rays per pixel.
    pub rays: u32,
    /// Measured frames: the times' median and spread are over these.
    pub frames: u32,
    /// Warm-up frames rendered and discarded before the measured ones.
    pub warmup: u32,
    /// Timing over the measured frames: the technique's passes, the whole frame and each pass
    /// (ms). Its fields sit at the record's top level in results.json.
    #[serde(flatten)]
    pub times: FrameTimes,
    /// Bytes of the technique's plan (g-buffer included) with texture reuse as planned...
    pub texture_bytes: u64,
    /// ...and if every transient texture had its own allocation.
    pub texture_bytes_unshared: u64,
    /// The last frame's errors against the reference over the non-sky pixels (MAE, RMSE, PSNR,
    /// SSIM, signed and edge-band errors), with the flicker over every measured frame.
    pub metrics: Metrics,
    /// The side-by-side image, relative to the output directory.
    pub image: Option<String>,
    /// Every pass under the device's peaks (empty when the run measured none).
    #[serde(default)]
    pub roofline: Vec<PassRoofline>,
    /// SSDO under the sky (`environment = "sky"`): its radiance outputs against the radiance
    /// reference; `None` for every other run.
    #[serde(default)]
    pub radiance: Option<RadianceScores>,
    /// The view's ceilings (the same for every row of the view); `None` in results written
    /// before they existed.
    #[serde(default)]
    pub ceilings: Option<CeilingScores>,
    /// Every frame since the reset scored against the reference (`bench --convergence N`);
    /// empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub convergence: Vec<ConvergencePoint>,
}

fn default_view() -> String {
    "default".into()
}

impl RunRecord {
    /// "scene" for the default view, else "scene / view": the key runs are grouped by.
    pub fn scene_view(&self) -> String {
        if self.view == "default" {
            self.scene.clone()
        } else {
            format!("{} / {}", self.scene, self.view)
        }
    }

    /// The share of R the technique reaches at the view's nearest geometry (1 when it
    /// reaches all of it or samples R in view space).
    pub fn radius_reached(&self) -> f32 {
        match (self.reach_px, self.radius_px) {
            (Some(reach), Some(need)) if need > 0.0 => (reach / need).min(1.0),
            _ => 1.0,
        }
    }
}

/// A finished run: its record and its last frame's accessibility.
pub struct RunOutput {
    /// The run's row of the results.
    pub record: RunRecord,
    /// The last measured frame's accessibility, row-major, 0..1 (for the side-by-side image).
    pub ao: Vec<f32>,
}

/// Builds an `[ao]` config for `set` at radius `radius`.
pub fn ao_config(set: &ParamSet, radius: Radius) -> AoConfig {
    let mut c = AoConfig {
        technique: set.technique.clone(),
        radius: RadiusSetting::Units(radius),
        ..AoConfig::default()
    };
    c.params.insert(set.technique.clone(), set.params.clone());
    c
}

/// An error naming `set` when the GPU reported validation errors during its run.
pub fn check_gpu_errors(ctx: &BenchContext, set: &ParamSet) -> AppResult<()> {
    let errors = ctx.gpu.take_errors();
    if !errors.is_empty() {
        return Err(AppError::InvalidArgument {
            name: format!("{} ({})", set.technique, set.label()),
            value: format!("GPU validation errors: {}", errors.join("; ")),
            allowed: "a run without validation errors".into(),
        });
    }
    Ok(())
}

/// Runs `set` on `reference`'s scene; `tick` is called after every frame (progress).
pub fn run_technique(
    ctx: &BenchContext,
    reference: &SceneReference,
    set: &ParamSet,
    s: &BenchSettings,
    tick: &mut dyn FnMut(),
) -> AppResult<RunOutput> {
    let extent = s.extent();
    let ao = ao_config(set, reference.prepared.radius);
    let mut r = Renderer::new(
        ctx.gpu.clone(),
        ctx.shaders.clone(),
        &ctx.registry,
        reference.prepared.scene.clone(),
        &ao,
        FrameOutputs::default(),
        extent,
    )?;
    let radius_px = reference.projected.map(|p| p.reach_needed_px());
    let technique = ao.resolve(&ctx.registry)?;
    let reach_px = if technique.is_baseline() {
        None
    } else {
        technique.reach_pixels(s.height, radius_px)
    };
    let mut flicker = FlickerMeter::new();
    let mut last = Vec::new();
    let mut convergence = Vec::new();
    // The last frame's scores, when every frame is scored (the run's metrics are the same).
    let mut scored = None;
    let score = |ao: &[f32]| {
        compare(
            ao,
            &reference.accessibility,
            &reference.depth,
            extent.width,
            extent.height,
            &s.metrics,
        )
    };
    let times = time_frames(&mut r, s.warmup, s.frames, tick, &mut |r| {
        last = r.read_ao()?;
        flicker.push(&last, &reference.valid);
        if s.score_every_frame {
            let m = score(&last)?;
            convergence.push(ConvergencePoint {
                frame: convergence.len() as u32 + 1,
                mae: m.mae,
                ssim: m.ssim,
                edge_mae: m.edge_mae,
            });
            scored = Some(m);
        }
        Ok(())
    })?;
    check_gpu_errors(ctx, set)?;
    // Radiance under the sky is what the radiance reference traces.
    let radiance = if technique.radiance() == Some(RadianceEnvironment::Sky) {
        let view = FrameView {
            scene: reference.prepared.scene.clone(),
            camera: reference.prepared.scene.camera_at(0.0),
            time: 0.0,
            extent,
        };
        let truth = radiance_reference(
            ctx.gpu.clone(),
            ctx.shaders.clone(),
            &view,
            &s.reference(reference.prepared.radius.get()),
        )?;
        let (direct, indirect) = r.read_radiance()?;
        radiance_scores(&direct, &indirect, &truth, &reference.valid)
    } else {
        None
    };
    let mut metrics = match scored {
        Some(m) => m,
        None => score(&last)?,
    };
    metrics.flicker = flicker.value();
    let (bytes, unshared) = texture_bytes(&r.plan, extent);
    let roofline = ctx
        .peaks
        .map(|p| passes_under(&p, &pass_costs(&r.plan, extent), &times.passes))
        .unwrap_or_default();
    let record = RunRecord {
        scene: reference.label.clone(),
        view: reference.view.clone(),
        technique: set.technique.clone(),
        baseline: technique.is_baseline(),
        label: set.label(),
        params: set.params.clone().into_iter().collect(),
        width: extent.width,
        height: extent.height,
        radius: reference.prepared.radius.get(),
        radius_px,
        reach_px,
        reference_mean: Some(reference.mean_accessibility),
        rays: s.rays,
        frames: s.frames,
        warmup: s.warmup,
        times,
        texture_bytes: bytes,
        texture_bytes_unshared: unshared,
        metrics,
        image: None,
        roofline,
        radiance,
        ceilings: Some(reference.ceilings),
        convergence,
    };
    Ok(RunOutput { record, ao: last })
}
