//! Files optimised by gltfpack load as their originals: a quantized copy (KHR_mesh_quantization,
//! gltfpack's default) and a meshopt-compressed copy (EXT_meshopt_compression, `-c`) of the
//! shared teapot and suzanne have the original's triangles, every vertex within the
//! quantization step of an original one, and the original's reference AO within its standard
//! error. The copies are made here by gltfpack (Debian package `gltfpack`, installed by
//! `scripts/ensure-gltfpack.sh`; `.ci/run` sets AOGRAPH_REQUIRE_GLTFPACK=1 so CI cannot skip).

mod common;

use aograph_scene::reference::{
    CpuGBuffer, ProgressMode, ReferenceMode, ReferenceNormals, ReferenceParams, TriangleBvh,
    trace_reference,
};
use aograph_scene::{Scene, import_gltf, load_scene, suggested_radius, test_scene};
use glam::Vec3;
use std::collections::HashMap;

/// Triangles with a non-zero area (gltfpack drops degenerate ones, which draw nothing).
fn drawn_triangles(scene: &Scene) -> usize {
    scene
        .world_triangles(0.0)
        .iter()
        .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length_squared() > 0.0)
        .count()
}

/// The farthest any vertex of `from` lies from the nearest vertex of `to` (a grid of `cell`
/// searched one cell around: exact for distances below `cell`, else reported as `cell`).
fn worst_vertex_distance(from: &Scene, to: &Scene, cell: f32) -> f32 {
    let key = |p: Vec3| (p / cell).floor().as_ivec3();
    let mut grid: HashMap<glam::IVec3, Vec<Vec3>> = HashMap::new();
    for p in to.world_triangles(0.0).iter().flatten() {
        grid.entry(key(*p)).or_default().push(*p);
    }
    let mut worst = 0.0f32;
    for p in from.world_triangles(0.0).iter().flatten() {
        let k = key(*p);
        let mut nearest = cell;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for q in grid
                        .get(&(k + glam::ivec3(dx, dy, dz)))
                        .into_iter()
                        .flatten()
                    {
                        nearest = nearest.min(p.distance(*q));
                    }
                }
            }
        }
        worst = worst.max(nearest);
    }
    worst
}

/// Mean reference accessibility over pixels both images cover, their difference's standard
/// error, and the share of pixels whose difference is within four standard errors.
fn reference_difference(original: &Scene, copy: &Scene) -> (f32, f32, f32, f32) {
    let camera = original.camera_at(0.0);
    let params = ReferenceParams {
        radius: suggested_radius(original).radius,
        rays_per_pixel: 64,
        mode: ReferenceMode::Binary,
        progress: ProgressMode::Never,
    };
    let trace = |scene: &Scene| {
        let surfaces =
            CpuGBuffer::trace(scene, &camera, 61, 43, 0.0).surfaces(ReferenceNormals::Geometric);
        let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
        (
            trace_reference(&bvh, &surfaces, &params).unwrap(),
            surfaces.valid,
        )
    };
    let ((a, valid_a), (b, valid_b)) = (trace(original), trace(copy));
    let both: Vec<usize> = (0..valid_a.len())
        .filter(|&i| valid_a[i] && valid_b[i])
        .collect();
    let n = both.len() as f32;
    let mean = |img: &[f32]| both.iter().map(|&i| img[i]).sum::<f32>() / n;
    let variance: f32 = both
        .iter()
        .map(|&i| a.std_error[i].powi(2) + b.std_error[i].powi(2))
        .sum::<f32>();
    let within = both
        .iter()
        .filter(|&&i| {
            let se = (a.std_error[i].powi(2) + b.std_error[i].powi(2)).sqrt();
            (a.accessibility[i] - b.accessibility[i]).abs() <= 4.0 * se + 1e-6
        })
        .count() as f32
        / n;
    (
        mean(&a.accessibility),
        mean(&b.accessibility),
        variance.sqrt() / n,
        within,
    )
}

/// The largest extent of `scene`'s world-space triangles.
fn extent(scene: &Scene) -> f32 {
    let (lo, hi) = (scene.world_triangles(0.0).iter().flatten())
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    (hi - lo).max_element()
}

