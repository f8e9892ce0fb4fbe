//! The stability rigs: techniques and their variants, the per-frame checks, the report of
//! failures, the invariance measurements, and the guarded case runner (`Rig`).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant;

use aograph_ao_passes::{AoConfig, IntermediateFormat, TechniqueRegistry};
use aograph_frame::DepthFormat;
use aograph_graph::{Extent, GpuContext};
use aograph_renderer::FrameOutputs;
use aograph_renderer::Renderer;
use aograph_scene::{Camera, Scene};

use super::*;

/// One technique with one parameter set.
#[derive(Clone, Debug)]
pub(crate) struct Variant {
    pub(crate) technique: String,
    pub(crate) params: &'static str,
}

impl Variant {
    /// Output pixels per pixel the technique's own passes shade: 4 at `resolution = "half"`.
    pub(crate) fn pixels_per_own_pixel(&self) -> usize {
        if self.params.contains("resolution = \"half\"") {
            4
        } else {
            1
        }
    }
    pub(crate) fn label(&self) -> String {
        if self.params.is_empty() {
            self.technique.clone()
        } else {
            format!("{} [{}]", self.technique, self.params)
        }
    }
}

/// Every registered technique at its defaults, plus `temporal = true` and `resolution = "half"`
/// for those that have them.
pub(crate) fn variants() -> Vec<Variant> {
    let registry = TechniqueRegistry::with_builtins();
    let mut out = Vec::new();
    for name in registry.names() {
        out.push(Variant {
            technique: name.clone(),
            params: "",
        });
        let t = registry.get(&name).expect("listed");
        if t.parameters().iter().any(|p| p.name == "temporal") {
            out.push(Variant {
                technique: name.clone(),
                params: "temporal = true",
            });
        }
        if t.parameters().iter().any(|p| p.name == "resolution") {
            out.push(Variant {
                technique: name.clone(),
                params: "resolution = \"half\"",
            });
        }
    }
    assert!(out.len() >= 7, "every built-in technique: {out:?}");
    out
}

/// For every technique with a `levels` parameter, the variant with the most levels its
/// description allows: the deepest pyramid, whose levels degenerate soonest at small sizes.
pub(crate) fn deepest_pyramids() -> Vec<Variant> {
    let registry = TechniqueRegistry::with_builtins();
    let mut out = Vec::new();
    for name in registry.names() {
        let t = registry.get(&name).expect("listed");
        if let Some(spec) = t.parameters().into_iter().find(|p| p.name == "levels") {
            let max = match spec.kind {
                aograph_ao_passes::ParamKind::WordOrNumber { max, .. }
                | aograph_ao_passes::ParamKind::Range { max, .. } => max as u32,
                _ => panic!("{name}: levels allowed {}", spec.allowed()),
            };
            let params: &'static str = Box::leak(format!("levels = {max}").into_boxed_str());
            out.push(Variant {
                technique: name,
                params,
            });
        }
    }
    out
}

/// True for the techniques that estimate occlusion at all (`none` is accessibility 1 by
/// definition, the cost floor).
pub(crate) fn occludes(technique: &str) -> bool {
    technique != "none"
}

/// What a case expects of the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Expect {
    /// Finite, in [0, 1], sky exactly 1.
    Valid,
    /// Valid, and some pixel below 0.91 (0.95 at 32x32, see `check_frame`): a view of the box
    /// and column at a radius that reaches them, where an implementation returning 1 (or
    /// bounded noise near 1) must fail.
    Occluded,
    /// Valid, some geometry in view, and every non-sky pixel >= 0.98 (an unoccluded plane, or
    /// a radius too small for anything to occlude).
    Flat,
    /// `Flat` for a technique that traces the real geometry: up to [`TRACED_CREASE_SHARE`] of
    /// the pixels may lie within R of geometry a depth buffer does not resolve (creases).
    FlatBesideCreases,
    /// Valid and no geometry at all: every pixel exactly 1.
    Sky,
}

