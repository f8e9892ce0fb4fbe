//! What a GPU trace runs against: the compute BVH ([`GpuSceneBvh`], storage buffers at
//! bindings 12-14 of common/bvh.wgsl) or the hardware acceleration structures
//! ([`HardwareSceneAs`], the TLAS and its two tables at the same bindings,
//! common/hardware_scene.wgsl). A tracer's shader is written once against
//! common/scene_trace.wgsl; its `RayTracer=hardware` variant runs it on the second backend, so
//! a tracer keeps two pipelines of one file and picks by the scene it is handed.
//!
//! Invariant: both backends bind exactly 12, 13 and 14 (every `scene_trace` reads all three).

use crate::error::TracingError;
use aograph_graph::{GpuContext, ShaderLibrary};

use super::gpu_bvh::GpuSceneBvh;
use super::gpu_io::compute_pipeline;
use super::hardware::HardwareSceneAs;

/// The scene a GPU trace runs against (the two backends of the GPU tracer).
#[derive(Clone, Copy)]
pub enum GpuTraceScene<'a> {
    /// The two-level BVH in storage buffers, traversed by compute shaders.
    Compute(&'a GpuSceneBvh),
    /// BLAS and TLAS, traversed by ray queries.
    Hardware(&'a HardwareSceneAs),
}

impl<'a> From<&'a GpuSceneBvh> for GpuTraceScene<'a> {
    fn from(b: &'a GpuSceneBvh) -> Self {
        Self::Compute(b)
    }
}

impl<'a> From<&'a HardwareSceneAs> for GpuTraceScene<'a> {
    fn from(a: &'a HardwareSceneAs) -> Self {
        Self::Hardware(a)
    }
}

impl<'a> GpuTraceScene<'a> {
    /// The scene's bind group entries (bindings 12-14).
    pub(crate) fn bindings(&self) -> [(u32, wgpu::BindingResource<'a>); 3] {
        match *self {
            Self::Compute(bvh) => [
                (12, bvh.nodes.as_entire_binding()),
                (13, bvh.instances.as_entire_binding()),
                (14, bvh.triangles.as_entire_binding()),
            ],
            Self::Hardware(a) => [
                (12, a.tlas.as_binding()),
                (13, a.instances.as_entire_binding()),
                (14, a.primitives.as_entire_binding()),
            ],
        }
    }

    /// The pipeline of a tracer for this scene: `compute`, or `hardware` (a device without
    /// ray queries has none: a named error).
    pub(crate) fn pick<'p>(
        &self,
        gpu: &GpuContext,
        compute: &'p wgpu::ComputePipeline,
        hardware: Option<&'p wgpu::ComputePipeline>,
    ) -> Result<&'p wgpu::ComputePipeline, TracingError> {
        match self {
            Self::Compute(_) => Ok(compute),
            Self::Hardware(_) => hardware.ok_or_else(|| TracingError::Unsupported {
                what: "a trace on acceleration structures".into(),
                detail: format!(
                    "adapter '{}' has no ray queries; trace against the compute BVH",
                    gpu.info.name
                ),
            }),
        }
    }
}

/// The `RayTracer=hardware` variant of `shader`, on a device with ray queries.
pub(crate) fn hardware_pipeline(
    gpu: &GpuContext,
    shaders: &ShaderLibrary,
    shader: &str,
) -> Result<Option<wgpu::ComputePipeline>, TracingError> {
    if !gpu.has_ray_queries() {
        return Ok(None);
    }
    let variant = aograph_frame::ray_tracer_variant(shader, true);
    compute_pipeline(gpu, shaders, &variant).map(Some)
}
