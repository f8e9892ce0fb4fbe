//! Arbitrary rays traced on the GPU (shaders/raytrace/trace_rays.wgsl) against either backend
//! ([`GpuTraceScene`]: the compute BVH, or the acceleration structures through the shader's
//! `RayTracer=hardware` variant): what the tests compare with the CPU tracer ray by ray, and
//! what the bench times in rays per second. Closest-hit or any-hit, one invocation per ray.

use crate::error::TracingError;
use std::sync::Arc;

use aograph_graph::{GpuContext, ShaderLibrary};
use bytemuck::{Pod, Zeroable};

use super::gpu_io::{
    bind_group, buffer_of, check_storage, compute_pipeline, dispatch_grid, read_back,
    submit_dispatch,
};
use super::trace_scene::{GpuTraceScene, hardware_pipeline};
use aograph_scene::error::SceneError;

/// One ray: `origin + t direction`, t in [t_min, t_max] (direction unit length for distances in
/// scene units).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct TraceRay {
    /// World-space start of the ray.
    pub origin: [f32; 3],
    /// Nearest parameter t counted as a hit (0 to start at the origin).
    pub t_min: f32,
    /// World-space direction; t is measured in multiples of its length.
    pub direction: [f32; 3],
    /// Farthest parameter t counted as a hit (`f32::INFINITY` for an unbounded ray).
    pub t_max: f32,
}

/// What one ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuRayHit {
    /// Ray parameter t of the hit: the distance from the origin in scene units when the
    /// direction is unit length.
    pub distance: f32,
    /// Index into `Scene::instances`.
    pub instance: u32,
    /// Index among the instance's mesh's valid triangles.
    pub primitive: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct TraceParams {
    count: u32,
    any_hit: u32,
    row: u32,
    pad: u32,
}

/// The ray batch pipelines (the hardware one on a device with ray queries).
pub struct GpuRayBatch {
    gpu: Arc<GpuContext>,
    pipeline: wgpu::ComputePipeline,
    hardware: Option<wgpu::ComputePipeline>,
}

const SHADER: &str = "raytrace/trace_rays.wgsl";

/// Closest hit or first hit found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HitQuery {
    /// The nearest hit within [t_min, t_max] (shading, distances).
    Closest,
    /// Whichever hit traversal finds first: enough for visibility and occlusion, and faster.
    Any,
}

impl GpuRayBatch {
    /// Compiles the `raytrace/trace_rays.wgsl` pipeline from `shaders` (and its hardware
    /// variant where the device has ray queries); a shader or pipeline failure is a
    /// [`TracingError::Gpu`].
    pub fn new(gpu: Arc<GpuContext>, shaders: &ShaderLibrary) -> Result<GpuRayBatch, TracingError> {
        let pipeline = compute_pipeline(&gpu, shaders, SHADER)?;
        let hardware = hardware_pipeline(&gpu, shaders, SHADER)?;
        Ok(GpuRayBatch {
            gpu,
            pipeline,
            hardware,
        })
    }

    /// Traces `rays`, `repeat` times over (for timing; every repeat gives the same answer), and
    /// reads the answers back.
    pub fn trace<'a>(
        &self,
        scene: impl Into<GpuTraceScene<'a>>,
        rays: &[TraceRay],
        query: HitQuery,
        repeat: u32,
    ) -> Result<Vec<Option<GpuRayHit>>, TracingError> {
        let scene = scene.into();
        let pipeline = scene.pick(&self.gpu, &self.pipeline, self.hardware.as_ref())?;
        let count = u32::try_from(rays.len()).map_err(|_| SceneError::InvalidParameter {
            name: "rays",
            value: rays.len().to_string(),
            allowed: "at most 2^32 - 1 rays per batch",
        })?;
        check_storage(&self.gpu, "rays", rays.len() as u64 * 32)?;
        let (x, y, row) = dispatch_grid(count);
        let params = TraceParams {
            count,
            any_hit: (query == HitQuery::Any) as u32,
            row,
            pad: 0,
        };
        let gpu = &self.gpu;
        let uniform = buffer_of(gpu, "trace params", &[params], wgpu::BufferUsages::UNIFORM);
        let ray_buffer = buffer_of(gpu, "rays", rays, wgpu::BufferUsages::STORAGE);
        let result_size = (rays.len().max(1) * 16) as u64;
        let results = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ray results"),
            size: result_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut entries = vec![
            (0, uniform.as_entire_binding()),
            (1, ray_buffer.as_entire_binding()),
            (2, results.as_entire_binding()),
        ];
        entries.extend(scene.bindings());
        let group = bind_group(gpu, pipeline, entries);
        for _ in 0..repeat.max(1) {
            submit_dispatch(gpu, pipeline, &group, (x, y));
        }
        let bytes = read_back(gpu, &results, result_size)?;
        let words: &[[u32; 4]] = bytemuck::cast_slice(&bytes);
        Ok(words[..rays.len()]
            .iter()
            .map(|w| {
                (w[3] == 1).then(|| GpuRayHit {
                    distance: f32::from_bits(w[0]),
                    instance: w[1],
                    primitive: w[2],
                })
            })
            .collect())
    }
}
