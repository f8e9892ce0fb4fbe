//! Where the workspace's tests, benches and examples find the real glTF files they load.
//!
//! A test scene is looked up in two places, in this order:
//!
//! 1. `tests/scenes/` in the repository: the files whose licences allow redistribution,
//!    vendored with their origin and licence (tests/scenes/README.md);
//! 2. `../shared/scenes/` beside the repository (as CI has it), which holds all of them;
//!    the environment variable `AOGRAPH_SHARED_SCENES` names another folder instead (for
//!    example a non-existent one, to see what a fresh clone without `../shared` does).
//!
//! A scene found in neither place is skipped with a printed reason, so that a fresh clone tests
//! itself, unless `AOGRAPH_REQUIRE_SCENES` is set (to anything but `0`): then the caller panics
//! naming the file. `.ci/run` sets it, so CI, which has `../shared`, cannot skip one. This is the
//! scenes' counterpart of `aograph_graph::test_gpu` (`AOGRAPH_REQUIRE_GPU`).
//!
//! Why it lives here, as public API of `aograph-scene`, rather than in a test-support module
//! included by `#[path]`: the root package's tests, examples and benches, and this crate's own
//! tests and benches, all depend on `aograph-scene` already, so one documented function serves
//! them all with no copy and no `#[allow(dead_code)]`; and `aograph_graph::test_gpu` set the
//! precedent of a test helper in a library's API. The folders are fixed when this crate is
//! compiled (from its `CARGO_MANIFEST_DIR`), so outside this repository's workspace nothing is
//! found and every caller skips.

use std::path::{Path, PathBuf};

/// Every test scene, by its path inside a scene folder. The vendored ones are `teapot.gltf`,
/// `CesiumMan.glb` and `FlightHelmet/FlightHelmet.gltf`; the others are only in
/// `../shared/scenes` (their terms do not allow redistribution, see tests/scenes/README.md).
pub const TEST_SCENES: [&str; 7] = [
    "teapot.gltf",
    "suzanne.gltf",
    "chinesedragon.gltf",
    "CesiumMan.glb",
    "FlightHelmet/FlightHelmet.gltf",
    "shadowscene_fire.gltf",
    "vulkanscene_shadow.gltf",
];

/// The repository's root (this crate lives in `crates/scene`).
fn repository() -> &'static Path {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest.parent().and_then(Path::parent).unwrap_or(manifest)
}

/// The folders a test scene is looked up in, in order: the repository's `tests/scenes`, then
/// `../shared/scenes` beside the repository (or the folder `AOGRAPH_SHARED_SCENES` names).
/// Either may be absent.
pub fn test_scene_dirs() -> [PathBuf; 2] {
    let beside = match std::env::var_os("AOGRAPH_SHARED_SCENES") {
        Some(dir) if !dir.is_empty() => PathBuf::from(dir),
        _ => repository()
            .parent()
            .unwrap_or(repository())
            .join("shared/scenes"),
    };
    [repository().join("tests/scenes"), beside]
}

/// The path of test scene `file` (a path inside a scene folder, e.g. `"teapot.gltf"` or
/// `"FlightHelmet/FlightHelmet.gltf"`): in the repository's `tests/scenes` if it is there, else
/// in `../shared/scenes` beside the repository (see the [module](self) documentation).
///
/// Found in neither: prints `SKIPPED: <needed_by> needs scene file <file>, ...` and returns
/// `None` (the caller skips what needs the file), unless `AOGRAPH_REQUIRE_SCENES` is set (to
/// anything but `0`), in which case it panics naming the file. `needed_by` names the test,
/// bench or example asking, for that message.
///
/// ```
/// if let Some(path) = aograph_scene::test_scene("a doc test", "teapot.gltf") {
///     let scene = aograph_scene::load_scene(path).unwrap();
///     assert!(scene.triangle_count() > 0);
/// }
/// ```
pub fn test_scene(needed_by: &str, file: &str) -> Option<PathBuf> {
    let [vendored, beside] = test_scene_dirs();
    if let Some(found) = [&vendored, &beside]
        .into_iter()
        .map(|dir| dir.join(file))
        .find(|path| path.is_file())
    {
        return Some(found);
    }
    if std::env::var_os("AOGRAPH_REQUIRE_SCENES").is_some_and(|v| v != "0") {
        panic!(
            "AOGRAPH_REQUIRE_SCENES is set but {needed_by} needs scene file {file}, which is \
             neither in {} nor in {}",
            vendored.display(),
            beside.display()
        );
    }
    let shared = if beside.is_dir() {
        format!("{} does not have it", beside.display())
    } else if std::env::var_os("AOGRAPH_SHARED_SCENES").is_some_and(|v| !v.is_empty()) {
        format!("{} (AOGRAPH_SHARED_SCENES) is absent", beside.display())
    } else {
        "../shared/scenes is absent".to_owned()
    };
    eprintln!(
        "SKIPPED: {needed_by} needs scene file {file}, which is not in the repository (not \
         redistributable) and {shared}; set AOGRAPH_REQUIRE_SCENES=1 to make this an error"
    );
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vendored_scenes_are_found_in_the_repository() {
        for file in [
            "teapot.gltf",
            "CesiumMan.glb",
            "FlightHelmet/FlightHelmet.gltf",
        ] {
            let path = test_scene("the_vendored_scenes_are_found_in_the_repository", file)
                .unwrap_or_else(|| panic!("{file} is vendored in tests/scenes"));
            assert!(
                path.starts_with(repository().join("tests/scenes")),
                "{file}"
            );
        }
        // The .gltf's external buffer travels with it.
        assert!(
            repository()
                .join("tests/scenes/FlightHelmet/FlightHelmet.bin")
                .is_file()
        );
    }
}
