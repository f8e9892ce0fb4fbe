//! aograph's measurement layer, what `aograph bench`, `tune`, `render` and the viewer share
//! beyond the renderer: the run configuration (config files and flags: [`AppConfig`], named
//! cameras, the radius R, scenes prepared for a command), the error metrics against the
//! ray-traced reference ([`metrics`]: MAE, SSIM, edge bands, flicker, radiance), the bench
//! (runs, sweeps, statistics, results.csv, report.md, Pareto plots, roofline, motion bench)
//! and image output.
//!
//! Which crate owns what: `aograph-renderer` renders a scene's frames and their reference;
//! this crate configures runs of it and scores them; the `aograph` binary parses the command
//! line and calls the commands. None of it needs a window (no winit or egui).
//!
//! ```
//! use aograph_bench::metrics::ssim::{SsimParams, ssim};
//! // A metric on two images, no GPU needed: an image against itself scores SSIM 1.
//! let (w, h) = (32, 24);
//! let image: Vec<f32> = (0..w * h).map(|i| (i % 7) as f32 / 7.0).collect();
//! let everywhere = vec![true; (w * h) as usize];
//! let s = ssim(&image, &image, &everywhere, w, h, &SsimParams::PAPER);
//! assert!((s - 1.0).abs() < 1e-9);
//! ```

#![warn(missing_docs)]

pub mod bench;
pub mod camera_spec;
pub mod config;
pub mod error;
pub mod images;
pub mod metrics;
pub mod prepared_scene;
pub mod reach;
mod shader_mount;

pub use config::{AppConfig, RadiusSetting, SceneSource};
pub use error::{AppError, AppResult};
pub use prepared_scene::PreparedScene;
pub use shader_mount::shader_mount;

/// Loads a scene by procedural name or glTF path.
pub fn load_scene(source: &SceneSource) -> AppResult<aograph_scene::Scene> {
    Ok(match source {
        SceneSource::Procedural(name) => aograph_scene::procedural_scene(name)?,
        SceneSource::File(path) => aograph_scene::load_scene(path)?,
    })
}
