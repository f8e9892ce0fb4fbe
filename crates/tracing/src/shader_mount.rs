//! The WGSL this crate owns: shaders/raytrace/ (the
//! GPU reference and ray batches), compiled in. They include shaders/common/, so a library that
//! runs them mounts `aograph_frame::shader_mount()` too ([`shader_library`]).
//!
//! Invariant: every WGSL file this crate's passes name is in this mount or the frame crate's.

use aograph_graph::{GraphResult, ShaderLibrary, ShaderMount};

/// shaders/raytrace/.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-tracing").with_files(aograph_shaders::RAYTRACE)
}

/// A library with what this crate's passes need: its mount and the frame crate's.
pub fn shader_library() -> GraphResult<ShaderLibrary> {
    ShaderLibrary::from_mounts([aograph_frame::shader_mount(), shader_mount()])
}
