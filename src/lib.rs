//! The `aograph` command line: the commands (render, bench, tune, reference, montage, graph,
//! techniques, scene) and the viewer, over the library crates.
//!
//! Which crate owns what: run configuration, metrics, the bench and its reports are
//! `aograph-bench`; the frame graph aograph renders, its `Renderer` and the reference of its
//! frames are `aograph-renderer` (import them from there: this package re-exports nothing);
//! aograph's AO in an application's own renderer is `aograph-embed`, which needs neither;
//! techniques are `aograph-ao-passes`, scenes and tracers `aograph-scene`, the render graph
//! `aograph-graph`. The viewer (`aograph view`: winit, egui) is behind the default `viewer`
//! feature.

pub mod commands;
pub mod runtime_dir;
#[cfg(feature = "viewer")]
pub mod viewer;

/// Every WGSL file aograph has, for the CLI and its tests: the renderer's mounts
/// (`aograph_renderer::renderer_mounts`), the embedding's adapters, the bench's kernel and the
/// viewer's display (shaders/viewer/, this package's own), with the folder `AOGRAPH_SHADERS`
/// names (if set) shadowing them for hot edits.
pub fn shader_library() -> std::sync::Arc<aograph_graph::ShaderLibrary> {
    let lib = aograph_renderer::shader_library();
    for mount in [
        aograph_embed::shader_mount(),
        aograph_bench::shader_mount(),
        aograph_graph::ShaderMount::new("aograph").with_files(aograph_shaders::VIEWER),
    ] {
        lib.mount(mount)
            .expect("aograph's own mounts give each file once (tested)");
    }
    lib
}
