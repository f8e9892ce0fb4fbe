//! Ray throughput of the CPU reference on the default `columns` scene.
//!
//! Measures one reference tile (default 128x128 pixels x 64 rays, binary mode, R = 1) and
//! reports rays per second (criterion's "elements/s"; only rays from valid, non-sky pixels are
//! counted). Change the tile with AOGRAPH_BENCH_SIZE (pixels per side) and AOGRAPH_BENCH_RAYS.
//! A full 512x512 x 256 run is the ignored test `columns_full_resolution_throughput`.
//! The same tile is traced by the GPU reference (`ray_tracing::GpuReferenceTracer`, suffix
//! `_gpu`) when a device exists, so CPU and GPU rays per second come from one run; then the
//! GPU BVH's build and per-frame update (a static scene: nothing; `dynamic`: the top level;
//! CesiumMan: the skinned bottom level's refit and the top level).
//! Then the three tracers on one batch of AO-like rays (`ray_batch`, any-hit, t_max = R: from
//! the tile's surface points, cosine-distributed): the CPU BVH, the GPU compute BVH and, where
//! the device has ray queries, the hardware acceleration structures (rays per second each),
//! and their per-frame update on `dynamic` and CesiumMan.

use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    ReferenceMode, ReferenceParams, TriangleBvh, primary_hits, procedural_scene, trace_reference,
};
use aograph_tracing::gpu::{
    GpuRayBatch, GpuReferenceTracer, GpuSceneBvh, HardwareSceneAs, HitQuery, SceneBvh, TraceRay,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn env_u32(name: &str, default: u32) -> u32 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .filter(|&v| v > 0)
        .unwrap_or(default)
}

fn reference_throughput(c: &mut Criterion) {
    let size = env_u32("AOGRAPH_BENCH_SIZE", 128);
    let rays = env_u32("AOGRAPH_BENCH_RAYS", 64);
    let scene = procedural_scene("columns").expect("columns is a built-in scene");
    let triangles = scene.world_triangles(0.0);
    let bvh = TriangleBvh::new(&triangles);
    let surfaces = primary_hits(&scene, &scene.camera, size, size, 0.0);
    let params = ReferenceParams {
        radius: 1.0,
        rays_per_pixel: rays,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Never,
    };
    let mut group = c.benchmark_group("reference");
    group.sample_size(10);
    group.throughput(Throughput::Elements(
        surfaces.valid_count() as u64 * u64::from(rays),
    ));
    group.bench_function(format!("columns_{size}x{size}x{rays}_binary"), |b| {
        b.iter(|| trace_reference(black_box(&bvh), black_box(&surfaces), &params))
    });
    let obscurance = ReferenceParams {
        mode: ReferenceMode::Obscurance,
        ..params
    };
    group.bench_function(format!("columns_{size}x{size}x{rays}_obscurance"), |b| {
        b.iter(|| trace_reference(black_box(&bvh), black_box(&surfaces), &obscurance))
    });
    if let Some(gpu) = aograph_graph::test_gpu() {
        let shaders = aograph_tracing::shader_library().expect("aograph's mounts");
        let tracer = GpuReferenceTracer::new(gpu.clone(), &shaders).expect("pipeline");
        let gpu_bvh = GpuSceneBvh::new(gpu.clone(), &scene, 0.0).expect("BVH fits");
        for (mode, p) in [("binary", params), ("obscurance", obscurance)] {
            group.bench_function(format!("columns_{size}x{size}x{rays}_{mode}_gpu"), |b| {
                b.iter(|| tracer.trace(&gpu_bvh, black_box(&surfaces), &p))
            });
        }
    }
    group.finish();
    ray_batch(c, &scene, &surfaces);
    c.bench_function("bvh_build_columns", |b| {
        b.iter(|| TriangleBvh::new(black_box(&triangles)))
    });
    c.bench_function("gpu_bvh_build_columns", |b| {
        b.iter(|| SceneBvh::build(black_box(&scene), 0.0))
    });
    let dynamic = procedural_scene("dynamic").expect("built-in scene");
    let mut moving = vec![("dynamic", dynamic)];
    if let Some(path) = aograph_scene::test_scene("the reference bench", "CesiumMan.glb") {
        let man = aograph_scene::load_scene(path).expect("CesiumMan loads");
        moving.push(("cesium_man", man));
    }
    let gpu = aograph_graph::test_gpu().filter(|g| g.has_ray_queries());
    for (name, s) in moving {
        let (mut bvh, _) = SceneBvh::build(&s, 0.0).expect("builds");
        let mut t = 0.0f32;
        c.bench_function(&format!("gpu_bvh_update_{name}"), |b| {
            b.iter(|| {
                t += 1.0 / 60.0;
                bvh.update(black_box(&s), t).expect("updates")
            })
        });
        // The hardware structures' per-frame work: the TLAS rebuilt, skins' BLAS rebuilt
        // (recorded and submitted; the device builds them before the next trace).
        if let Some(gpu) = &gpu {
            let mut accel = HardwareSceneAs::build(gpu, &s, 0.0).expect("builds");
            let mut t = 0.0f32;
            c.bench_function(&format!("hardware_as_update_{name}"), |b| {
                b.iter(|| {
                    t += 1.0 / 60.0;
                    accel.update(gpu, black_box(&s), t).expect("updates")
                })
            });
        }
    }
}

