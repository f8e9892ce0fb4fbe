//! The CLI's one error type: every lower crate's error plus file-system and config problems,
//! each naming the path or key at fault.

use std::path::PathBuf;

use thiserror::Error;

/// Everything that can go wrong in aograph's commands: a lower crate's error passed through
/// unchanged, or a config, argument, file or image problem that names the path, key or flag at
/// fault. Its `Display` text is the one-line message the CLI prints.
#[derive(Debug, Error)]
pub enum AppError {
    /// The render graph refused a declaration, a compile or a frame; its message is kept as is.
    #[error(transparent)]
    Graph(#[from] aograph_graph::GraphError),
    /// A technique or its parameters (or R) were refused; its message is kept as is.
    #[error(transparent)]
    Ao(#[from] aograph_ao_passes::AoError),
    /// A scene could not be built, loaded or traced (unknown procedural name, missing or
    /// malformed glTF, ...); its message is kept as is.
    #[error(transparent)]
    Scene(#[from] aograph_scene::SceneError),
    /// A GPU ray tracer, the reference's cache or its ceilings failed; its message is kept as
    /// is.
    #[error(transparent)]
    Tracing(#[from] aograph_tracing::TracingError),
    /// The renderer or the reference failed; its message is kept as is.
    #[error(transparent)]
    Render(#[from] aograph_renderer::RenderError),
    /// A config, sweep or search file that does not parse or holds a value outside what is
    /// allowed.
    #[error("config {path}: {message}")]
    Config {
        /// The file at fault as it was named (a path, or a label such as `sweep` for text
        /// that came from no file).
        path: String,
        /// What is wrong, naming the key and, where there is one, the allowed range or the
        /// nearest valid key.
        message: String,
    },
    /// A flag, name or input outside what is allowed: an unknown `--camera`, a bad
    /// `--motion`, an image of the wrong size handed to a metric, a run with GPU validation
    /// errors.
    #[error("invalid value for {name}: {value} (allowed: {allowed})")]
    InvalidArgument {
        /// What was given the value: a flag (`--camera`), a technique and its parameter set,
        /// or an input such as `depth`.
        name: String,
        /// The value given, as text (or what was wrong with it, e.g. "1200 pixels").
        value: String,
        /// What would have been accepted: the known names, a range, or an example.
        allowed: String,
    },
    /// A file-system operation (or a JSON read or write) that failed.
    #[error("cannot {action} {path}: {message}")]
    Io {
        /// What was attempted, as a verb phrase that follows "cannot": `read config`,
        /// `write`, `append to`, `create output directory`, `parse`, `serialise`.
        action: &'static str,
        /// The file or directory it was attempted on.
        path: PathBuf,
        /// The underlying error's text (the OS error, or serde_json's).
        message: String,
    },
    /// `aograph docs --check`: text a tool owns differs from what the committed inputs make.
    #[error("generated text is out of date in {files}: run `aograph docs` and commit the result")]
    StaleDocs {
        /// The files, comma-separated.
        files: String,
    },
    /// A marker of generated text that `aograph docs` cannot follow.
    #[error("{path}:{line}: {message}")]
    DocsMarker {
        /// The Markdown file.
        path: PathBuf,
        /// Its line, from 1.
        line: usize,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A PNG that could not be encoded.
    #[error("image {path}: {message}")]
    Image {
        /// The PNG being written.
        path: PathBuf,
        /// The encoder's error text.
        message: String,
    },
}

impl AppError {
    /// An [`AppError::Io`] for a failed `action` on `path`, keeping `e`'s text as the message
    /// (e.g. `AppError::io("read config", path, e)` prints "cannot read config PATH: ...").
    pub fn io(action: &'static str, path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        AppError::Io {
            action,
            path: path.into(),
            message: e.to_string(),
        }
    }
}

/// `Result` with an [`AppError`]: what every fallible function of this crate returns.
pub type AppResult<T> = Result<T, AppError>;
