//! aograph's run configuration, what every command and the viewer start from: config files
//! and their flags ([`AppConfig`]: scene, technique and `[ao]` table, size, views, reference
//! settings), named cameras and inline ones ([`camera_spec`]), the scene prepared for a
//! command with its views and radius R ([`PreparedScene`]), and the one error type of the
//! application layer ([`AppError`]), which every lower crate's error converts into.
//!
//! Which crate owns what: `aograph-renderer` renders frames; this crate says which frames a
//! command asks for; `aograph-bench` measures them; the `aograph` binary parses the command
//! line. Nothing here needs a device.
//!
//! ```
//! use aograph_app_config::{AppConfig, SceneSource};
//! let registry = aograph_ao_passes::TechniqueRegistry::with_builtins();
//! let text = "[scene]\nname = \"columns\"\n[output]\nwidth = 320\nheight = 180\n[ao]\ntechnique = \"gtao\"\n";
//! let config = AppConfig::parse(text, "example.toml", &registry)?;
//! assert_eq!(config.scene, SceneSource::Procedural("columns".into()));
//! assert_eq!((config.width, config.height), (320, 180));
//! # Ok::<(), aograph_app_config::AppError>(())
//! ```

#![warn(missing_docs)]

pub mod camera_spec;
pub mod config;
pub mod error;
pub mod prepared_scene;

pub use config::{AppConfig, RadiusSetting, SceneSource};
pub use error::{AppError, AppResult};
pub use prepared_scene::PreparedScene;

/// Loads a scene by procedural name or glTF path.
pub fn load_scene(source: &SceneSource) -> AppResult<aograph_scene::Scene> {
    Ok(match source {
        SceneSource::Procedural(name) => aograph_scene::procedural_scene(name)?,
        SceneSource::File(path) => aograph_scene::load_scene(path)?,
    })
}