/// `own_pixels`: how many pixels the technique's own passes shade (a quarter of the image at
/// `resolution = "half"`), which decides the `Occluded` bar.
pub(crate) fn check_frame(
    ao: &[f32],
    depth: &[f32],
    expect: Expect,
    own_pixels: usize,
) -> Result<(), String> {
    if ao.len() != depth.len() {
        return Err(format!(
            "{} AO pixels but {} depth pixels",
            ao.len(),
            depth.len()
        ));
    }
    for (i, (&v, &d)) in ao.iter().zip(depth).enumerate() {
        if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
            return Err(format!("pixel {i} = {v} (depth {d})"));
        }
        if !(d.is_finite() && d >= 0.0) {
            return Err(format!("pixel {i}: linear depth {d}"));
        }
        if d <= 0.0 && v != 1.0 {
            return Err(format!("sky pixel {i} = {v}, must be exactly 1"));
        }
    }
    let geometry = depth.iter().filter(|d| **d > 0.0).count();
    match expect {
        Expect::Valid => {}
        Expect::Occluded => {
            // Below 0.9 at 97x61 and larger. At 32x32 the box's contact spans a few pixels and
            // the techniques' 5-tap blurs dilute it: HBAO's horizon-weighted estimator reaches
            // 0.928 there, so 0.95 is the bar at that size (returning 1, or bounded noise near
            // it, fails either). At 97x61 the bar is 0.91: hbao with `temporal = true` averages
            // its noise over frames and its darkest pixel, on box-on-plane with the island,
            // reads 0.9003, the estimator's mean where one frame's noise dips below 0.9.
            // At half resolution the passes see a quarter of the pixels: hbao at half reads
            // 0.9115 at 97x61, whose half is 49x31, below 64x48, so the small sizes' bar holds.
            let threshold = if own_pixels >= 64 * 48 { 0.91 } else { 0.95 };
            let min = ao
                .iter()
                .zip(depth)
                .filter(|(_, d)| **d > 0.0)
                .map(|(a, _)| *a)
                .fold(1.0f32, f32::min);
            if min.is_nan() || min >= threshold {
                return Err(format!(
                    "the view has occluders within R, but no pixel is below {threshold} (darkest {min})"
                ));
            }
        }
        Expect::Sky if geometry > 0 => {
            return Err(format!(
                "{geometry} pixels see geometry; the case expects sky only"
            ));
        }
        Expect::Sky => {}
        Expect::Flat | Expect::FlatBesideCreases if geometry == 0 => {
            return Err("no pixel sees the plane: the case is vacuous".into());
        }
        Expect::Flat | Expect::FlatBesideCreases => {
            let (i, min) = ao
                .iter()
                .zip(depth)
                .enumerate()
                .filter(|(_, (_, d))| **d > 0.0)
                .map(|(i, (a, _))| (i, *a))
                .fold((0, 1.0f32), |m, x| if x.1 < m.1 { x } else { m });
            let dark = ao
                .iter()
                .zip(depth)
                .filter(|(a, d)| **d > 0.0 && **a < 0.98)
                .count();
            let allowed = if expect == Expect::FlatBesideCreases {
                (geometry as f32 * TRACED_CREASE_SHARE) as usize
            } else {
                0
            };
            if min < 0.98 && dark > allowed {
                return Err(format!(
                    "unoccluded plane: darkest pixel {i} = {min} (depth {}), {dark} of {geometry} pixels below 0.98",
                    depth[i]
                ));
            }
        }
    }
    Ok(())
}

/// Failures of one test, reported together at the end.
#[derive(Default)]
pub(crate) struct Report {
    pub(crate) failures: Vec<String>,
    pub(crate) cases: usize,
}

impl Report {
    /// Reports and checks the failures, and that exactly `expected` cases ran (a case that
    /// silently stopped running would otherwise go unnoticed).
    pub(crate) fn finish(self, test: &str, started: Instant, expected: usize) {
        println!(
            "{test}: {} cases in {:.1} s",
            self.cases,
            started.elapsed().as_secs_f32()
        );
        assert!(
            self.failures.is_empty(),
            "{test}: {} of {} cases failed:\n{}",
            self.failures.len(),
            self.cases,
            self.failures.join("\n")
        );
        assert_eq!(
            self.cases, expected,
            "{test}: {} cases ran, {expected} expected",
            self.cases
        );
    }
}

/// The invariance cases: a frame that must match a baseline frame of the same view (the scene
/// scaled with R, moved far from the origin, rendered with another depth format or a reversed-Z
/// camera), as the mean absolute difference over the frame's pixels.
#[derive(Default)]
pub(crate) struct Invariance {
    pub(crate) measured: Vec<(String, f32, f32)>,
}

