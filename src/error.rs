//! The CLI's one error type: every lower crate's error plus file-system and config problems,
//! each naming the path or key at fault.

use std::path::PathBuf;

use thiserror::Error;

#[derive(Debug, Error)]
pub enum AppError {
    #[error(transparent)]
    Graph(#[from] aograph_graph::GraphError),
    #[error(transparent)]
    Ao(#[from] aograph_ao::AoError),
    #[error(transparent)]
    Scene(#[from] aograph_scene::SceneError),
    #[error(transparent)]
    Render(#[from] aograph_renderer::RenderError),
    #[error("config {path}: {message}")]
    Config { path: String, message: String },
    #[error("invalid value for {name}: {value} (allowed: {allowed})")]
    InvalidArgument {
        name: String,
        value: String,
        allowed: String,
    },
    #[error("cannot {action} {path}: {message}")]
    Io {
        action: &'static str,
        path: PathBuf,
        message: String,
    },
    #[error("image {path}: {message}")]
    Image { path: PathBuf, message: String },
}

impl AppError {
    pub fn io(action: &'static str, path: impl Into<PathBuf>, e: impl std::fmt::Display) -> Self {
        AppError::Io {
            action,
            path: path.into(),
            message: e.to_string(),
        }
    }
}

pub type AppResult<T> = Result<T, AppError>;
