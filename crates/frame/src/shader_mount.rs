//! The WGSL this crate owns: shaders/common/, the files techniques and suppliers both include
//! (the View block, g-buffer rows, the normal encoding, ray directions, the scene trace), and
//! the ray tracer's include variant, which swaps the compute-BVH trace for the ray-query one.
//!
//! Invariant: [`RAY_TRACER`] swaps files that are in this mount, so a library with this mount
//! can build every variant it names.

use aograph_graph::{IncludeVariant, ShaderMount};

/// The include every ray-tracing pass is written against: one ray against the compute BVH.
pub const SCENE_TRACE: &str = "common/scene_trace.wgsl";
/// The same function with ray queries (wgpu's `EXPERIMENTAL_RAY_QUERY`).
pub const SCENE_TRACE_HARDWARE: &str = "common/scene_trace_hardware.wgsl";

/// `file.wgsl?RayTracer=hardware`: `file.wgsl` tracing with ray queries instead of the compute
/// BVH (it must include [`SCENE_TRACE`]); `?RayTracer=compute` is the file as written.
pub const RAY_TRACER: IncludeVariant = IncludeVariant {
    key: "RayTracer",
    written: "compute",
    swapped: "hardware",
    include: SCENE_TRACE,
    replacement: SCENE_TRACE_HARDWARE,
};

/// shaders/common/ with the ray tracer's variant: mount it in every library whose shaders
/// include a common file (every aograph library does).
pub fn shader_mount() -> ShaderMount {
    ShaderMount::new("aograph-frame")
        .with_files(aograph_shaders::COMMON)
        .with_include_variant(RAY_TRACER)
}

/// The name of `file`'s variant that traces its rays with ray queries (`hardware`) or with the
/// compute BVH (the file itself).
pub fn ray_tracer_variant(file: &str, hardware: bool) -> String {
    RAY_TRACER.of(file, hardware)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ray_tracer_variant_swaps_two_files_of_this_mount() {
        let mount = shader_mount();
        assert!(mount.source(SCENE_TRACE).is_some());
        assert!(mount.source(SCENE_TRACE_HARDWARE).is_some());
        assert!(mount.names().all(|n| n.starts_with("common/")));
        assert_eq!(
            ray_tracer_variant("raytrace/reference.wgsl", true),
            "raytrace/reference.wgsl?RayTracer=hardware"
        );
        assert_eq!(ray_tracer_variant("a.wgsl", false), "a.wgsl");
    }
}