impl Invariance {
    /// Checks `frame` against `baseline` within `tolerance` (a missing frame already failed).
    pub(crate) fn check(
        &mut self,
        report: &mut Report,
        what: String,
        frame: Option<&[f32]>,
        baseline: Option<&[f32]>,
        tolerance: f32,
    ) {
        let (Some(a), Some(b)) = (frame, baseline) else {
            return;
        };
        report.cases += 1;
        let mae = if a.len() == b.len() {
            a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f32>() / a.len().max(1) as f32
        } else {
            f32::INFINITY
        };
        if mae.is_nan() || mae > tolerance {
            report.failures.push(format!(
                "{what}: MAE {mae:.5} against the baseline frame, allowed {tolerance}"
            ));
        }
        self.measured.push((what, mae, tolerance));
    }

    pub(crate) fn print(&self, test: &str) {
        let worst = self.measured.iter().fold(
            ("", 0.0f32),
            |w, (what, m, _)| if *m > w.1 { (what, *m) } else { w },
        );
        println!(
            "{test}: {} invariance checks, worst MAE {:.5} ({})",
            self.measured.len(),
            worst.1,
            worst.0
        );
        for (what, mae, tolerance) in &self.measured {
            println!("    {what}: {mae:.5} (allowed {tolerance})");
        }
    }
}

/// Runs `f` inside wgpu error scopes, catching panics; any error, panic or uncaptured device
/// error becomes a failure named `what`.
pub(crate) fn guarded(
    gpu: &GpuContext,
    report: &mut Report,
    what: &str,
    f: impl FnOnce() -> Result<(), String>,
) {
    report.cases += 1;
    let scopes = [
        wgpu::ErrorFilter::Validation,
        wgpu::ErrorFilter::OutOfMemory,
        wgpu::ErrorFilter::Internal,
    ]
    .map(|filter| gpu.device.push_error_scope(filter));
    let result = catch_unwind(AssertUnwindSafe(f));
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    let mut errors: Vec<String> = scopes
        .into_iter()
        .rev()
        .filter_map(|s| pollster::block_on(s.pop()))
        .map(|e| e.to_string())
        .collect();
    errors.extend(gpu.take_errors());
    let mut problems = Vec::new();
    match result {
        Ok(Ok(())) => {}
        Ok(Err(e)) => problems.push(e),
        Err(panic) => problems.push(format!(
            "panicked: {}",
            panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default()
        )),
    }
    if !errors.is_empty() {
        problems.push(format!("wgpu errors: {}", errors.join(" | ")));
    }
    if !problems.is_empty() {
        report
            .failures
            .push(format!("{what}: {}", problems.join("; ")));
    }
}

/// One technique on one scene: a renderer reused for every camera and size of the rig.
pub(crate) struct Rig<'a> {
    pub(crate) gpu: Arc<GpuContext>,
    pub(crate) variant: &'a Variant,
    pub(crate) scene_name: String,
    pub(crate) renderer: Option<Renderer>,
    pub(crate) time: f32,
}

