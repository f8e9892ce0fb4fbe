//! The one error type of the render graph.
//!
//! Every variant names what is at fault (the pass, the resource, the shader file and line) and,
//! where there is one, the fix, so a message can be acted on without reading the source.
//! User input (configs, declarations, shaders) never panics; it ends up here.

use thiserror::Error;

/// Everything that can go wrong while declaring, compiling or executing a graph.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GraphError {
    #[error("cycle in the graph: pass `{pass}` depends (through its reads) on its own output")]
    Cycle { pass: String },

    #[error(
        "pass `{pass}` reads `{resource}`, which no pass writes and which is not imported; write it in an earlier pass or import it"
    )]
    ReadOfUnwritten { pass: String, resource: String },

    #[error(
        "conflicting writes to `{resource}`: pass `{second}` writes a version that pass `{first}` already overwrote; write the handle `{first}` returned"
    )]
    ConflictingWrites {
        resource: String,
        first: String,
        second: String,
    },

    #[error(
        "size mismatch in pass `{pass}`: `{resource}` is {found} but the pass needs {expected}"
    )]
    SizeMismatch {
        pass: String,
        resource: String,
        expected: String,
        found: String,
    },

    #[error(
        "format mismatch in pass `{pass}`: `{resource}` is {found:?} but the pass needs {expected}"
    )]
    FormatMismatch {
        pass: String,
        resource: String,
        expected: String,
        found: wgpu::TextureFormat,
    },

    #[error(
        "history resource `{resource}` is read but never written this frame; add a pass that writes it"
    )]
    HistoryNeverWritten { resource: String },

    #[error(
        "two {kind}s are named `{name}`: {kind}s are bound by name, so they would silently share one resource; give each its own name"
    )]
    DuplicateName { kind: String, name: String },

    #[error(
        "imported texture `{resource}` was created without usage {missing}, which the plan needs (it has {has}); add it to the texture's usage"
    )]
    ImportUsage {
        resource: String,
        missing: String,
        has: String,
    },

    #[error("pass `{pass}`: {message}")]
    InvalidPass { pass: String, message: String },

    #[error("pass `{pass}`, sampler `{binding}`: {message}")]
    Sampler {
        pass: String,
        binding: String,
        message: String,
    },

    #[error("invalid parameter `{name}` = {value} for `{owner}`: allowed {allowed}")]
    InvalidParameter {
        owner: String,
        name: String,
        value: String,
        allowed: String,
    },

    #[error("shader `{file}` line {line}: {message}")]
    Shader {
        file: String,
        line: u32,
        message: String,
    },

    #[error("cannot read shader `{file}`: {message}")]
    ShaderFile { file: String, message: String },

    #[error(
        "no GPU adapter found ({detail}). aograph needs a Vulkan device; without a GPU install Mesa's software driver: on Debian/Ubuntu `apt-get install mesa-vulkan-drivers`"
    )]
    NoAdapter { detail: String },

    #[error("GPU error: {0}")]
    Gpu(String),

    #[error(
        "texture `{resource}` is {format:?}, which this device ({device}) cannot use as {usage}; declare it in a format the device supports for that use"
    )]
    UnsupportedFormat {
        resource: String,
        format: wgpu::TextureFormat,
        usage: String,
        device: String,
    },

    #[error("resource `{resource}` is not available: {message}")]
    MissingResource { resource: String, message: String },
}

/// Result with [`GraphError`].
pub type GraphResult<T> = Result<T, GraphError>;
