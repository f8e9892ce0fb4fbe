//! The GPU ray tracer against the CPU one (`TriangleBvh` over `Scene::world_triangles`), ray by
//! ray: random triangle soups (instanced under rotations, non-uniform scales and mirrors) and
//! every procedural scene, closest-hit and any-hit. Hit or miss must agree on >= 99.99% of
//! rays and distances within 1e-5 relative. The only expected disagreements are rays grazing a
//! triangle edge within float rounding: the GPU tests an instanced ray in object space, the CPU
//! the transformed triangle in world space, so the two round differently there; every
//! disagreement is printed with its barycentric margin to show it is such a ray.
//! Then: the BVH work per frame (static: none; moving instances: the top level only; a
//! skinned mesh: its refit), the GPU after updates against the CPU at the new time, and the
//! GPU reference against the CPU reference (statistically: within 4 standard errors).

use std::path::PathBuf;
use std::sync::Arc;

use aograph_graph::{GpuContext, ShaderLibrary};
use aograph_scene::ray_tracing::{
    GpuRayBatch, GpuRayHit, GpuReferenceTracer, GpuSceneBvh, HardwareSceneAs, HitQuery, TraceRay,
};
use aograph_scene::reference::ProgressMode;
use aograph_scene::{
    CpuGBuffer, Mesh, PROCEDURAL_SCENE_NAMES, ReferenceMode, ReferenceNormals, ReferenceParams,
    Scene, SceneBuilder, TriangleBvh, procedural_scene, trace_reference,
};
use glam::{Mat4, Quat, Vec3};

fn shaders() -> ShaderLibrary {
    ShaderLibrary::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shaders"))
}

fn shared_scene(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/scenes"
    ))
    .join(name)
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vec(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        lo + (hi - lo) * Vec3::new(self.next(), self.next(), self.next())
    }
    fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec(Vec3::splat(-1.0), Vec3::ONE);
            if let Some(d) = v.try_normalize().filter(|_| v.length_squared() <= 1.0) {
                return d;
            }
        }
    }
}

fn soup(rng: &mut Rng, triangles: usize, extent: f32, size: f32) -> Mesh {
    let mut positions = Vec::new();
    for _ in 0..triangles {
        let c = rng.vec(Vec3::splat(-extent), Vec3::splat(extent));
        for _ in 0..3 {
            positions.push(c + rng.vec(Vec3::splat(-size), Vec3::splat(size)));
        }
    }
    Mesh {
        name: "soup".into(),
        indices: (0..positions.len() as u32).collect(),
        positions,
        normals: Vec::new(),
        material: 0,
        skin_weights: Vec::new(),
    }
}

/// Rays from random points in `bounds` grown by a fifth of its diagonal on every axis (so no
/// origin lies exactly on a flat scene's plane, where a hit at t = 0 = t_min is a tie either
/// tracer may break), two in three aimed at a point of the box, the others anywhere; t_max infinite for a third, else random within the
/// diagonal; t_min 0 or a little more.
fn random_rays(rng: &mut Rng, lo: Vec3, hi: Vec3, count: usize) -> Vec<TraceRay> {
    let diagonal = (hi - lo).length();
    let pad = Vec3::splat(diagonal * 0.2);
    (0..count)
        .map(|i| {
            let origin = rng.vec(lo - pad, hi + pad);
            // Two rays in three aim at a point of the scene's box, the rest anywhere.
            let direction = if i % 3 == 2 {
                rng.direction()
            } else {
                (rng.vec(lo, hi) - origin)
                    .try_normalize()
                    .unwrap_or(Vec3::Y)
            };
            TraceRay {
                origin: origin.into(),
                t_min: if i % 5 == 0 { 1e-3 * diagonal } else { 0.0 },
                direction: direction.into(),
                t_max: if i % 3 == 0 {
                    f32::INFINITY
                } else {
                    rng.next() * diagonal
                },
            }
        })
        .collect()
}

