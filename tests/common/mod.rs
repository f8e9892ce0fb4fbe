//! Shared harness of the end-to-end tests: render a scene with a technique on the GPU at a
//! small size, trace the reference on the same g-buffer surfaces, and compare.
#![allow(dead_code)]

use std::sync::Arc;

use aograph::{FrameOutputs, ReferenceSettings, Renderer};
use aograph_ao::{AoConfig, TechniqueRegistry};
use aograph_graph::{Extent, test_gpu};
use aograph_scene::Scene;

/// One technique's result on one frame.
pub struct AoRun {
    pub ao: Vec<f32>,
    /// Linear depth (0 = sky).
    pub depth: Vec<f32>,
    pub renderer: Renderer,
}

/// An `[ao]` config for `technique` with parameters from a TOML snippet (may be empty).
pub fn ao_config(technique: &str, radius: f32, params_toml: &str) -> AoConfig {
    let mut c = AoConfig {
        technique: technique.into(),
        radius,
        ..AoConfig::default()
    };
    let table: toml::Table = params_toml.parse().expect("test params are valid TOML");
    c.params.insert(technique.into(), table);
    c
}

/// Renders `frames` frames (static time 0) of `scene` with `config`; `None` when the test must
/// skip because there is no GPU (never in CI).
pub fn render_ao(scene: Scene, config: &AoConfig, size: Extent, frames: u32) -> Option<AoRun> {
    let gpu = test_gpu()?;
    let registry = TechniqueRegistry::with_builtins();
    let outputs = FrameOutputs {
        linear_depth: true,
        ..Default::default()
    };
    let mut renderer = Renderer::new(
        gpu,
        aograph::shader_library(),
        &registry,
        Arc::new(scene),
        config,
        outputs,
        size,
    )
    .expect("frame graph builds");
    for _ in 0..frames {
        renderer.render(0.0).expect("frame renders");
    }
    let ao = renderer.read_ao().expect("ao reads back");
    let depth = renderer.read_linear_depth().expect("depth reads back");
    Some(AoRun {
        ao,
        depth,
        renderer,
    })
}

/// The reference for the run's last frame (binary mode), cached on disk.
pub fn reference(run: &AoRun, radius: f32, rays: u32) -> Vec<f32> {
    aograph::frame_reference(&run.renderer, &ReferenceSettings::new(radius, rays), false)
        .expect("reference traces")
        .accessibility
}

/// The world-space points and geometric normals of the run's last frame, from a g-buffer of
/// their own (the technique's renderer writes only what the technique reads).
pub fn surfaces(run: &AoRun) -> aograph_scene::SurfaceBuffer {
    let view = aograph::FrameView::of(&run.renderer);
    aograph::frame_reference::reference_surfaces(
        run.renderer.gpu.clone(),
        run.renderer.shaders.clone(),
        &view,
        aograph_scene::ReferenceNormals::Geometric,
    )
    .expect("surfaces render")
    .0
}

/// `plane` seen from `degrees` off its normal, 6 units from the origin (the self-occlusion
/// check every technique runs from straight down to grazing).
pub fn plane_at(degrees: f32) -> Scene {
    let mut scene = aograph_scene::procedural_scene("plane").expect("plane exists");
    let a = degrees.to_radians();
    scene.camera = aograph_scene::Camera::perspective(
        glam::Vec3::new(0.0, a.cos(), a.sin()) * 6.0,
        glam::Vec3::ZERO,
        50f32.to_radians(),
        0.05,
        2000.0,
    );
    scene
}

/// Mean absolute error over non-sky pixels.
pub fn mae(a: &[f32], b: &[f32], depth: &[f32]) -> f32 {
    let (sum, n) = a
        .iter()
        .zip(b)
        .zip(depth)
        .filter(|(_, d)| **d > 0.0)
        .fold((0.0f64, 0usize), |(s, n), ((x, y), _)| {
            (s + (x - y).abs() as f64, n + 1)
        });
    (sum / n.max(1) as f64) as f32
}

/// (pixels of `ao` below `threshold`, pixels of `reference` below it, pixels below it in both).
pub fn dark_overlap(ao: &[f32], reference: &[f32], threshold: f32) -> (usize, usize, usize) {
    let dark = ao.iter().filter(|a| **a < threshold).count();
    let dark_ref = reference.iter().filter(|a| **a < threshold).count();
    let both = ao
        .iter()
        .zip(reference)
        .filter(|(a, r)| **a < threshold && **r < threshold)
        .count();
    (dark, dark_ref, both)
}

/// Every value finite and within [0, 1]; sky pixels exactly 1.
pub fn assert_valid_ao(ao: &[f32], depth: &[f32], what: &str) {
    for (i, (v, d)) in ao.iter().zip(depth).enumerate() {
        assert!(
            v.is_finite() && (0.0..=1.0).contains(v),
            "{what}: pixel {i} = {v}"
        );
        if *d <= 0.0 {
            assert_eq!(*v, 1.0, "{what}: sky pixel {i} must be 1");
        }
    }
}

/// Mean of `ao` over non-sky pixels.
pub fn mean_over_geometry(ao: &[f32], depth: &[f32]) -> f32 {
    let (sum, n) = ao
        .iter()
        .zip(depth)
        .filter(|(_, d)| **d > 0.0)
        .fold((0.0f64, 0usize), |(s, n), (a, _)| (s + *a as f64, n + 1));
    (sum / n.max(1) as f64) as f32
}
