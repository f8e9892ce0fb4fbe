//! The WGSL this crate owns: shaders/render/ (the shaded view), compiled in, and the library
//! aograph's renderer runs on: the frame crate's common files, the techniques', the scene's
//! g-buffer and tracers', and this crate's.
//!
//! Invariant: nothing here reads a file, unless the developer sets `AOGRAPH_SHADERS` to a
//! shader folder for hot edits (its files shadow the compiled-in ones of the same name).

use std::sync::Arc;

use aograph_graph::{ShaderLibrary, ShaderMount};

/// shaders/render/.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-renderer")
        .with_files(aograph_shaders::RENDER)
        // The g-buffer node (crate::gbuffer) rasterises with shaders/scene/.
        .with_files(aograph_shaders::SCENE)
}

/// The mounts of everything aograph's renderer runs: frame, techniques, scene, renderer.
pub fn renderer_mounts() -> Vec<ShaderMount> {
    vec![
        aograph_frame::shader_mount(),
        aograph_ao_passes::shader_mount(),
        aograph_tracing::shader_mount(),
        shader_mount(),
    ]
}

/// A shader library over [`renderer_mounts`], with the folder `AOGRAPH_SHADERS` names (if set)
/// shadowing them for hot edits. Mount more (the application's technique) with
/// [`ShaderLibrary::mount`].
pub fn shader_library() -> Arc<ShaderLibrary> {
    let lib = ShaderLibrary::from_mounts(renderer_mounts())
        .expect("aograph's own mounts give each file once (tested)");
    Arc::new(match std::env::var_os("AOGRAPH_SHADERS") {
        Some(dir) if !dir.is_empty() => lib.with_directory_override(dir),
        _ => lib,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_renderer_library_mounts_every_folder_but_the_apps_once() {
        let lib = super::shader_library();
        let files = lib.files();
        for folder in [
            "common/",
            "ao/",
            "blocks/",
            "scene/",
            "raytrace/",
            "render/",
        ] {
            assert!(files.iter().any(|f| f.starts_with(folder)), "{folder}");
        }
        assert!(
            !files
                .iter()
                .any(|f| f.starts_with("embed/") || f.starts_with("viewer/"))
        );
    }
}
