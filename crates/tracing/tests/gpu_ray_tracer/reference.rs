//! The GPU reference (compute and hardware) against the CPU reference, its bands, and its
//! limit on rays.

use std::sync::Arc;

use aograph_graph::GpuContext;
use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    CpuGBuffer, ReferenceMode, ReferenceNormals, ReferenceParams, TriangleBvh, procedural_scene,
    trace_reference,
};
use aograph_tracing::gpu::{GpuReferenceTracer, GpuSceneBvh, HardwareSceneAs};

use super::*;

/// Pixels whose GPU and CPU estimates differ by more than 4 combined standard errors.
fn outliers(a: &aograph_scene::ReferenceImage, b: &aograph_scene::ReferenceImage) -> usize {
    a.accessibility
        .iter()
        .zip(&b.accessibility)
        .zip(a.std_error.iter().zip(&b.std_error))
        .filter(|((x, y), (sx, sy))| {
            // Identical rays give near-identical estimates; the floor covers rounding where
            // the standard error is 0 (fully open or fully closed pixels).
            (*x - *y).abs() > 4.0 * (*sx * *sx + *sy * *sy).sqrt() + 1e-4
        })
        .count()
}

#[test]
fn gpu_reference_matches_the_cpu_reference_within_four_standard_errors() {
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    reference_matches_the_cpu(&gpu, false);
}

#[test]
fn hardware_reference_matches_the_cpu_reference_within_four_standard_errors() {
    let Some((gpu, _)) = hardware_batch() else {
        return;
    };
    reference_matches_the_cpu(&gpu, true);
}

/// The scenes both comparisons trace: (name, mode, size).
const SCENES: [(&str, ReferenceMode, (u32, u32)); 3] = [
    ("cornell-box", ReferenceMode::Binary, (45, 31)),
    ("columns", ReferenceMode::Obscurance, (40, 24)),
    ("room", ReferenceMode::Binary, (33, 20)),
];

/// The GPU reference (compute BVH, or with `hardware` the acceleration structures) against
/// the CPU reference on three scenes: within 4 standard errors on 99 % of pixels, and, the
/// rays being the same rays, within one ray's worth on 99 % of pixels.
fn reference_matches_the_cpu(gpu: &Arc<GpuContext>, hardware: bool) {
    let backend = if hardware { "hardware" } else { "compute" };
    for (name, mode, size) in SCENES {
        let (surfaces, params, cpu, gpu_image) = both_references(gpu, hardware, name, mode, size);
        let name = format!("{name} ({backend})");
        assert_eq!(gpu_image.accessibility.len(), cpu.accessibility.len());
        let bad = outliers(&gpu_image, &cpu);
        let pixels = cpu.accessibility.len();
        assert!(
            bad * 100 <= pixels,
            "{name}: {bad} of {pixels} pixels beyond 4 SE"
        );
        // Stronger, because the rays are the same rays: on 99% of pixels at most one of the
        // 64 rays may answer differently (a ray grazing an edge), so the estimates differ
        // by at most 1/64 (plus float rounding of the sums).
        let one_ray = 1.0 / params.rays_per_pixel as f32 + 1e-5;
        let differing = (gpu_image.accessibility.iter())
            .zip(&cpu.accessibility)
            .filter(|(g, c)| (*g - *c).abs() > one_ray)
            .count();
        eprintln!(
            "{name}: {bad} pixels beyond 4 SE, {differing} differing by more than one ray, of {pixels}"
        );
        assert!(
            differing * 100 <= pixels,
            "{name}: {differing} of {pixels} pixels differ by more than one ray"
        );
        // Sky is exactly 1 with error 0 on both.
        for i in 0..pixels {
            if !surfaces.valid[i] {
                assert_eq!(
                    (gpu_image.accessibility[i], gpu_image.std_error[i]),
                    (1.0, 0.0)
                );
            }
        }
    }
}

/// The CPU reference and the GPU one (compute, or `hardware`) of scene `name`'s camera, on the
/// same rays: (surfaces, parameters, CPU image, GPU image).
fn both_references(
    gpu: &Arc<GpuContext>,
    hardware: bool,
    name: &str,
    mode: ReferenceMode,
    size: (u32, u32),
) -> (
    aograph_scene::SurfaceBuffer,
    ReferenceParams,
    aograph_scene::ReferenceImage,
    aograph_scene::ReferenceImage,
) {
    let tracer = GpuReferenceTracer::new(gpu.clone(), &shaders()).unwrap();
    let scene = procedural_scene(name).unwrap();
    let camera = scene.camera_at(0.0);
    let surfaces = CpuGBuffer::trace(&scene, &camera, size.0, size.1, 0.0)
        .surfaces(ReferenceNormals::Geometric);
    let params = ReferenceParams {
        radius: aograph_scene::suggested_radius(&scene).radius,
        rays_per_pixel: 64,
        mode,
        progress: ProgressMode::Never,
    };
    let cpu = trace_reference(
        &TriangleBvh::new(&scene.world_triangles(0.0)),
        &surfaces,
        &params,
    )
    .unwrap();
    let gpu_image = if hardware {
        let accel = HardwareSceneAs::build(gpu, &scene, 0.0).unwrap();
        tracer.trace(&accel, &surfaces, &params).unwrap()
    } else {
        let bvh = GpuSceneBvh::new(gpu.clone(), &scene, 0.0).unwrap();
        tracer.trace(&bvh, &surfaces, &params).unwrap()
    };
    (surfaces, params, cpu, gpu_image)
}