impl<'a> Rig<'a> {
    pub(crate) fn new(
        gpu: &Arc<GpuContext>,
        report: &mut Report,
        variant: &'a Variant,
        scene_name: &str,
        scene: Scene,
        radius: f32,
        depth_format: DepthFormat,
    ) -> Self {
        Self::with_format(
            gpu,
            report,
            variant,
            scene_name,
            scene,
            radius,
            depth_format,
            IntermediateFormat::default(),
        )
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn with_format(
        gpu: &Arc<GpuContext>,
        report: &mut Report,
        variant: &'a Variant,
        scene_name: &str,
        scene: Scene,
        radius: f32,
        depth_format: DepthFormat,
        intermediate: IntermediateFormat,
    ) -> Self {
        let mut renderer = None;
        let what = format!("{} on {scene_name}: building the renderer", variant.label());
        guarded(gpu, report, &what, || {
            let config = AoConfig {
                intermediate_format: intermediate,
                ..common::ao_config(&variant.technique, radius, variant.params)
            };
            let registry = TechniqueRegistry::with_builtins();
            let outputs = FrameOutputs {
                linear_depth: true,
                depth_format,
                ..Default::default()
            };
            renderer = Some(
                Renderer::new(
                    gpu.clone(),
                    aograph::shader_library(),
                    &registry,
                    Arc::new(scene),
                    &config,
                    outputs,
                    SIZE,
                )
                .map_err(|e| e.to_string())?,
            );
            Ok(())
        });
        Self {
            gpu: gpu.clone(),
            variant,
            scene_name: scene_name.to_string(),
            renderer,
            time: 0.0,
        }
    }

    /// Renders `frames` frames from `camera` at `size`, the clock advancing by `dt` per frame,
    /// and checks the last one; returns its accessibility when the case passed.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn case(
        &mut self,
        report: &mut Report,
        case: &str,
        camera: Camera,
        size: Extent,
        frames: u32,
        dt: f32,
        expect: Expect,
    ) -> Option<Vec<f32>> {
        let r = self.renderer.as_mut()?;
        let mut out = None;
        let what = format!(
            "{} on {}: {case} at {size}",
            self.variant.label(),
            self.scene_name
        );
        let traces = aograph_ao_passes::TraceBackend::declared_by(&r.graph.declared).is_some();
        let expect = match expect {
            Expect::Occluded if !occludes(&self.variant.technique) => Expect::Valid,
            Expect::Flat if traces => Expect::FlatBesideCreases,
            e => e,
        };
        let time = &mut self.time;
        guarded(&self.gpu, report, &what, || {
            r.resize(size).map_err(|e| format!("resize: {e}"))?;
            for _ in 0..frames {
                *time += dt;
                r.render_with_camera(*time, camera)
                    .map_err(|e| format!("execute: {e}"))?;
            }
            let ao = r.read_ao().map_err(|e| e.to_string())?;
            let depth = r.read_linear_depth().map_err(|e| e.to_string())?;
            let own_pixels = ao.len() / self.variant.pixels_per_own_pixel();
            check_frame(&ao, &depth, expect, own_pixels)?;
            out = Some(ao);
            Ok(())
        });
        out
    }

    /// Renders `a` and then `b` (the same pose, another projection convention) and checks
    /// that both frames are valid and see the same surfaces: linear depth equal to 1e-3
    /// (relative) on at least 99% of the pixels.
    pub(crate) fn same_surfaces(
        &mut self,
        report: &mut Report,
        case: &str,
        a: Camera,
        b: Camera,
    ) -> Option<(Vec<f32>, Vec<f32>)> {
        let r = self.renderer.as_mut()?;
        let mut out = None;
        let what = format!("{} on {}: {case}", self.variant.label(), self.scene_name);
        let time = &mut self.time;
        guarded(&self.gpu, report, &what, || {
            r.resize(SIZE).map_err(|e| format!("resize: {e}"))?;
            let (mut depths, mut aos) = (Vec::new(), Vec::new());
            for camera in [a, b] {
                *time += FRAME;
                r.render_with_camera(*time, camera)
                    .map_err(|e| format!("execute: {e}"))?;
                let depth = r.read_linear_depth().map_err(|e| e.to_string())?;
                let ao = r.read_ao().map_err(|e| e.to_string())?;
                check_frame(&ao, &depth, Expect::Valid, ao.len())?;
                depths.push(depth);
                aos.push(ao);
            }
            let same = depths[0]
                .iter()
                .zip(&depths[1])
                .filter(|(x, y)| (*x - *y).abs() <= 1e-3 * x.abs().max(1e-6))
                .count();
            if same * 100 < depths[0].len() * 99 {
                return Err(format!(
                    "only {same} of {} pixels see the same surface",
                    depths[0].len()
                ));
            }
            out = Some((aos.remove(0), aos.remove(0)));
            Ok(())
        });
        out
    }

    /// True when the variant's graph traces the real geometry (it declared the scene BVH or acceleration structures).
    pub(crate) fn traces_geometry(&self) -> bool {
        self.renderer.as_ref().is_some_and(|r| {
            aograph_ao_passes::TraceBackend::declared_by(&r.graph.declared).is_some()
        })
    }

    pub(crate) fn cut(&mut self) {
        if let Some(r) = self.renderer.as_mut() {
            r.cut();
        }
    }
}
