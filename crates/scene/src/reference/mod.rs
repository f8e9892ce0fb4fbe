//! The ray-traced AO reference: cosine-weighted rays against the real geometry from the same
//! per-pixel points and normals the screen-space techniques see.
//!
//! Definition (DESIGN.md, "AO conventions"): A(p) = (1/pi) * integral over the hemisphere of
//! V(p, w) cos(theta) dw. Binary mode: V = 0 when a ray hits geometry within the radius R, so
//! with cosine-weighted rays A is the fraction of rays that escape. Obscurance mode: a hit at
//! distance d contributes occlusion rho(d) = 1 - min(1, (d/R)^2) (MSSAO's Eq. 4), so
//! A = 1 - mean(hit ? rho(d) : 0). Invalid (sky) pixels get exactly A = 1 and error 0.
//! Invariants: results are deterministic (same input, same image, bit for bit, whatever the
//! thread count) and every output value is finite and in [0, 1].

mod brute_force;
mod bvh;
mod cpu_gbuffer;
mod output;
mod progress;
mod sampling;
mod scene_rays;
mod tracer;

pub use brute_force::BruteForceTracer;
pub use bvh::is_traceable;
pub use bvh::{RayHitRecord, RayQueries, TriangleBvh};
pub use cpu_gbuffer::{CpuGBuffer, primary_hits, surface_normals};
pub use output::{
    RAW_MAGIC, RawF32Image, ReferenceImage, read_raw_f32, write_png16, write_raw_f32,
};
pub use progress::ProgressMode;
pub use sampling::{cosine_hemisphere, pixel_scramble, sobol_2d, tangent_frame};
pub use scene_rays::SceneRays;
pub use tracer::check_inputs;
pub use tracer::{offset_epsilon, trace_reference, trace_reference_rows};

/// The code of the AO integrator whose output a cached reference holds (the tracer, its
/// sampling and its BVH): the reference cache hashes it into every key, so any edit to it
/// invalidates what was traced before.
pub const INTEGRATOR_SOURCES: [&str; 3] = [
    include_str!("tracer.rs"),
    include_str!("sampling.rs"),
    include_str!("bvh.rs"),
];

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// How a ray hit turns into occlusion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ReferenceMode {
    /// A hit within R occludes fully.
    #[default]
    Binary,
    /// A hit at distance d occludes by rho(d) = 1 - min(1, (d/R)^2).
    Obscurance,
}

/// Which normal orients the reference's hemisphere at each pixel. Every technique in a run is
/// scored against one reference, whatever normals the technique reads itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ReferenceNormals {
    /// The hit triangle's plane normal, facing the camera: the surface the rays can actually
    /// leave, as ray-traced AO references (and offline renderers' AO passes) use. The default.
    #[default]
    Geometric,
    /// The interpolated vertex normal (turned to the geometric normal's side), as shading and
    /// most screen-space techniques see the surface.
    Shading,
}

impl ReferenceNormals {
    /// The config spelling: "geometric" or "shading".
    pub fn name(self) -> &'static str {
        match self {
            ReferenceNormals::Geometric => "geometric",
            ReferenceNormals::Shading => "shading",
        }
    }

    /// Parses the config spelling, naming the allowed values on error.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "geometric" => Ok(ReferenceNormals::Geometric),
            "shading" => Ok(ReferenceNormals::Shading),
            _ => Err(format!(
                "reference normals `{s}` are not known (allowed: geometric, shading)"
            )),
        }
    }
}

