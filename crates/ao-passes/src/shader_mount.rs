//! The WGSL this crate owns: shaders/ao/ (one folder per technique) and shaders/blocks/ (the
//! shared AO blocks), compiled in. Its files include shaders/common/, so a library that runs
//! the techniques mounts `aograph_frame::shader_mount()` beside this one ([`shader_library`]).
//!
//! Invariant: every WGSL file a technique or block of this crate names is in this mount or the
//! frame crate's.

use aograph_graph::{GraphResult, ShaderLibrary, ShaderMount};

/// shaders/ao/ and shaders/blocks/.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-ao-passes")
        .with_files(aograph_shaders::AO)
        .with_files(aograph_shaders::BLOCKS)
}

/// A library with what the techniques and blocks need: this crate's mount and the frame
/// crate's (shaders/common/). Mount an application's technique's own WGSL on it with
/// [`ShaderLibrary::mount`].
pub fn shader_library() -> GraphResult<ShaderLibrary> {
    ShaderLibrary::from_mounts([aograph_frame::shader_mount(), shader_mount()])
}
