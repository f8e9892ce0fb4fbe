//! `aograph view`: an interactive viewer over the same frame graph as `render` and `bench`.
//! Techniques swap live in one executor (plans seen before come back with their pipelines),
//! parameters get controls generated from each technique's specs, per-pass times show as bars,
//! and the ray-traced reference of the current view is traced on a background thread and shown
//! beside the technique or as a signed-error heat map. `--script FILE` drives it for tests and
//! demos (see `script.rs`).
//!
//! Modules: `session` (state and changes, no window), `display` (the picture as a graph pass),
//! `reference_worker`, `camera_control`, `panel` (egui; parameter controls from each
//! technique's descriptions),
//! `script`, `save` (settings as a config), `app` (the window and frame loop).

mod app;
mod camera_control;
mod display;
mod panel;
mod reference_worker;
mod save;
mod script;
mod session;

use std::path::PathBuf;

use aograph_graph::Extent;

pub use display::DisplayMode;
pub use script::Script;
pub use session::Session;

use aograph_app_config::AppConfig;
use aograph_app_config::error::{AppError, AppResult};

/// What to do when there is no display.
pub const NO_DISPLAY_FIX: &str = "an X11 display: set DISPLAY, or on a machine without one run \
     the viewer under a virtual display, `xvfb-run -a aograph view ...` (Debian/Ubuntu package \
     xvfb), e.g. with `--script` to take screenshots";

/// What the viewer opens: a run configuration (resolved by whoever starts it: the command
/// line's flags over a config file), a window size, and a script to run.
#[derive(Clone, Debug, Default)]
pub struct ViewArgs {
    /// The scene, technique, radius and views.
    pub config: AppConfig,
    /// The window's size in pixels, when one was asked for (`None`: the viewer's own).
    pub size: Option<Extent>,
    /// A script of actions and screenshots (`--script`).
    pub script: Option<PathBuf>,
}

/// Opens the viewer and runs it until the window closes or the script quits.
pub fn view(args: &ViewArgs) -> AppResult<()> {
    let config = args.config.clone();
    let script = args.script.as_deref().map(Script::load).transpose()?;
    let size = args.size;
    if std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        return Err(AppError::InvalidArgument {
            name: "display".into(),
            value: "none (DISPLAY is not set)".into(),
            allowed: NO_DISPLAY_FIX.into(),
        });
    }
    let event_loop =
        winit::event_loop::EventLoop::new().map_err(|e| AppError::InvalidArgument {
            name: "display".into(),
            value: format!("cannot be opened ({e})"),
            allowed: NO_DISPLAY_FIX.into(),
        })?;
    let mut app = app::ViewerApp::new(app::ViewerOptions {
        config,
        size,
        script,
    });
    event_loop
        .run_app(&mut app)
        .map_err(|e| AppError::InvalidArgument {
            name: "window".into(),
            value: e.to_string(),
            allowed: NO_DISPLAY_FIX.into(),
        })?;
    app.result
}