struct Agreement {
    rays: usize,
    /// Rays the CPU finds a hit for (closest-hit queries).
    hits: usize,
    hit_disagreements: usize,
    distance_disagreements: usize,
}

/// Traces `rays` both ways at scene time `t` and counts disagreements.
fn compare(
    gpu: &Arc<GpuContext>,
    batch: &GpuRayBatch,
    bvh: &GpuSceneBvh,
    scene: &Scene,
    t: f32,
    rays: &[TraceRay],
    label: &str,
) -> Agreement {
    let _ = gpu;
    let trace = |query| batch.trace(bvh, rays, query, 1).unwrap();
    compare_traced(&trace, scene, t, rays, label)
}

/// [`compare`] for any GPU tracer: `trace` answers `rays` for a query.
fn compare_traced(
    trace: &dyn Fn(HitQuery) -> Vec<Option<GpuRayHit>>,
    scene: &Scene,
    t: f32,
    rays: &[TraceRay],
    label: &str,
) -> Agreement {
    let cpu = TriangleBvh::new(&scene.world_triangles(t));
    let closest = trace(HitQuery::Closest);
    let any = trace(HitQuery::Any);
    let mut a = Agreement {
        rays: rays.len() * 2,
        hits: 0,
        hit_disagreements: 0,
        distance_disagreements: 0,
    };
    for (i, r) in rays.iter().enumerate() {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.direction));
        let want = cpu.closest_hit(o, d, r.t_min, r.t_max);
        a.hits += want.is_some() as usize;
        match (want, closest[i]) {
            (Some(w), Some(g)) => {
                // Relative 1e-5 of the larger of the distance and the origin's magnitude:
                // float points are known to their coordinates' ulp (6e-8 relative), and both
                // tracers round there, the CPU restarting each ray `lead` behind its origin
                // (reference/bvh.rs), the GPU moving it into object space. A larger
                // difference is a different triangle hit (edge-grazing rays; printed).
                let scale = w.distance.abs().max(o.abs().max_element());
                let rel = (w.distance - g.distance).abs() / scale.max(1e-30);
                if rel > 1e-5 {
                    a.distance_disagreements += 1;
                    eprintln!(
                        "{label}: ray {i} distance cpu {} gpu {} (rel {rel:e})",
                        w.distance, g.distance
                    );
                }
            }
            (None, None) => {}
            (w, g) => {
                a.hit_disagreements += 1;
                eprintln!("{label}: ray {i} {r:?}: cpu {w:?}, gpu {g:?}");
            }
        }
        let want_any = cpu.any_hit(o, d, r.t_min, r.t_max);
        if want_any != any[i].is_some() {
            a.hit_disagreements += 1;
            eprintln!("{label}: ray {i} any-hit cpu {want_any}, gpu {:?}", any[i]);
        }
    }
    a
}

fn assert_agrees(a: &Agreement, label: &str) {
    eprintln!(
        "{label}: {} rays, {} closest hits; {} hit/miss and {} distance disagreements",
        a.rays, a.hits, a.hit_disagreements, a.distance_disagreements
    );
    // The comparison means something only where rays hit things.
    assert!(
        a.hits * 4 >= a.rays / 2,
        "{label}: only {} of {} rays hit",
        a.hits,
        a.rays / 2
    );
    // 99.99% of rays: at most one disagreement in 10 000 (see the module docs for which).
    assert!(
        a.hit_disagreements * 10_000 <= a.rays,
        "{label}: hit/miss differs on {} of {} rays",
        a.hit_disagreements,
        a.rays
    );
    assert!(
        a.distance_disagreements * 10_000 <= a.rays,
        "{label}: distance differs by more than 1e-5 on {} of {} rays",
        a.distance_disagreements,
        a.rays
    );
}

