//! Every test scene (tests/scenes in the repository, else ../shared/scenes beside it: see
//! `aograph_scene::test_scene`) loads with the expected triangle count.

use aograph_scene::test_scenes::test_scene_dirs;
use aograph_scene::{Projection, TEST_SCENES, import_gltf, load_scene, test_scene};

/// (file, expected triangles, relative tolerance) from shared/scenes/README.md, which counts
/// each mesh once however many nodes place it.
const EXPECTED: &[(&str, usize, f64)] = &[
    ("teapot.gltf", 9_128, 0.0),
    ("suzanne.gltf", 15_744, 0.0),
    ("chinesedragon.gltf", 100_960, 0.0),
    ("CesiumMan.glb", 4_700, 0.1),
    ("FlightHelmet/FlightHelmet.gltf", 94_722, 0.0),
    ("shadowscene_fire.gltf", 3_104, 0.0),
    ("vulkanscene_shadow.gltf", 53_583, 0.0),
];

#[test]
fn every_shared_scene_loads_with_its_triangle_count() {
    for &(file, expected, tolerance) in EXPECTED {
        let Some(path) = test_scene("every_shared_scene_loads_with_its_triangle_count", file)
        else {
            continue;
        };
        let scene = load_scene(path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let count: usize = scene.meshes.iter().map(|m| m.triangle_count()).sum();
        eprintln!(
            "{file}: {count} mesh triangles, {} placed in {} instances",
            scene.triangle_count(),
            scene.instances.len()
        );
        let off = (count as f64 - expected as f64).abs() / expected as f64;
        assert!(
            off <= tolerance,
            "{file}: {count} triangles, README says {expected}"
        );
        let bounds = scene.bounds();
        assert!(
            !bounds.is_empty() && bounds.min.is_finite() && bounds.max.is_finite(),
            "{file}"
        );
        // No camera in these files: the outside view looks at the content's centre from where
        // its bounding sphere fills a 45-degree field of view (none of them is enclosed).
        let (centre, r) = (bounds.centre(), 0.5 * bounds.diagonal());
        let distance = scene.camera.position.distance(centre);
        let fit = r / (0.5 * aograph_scene::views::OUTSIDE_FOV_DEGREES.to_radians()).sin();
        assert!(
            (distance / fit - 1.0).abs() < 1e-3 && scene.camera.target.distance(centre) < 1e-3 * r,
            "{file}: camera at {distance}, the sphere fits at {fit}"
        );
        assert!(matches!(
            scene.camera.projection,
            Projection::Perspective { .. }
        ));
        for mesh in &scene.meshes {
            assert_eq!(
                mesh.normals.len(),
                mesh.positions.len(),
                "{file}: {}",
                mesh.name
            );
            assert!(
                mesh.indices
                    .iter()
                    .all(|&i| (i as usize) < mesh.positions.len())
            );
        }
    }
}

#[test]
fn instanced_meshes_are_placed_once_per_node() {
    // shadowscene_fire places 24 mesh nodes over 10 meshes (11 cylinders share one mesh, three
    // tori another, two tubes a third): 3,104 mesh triangles, 4,656 placed (counted from the
    // file's accessors).
    let Some(path) = test_scene(
        "instanced_meshes_are_placed_once_per_node",
        "shadowscene_fire.gltf",
    ) else {
        return;
    };
    let scene = load_scene(path).unwrap();
    assert_eq!(scene.instances.len(), 24);
    assert_eq!(scene.triangle_count(), 4_656);
}

#[test]
fn every_file_in_the_shared_folder_is_covered() {
    // The locator's list of scenes is the one counted here.
    let mut expected: Vec<&str> = EXPECTED.iter().map(|(name, ..)| *name).collect();
    let mut listed = TEST_SCENES.to_vec();
    expected.sort_unstable();
    listed.sort_unstable();
    assert_eq!(listed, expected, "aograph_scene::TEST_SCENES");
    // Each scene folder there is (the repository's tests/scenes, ../shared/scenes).
    for dir in test_scene_dirs().into_iter().filter(|d| d.is_dir()) {
        let mut found = Vec::new();
        for entry in std::fs::read_dir(&dir)
            .unwrap()
            .chain(std::fs::read_dir(dir.join("FlightHelmet")).unwrap())
        {
            let path = entry.unwrap().path();
            if matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("gltf" | "glb")
            ) {
                found.push(
                    path.strip_prefix(&dir)
                        .unwrap()
                        .to_string_lossy()
                        .replace('\\', "/"),
                );
            }
        }
        for file in &found {
            assert!(
                EXPECTED.iter().any(|(name, ..)| name == file),
                "{file} is in {} but has no expected triangle count here",
                dir.display()
            );
        }
    }
}

#[test]
fn flight_helmet_warns_about_its_missing_images_and_still_loads() {
    let Some(path) = test_scene(
        "flight_helmet_warns_about_its_missing_images_and_still_loads",
        "FlightHelmet/FlightHelmet.gltf",
    ) else {
        return;
    };
    let import = import_gltf(path).unwrap();
    let warning = import
        .warnings
        .iter()
        .find(|w| w.contains("image"))
        .expect("a warning about the missing images");
    assert!(warning.starts_with("15 referenced image"), "{warning}");
    assert_eq!(import.scene.meshes.len(), 5, "FlightHelmet has five meshes");
}

#[test]
fn cesium_man_is_upright_in_its_bind_pose() {
    let Some(path) = test_scene("cesium_man_is_upright_in_its_bind_pose", "CesiumMan.glb") else {
        return;
    };
    let scene = load_scene(path).unwrap();
    let size = scene.bounds().size();
    // The model is authored Z-up with a root rotation to glTF's Y-up: it should be taller than
    // it is deep.
    assert!(
        size.y > size.z && size.y > 1.0 && size.y < 2.5,
        "bounds size {size}"
    );
}
