//! The GPU ray tracer: the scene's geometry as a two-level BVH in storage buffers, traversed by
//! WGSL compute passes (shaders/common/bvh.wgsl), for the `rtao` technique and the GPU
//! reference. Built on the CPU with obvhs and flattened to a BVH2 ([`flat_bvh`]); one bottom
//! level per mesh (per skinned instance), one top level over instances ([`scene_bvh`]); only
//! what moves is refit or rebuilt per frame; a BVH over the device's limits is an error
//! ([`limits`]) before any buffer is made ([`gpu_bvh`]). [`ray_batch`] traces arbitrary rays;
//! [`gpu_reference`] traces the reference's rays. [`hardware`] is the second backend: the same
//! rays against Vulkan acceleration structures with ray queries, where the device has them.
//!
//! Invariant: the GPU answers the CPU tracer's questions with the CPU tracer's triangle test
//! (`obvhs::triangle::Triangle::intersect`), so the two agree ray by ray up to float rounding
//! in the instance transforms (tests/gpu_ray_tracer/ measures it).

pub mod flat_bvh;
pub mod gpu_bvh;
mod gpu_io;
pub mod gpu_reference;
pub mod hardware;
pub mod limits;
pub mod ray_batch;
pub mod scene_bvh;
pub mod trace_scene;

pub use flat_bvh::{FlatBvh, FlatNode};
pub use gpu_bvh::GpuSceneBvh;
pub use gpu_reference::{GPU_MAX_RAYS_PER_PIXEL, GpuReferenceTracer};
pub use hardware::{AsWork, HardwareSceneAs};
pub use limits::{BvhSizes, check_bvh_fits};
pub use ray_batch::{GpuRayBatch, GpuRayHit, HitQuery, TraceRay};
pub use scene_bvh::{BvhUpdate, BvhWork, GpuInstance, GpuTriangle, SceneBvh};
pub use trace_scene::GpuTraceScene;