/// Two random triangle soups placed five times: identity, rotation with non-uniform scale, a
/// mirror, a tiny and a large copy.
fn instanced_soups(rng: &mut Rng) -> Scene {
    let mut b = SceneBuilder::new();
    let dense = b.mesh(soup(rng, 3000, 2.0, 0.3));
    let sparse = b.mesh(soup(rng, 400, 5.0, 1.0));
    // Identity, rotation + non-uniform scale, a mirror, a tiny and a large copy.
    b.place(dense, Mat4::IDENTITY);
    b.place(
        dense,
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 0.5, 2.0),
            Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.3),
            Vec3::new(4.0, 0.0, -1.0),
        ),
    );
    b.place(
        dense,
        Mat4::from_translation(Vec3::new(-4.0, 1.0, 0.0))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    );
    b.place(sparse, Mat4::from_scale(Vec3::splat(0.01)));
    b.place(
        sparse,
        Mat4::from_translation(Vec3::new(0.0, 8.0, 0.0)) * Mat4::from_scale(Vec3::splat(3.0)),
    );
    b.build(aograph_scene::Camera::perspective(
        Vec3::new(0.0, 2.0, 12.0),
        Vec3::ZERO,
        0.8,
        0.1,
        100.0,
    ))
}

fn gpu_and_batch() -> Option<(Arc<GpuContext>, GpuRayBatch)> {
    let gpu = aograph_graph::test_gpu()?;
    let batch = GpuRayBatch::new(gpu.clone(), &shaders()).unwrap();
    Some((gpu, batch))
}

#[test]
fn gpu_agrees_with_cpu_on_random_soups_under_instance_transforms() {
    let Some((gpu, batch)) = gpu_and_batch() else {
        return;
    };
    let mut rng = Rng(7);
    let scene = instanced_soups(&mut rng);
    let bvh = GpuSceneBvh::new(gpu.clone(), &scene, 0.0).unwrap();
    assert_eq!(
        bvh.work.blas_builds, 2,
        "one bottom level per mesh, shared by its instances"
    );
    let bounds = scene.bounds();
    let rays = random_rays(&mut rng, bounds.min, bounds.max, 20_000);
    let a = compare(&gpu, &batch, &bvh, &scene, 0.0, &rays, "soups");
    assert_agrees(&a, "soups");
}

#[test]
fn gpu_agrees_with_cpu_on_every_procedural_scene() {
    let Some((gpu, batch)) = gpu_and_batch() else {
        return;
    };
    let mut rng = Rng(11);
    for name in PROCEDURAL_SCENE_NAMES {
        let scene = procedural_scene(name).unwrap();
        let bvh = GpuSceneBvh::new(gpu.clone(), &scene, 0.0).unwrap();
        let bounds = scene.bounds();
        let rays = random_rays(&mut rng, bounds.min, bounds.max, 5_000);
        let a = compare(&gpu, &batch, &bvh, &scene, 0.0, &rays, name);
        assert_agrees(&a, name);
    }
}

