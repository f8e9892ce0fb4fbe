//! aograph's application layer: config, the frame graph (g-buffer + technique + shading), the
//! renderer, image output and the commands behind the `aograph` binary. The viewer
//! (`aograph view`: winit, egui) is behind the default `viewer` feature; an application that
//! only wants aograph's AO in its own renderer depends on `aograph-embed`, which needs none of
//! this crate.

pub mod bench;
pub mod camera_spec;
pub mod commands;
pub mod config;
pub mod error;
pub mod frame_graph;
pub mod frame_reference;
pub mod images;
pub mod metrics;
pub mod pass_owner;
pub mod prepared_scene;
pub mod reach;
pub mod renderer;
pub mod runtime_dir;
#[cfg(feature = "viewer")]
pub mod viewer;

pub use config::{AppConfig, RadiusSetting, SceneSource};
pub use error::{AppError, AppResult};
pub use frame_graph::{FrameGraph, FrameOutputs, build_frame_graph, build_frame_graph_with};
pub use frame_reference::{FrameView, ReferenceSettings, frame_reference};
pub use pass_owner::{PassOwner, PassOwners};
pub use prepared_scene::PreparedScene;
pub use renderer::{Renderer, shader_dir, shader_library};

/// Loads a scene by procedural name or glTF path.
pub fn load_scene(source: &SceneSource) -> AppResult<aograph_scene::Scene> {
    Ok(match source {
        SceneSource::Procedural(name) => aograph_scene::procedural_scene(name)?,
        SceneSource::File(path) => aograph_scene::load_scene(path)?,
    })
}