#[test]
fn gpu_standard_errors_equal_the_cpu_ones_for_the_same_rays() {
    for hardware in [false, true] {
        let gpu = if hardware {
            match hardware_batch() {
                Some((gpu, _)) => gpu,
                None => continue,
            }
        } else {
            match aograph_graph::test_gpu() {
                Some(gpu) => gpu,
                None => return,
            }
        };
        let backend = if hardware { "hardware" } else { "compute" };
        for (name, mode, size) in SCENES {
            let (_, _, cpu, gpu_image) = both_references(&gpu, hardware, name, mode, size);
            let name = format!("{name} ({backend})");
            let pixels = cpu.accessibility.len();
            // The standard errors, pixel by pixel: where every ray answered alike (the estimates
            // agree to rounding), both tracers summed the same samples, so sqrt(s^2 / N) must
            // agree to rounding too. A tracer reporting sqrt(s^2), or dividing by N twice, is off
            // by a factor of 8 (N = 64) on every partly occluded pixel.
            let (mut compared, mut partly_occluded) = (0, 0);
            for i in 0..pixels {
                let (g, c) = (gpu_image.accessibility[i], cpu.accessibility[i]);
                if (g - c).abs() > 1e-5 {
                    continue;
                }
                compared += 1;
                let (sg, sc) = (gpu_image.std_error[i], cpu.std_error[i]);
                partly_occluded += (sc > 0.0) as usize;
                // f32 sums of 64 samples on the GPU against the CPU's: relative 1e-4, and 1e-6
                // absolute where the error is 0.
                assert!(
                    (sg - sc).abs() <= 1e-4 * sc + 1e-6,
                    "{name}: pixel {i} (accessibility {c}): standard error {sg} on the GPU, \
                     {sc} on the CPU"
                );
            }
            eprintln!(
                "{name}: standard errors equal on {compared} pixels ({partly_occluded} partly occluded)"
            );
            assert!(
                compared * 10 >= pixels * 9 && partly_occluded * 10 >= pixels,
                "{name}: only {compared} pixels ({partly_occluded} partly occluded) of {pixels} to compare"
            );
        }
    }
}

#[test]
fn gpu_reference_bands_traced_one_by_one_make_exactly_the_whole_image() {
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    let tracer = GpuReferenceTracer::new(gpu.clone(), &shaders()).unwrap();
    let scene = procedural_scene("columns").unwrap();
    let surfaces = CpuGBuffer::trace(&scene, &scene.camera_at(0.0), 29, 17, 0.0)
        .surfaces(ReferenceNormals::Geometric);
    let params = ReferenceParams {
        radius: aograph_scene::suggested_radius(&scene).radius,
        rays_per_pixel: 16,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Never,
    };
    let bvh = GpuSceneBvh::new(gpu, &scene, 0.0).unwrap();
    let whole = tracer.trace(&bvh, &surfaces, &params).unwrap();
    let mut bands = Vec::new();
    for y in (0..17).step_by(5) {
        let band = tracer
            .trace_rows(&bvh, &surfaces, &params, y..y + 5)
            .unwrap();
        assert_eq!(band.height, 5.min(17 - y));
        bands.extend(band.accessibility);
    }
    assert_eq!(bands, whole.accessibility);
}

#[test]
fn the_gpu_reference_refuses_more_rays_than_its_f32_sums_hold_naming_the_limit() {
    let Some(gpu) = aograph_graph::test_gpu() else {
        return;
    };
    let tracer = GpuReferenceTracer::new(gpu.clone(), &shaders()).unwrap();
    let scene = procedural_scene("plane").unwrap();
    let surfaces = CpuGBuffer::trace(&scene, &scene.camera_at(0.0), 4, 3, 0.0)
        .surfaces(ReferenceNormals::Geometric);
    let bvh = GpuSceneBvh::new(gpu, &scene, 0.0).unwrap();
    let params = ReferenceParams {
        rays_per_pixel: aograph_tracing::gpu::GPU_MAX_RAYS_PER_PIXEL + 1,
        progress: ProgressMode::Never,
        ..ReferenceParams::default()
    };
    let e = tracer
        .trace(&bvh, &surfaces, &params)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rays_per_pixel = 4097") && e.contains("1 to 4096"),
        "{e}"
    );
}