#[test]
fn static_scene_builds_once_moving_instances_rebuild_only_the_top_level_skins_refit() {
    let Some((gpu, batch)) = gpu_and_batch() else {
        return;
    };
    // Static: the build, then nothing, whatever the time.
    let columns = procedural_scene("columns").unwrap();
    let mut bvh = GpuSceneBvh::new(gpu.clone(), &columns, 0.0).unwrap();
    assert_eq!(bvh.work.tlas_builds, 1);
    assert!(bvh.work.blas_builds >= 1);
    let uploaded = bvh.bytes_uploaded;
    for t in [0.5, 1.0, 7.25] {
        assert!(
            bvh.update(&columns, t).unwrap().is_none(),
            "a static scene does nothing at t = {t}"
        );
    }
    assert_eq!(bvh.bytes_uploaded, uploaded, "and uploads nothing");

    // Rigid motion: one top-level rebuild per frame, no bottom level touched.
    let dynamic = procedural_scene("dynamic").unwrap();
    let mut bvh = GpuSceneBvh::new(gpu.clone(), &dynamic, 0.0).unwrap();
    let mut rng = Rng(3);
    for t in [0.3, 0.9] {
        let before = bvh.bytes_uploaded;
        let w = bvh.update(&dynamic, t).unwrap();
        eprintln!(
            "dynamic at t = {t}: {w:?}, {} bytes uploaded of {}",
            bvh.bytes_uploaded - before,
            bvh.bvh.sizes().total()
        );
        assert_eq!(
            (
                w.tlas_builds,
                w.blas_builds,
                w.blas_refits,
                w.triangles_written
            ),
            (1, 0, 0, 0)
        );
        let b = dynamic.bounds_at(t);
        let rays = random_rays(&mut rng, b.min, b.max, 4_000);
        assert_agrees(
            &compare(&gpu, &batch, &bvh, &dynamic, t, &rays, "dynamic"),
            "dynamic",
        );
    }

    // A skinned mesh: its bottom level refit (never rebuilt) and its triangles rewritten.
    let man = aograph_scene::load_scene(shared_scene("CesiumMan.glb")).unwrap();
    let mut bvh = GpuSceneBvh::new(gpu.clone(), &man, 0.0).unwrap();
    let skinned = man.instances.iter().filter(|i| i.skin.is_some()).count() as u32;
    assert!(skinned >= 1);
    for t in [0.4, 1.1] {
        let before = bvh.bytes_uploaded;
        let w = bvh.update(&man, t).unwrap();
        eprintln!(
            "man at t = {t}: {w:?}, {} bytes uploaded of {}",
            bvh.bytes_uploaded - before,
            bvh.bvh.sizes().total()
        );
        assert_eq!(
            (w.tlas_builds, w.blas_builds, w.blas_refits),
            (1, 0, skinned)
        );
        assert!(w.triangles_written > 0);
        let b = man.bounds_at(t);
        let rays = random_rays(&mut rng, b.min, b.max, 4_000);
        assert_agrees(
            &compare(&gpu, &batch, &bvh, &man, t, &rays, "CesiumMan"),
            "CesiumMan",
        );
    }
}

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

