//! The progress bar of long reference runs.
//!
//! Invariant: nothing is drawn unless stderr is a terminal ([`ProgressMode::Auto`]) or the
//! caller asked for it ([`ProgressMode::Always`]), so logs and CI output stay clean.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::io::IsTerminal;

/// When to show a progress bar.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ProgressMode {
    /// Only when stderr is a terminal.
    #[default]
    Auto,
    /// Always, even when stderr is redirected to a file or pipe.
    Always,
    /// Never.
    Never,
}

/// A bar over `rows` image rows, hidden unless `mode` says to draw it.
pub(crate) fn row_progress(mode: ProgressMode, rows: u64) -> ProgressBar {
    let visible = match mode {
        ProgressMode::Auto => std::io::stderr().is_terminal(),
        ProgressMode::Always => true,
        ProgressMode::Never => false,
    };
    if !visible {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(rows), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(
        "reference AO {bar:40} {pos}/{len} rows, {elapsed} elapsed, ~{eta} left",
    ) {
        bar.set_style(style);
    }
    bar
}