/// Which tracer traces the reference: the CPU's BVH (rayon over cores), the GPU ray tracer's
/// compute BVH, or its hardware backend (acceleration structures and ray queries;
/// `aograph_tracing::gpu::hardware`), the same rays every way. `Auto` is the hardware backend on
/// a hardware device with ray queries, the compute BVH on one without, and the CPU on a
/// software device (lavapipe runs compute and its software ray queries on the same cores,
/// slower than the CPU tracer's SIMD BVH).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum ReferenceTracer {
    /// Chosen for the device ([`ReferenceTracer::resolve`]).
    #[default]
    Auto,
    /// The CPU BVH tracer, parallel over rows with rayon; any number of rays per pixel.
    Cpu,
    /// The GPU ray tracer's compute BVH (`aograph_tracing::gpu`; spelled "gpu" or "compute");
    /// at most `aograph_tracing::gpu::GPU_MAX_RAYS_PER_PIXEL` rays per pixel.
    Gpu,
    /// The GPU ray tracer's hardware backend (ray queries); a device without them is a named
    /// error. Same ray limit as [`ReferenceTracer::Gpu`].
    Hardware,
}

impl ReferenceTracer {
    /// The config spelling: "auto", "cpu", "gpu" or "hardware".
    pub fn name(self) -> &'static str {
        match self {
            ReferenceTracer::Auto => "auto",
            ReferenceTracer::Cpu => "cpu",
            ReferenceTracer::Gpu => "gpu",
            ReferenceTracer::Hardware => "hardware",
        }
    }

    /// Parses the config spelling ("compute" is "gpu"), naming the allowed values on error.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(ReferenceTracer::Auto),
            "cpu" => Ok(ReferenceTracer::Cpu),
            "gpu" | "compute" => Ok(ReferenceTracer::Gpu),
            "hardware" => Ok(ReferenceTracer::Hardware),
            _ => Err(format!(
                "reference tracer `{s}` is not known (allowed: auto, cpu, gpu or compute, hardware)"
            )),
        }
    }

    /// `Auto` made concrete for a device (`software`: `GpuContext::is_software`;
    /// `ray_queries`: `GpuContext::has_ray_queries`).
    pub fn resolve(self, software: bool, ray_queries: bool) -> ReferenceTracer {
        match self {
            ReferenceTracer::Auto if software => ReferenceTracer::Cpu,
            ReferenceTracer::Auto if ray_queries => ReferenceTracer::Hardware,
            ReferenceTracer::Auto => ReferenceTracer::Gpu,
            t => t,
        }
    }
}

/// Parameters of a reference run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReferenceParams {
    /// World-space AO radius R shared with the techniques (> 0).
    pub radius: f32,
    /// Rays per pixel (>= 1; powers of two stratify best).
    pub rays_per_pixel: u32,
    /// How a hit turns into occlusion: binary within R, or distance-weighted obscurance.
    pub mode: ReferenceMode,
    /// Whether to draw a progress bar on stderr. Not part of the cache key.
    pub progress: ProgressMode,
}

impl Default for ReferenceParams {
    fn default() -> Self {
        ReferenceParams {
            radius: 1.0,
            rays_per_pixel: 256,
            mode: ReferenceMode::Binary,
            progress: ProgressMode::Auto,
        }
    }
}

/// Per-pixel world-space surface points and normals, row-major, top row first: a g-buffer
/// read back from the GPU or the CPU's ([`CpuGBuffer`]). `valid[i] == false` marks sky.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SurfaceBuffer {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// World-space surface point of each pixel, where its rays start (ignored on sky).
    pub points: Vec<Vec3>,
    /// Unit normals facing the viewer.
    pub normals: Vec<Vec3>,
    /// `true` where the pixel sees geometry; `false` marks sky, which gets A = 1 untraced.
    pub valid: Vec<bool>,
}

impl SurfaceBuffer {
    /// Number of pixels (width * height).
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Number of valid (non-sky) pixels.
    pub fn valid_count(&self) -> usize {
        self.valid.iter().filter(|&&v| v).count()
    }

    /// A 1x1 buffer seeing `point` with `normal` (a single probe, as the tracers' tests use).
    pub fn one_pixel(point: Vec3, normal: Vec3) -> SurfaceBuffer {
        SurfaceBuffer {
            width: 1,
            height: 1,
            points: vec![point],
            normals: vec![normal],
            valid: vec![true],
        }
    }
}
