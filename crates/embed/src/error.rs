//! The embedding API's one error type: what went wrong with the application's inputs, settings
//! or device, in words that say what is allowed.

use thiserror::Error;

/// Errors of [`crate::AmbientOcclusion`].
#[derive(Debug, Error)]
pub enum EmbedError {
    /// The technique, its parameters or the radius were refused.
    #[error(transparent)]
    Ao(#[from] aograph_ao_passes::AoError),
    /// The frame graph refused the frame (an input of the wrong size or usage, say).
    #[error(transparent)]
    Graph(#[from] aograph_graph::GraphError),
    /// An input texture has a format the adapters do not read.
    #[error("{input} has format {found:?}: allowed {allowed}")]
    InputFormat {
        /// Which input.
        input: &'static str,
        /// Its format.
        found: wgpu::TextureFormat,
        /// The formats accepted there.
        allowed: &'static str,
    },
    /// An input texture's size differs from the depth texture's.
    #[error(
        "{input} is {found} but the depth texture is {expected}: every input has the depth's size"
    )]
    InputSize {
        /// Which input.
        input: &'static str,
        /// Its size, "WxH".
        found: String,
        /// The depth texture's size.
        expected: String,
    },
    /// The projection matrix is not one aograph can read depth through.
    #[error("projection matrix: {0}")]
    Projection(String),
    /// A setting outside what the embedding API supports.
    #[error("invalid {name} = {value}: allowed {allowed}")]
    InvalidSetting {
        /// The setting.
        name: String,
        /// The value given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// The technique reads something an application's frame does not carry.
    #[error("technique `{technique}` reads {what}, which AoInputs does not carry: {fix}")]
    UnsupportedTechnique {
        /// The technique's name.
        technique: String,
        /// What it reads.
        what: String,
        /// What to change.
        fix: String,
    },
}

/// Results of the embedding API.
pub type EmbedResult<T> = Result<T, EmbedError>;
