//! Numerical stability at the extremes (issue 9), for every registered technique (plus the
//! temporal variant of every technique that has a `temporal` switch), on the GPU at small sizes.
//!
//! Cases: near planes 1e-4 to 10 and far planes 10 to 1e7 with Depth32Float and Depth24Plus,
//! an infinite reversed-Z far plane (on a reversed scene, and as a frame's camera on a plain
//! one) and an orthographic camera; scene scale 1e-3 to 1e4 with R scaled alike, a scene 1e5
//! units from the origin; R = 1e-4 (no occlusion expected) to R far larger than the scene;
//! output sizes 1x1, 2x3, 97x61, 4096x8, 8x4096 with resizes between frames; a camera inside
//! a box, in the floor's plane, 1e-3 above it, seeing only sky; a plane at 89.9 degrees to the
//! view; degenerate triangles and coincident vertices; for every technique (temporal or not)
//! a camera jump of 1e4 units, a 180-degree turn and zero-length frame times.
//!
//! Every rig uses the default intermediate format except one that repeats the near/far sweep
//! at the other (r32float or r16float). Every case asserts: no panic, `execute` returns Ok,
//! no wgpu error (an error scope around the case, and the device's uncaptured-error sink);
//! every pixel finite and in [0, 1]; sky exactly 1; and where the view holds only an
//! unoccluded plane, or R is too small for anything to occlude (the `Flat` cases), every
//! non-sky pixel at least 0.98. Failures are collected and reported together, one line each.
//!
//! Speed: lavapipe compiles pipelines on the CPU, so one renderer per (technique, scene, R,
//! depth format) is built and cameras and sizes vary through `render_with_camera` and
//! `resize`. The three tests split the rigs so the harness runs them on both cores.

mod common;

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;
use std::time::Instant;

use aograph::{FrameOutputs, Renderer};
use aograph_ao::{AoConfig, IntermediateFormat, TechniqueRegistry};
use aograph_frame::DepthFormat;
use aograph_graph::{Extent, GpuContext, test_gpu};
use aograph_scene::primitives::{cuboid, quad};
use aograph_scene::{Camera, Mesh, Projection, Scene, SceneBuilder};
use glam::{Mat4, Vec3};

const SIZE: Extent = Extent {
    width: 32,
    height: 32,
};
/// Invariance tolerances (MAE against the baseline frame over all pixels), from the measured
/// values printed by the tests with about 3x headroom; see each check.
/// Scale 1e-3 to 1e4: measured at most 0.0032 (mssao at 1e-3: its fp16 tuples round sums of
/// scaled distances differently).
const TOL_SCALE: f32 = 0.01;
/// 1e5 units from the origin: measured at most 0.0012 (points rebuilt from linear depth lose
/// a few bits against the origin's).
const TOL_OFFSET: f32 = 0.004;
/// The same for a technique that traces the real geometry (rtao): measured 0.0042. Its rays
/// leave the surface by the reference's offset, 1e-4 R + 4e-6 |p| (reference/tracer.rs), which
/// at 1e5 units is 0.57 units instead of 0.0001: contact occlusion closer than that is lost,
/// by the reference as much as by rtao (the offset is the reference's rule, not rtao's).
const TOL_OFFSET_TRACED: f32 = 0.012;
/// Share of an unoccluded view's pixels a technique tracing the real geometry may find
/// occluded: crease pixels whose point lies within R of the other face even at R = 1e-4
/// (box-on-plane at 32x32: pixel 815, 0.848 in both rtao and the reference).
const TRACED_CREASE_SHARE: f32 = 0.01;
/// Depth24Plus against Depth32Float: measured exactly 0. Techniques read linear depth and
/// positions from colour targets; the depth format only decides visibility ties.
const TOL_DEPTH24: f32 = 1e-4;
/// A reversed-Z camera against the plain one (both ways): measured at most 0.0055 (tssao, whose
/// history sees a frame of the other convention between the two).
const TOL_REVERSED_Z: f32 = 0.015;
/// Where the temporal island floor lies (scene units, scale 1): the camera jump's length.
const JUMP: f32 = 1.0e4;

/// One technique with one parameter set.
#[derive(Clone, Debug)]
struct Variant {
    technique: String,
    params: &'static str,
}

