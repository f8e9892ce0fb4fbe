//! The AO reference traced on the GPU (shaders/raytrace/reference.wgsl): the CPU reference's
//! rays (same Sobol points, scramble, hemisphere, origin offset and occlusion rule) and its
//! estimator, against the GPU ray tracer instead of the CPU BVH. Rows are traced in bands of
//! at most [`RAYS_PER_DISPATCH`] rays, so no single dispatch runs long enough to trip a
//! driver's watchdog. Same inputs and errors as `reference::trace_reference`.
//!
//! The same shader runs on either backend of the tracer: against the compute BVH
//! ([`super::GpuSceneBvh`]) as written, against the hardware acceleration structures
//! ([`super::HardwareSceneAs`], ray queries) as its `RayTracer=hardware` variant, which swaps
//! the scene trace's include (`aograph_frame::ray_tracer_variant`): the same rays and estimator
//! either way.
//!
//! Invariant: sky and unusable pixels are exactly (1, 0), as on the CPU; every other pixel's
//! estimate is the CPU's up to float rounding (its rays are the same rays), so the two agree
//! within their standard errors (tests/gpu_ray_tracer/).

use crate::error::TracingError;
use std::sync::Arc;

use aograph_graph::{GpuContext, ShaderLibrary};
use bytemuck::{Pod, Zeroable};

use super::gpu_io::{
    bind_group, buffer_of, check_storage, compute_pipeline, read_back, submit_dispatch,
};
use super::trace_scene::GpuTraceScene;
use super::trace_scene::hardware_pipeline;
use aograph_scene::error::SceneError;
use aograph_scene::reference::{
    ReferenceImage, ReferenceMode, ReferenceParams, SurfaceBuffer, check_inputs,
};

/// Most rays one dispatch traces (a band of rows).
pub const RAYS_PER_DISPATCH: u64 = 1 << 22;
/// Most rays per pixel the GPU tracer takes: its per-pixel sums are f32 (exact to 2^24), and
/// one row at this count stays a short dispatch. More is the CPU tracer's job.
pub const GPU_MAX_RAYS_PER_PIXEL: u32 = 4096;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ReferenceUniform {
    width: u32,
    height: u32,
    rays: u32,
    mode: u32,
    radius: f32,
    row_start: u32,
    rows: u32,
    pad: u32,
}

const SHADER: &str = "raytrace/reference.wgsl";

/// The GPU reference pipeline (one per backend the device has).
pub struct GpuReferenceTracer {
    gpu: Arc<GpuContext>,
    pipeline: wgpu::ComputePipeline,
    /// The `RayTracer=hardware` variant, on a device with ray queries.
    hardware: Option<wgpu::ComputePipeline>,
}

impl GpuReferenceTracer {
    /// Compiles the `raytrace/reference.wgsl` pipeline from `shaders`; a shader or pipeline
    /// failure is a [`TracingError::Gpu`].
    pub fn new(
        gpu: Arc<GpuContext>,
        shaders: &ShaderLibrary,
    ) -> Result<GpuReferenceTracer, TracingError> {
        let pipeline = compute_pipeline(&gpu, shaders, SHADER)?;
        let hardware = hardware_pipeline(&gpu, shaders, SHADER)?;
        Ok(GpuReferenceTracer {
            gpu,
            pipeline,
            hardware,
        })
    }

