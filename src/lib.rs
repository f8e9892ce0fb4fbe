//! aograph's application layer, behind the `aograph` binary: config files and flags, scenes
//! prepared for a command (camera, radius), image output, the commands, the bench, tune and
//! metrics, and the viewer.
//!
//! Which crate owns what: the frame graph aograph renders, its `Renderer` and the reference of
//! its frames are `aograph-renderer` (re-exported here under their old paths); aograph's AO in
//! an application's own renderer is `aograph-embed`, which needs neither crate; techniques are
//! `aograph-ao`, scenes and tracers `aograph-scene`, the render graph `aograph-graph`. The
//! viewer (`aograph view`: winit, egui) is behind the default `viewer` feature.

pub mod bench;
pub mod camera_spec;
pub mod commands;
pub mod config;
pub mod error;
pub mod images;
pub mod metrics;
pub mod prepared_scene;
pub mod reach;
pub mod runtime_dir;
#[cfg(feature = "viewer")]
pub mod viewer;

pub use config::{AppConfig, RadiusSetting, SceneSource};
pub use error::{AppError, AppResult};
// aograph's own renderer lives in aograph-renderer; its modules keep their paths here.
pub use aograph_renderer::{
    FrameGraph, FrameOutputs, FrameView, PassOwner, PassOwners, ReferenceSettings, RenderError,
    Renderer, build_frame_graph, build_frame_graph_with, frame_graph, frame_reference, pass_owner,
    renderer, shader_dir, shader_library,
};
pub use prepared_scene::PreparedScene;

/// Loads a scene by procedural name or glTF path.
pub fn load_scene(source: &SceneSource) -> AppResult<aograph_scene::Scene> {
    Ok(match source {
        SceneSource::Procedural(name) => aograph_scene::procedural_scene(name)?,
        SceneSource::File(path) => aograph_scene::load_scene(path)?,
    })
}
