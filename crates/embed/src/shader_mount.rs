//! The WGSL this crate owns: shaders/embed/ (the adapters from an application's depth, normals
//! and motion to aograph's channels, and the output write), compiled in, and the library the
//! embedding runs on: the frame crate's common files, the techniques' and these.
//!
//! Invariant: nothing here reads a file, unless the developer sets `AOGRAPH_SHADERS` to a
//! shader folder for hot edits.

use aograph_graph::{GraphResult, ShaderLibrary, ShaderMount};

/// shaders/embed/.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-embed").with_files(aograph_shaders::EMBED)
}

/// The embedding's library: `aograph_frame`'s, `aograph_ao_passes`'s and this crate's mounts, with
/// the folder `AOGRAPH_SHADERS` names (if set) shadowing them for hot edits.
pub fn shader_library() -> GraphResult<ShaderLibrary> {
    let lib = ShaderLibrary::from_mounts([
        aograph_frame::shader_mount(),
        aograph_ao_passes::shader_mount(),
        shader_mount(),
    ])?;
    Ok(match std::env::var_os("AOGRAPH_SHADERS") {
        Some(dir) if !dir.is_empty() => lib.with_directory_override(dir),
        _ => lib,
    })
}