    /// Traces the reference of every pixel of `surfaces` against `scene` (the compute BVH or
    /// the hardware acceleration structures).
    pub fn trace<'a>(
        &self,
        scene: impl Into<GpuTraceScene<'a>>,
        surfaces: &SurfaceBuffer,
        params: &ReferenceParams,
    ) -> Result<ReferenceImage, TracingError> {
        self.trace_rows(scene, surfaces, params, 0..surfaces.height)
    }

    /// Traces rows `rows` of `surfaces` only (a band of a progressive trace, as
    /// `reference::trace_reference_rows`): each pixel's rays are the ones [`Self::trace`]
    /// gives it, so bands make exactly the whole image. The result is `rows.len()` rows tall.
    pub fn trace_rows<'a>(
        &self,
        scene: impl Into<GpuTraceScene<'a>>,
        surfaces: &SurfaceBuffer,
        params: &ReferenceParams,
        rows: std::ops::Range<u32>,
    ) -> Result<ReferenceImage, TracingError> {
        let scene = scene.into();
        let pipeline = match scene {
            GpuTraceScene::Compute(_) => &self.pipeline,
            GpuTraceScene::Hardware(_) => {
                self.hardware
                    .as_ref()
                    .ok_or_else(|| TracingError::Unsupported {
                        what: "the hardware reference".into(),
                        detail: format!(
                            "adapter '{}' has no ray queries; trace against the compute BVH",
                            self.gpu.info.name
                        ),
                    })?
            }
        };
        check_inputs(surfaces, params)?;
        if params.rays_per_pixel > GPU_MAX_RAYS_PER_PIXEL {
            return Err(SceneError::InvalidParameter {
                name: "rays_per_pixel",
                value: params.rays_per_pixel.to_string(),
                allowed: "1 to 4096 on the GPU tracer (use the CPU tracer for more)",
            }
            .into());
        }
        let gpu = &self.gpu;
        let (width, height) = (surfaces.width, surfaces.height);
        check_storage(gpu, "surface points", surfaces.pixel_count() as u64 * 16)?;
        let rows = rows.start.min(height)..rows.end.min(height);
        let pixels = surfaces.pixel_count();
        if pixels == 0 || rows.is_empty() {
            return Ok(ReferenceImage {
                width,
                height: rows.end - rows.start,
                accessibility: Vec::new(),
                std_error: Vec::new(),
            });
        }
        let points: Vec<[f32; 4]> = (0..pixels)
            .map(|i| {
                let p = surfaces.points[i];
                [p.x, p.y, p.z, if surfaces.valid[i] { 1.0 } else { 0.0 }]
            })
            .collect();
        let normals: Vec<[f32; 4]> = surfaces
            .normals
            .iter()
            .map(|n| [n.x, n.y, n.z, 0.0])
            .collect();
        let storage = wgpu::BufferUsages::STORAGE;
        let point_buffer = buffer_of(gpu, "reference points", &points, storage);
        let normal_buffer = buffer_of(gpu, "reference normals", &normals, storage);
        let result_size = (pixels * 8) as u64;
        let result = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reference result"),
            size: result_size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let rays_per_row = u64::from(width) * u64::from(params.rays_per_pixel);
        let band = (RAYS_PER_DISPATCH / rays_per_row.max(1)).clamp(1, u64::from(height)) as u32;
        let mut row_start = rows.start;
        while row_start < rows.end {
            let band_rows = band.min(rows.end - row_start);
            let uniform = ReferenceUniform {
                width,
                height,
                rays: params.rays_per_pixel,
                mode: match params.mode {
                    ReferenceMode::Binary => 0,
                    ReferenceMode::Obscurance => 1,
                },
                radius: params.radius,
                row_start,
                rows: band_rows,
                pad: 0,
            };
            let uniform = buffer_of(
                gpu,
                "reference params",
                &[uniform],
                wgpu::BufferUsages::UNIFORM,
            );
            let mut entries = vec![
                (0, uniform.as_entire_binding()),
                (1, point_buffer.as_entire_binding()),
                (2, normal_buffer.as_entire_binding()),
                (3, result.as_entire_binding()),
            ];
            entries.extend(scene.bindings());
            let group = bind_group(gpu, pipeline, entries);
            submit_dispatch(
                gpu,
                pipeline,
                &group,
                (width.div_ceil(8), band_rows.div_ceil(8)),
            );
            row_start += band_rows;
        }
        let bytes = read_back(gpu, &result, result_size)?;
        let values: &[[f32; 2]] = bytemuck::cast_slice(&bytes);
        let band = (rows.start * width) as usize..(rows.end * width) as usize;
        let (accessibility, std_error) = values[band].iter().map(|v| (v[0], v[1])).unzip();
        Ok(ReferenceImage {
            width,
            height: rows.end - rows.start,
            accessibility,
            std_error,
        })
    }
}