/// The GPU reference (compute BVH, or with `hardware` the acceleration structures) against
/// the CPU reference on three scenes: within 4 standard errors on 99 % of pixels, and, the
/// rays being the same rays, within one ray's worth on 99 % of pixels.
fn reference_matches_the_cpu(gpu: &Arc<GpuContext>, hardware: bool) {
    let tracer = GpuReferenceTracer::new(gpu.clone(), &shaders()).unwrap();
    let backend = if hardware { "hardware" } else { "compute" };
    for (name, mode, size) in [
        ("cornell-box", ReferenceMode::Binary, (45, 31)),
        ("columns", ReferenceMode::Obscurance, (40, 24)),
        ("room", ReferenceMode::Binary, (33, 20)),
    ] {
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
        rays_per_pixel: aograph_scene::ray_tracing::GPU_MAX_RAYS_PER_PIXEL + 1,
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

/// The device and the ray batch, when the device has ray queries (the batch then has its
/// hardware pipeline); without them the hardware tests skip (saying so), unless
/// AOGRAPH_REQUIRE_RAY_QUERY=1 (CI) makes that a failure.
fn hardware_batch() -> Option<(Arc<GpuContext>, GpuRayBatch)> {
    let gpu = aograph_graph::test_gpu()?;
    if !gpu.has_ray_queries() {
        let why = format!(
            "{} ({}) has no ray queries: scripts/ensure-vulkan.sh installs a lavapipe with them",
            gpu.info.name, gpu.info.driver_info
        );
        assert!(
            std::env::var("AOGRAPH_REQUIRE_RAY_QUERY").as_deref() != Ok("1"),
            "AOGRAPH_REQUIRE_RAY_QUERY=1 but {why}"
        );
        eprintln!("skipping the hardware tracer: {why}");
        return None;
    }
    let batch = GpuRayBatch::new(gpu.clone(), &shaders()).unwrap();
    Some((gpu, batch))
}

#[test]
fn hardware_agrees_with_cpu_on_random_soups_under_instance_transforms() {
    let Some((gpu, batch)) = hardware_batch() else {
        return;
    };
    let mut rng = Rng(7);
    let scene = instanced_soups(&mut rng);
    let accel = HardwareSceneAs::build(&gpu, &scene, 0.0).unwrap();
    assert_eq!(
        accel.work.blas_builds, 2,
        "one BLAS per mesh, shared by its instances"
    );
    let bounds = scene.bounds();
    let rays = random_rays(&mut rng, bounds.min, bounds.max, 20_000);
    let trace = |query| batch.trace(&accel, &rays, query, 1).unwrap();
    let a = compare_traced(&trace, &scene, 0.0, &rays, "hardware soups");
    assert_agrees(&a, "hardware soups");
}

#[test]
fn hardware_agrees_with_cpu_on_every_procedural_scene() {
    let Some((gpu, batch)) = hardware_batch() else {
        return;
    };
    let mut rng = Rng(11);
    for name in PROCEDURAL_SCENE_NAMES {
        let scene = procedural_scene(name).unwrap();
        let accel = HardwareSceneAs::build(&gpu, &scene, 0.0).unwrap();
        let bounds = scene.bounds();
        let rays = random_rays(&mut rng, bounds.min, bounds.max, 5_000);
        let label = format!("hardware {name}");
        let trace = |query| batch.trace(&accel, &rays, query, 1).unwrap();
        let a = compare_traced(&trace, &scene, 0.0, &rays, &label);
        assert_agrees(&a, &label);
    }
}

#[test]
fn hardware_static_scene_builds_once_moving_instances_rebuild_the_tlas_skins_their_blas() {
    let Some((gpu, batch)) = hardware_batch() else {
        return;
    };
    use aograph_scene::ray_tracing::hardware::AsWork;
    // Static: the build, then nothing, whatever the time.
    let columns = procedural_scene("columns").unwrap();
    let mut accel = HardwareSceneAs::build(&gpu, &columns, 0.0).unwrap();
    assert_eq!(accel.work.tlas_builds, 1);
    assert!(accel.work.blas_builds >= 1);
    for t in [0.5, 1.0, 7.25] {
        assert_eq!(
            accel.update(&gpu, &columns, t).unwrap(),
            AsWork::default(),
            "a static scene does nothing at t = {t}"
        );
    }
    // Rigid motion: the top level rebuilt, no bottom level; then it answers at the new time.
    let mut rng = Rng(5);
    let dynamic = procedural_scene("dynamic").unwrap();
    let mut accel = HardwareSceneAs::build(&gpu, &dynamic, 0.0).unwrap();
    for t in [0.3, 0.9] {
        let w = accel.update(&gpu, &dynamic, t).unwrap();
        assert_eq!(
            w,
            AsWork {
                blas_builds: 0,
                tlas_builds: 1
            },
            "dynamic at t = {t}"
        );
        let b = dynamic.bounds_at(t);
        let rays = random_rays(&mut rng, b.min, b.max, 4_000);
        let trace = |query| batch.trace(&accel, &rays, query, 1).unwrap();
        let label = format!("hardware dynamic at t = {t}");
        assert_agrees(&compare_traced(&trace, &dynamic, t, &rays, &label), &label);
    }
    // A skinned mesh: its own BLAS rebuilt from the posed vertices, and the top level.
    let man = aograph_scene::load_scene(shared_scene("CesiumMan.glb")).unwrap();
    let mut accel = HardwareSceneAs::build(&gpu, &man, 0.0).unwrap();
    let skinned = man.instances.iter().filter(|i| i.skin.is_some()).count() as u32;
    assert!(skinned >= 1);
    for t in [0.4, 1.1] {
        let w = accel.update(&gpu, &man, t).unwrap();
        assert_eq!(
            w,
            AsWork {
                blas_builds: skinned,
                tlas_builds: 1
            },
            "CesiumMan at t = {t}"
        );
        let b = man.bounds_at(t);
        let rays = random_rays(&mut rng, b.min, b.max, 4_000);
        let trace = |query| batch.trace(&accel, &rays, query, 1).unwrap();
        let label = format!("hardware CesiumMan at t = {t}");
        assert_agrees(&compare_traced(&trace, &man, t, &rays, &label), &label);
    }
}
