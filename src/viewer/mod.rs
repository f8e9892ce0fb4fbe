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

use aograph_ao_passes::TechniqueRegistry;
use aograph_graph::Extent;

pub use display::DisplayMode;
pub use script::Script;
pub use session::Session;

use crate::commands::CommonArgs;
use crate::error::{AppError, AppResult};

/// What to do when there is no display.
pub const NO_DISPLAY_FIX: &str = "an X11 display: set DISPLAY, or on a machine without one run \
     the viewer under a virtual display, `xvfb-run -a aograph view ...` (Debian/Ubuntu package \
     xvfb), e.g. with `--script` to take screenshots";

/// `aograph view`'s arguments.
#[derive(Clone, Debug, Default)]
pub struct ViewArgs {
    pub common: CommonArgs,
    pub script: Option<PathBuf>,
}

/// Opens the viewer and runs it until the window closes or the script quits.
pub fn view(args: &ViewArgs) -> AppResult<()> {
    let registry = TechniqueRegistry::with_builtins();
    let config = args.common.resolve(&registry)?;
    let script = args.script.as_deref().map(Script::load).transpose()?;
    // A size is fixed only when asked for; the config's default size is not a request.
    let size = match (args.common.width, args.common.height) {
        (Some(w), Some(h)) => Some(Extent::new(w, h)),
        (None, None) => None,
        _ => Some(Extent::new(config.width, config.height)),
    };
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
