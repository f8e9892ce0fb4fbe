//! Ray by ray against the CPU tracer, on the compute BVH and on the acceleration structures,
//! and what each rebuilds per frame.

use aograph_scene::{PROCEDURAL_SCENE_NAMES, procedural_scene};
use aograph_tracing::gpu::{GpuSceneBvh, HardwareSceneAs};

use super::*;

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
    let Some(path) = aograph_scene::test_scene(
        "static_scene_builds_once_moving_instances_rebuild_only_the_top_level_skins_refit",
        "CesiumMan.glb",
    ) else {
        return;
    };
    let man = aograph_scene::load_scene(path).unwrap();
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
    use aograph_tracing::gpu::hardware::AsWork;
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
    let Some(path) = aograph_scene::test_scene(
        "hardware_static_scene_builds_once_moving_instances_rebuild_the_tlas_skins_their_blas",
        "CesiumMan.glb",
    ) else {
        return;
    };
    let man = aograph_scene::load_scene(path).unwrap();
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
