//! Shared harness of the end-to-end tests: render a scene with a technique on the GPU at a
//! small size, trace the reference on the same g-buffer surfaces, and compare.
#![allow(dead_code)]

pub mod parity;
pub mod user_frame;

use std::sync::Arc;

use aograph_ao_passes::{AoConfig, TechniqueRegistry};
use aograph_graph::{Extent, test_gpu};
use aograph_renderer::FrameOutputs;
use aograph_renderer::ReferenceSettings;
use aograph_renderer::Renderer;
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
        radius: aograph_ao_passes::RadiusSetting::Units(
            aograph_ao_passes::Radius::new("R", radius).expect("test radii are positive"),
        ),
        ..AoConfig::default()
    };
    let table: toml::Table = params_toml.parse().expect("test params are valid TOML");
    c.params.insert(technique.into(), table);
    c
}

/// A renderer of `scene` with `config` at `size` that also outputs linear depth; `None` when
/// the test must skip because there is no GPU (never in CI).
pub fn renderer(scene: Scene, config: &AoConfig, size: Extent) -> Option<Renderer> {
    let outputs = FrameOutputs {
        linear_depth: true,
        ..Default::default()
    };
    renderer_with(scene, config, size, outputs)
}

/// [`renderer`] with the read-backs in `outputs`.
pub fn renderer_with(
    scene: Scene,
    config: &AoConfig,
    size: Extent,
    outputs: FrameOutputs,
) -> Option<Renderer> {
    let gpu = test_gpu()?;
    let registry = TechniqueRegistry::with_builtins();
    Some(
        Renderer::new(
            gpu,
            aograph::shader_library(),
            &registry,
            Arc::new(scene),
            config,
            outputs,
            size,
        )
        .expect("frame graph builds"),
    )
}

/// Renders `frames` frames (static time 0) of `scene` with `config`; `None` when the test must
/// skip because there is no GPU (never in CI).
pub fn render_ao(scene: Scene, config: &AoConfig, size: Extent, frames: u32) -> Option<AoRun> {
    let mut renderer = renderer(scene, config, size)?;
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
    aograph_renderer::frame_reference(&run.renderer, &ReferenceSettings::new(radius, rays), false)
        .expect("reference traces")
        .accessibility
}

/// The world-space points and geometric normals of the run's last frame, from a g-buffer of
/// their own (the technique's renderer writes only what the technique reads).
pub fn surfaces(run: &AoRun) -> aograph_scene::SurfaceBuffer {
    let view = aograph_renderer::FrameView::of(&run.renderer);
    aograph_renderer::frame_reference::reference_surfaces(
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

/// A pit whose walls lie on the cone of elevation `beta` around the origin: a flat floor disc
/// of radius `floor_radius` at y = 0, a vertical step at its rim up to the cone, and the cone
/// y = r tan β out to `outer`. Every wall point has elevation exactly β seen from the origin
/// (each facet's plane contains the origin; 256 segments keep the facets' bulge below 1e-4).
pub fn cone_pit(beta: f32, floor_radius: f32, outer: f32, tilt_degrees: f32) -> Scene {
    let mut b = aograph_scene::SceneBuilder::new();
    let material = b.material([0.8, 0.8, 0.8]);
    let mut mesh = aograph_scene::Mesh {
        name: "cone pit".into(),
        material,
        ..aograph_scene::Mesh::default()
    };
    let segments = 256;
    let t = beta.tan();
    let ring = |r: f32, y: f32, k: u32| {
        let a = std::f32::consts::TAU * k as f32 / segments as f32;
        glam::Vec3::new(r * a.cos(), y, r * a.sin())
    };
    for k in 0..segments {
        let (k0, k1) = (k, k + 1);
        let mid = std::f32::consts::TAU * (k as f32 + 0.5) / segments as f32;
        let inward = -glam::Vec3::new(mid.cos(), 0.0, mid.sin());
        push_triangle(
            &mut mesh,
            [
                glam::Vec3::ZERO,
                ring(floor_radius, 0.0, k0),
                ring(floor_radius, 0.0, k1),
            ],
            glam::Vec3::Y,
        );
        let (a, c) = (floor_radius, floor_radius * t);
        push_triangle(
            &mut mesh,
            [ring(a, 0.0, k0), ring(a, 0.0, k1), ring(a, c, k1)],
            inward,
        );
        push_triangle(
            &mut mesh,
            [ring(a, 0.0, k0), ring(a, c, k1), ring(a, c, k0)],
            inward,
        );
        let up = (inward * beta.sin() + glam::Vec3::Y * beta.cos()).normalize();
        let (p0, p1) = (ring(a, c, k0), ring(a, c, k1));
        let (q0, q1) = (ring(outer, outer * t, k0), ring(outer, outer * t, k1));
        push_triangle(&mut mesh, [p0, p1, q1], up);
        push_triangle(&mut mesh, [p0, q1, q0], up);
    }
    b.add(mesh, glam::Mat4::IDENTITY);
    let tilt = tilt_degrees.to_radians();
    b.build(aograph_scene::Camera::perspective(
        glam::Vec3::new(tilt.sin(), tilt.cos(), 0.0) * 4.0,
        glam::Vec3::ZERO,
        60f32.to_radians(),
        0.05,
        100.0,
    ))
}

/// Appends triangle `p` facing `normal` (reordered to be counter-clockwise seen from it).
pub fn push_triangle(mesh: &mut aograph_scene::Mesh, mut p: [glam::Vec3; 3], normal: glam::Vec3) {
    if (p[1] - p[0]).cross(p[2] - p[0]).dot(normal) < 0.0 {
        p.swap(1, 2);
    }
    let base = mesh.positions.len() as u32;
    mesh.positions.extend(p);
    mesh.normals.extend([normal; 3]);
    mesh.indices.extend([base, base + 1, base + 2]);
}

/// The centre pixel of an odd-sized image looks straight down the pit's axis: V = n.
pub fn centre_value(ao: &[f32], size: Extent) -> f32 {
    ao[(size.height / 2 * size.width + size.width / 2) as usize]
}

/// The Cornell box's floor pixels (y = 0, facing +Y) with x in `xs`, kept away from the back
/// wall's crease (z > -0.6): the bands SSDO's bounce is measured in.
pub fn cornell_floor_pixels(
    s: &aograph_scene::SurfaceBuffer,
    xs: std::ops::Range<f32>,
) -> Vec<usize> {
    (0..s.points.len())
        .filter(|&i| {
            let (p, n) = (s.points[i], s.normals[i]);
            s.valid[i] && p.y.abs() < 0.02 && n.y > 0.95 && xs.contains(&p.x) && p.z > -0.6
        })
        .collect()
}

/// The GPU ray tracer's backends `gpu` runs, as rtao's `tracer` spells them: compute always,
/// hardware where the device has ray queries. Without them the hardware path is skipped
/// (saying so), unless AOGRAPH_REQUIRE_RAY_QUERY=1 (CI) makes that a failure.
pub fn ray_tracers(gpu: &aograph_graph::GpuContext) -> Vec<&'static str> {
    if gpu.has_ray_queries() {
        return vec!["compute", "hardware"];
    }
    assert!(
        std::env::var("AOGRAPH_REQUIRE_RAY_QUERY").as_deref() != Ok("1"),
        "AOGRAPH_REQUIRE_RAY_QUERY=1 but {} has no ray queries",
        gpu.describe()
    );
    eprintln!(
        "skipping the hardware tracer: {} has no ray queries",
        gpu.describe()
    );
    vec!["compute"]
}