/// Checks `copy` (gltfpack's `label`) against `original`: the same drawn triangles, every
/// vertex within half a quantization `step` per axis of one of the other's, and the same
/// reference AO within the standard error.
fn check_copy(label: &str, original: &Scene, copy: &Scene, step: f32) {
    assert_eq!(
        drawn_triangles(copy),
        drawn_triangles(original),
        "{label}: triangles"
    );
    // Half a step on each axis: sqrt(3)/2 steps at most, plus float rounding of the
    // dequantizing node transform (a 1e-3 step margin).
    let bound = step * (0.75f32.sqrt() + 1e-3);
    let worst = worst_vertex_distance(copy, original, 4.0 * step).max(worst_vertex_distance(
        original,
        copy,
        4.0 * step,
    ));
    let (ao_original, ao_copy, se, within) = reference_difference(original, copy);
    eprintln!(
        "{label}: {} triangles ({} in the original), worst vertex {worst:.3e} (step \
         {step:.3e}), reference AO {ao_copy:.4} vs {ao_original:.4} (SE {se:.1e}), {:.1}% of \
         pixels within 4 SE",
        copy.triangle_count(),
        original.triangle_count(),
        100.0 * within
    );
    assert!(
        worst <= bound,
        "{label}: a vertex moved {worst}, over {bound}"
    );
    // The same rays on the same pixels: the means differ by the geometry's change only,
    // which must stay inside three standard errors of the difference.
    assert!(
        (ao_original - ao_copy).abs() <= 3.0 * se,
        "{label}: reference AO {ao_copy} vs {ao_original}, 3 SE = {}",
        3.0 * se
    );
    assert!(within >= 0.99, "{label}: {within} of pixels within 4 SE");
}

/// The extension names a loaded copy reports.
fn extensions(import: &aograph_scene::GltfImport) -> Vec<&str> {
    (import.info.extensions.iter())
        .map(|e| e.name.as_str())
        .collect()
}

#[test]
fn quantized_and_meshopt_copies_load_as_their_originals() {
    let dir = common::temp_dir("gltfpack-copies");
    for scene_name in ["teapot", "suzanne"] {
        let Some(source) = test_scene(
            "quantized_and_meshopt_copies_load_as_their_originals",
            &format!("{scene_name}.gltf"),
        ) else {
            continue;
        };
        let original = load_scene(&source).unwrap();
        // gltfpack's default is 14-bit positions over the mesh's largest extent: one step is
        // extent / (2^14 - 1), and rounding moves each coordinate by at most half of it.
        let step = extent(&original) / 16383.0;
        for (kind, args) in [("quantized", &[][..]), ("meshopt", &["-c"][..])] {
            let copy_path = dir.join(format!("{scene_name}-{kind}.glb"));
            if common::gltfpack(&source, &copy_path, args).is_none() {
                return;
            }
            let label = format!("{scene_name} {kind}");
            let import = import_gltf(&copy_path).unwrap_or_else(|e| panic!("{label}: {e}"));
            let used = extensions(&import);
            assert!(used.contains(&"KHR_mesh_quantization"), "{label}: {used:?}");
            assert_eq!(
                used.contains(&"EXT_meshopt_compression"),
                kind == "meshopt",
                "{label}: {used:?}"
            );
            check_copy(&label, &original, &import.scene, step);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_instanced_copy_places_every_instance() {
    // gltfpack -mi writes the ten identical columns of `columns` as one EXT_mesh_gpu_instancing
    // node; every column must come back where it was.
    let dir = common::temp_dir("gltfpack-instanced");
    let source = dir.join("columns.glb");
    let mut original = aograph_scene::procedural_scene("columns").unwrap();
    aograph_scene::export_glb(&original, &source).unwrap();
    original = load_scene(&source).unwrap();
    let copy_path = dir.join("columns-instanced.glb");
    if common::gltfpack(&source, &copy_path, &["-mi"]).is_none() {
        return;
    }
    let import = import_gltf(&copy_path).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        extensions(&import).contains(&"EXT_mesh_gpu_instancing"),
        "{:?}",
        extensions(&import)
    );
    // Each mesh is quantized over its own extent, at most the scene's.
    check_copy(
        "columns instanced",
        &original,
        &import.scene,
        extent(&original) / 16383.0,
    );
    let _ = std::fs::remove_dir_all(&dir);
}
