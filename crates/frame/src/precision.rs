//! The precision of AO intermediates: R32Float, or R16Float to halve their bandwidth.
//!
//! A pass whose storage output follows the intermediate precision declares that output's type
//! once, on a line of its own, as written at 32-bit precision:
//!
//! ```text
//! alias IntermediateStorage = texture_storage_2d<r32float, write>;
//! ```
//!
//! and the 16-bit variant is the graph's generic storage-precision variant of that alias
//! (`file?IntermediateStorage=f16`, see `aograph_graph::ShaderLibrary`): r32float becomes
//! r16float, rgba32float rgba16float, nothing else in the file changes.

/// The type alias a precision-aware shader declares for its intermediate outputs.
pub const INTERMEDIATE_ALIAS: &str = "IntermediateStorage";

/// The shader `file` at the intermediate precision `format`: its `?IntermediateStorage=f16`
/// variant under R16Float, `file` itself (as written, 32-bit) otherwise.
pub fn intermediate_shader(file: &str, format: wgpu::TextureFormat) -> String {
    match format {
        wgpu::TextureFormat::R16Float => {
            aograph_graph::storage_precision_variant(file, INTERMEDIATE_ALIAS, true)
        }
        _ => file.to_string(),
    }
}