impl Variant {
    /// Output pixels per pixel the technique's own passes shade: 4 at `resolution = "half"`.
    fn pixels_per_own_pixel(&self) -> usize {
        if self.params.contains("resolution = \"half\"") {
            4
        } else {
            1
        }
    }
    fn label(&self) -> String {
        if self.params.is_empty() {
            self.technique.clone()
        } else {
            format!("{} [{}]", self.technique, self.params)
        }
    }
}

/// Every registered technique at its defaults, plus `temporal = true` and `resolution = "half"`
/// for those that have them.
fn variants() -> Vec<Variant> {
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
fn deepest_pyramids() -> Vec<Variant> {
    let registry = TechniqueRegistry::with_builtins();
    let mut out = Vec::new();
    for name in registry.names() {
        let t = registry.get(&name).expect("listed");
        if let Some(spec) = t.parameters().into_iter().find(|p| p.name == "levels") {
            let max = match spec.kind {
                aograph_ao::ParamKind::WordOrNumber { max, .. }
                | aograph_ao::ParamKind::Range { max, .. } => max as u32,
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
fn occludes(technique: &str) -> bool {
    technique != "none"
}

/// What a case expects of the frame.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Expect {
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
fn check_frame(ao: &[f32], depth: &[f32], expect: Expect, own_pixels: usize) -> Result<(), String> {
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
struct Report {
    failures: Vec<String>,
    cases: usize,
}

impl Report {
    /// Reports and checks the failures, and that exactly `expected` cases ran (a case that
    /// silently stopped running would otherwise go unnoticed).
    fn finish(self, test: &str, started: Instant, expected: usize) {
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
struct Invariance {
    measured: Vec<(String, f32, f32)>,
}

impl Invariance {
    /// Checks `frame` against `baseline` within `tolerance` (a missing frame already failed).
    fn check(
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

    fn print(&self, test: &str) {
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
fn guarded(
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
struct Rig<'a> {
    gpu: Arc<GpuContext>,
    variant: &'a Variant,
    scene_name: String,
    renderer: Option<Renderer>,
    time: f32,
}

impl<'a> Rig<'a> {
    fn new(
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
    fn with_format(
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
    fn case(
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
        let traces = r.graph.declared.trace_backend().is_some();
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
    fn same_surfaces(
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
    fn traces_geometry(&self) -> bool {
        self.renderer
            .as_ref()
            .is_some_and(|r| r.graph.declared.trace_backend().is_some())
    }

    fn cut(&mut self) {
        if let Some(r) = self.renderer.as_mut() {
            r.cut();
        }
    }
}

// ---- Scenes -------------------------------------------------------------------------------

/// A floor of `size` x `size` at y = 0, centred on `centre`, made of `cells` x `cells` quads so
/// no triangle is much larger than the view (interpolation stays exact to f32's precision).
fn floor(b: &mut SceneBuilder, centre: Vec3, size: f32, cells: u32) {
    let cell = size / cells as f32;
    let m = b.mesh(quad(cell, cell, 0));
    for i in 0..cells {
        for j in 0..cells {
            let c = centre
                + Vec3::new(
                    (i as f32 + 0.5) * cell - 0.5 * size,
                    0.0,
                    (j as f32 + 0.5) * cell - 0.5 * size,
                );
            b.place(m, Mat4::from_translation(c));
        }
    }
}

/// `box-on-plane` at `scale`, moved by `offset`: a 200 x 200 floor, a unit box and a 1 x 3 x 1
/// column at the origin; with `island`, a second, empty 200 x 200 floor at x = [`JUMP`].
fn box_scene(scale: f32, offset: Vec3, island: bool, reversed: bool) -> Scene {
    let mut b = SceneBuilder::new();
    b.material([0.6, 0.6, 0.6]);
    floor(&mut b, offset, 200.0 * scale, 4);
    b.add(
        cuboid(Vec3::splat(scale), 0),
        Mat4::from_translation(offset + Vec3::new(0.0, 0.5, 0.0) * scale),
    );
    b.add(
        cuboid(Vec3::new(1.0, 3.0, 1.0) * scale, 0),
        Mat4::from_translation(offset + Vec3::new(-1.5, 1.5, -1.0) * scale),
    );
    if island {
        floor(&mut b, offset + Vec3::X * JUMP * scale, 200.0 * scale, 4);
    }
    let mut camera = Camera::perspective(
        offset + Vec3::new(0.0, 3.0, 8.0) * scale,
        offset + Vec3::Y * 0.5 * scale,
        50f32.to_radians(),
        0.05 * scale,
        1000.0 * scale,
    );
    if reversed {
        camera.projection = Projection::Perspective {
            fov_y: 50f32.to_radians(),
            near: 0.05 * scale,
            far: 0.0,
            reversed_z_infinite: true,
        };
    }
    b.build(camera)
}

/// A floor with zero-area geometry on and above it: triangles with repeated indices, collinear
/// triangles, a box whose 24 vertices all coincide, a floor piece built of coincident
/// (unwelded) vertices with zero-length normals, and a sliver 1e-6 wide.
fn degenerate_scene() -> Scene {
    let mut b = SceneBuilder::new();
    b.material([0.6, 0.6, 0.6]);
    floor(&mut b, Vec3::ZERO, 200.0, 4);
    // Repeated indices and collinear vertices, lying on the floor and standing above it.
    let p = vec![
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.5, 0.5, 0.5),
    ];
    let degenerate = Mesh {
        name: "degenerate".into(),
        normals: vec![Vec3::Y; p.len()],
        positions: p,
        indices: vec![0, 0, 1, 2, 2, 2, 0, 1, 2, 2, 3, 4, 5, 5, 3, 1, 1, 1],
        material: 0,
        skin_weights: Vec::new(),
    };
    b.add(degenerate, Mat4::from_translation(Vec3::new(0.0, 0.0, 0.0)));
    // A box collapsed to one point (every vertex coincides), above the floor.
    let mut collapsed = cuboid(Vec3::ONE, 0);
    collapsed
        .positions
        .iter_mut()
        .for_each(|p| *p = Vec3::new(0.3, 0.7, 0.2));
    b.add(collapsed, Mat4::IDENTITY);
    // A raised platform (0.02 above the floor, 4 x 4) of unwelded quads: every corner is four
    // coincident vertices, normals zero-length (the g-buffer must derive them).
    let mut platform = Mesh {
        name: "platform".into(),
        material: 0,
        ..Mesh::default()
    };
    for i in 0..4 {
        for j in 0..4 {
            let o = Vec3::new(i as f32 - 2.0, 0.02, j as f32 - 2.0);
            let base = platform.positions.len() as u32;
            platform
                .positions
                .extend([o, o + Vec3::Z, o + Vec3::X + Vec3::Z, o + Vec3::X]);
            platform.normals.extend([Vec3::ZERO; 4]);
            platform
                .indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    b.add(platform, Mat4::from_translation(Vec3::new(20.0, 0.0, 0.0)));
    // A sliver: two vertices 1e-6 apart, standing up.
    let sliver = Mesh {
        name: "sliver".into(),
        positions: vec![
            Vec3::ZERO,
            Vec3::new(1e-6, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 3],
        indices: vec![0, 1, 2],
        material: 0,
        skin_weights: Vec::new(),
    };
    b.add(sliver, Mat4::from_translation(Vec3::new(-0.7, 0.0, 0.3)));
    b.build(Camera::perspective(
        Vec3::new(0.0, 3.0, 8.0),
        Vec3::new(0.0, 0.5, 0.0),
        50f32.to_radians(),
        0.05,
        1000.0,
    ))
}

// ---- Cameras ------------------------------------------------------------------------------

fn perspective(position: Vec3, target: Vec3, near: f32, far: f32) -> Camera {
    Camera::perspective(position, target, 50f32.to_radians(), near, far)
}

/// The view of the box and column at `scale`, moved by `offset`.
fn occluders(scale: f32, offset: Vec3) -> Camera {
    // Close enough that the box's contact and the column's foot span several pixels at 32x32
    // (from 8 units away they were 4 pixels wide and a 5-tap blur diluted them to 0.92).
    perspective(
        offset + Vec3::new(0.6, 2.2, 4.5) * scale,
        offset + Vec3::new(-0.6, 0.6, -0.5) * scale,
        0.05 * scale,
        1000.0 * scale,
    )
}

/// A view of open floor 40 units (times `scale`) from the box: only the plane, the box far
/// outside the view (at 32x32).
fn open_floor(scale: f32, offset: Vec3) -> Camera {
    perspective(
        offset + Vec3::new(40.0, 3.0, 8.0) * scale,
        offset + Vec3::new(40.0, 0.0, 0.0) * scale,
        0.05 * scale,
        1000.0 * scale,
    )
}

/// The floor at 89.9 degrees to the central ray (grazing by 0.1 degree) from 0.1 above it
/// (times `scale`): the central ray meets it 57 units ahead; the box is out of view at 32x32.
fn grazing(scale: f32, offset: Vec3) -> Camera {
    let pitch = 0.1f32.to_radians();
    let eye = offset + Vec3::new(40.0, 0.1, 50.0) * scale;
    perspective(
        eye,
        eye + Vec3::new(0.0, -pitch.sin(), -pitch.cos()) * scale,
        0.01 * scale,
        1000.0 * scale,
    )
}

/// A view of the empty island floor (scale 1): only the plane at any aspect ratio.
fn island_view() -> Camera {
    perspective(
        Vec3::new(JUMP, 3.0, 8.0),
        Vec3::new(JUMP, 0.0, 0.0),
        0.05,
        1000.0,
    )
}

fn reversed(mut c: Camera) -> Camera {
    if let Projection::Perspective { fov_y, near, .. } = c.projection {
        c.projection = Projection::Perspective {
            fov_y,
            near,
            far: 0.0,
            reversed_z_infinite: true,
        };
    }
    c
}

fn with_planes(mut c: Camera, near: f32, far: f32) -> Camera {
    if let Projection::Perspective {
        fov_y,
        reversed_z_infinite,
        ..
    } = c.projection
    {
        c.projection = Projection::Perspective {
            fov_y,
            near,
            far,
            reversed_z_infinite,
        };
    }
    c
}

const FRAME: f32 = 1.0 / 60.0;

/// Near planes 1e-4..10 and far planes 10..1e7 on the occluders (valid) and on open floor (flat).
/// The near/far sweep; returns the frame of the occluders at near 0.05, far 1e4 (the baseline
/// of the depth-format invariance).
fn depth_range_cases(rig: &mut Rig, report: &mut Report) -> Option<Vec<f32>> {
    let mut baseline = None;
    for near in [1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0] {
        // Near 10 clips the box and column (about 8 units away): only the floor is left.
        rig.case(
            report,
            &format!("near {near:e}, far 1e4, occluders"),
            with_planes(occluders(1.0, Vec3::ZERO), near, 1e4),
            SIZE,
            1,
            FRAME,
            if near < 10.0 {
                Expect::Occluded
            } else {
                Expect::Valid
            },
        );
        // The open floor seen from 3 units up: near 10 clips the floor nearer than 10.
        rig.case(
            report,
            &format!("near {near:e}, far 1e4, open floor"),
            with_planes(open_floor(1.0, Vec3::ZERO), near, 1e4),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    for far in [10.0, 100.0, 1e4, 1e5, 1e7] {
        let frame = rig.case(
            report,
            &format!("near 0.05, far {far:e}, occluders"),
            with_planes(occluders(1.0, Vec3::ZERO), 0.05, far),
            SIZE,
            1,
            FRAME,
            Expect::Occluded,
        );
        if far == 1e4 {
            baseline = frame;
        }
        rig.case(
            report,
            &format!("near 0.05, far {far:e}, open floor"),
            with_planes(open_floor(1.0, Vec3::ZERO), 0.05, far),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    rig.case(
        report,
        "near 1e-4, far 1e7, occluders",
        with_planes(occluders(1.0, Vec3::ZERO), 1e-4, 1e7),
        SIZE,
        1,
        FRAME,
        Expect::Occluded,
    );
    rig.case(
        report,
        "near 1e-4, far 1e7, open floor",
        with_planes(open_floor(1.0, Vec3::ZERO), 1e-4, 1e7),
        SIZE,
        1,
        FRAME,
        Expect::Flat,
    );
    for (near, far) in [(1e-4, 1e7), (0.01, 100.0), (1.0, 1e4)] {
        rig.case(
            report,
            &format!("near {near:e}, far {far:e}, plane at 89.9 degrees"),
            with_planes(grazing(1.0, Vec3::ZERO), near, far),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    baseline
}

#[test]
fn depth_ranges_formats_and_projections() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let mut invariance = Invariance::default();
    for v in &variants() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (Depth32Float)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        let depth32 = depth_range_cases(&mut rig, &mut report);
        let ortho = Camera {
            projection: Projection::Orthographic {
                height: 8.0,
                near: 0.05,
                far: 1000.0,
            },
            ..occluders(1.0, Vec3::ZERO)
        };
        rig.case(
            &mut report,
            "orthographic, occluders",
            ortho,
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        // The scene's camera is not reversed; a frame's camera may be (the g-buffer switches
        // its depth test per frame).
        let a = occluders(1.0, Vec3::ZERO);
        let pair = rig.same_surfaces(
            &mut report,
            "reversed-Z camera on a scene whose camera is not",
            a,
            reversed(a),
        );
        invariance.check(
            &mut report,
            format!("{}: reversed-Z camera against the plain one", v.label()),
            pair.as_ref().map(|p| p.1.as_slice()),
            pair.as_ref().map(|p| p.0.as_slice()),
            TOL_REVERSED_Z,
        );
        let ortho = Camera {
            projection: Projection::Orthographic {
                height: 8.0,
                near: 0.05,
                far: 1000.0,
            },
            ..open_floor(1.0, Vec3::ZERO)
        };
        rig.case(
            &mut report,
            "orthographic, open floor",
            ortho,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );

        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (Depth24Plus)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth24Plus,
        );
        let depth24 = depth_range_cases(&mut rig, &mut report);
        invariance.check(
            &mut report,
            format!("{}: Depth24Plus against Depth32Float", v.label()),
            depth24.as_deref(),
            depth32.as_deref(),
            TOL_DEPTH24,
        );

        // The other intermediate precision (the rest of the suite runs the default).
        let other = match IntermediateFormat::default() {
            IntermediateFormat::R16Float => IntermediateFormat::R32Float,
            IntermediateFormat::R32Float => IntermediateFormat::R16Float,
        };
        let mut rig = Rig::with_format(
            &gpu,
            &mut report,
            v,
            &format!("box-on-plane ({other:?} intermediates)"),
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
            other,
        );
        depth_range_cases(&mut rig, &mut report);

        // The g-buffer clears depth to 0 and tests Greater when the scene's camera is reversed.
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (reversed-Z infinite)",
            box_scene(1.0, Vec3::ZERO, false, true),
            1.0,
            DepthFormat::Depth32Float,
        );
        for near in [1e-4, 0.05, 1.0] {
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, occluders"),
                with_planes(reversed(occluders(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Valid,
            );
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, open floor"),
                with_planes(reversed(open_floor(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                &format!("reversed-Z infinite, near {near:e}, plane at 89.9 degrees"),
                with_planes(reversed(grazing(1.0, Vec3::ZERO)), near, 0.0),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
        }
        let a = occluders(1.0, Vec3::ZERO);
        let pair = rig.same_surfaces(
            &mut report,
            "plain camera on a reversed-Z scene",
            reversed(a),
            a,
        );
        invariance.check(
            &mut report,
            format!(
                "{}: plain camera on a reversed-Z scene against reversed",
                v.label()
            ),
            pair.as_ref().map(|p| p.1.as_slice()),
            pair.as_ref().map(|p| p.0.as_slice()),
            TOL_REVERSED_Z,
        );
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane (reversed-Z, Depth24Plus)",
            box_scene(1.0, Vec3::ZERO, false, true),
            1.0,
            DepthFormat::Depth24Plus,
        );
        rig.case(
            &mut report,
            "reversed-Z infinite, occluders",
            reversed(occluders(1.0, Vec3::ZERO)),
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "reversed-Z infinite, open floor",
            reversed(open_floor(1.0, Vec3::ZERO)),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
    }
    invariance.print("depth_ranges_formats_and_projections");
    // Per technique variant: 101 cases and 3 invariance checks (Depth24Plus and the two
    // reversed-Z pairs).
    report.finish(
        "depth_ranges_formats_and_projections",
        started,
        104 * variants().len(),
    );
}

#[test]
fn scene_scale_offset_and_radius() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let mut invariance = Invariance::default();
    for v in &variants() {
        // The baseline frame: the occluders at scale 1, R = 1, at the origin.
        let baseline = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane x 1 (baseline)",
            box_scene(1.0, Vec3::ZERO, false, false),
            1.0,
            DepthFormat::Depth32Float,
        )
        .case(
            &mut report,
            "occluders",
            occluders(1.0, Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Occluded,
        );
        // Scale 1e-3 to 1e4, R scaled alike: the same frame up to rounding.
        for scale in [1e-3f32, 1e-2, 0.1, 10.0, 1e2, 1e3, 1e4] {
            let mut rig = Rig::new(
                &gpu,
                &mut report,
                v,
                &format!("box-on-plane x {scale:e}"),
                box_scene(scale, Vec3::ZERO, false, false),
                scale,
                DepthFormat::Depth32Float,
            );
            let frame = rig.case(
                &mut report,
                "occluders",
                occluders(scale, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Occluded,
            );
            invariance.check(
                &mut report,
                format!("{}: scene and R scaled by {scale:e}", v.label()),
                frame.as_deref(),
                baseline.as_deref(),
                TOL_SCALE,
            );
            rig.case(
                &mut report,
                "open floor",
                open_floor(scale, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(scale, Vec3::ZERO),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "occluders at 97x61",
                occluders(scale, Vec3::ZERO),
                Extent::new(97, 61),
                1,
                FRAME,
                Expect::Occluded,
            );
        }
        // 1e5 units from the origin on two axes.
        let offset = Vec3::new(1e5, 0.0, 1e5);
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane at (1e5, 0, 1e5)",
            box_scene(1.0, offset, false, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        let frame = rig.case(
            &mut report,
            "occluders",
            occluders(1.0, offset),
            SIZE,
            2,
            FRAME,
            Expect::Occluded,
        );
        invariance.check(
            &mut report,
            format!("{}: scene moved to (1e5, 0, 1e5)", v.label()),
            frame.as_deref(),
            baseline.as_deref(),
            if rig.traces_geometry() {
                TOL_OFFSET_TRACED
            } else {
                TOL_OFFSET
            },
        );
        rig.case(
            &mut report,
            "open floor",
            open_floor(1.0, offset),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "open floor, near 1e-3 far 1e7",
            with_planes(open_floor(1.0, offset), 1e-3, 1e7),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "plane at 89.9 degrees",
            grazing(1.0, offset),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders at 97x61",
            occluders(1.0, offset),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Occluded,
        );
        // R = 1e-4: nothing can occlude, not even at the box's contact.
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane, R = 1e-4",
            box_scene(1.0, Vec3::ZERO, false, false),
            1e-4,
            DepthFormat::Depth32Float,
        );
        rig.case(
            &mut report,
            "occluders (R = 1e-4: no occlusion)",
            occluders(1.0, Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders close up (R = 1e-4: no occlusion)",
            perspective(
                Vec3::new(0.8, 0.3, 1.2),
                Vec3::new(0.0, 0.2, 0.0),
                1e-3,
                100.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "open floor",
            open_floor(1.0, Vec3::ZERO),
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "occluders at 97x61 (R = 1e-4: no occlusion)",
            occluders(1.0, Vec3::ZERO),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );
        // R from small to larger than the whole scene (the floor is 200 across).
        for radius in [1e-2f32, 10.0, 1e3, 1e6] {
            let mut rig = Rig::new(
                &gpu,
                &mut report,
                v,
                &format!("box-on-plane, R = {radius:e}"),
                box_scene(1.0, Vec3::ZERO, false, false),
                radius,
                DepthFormat::Depth32Float,
            );
            // R = 1e-2 projects to well under a pixel at 32x32: nothing visibly occludes. R of
            // 1e3 and 1e6 dwarf the scene: a technique that places its samples in view space
            // within R (ssdo) puts every sample off screen and sees nothing; valid is enough.
            let occluded = if (1.0..=10.0).contains(&radius) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                occluded,
            );
            // Another view of the same scene: a cut, as the viewer makes on a jump. Without one
            // a temporal filter rightly keeps the occluders view's history of the floor points
            // both views see (Eq. 13 holds: same points, same depths), and at R >= 10 that
            // history holds the box's occlusion, which R reaches and this view cannot see.
            rig.cut();
            rig.case(
                &mut report,
                "open floor",
                open_floor(1.0, Vec3::ZERO),
                SIZE,
                2,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(1.0, Vec3::ZERO),
                SIZE,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "occluders at 97x61",
                occluders(1.0, Vec3::ZERO),
                Extent::new(97, 61),
                1,
                FRAME,
                occluded,
            );
        }
    }
    invariance.print("scene_scale_offset_and_radius");
    // Per technique variant: 68 cases and 8 invariance checks (7 scales and the offset).
    report.finish(
        "scene_scale_offset_and_radius",
        started,
        76 * variants().len(),
    );
}

#[test]
fn sizes_cameras_geometry_and_time() {
    let Some(gpu) = test_gpu() else { return };
    let started = Instant::now();
    let mut report = Report::default();
    let sizes = [
        Extent::new(1, 1),
        Extent::new(2, 3),
        Extent::new(97, 61),
        Extent::new(4096, 8),
        Extent::new(8, 4096),
        SIZE,
    ];
    for v in &variants() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane with island",
            box_scene(1.0, Vec3::ZERO, true, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        // Output sizes (pyramids with odd and degenerate levels); each size is a resize
        // between frames, two frames each so temporal history is used at the new size.
        for size in sizes {
            // The slivers (1x1, 2x3, 4096x8, 8x4096) may miss the contact: valid is enough there.
            let occluded = if size == SIZE || size == Extent::new(97, 61) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                size,
                2,
                FRAME,
                occluded,
            );
            rig.case(
                &mut report,
                "island floor",
                island_view(),
                size,
                2,
                FRAME,
                Expect::Flat,
            );
        }
        // A camera inside the box, looking out through its walls.
        let inside = perspective(
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::new(1.0, 0.4, 0.3),
            0.01,
            1000.0,
        );
        rig.case(
            &mut report,
            "camera inside the box",
            inside,
            SIZE,
            2,
            FRAME,
            Expect::Valid,
        );
        // A camera on the floor (in its plane), and one just below it looking up.
        rig.case(
            &mut report,
            "camera in the floor's plane",
            perspective(
                Vec3::new(40.0, 0.0, 8.0),
                Vec3::new(40.0, 0.0, 0.0),
                0.05,
                1000.0,
            ),
            SIZE,
            1,
            FRAME,
            Expect::Valid,
        );
        // Only sky: straight up, and up with the up vector parallel to the view.
        rig.case(
            &mut report,
            "sky only",
            perspective(
                Vec3::new(0.0, 3.0, 8.0),
                Vec3::new(0.0, 10.0, 7.0),
                0.05,
                1000.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Sky,
        );
        rig.case(
            &mut report,
            "sky only, straight up",
            perspective(
                Vec3::new(0.0, 3.0, 8.0),
                Vec3::new(0.0, 10.0, 8.0),
                0.05,
                1000.0,
            ),
            SIZE,
            1,
            FRAME,
            Expect::Sky,
        );
        // The island floor at 89.9 degrees to the central ray (grazing by 0.1 degree), 0.1
        // above it: the central ray meets it 57 units ahead. Every size: the island is empty.
        let island_grazing = grazing(1.0, Vec3::new(JUMP - 40.0, 0.0, 0.0));
        for size in sizes {
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                island_grazing,
                size,
                2,
                FRAME,
                Expect::Flat,
            );
        }
        // Near 1e-4 with the floor 1e-3 below the camera: R covers far more than the screen.
        let low = perspective(
            Vec3::new(JUMP, 1e-3, 0.0),
            Vec3::new(JUMP, 0.0, -1e-3),
            1e-4,
            1000.0,
        );
        rig.case(
            &mut report,
            "camera 1e-3 above the floor, near 1e-4",
            low,
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "camera 1e-3 above the floor, near 1e-4",
            low,
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );

        // Time: a camera jump of 1e4 units, a 180-degree turn, zero-length frame times. After
        // the jump and the turn the view holds only open floor, so stale (occluded) history
        // leaking into it would fail the flat check.
        rig.cut();
        let a = occluders(1.0, Vec3::ZERO);
        rig.case(
            &mut report,
            "before the jump",
            a,
            SIZE,
            4,
            FRAME,
            Expect::Valid,
        );
        let jumped = Camera {
            position: a.position + Vec3::X * JUMP,
            target: a.target + Vec3::X * JUMP,
            ..a
        };
        rig.case(
            &mut report,
            "first frame after a 1e4 jump",
            jumped,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "frames after a 1e4 jump",
            jumped,
            SIZE,
            3,
            FRAME,
            Expect::Flat,
        );
        rig.case(&mut report, "jump back", a, SIZE, 3, FRAME, Expect::Valid);
        let turned = Camera {
            target: a.position + (a.position - a.target) * Vec3::new(1.0, -1.0, 1.0),
            ..a
        };
        rig.case(
            &mut report,
            "first frame after a 180-degree turn",
            turned,
            SIZE,
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "frames after a 180-degree turn",
            turned,
            SIZE,
            3,
            FRAME,
            Expect::Flat,
        );
        rig.case(&mut report, "turn back", a, SIZE, 3, FRAME, Expect::Valid);
        rig.case(
            &mut report,
            "zero-length frame time, still camera",
            a,
            SIZE,
            3,
            0.0,
            Expect::Valid,
        );
        let nudged = Camera {
            position: a.position + Vec3::new(0.05, 0.0, 0.0),
            ..a
        };
        rig.case(
            &mut report,
            "zero-length frame time, moving camera",
            nudged,
            SIZE,
            1,
            0.0,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "zero-length frame time, jump",
            jumped,
            SIZE,
            2,
            0.0,
            Expect::Flat,
        );

        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "degenerate geometry",
            degenerate_scene(),
            1.0,
            DepthFormat::Depth32Float,
        );
        // Only zero-area geometry stands on the floor: the view is an unoccluded plane.
        let at =
            |target: Vec3| perspective(target + Vec3::new(0.0, 2.0, 4.0), target, 0.05, 1000.0);
        rig.case(
            &mut report,
            "degenerate and collinear triangles, collapsed box, sliver",
            at(Vec3::ZERO),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "degenerate triangles at 97x61",
            at(Vec3::ZERO),
            Extent::new(97, 61),
            1,
            FRAME,
            Expect::Flat,
        );
        rig.case(
            &mut report,
            "coincident unwelded vertices with zero normals (platform)",
            at(Vec3::new(20.0, 0.0, 0.0)),
            SIZE,
            2,
            FRAME,
            Expect::Valid,
        );
        rig.case(
            &mut report,
            "coincident vertices, platform top only",
            perspective(
                Vec3::new(20.0, 1.0, 0.0),
                Vec3::new(20.0, 0.02, -0.5),
                0.05,
                1000.0,
            ),
            SIZE,
            2,
            FRAME,
            Expect::Flat,
        );
    }
    // The deepest pyramids at every size.
    for v in &deepest_pyramids() {
        let mut rig = Rig::new(
            &gpu,
            &mut report,
            v,
            "box-on-plane with island",
            box_scene(1.0, Vec3::ZERO, true, false),
            1.0,
            DepthFormat::Depth32Float,
        );
        for size in sizes {
            // The slivers (1x1, 2x3, 4096x8, 8x4096) may miss the contact: valid is enough there.
            let occluded = if size == SIZE || size == Extent::new(97, 61) {
                Expect::Occluded
            } else {
                Expect::Valid
            };
            rig.case(
                &mut report,
                "occluders",
                occluders(1.0, Vec3::ZERO),
                size,
                2,
                FRAME,
                occluded,
            );
            rig.case(
                &mut report,
                "island floor",
                island_view(),
                size,
                1,
                FRAME,
                Expect::Flat,
            );
            rig.case(
                &mut report,
                "plane at 89.9 degrees",
                grazing(1.0, Vec3::new(JUMP - 40.0, 0.0, 0.0)),
                size,
                1,
                FRAME,
                Expect::Flat,
            );
        }
    }
    // Per technique variant 40 cases (its rig and every case above); per deepest pyramid 19
    // (its rig and 6 sizes x 3).
    report.finish(
        "sizes_cameras_geometry_and_time",
        started,
        40 * variants().len() + 19 * deepest_pyramids().len(),
    );
}