/// AO-like rays of R = 1 from every valid surface point of the tile, four per point in fixed
/// directions around its normal (a deterministic, cosine-leaning set).
fn ao_rays(surfaces: &aograph_scene::SurfaceBuffer) -> Vec<TraceRay> {
    let mut rays = Vec::new();
    for i in 0..surfaces.points.len() {
        if !surfaces.valid[i] {
            continue;
        }
        let (p, n) = (surfaces.points[i], surfaces.normals[i].normalize_or_zero());
        let t = n.any_orthonormal_vector();
        let b = n.cross(t);
        for k in 0..4 {
            let phi = std::f32::consts::FRAC_PI_2 * k as f32 + 0.3;
            let d = (n * 0.8 + (t * phi.cos() + b * phi.sin()) * 0.6).normalize();
            rays.push(TraceRay {
                origin: (p + n * 1e-4).to_array(),
                t_min: 0.0,
                direction: d.to_array(),
                t_max: 1.0,
            });
        }
    }
    rays
}

/// The three tracers on the same any-hit rays: CPU (obvhs, rayon), GPU compute, hardware.
fn ray_batch(
    c: &mut Criterion,
    scene: &aograph_scene::Scene,
    surfaces: &aograph_scene::SurfaceBuffer,
) {
    use rayon::prelude::*;
    let rays = ao_rays(surfaces);
    let triangles = scene.world_triangles(0.0);
    let cpu = TriangleBvh::new(&triangles);
    let mut group = c.benchmark_group("ray_batch");
    group.sample_size(10);
    group.throughput(Throughput::Elements(rays.len() as u64));
    group.bench_function("columns_any_hit_cpu", |b| {
        b.iter(|| {
            rays.par_iter()
                .filter(|r| cpu.any_hit(r.origin.into(), r.direction.into(), r.t_min, r.t_max))
                .count()
        })
    });
    if let Some(gpu) = aograph_graph::test_gpu() {
        let shaders = aograph_tracing::shader_library().expect("aograph's mounts");
        let compute = GpuRayBatch::new(gpu.clone(), &shaders).expect("pipeline");
        let bvh = GpuSceneBvh::new(gpu.clone(), scene, 0.0).expect("BVH fits");
        group.bench_function("columns_any_hit_compute", |b| {
            b.iter(|| compute.trace(&bvh, black_box(&rays), HitQuery::Any, 1))
        });
        if gpu.has_ray_queries() {
            let accel = HardwareSceneAs::build(&gpu, scene, 0.0).expect("builds");
            group.bench_function("columns_any_hit_hardware", |b| {
                b.iter(|| compute.trace(&accel, black_box(&rays), HitQuery::Any, 1))
            });
            group.bench_function("columns_as_build_hardware", |b| {
                b.iter(|| HardwareSceneAs::build(&gpu, black_box(scene), 0.0))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, reference_throughput);
criterion_main!(benches);
