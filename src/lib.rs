//! The `aograph` command line: the commands (render, bench, tune, reference, montage, graph,
//! techniques, scene) and the viewer, over the library crates.
//!
//! Which crate owns what: run configuration, metrics, the bench and its reports are
//! `aograph-bench`; the frame graph aograph renders, its `Renderer` and the reference of its
//! frames are `aograph-renderer` (both re-exported here under their old paths); aograph's AO in
//! an application's own renderer is `aograph-embed`, which needs neither; techniques are
//! `aograph-ao`, scenes and tracers `aograph-scene`, the render graph `aograph-graph`. The
//! viewer (`aograph view`: winit, egui) is behind the default `viewer` feature.

pub mod commands;
pub mod runtime_dir;
#[cfg(feature = "viewer")]
pub mod viewer;

// The measurement layer lives in aograph-bench and the renderer in aograph-renderer; their
// modules keep their paths here.
pub use aograph_bench::{
    AppConfig, AppError, AppResult, PreparedScene, RadiusSetting, SceneSource, bench, camera_spec,
    config, error, images, load_scene, metrics, prepared_scene, reach,
};
pub use aograph_renderer::{
    FrameGraph, FrameOutputs, FrameView, PassOwner, PassOwners, ReferenceSettings, RenderError,
    Renderer, build_frame_graph, build_frame_graph_with, frame_graph, frame_reference, pass_owner,
    renderer, shader_dir, shader_library,
};
