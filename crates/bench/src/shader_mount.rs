//! The WGSL this crate owns: shaders/bench/ (the roofline's load-throughput kernel), compiled
//! in.
//!
//! Invariant: the bench's passes name only files of this mount and the renderer's.

use aograph_graph::ShaderMount;

/// shaders/bench/.
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-bench").with_files(aograph_shaders::BENCH)
}
