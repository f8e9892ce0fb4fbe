//! The renderer's one error type: the lower crates' errors, and settings a caller chose
//! outside what is allowed, named with what is.

use thiserror::Error;

/// Errors of [`crate::Renderer`], the frame graph and the reference.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The frame graph refused a declaration, a plan or a frame.
    #[error(transparent)]
    Graph(#[from] aograph_graph::GraphError),
    /// The technique or its parameters were refused.
    #[error(transparent)]
    Ao(#[from] aograph_ao_passes::AoError),
    /// The scene, its g-buffer or the CPU reference tracer failed.
    #[error(transparent)]
    Scene(#[from] aograph_scene::SceneError),
    /// A GPU ray tracer, the reference's cache or its ceilings failed.
    #[error(transparent)]
    Tracing(#[from] aograph_tracing::TracingError),
    /// A setting outside what is allowed.
    #[error("invalid value for {name}: {value} (allowed: {allowed})")]
    InvalidArgument {
        /// The setting (a flag, key or read-back).
        name: String,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
}

/// Results of the renderer.
pub type RenderResult<T> = Result<T, RenderError>;
