//! aograph's reference as the bench, the viewer and `rtao` use it, on top of the scene crate's
//! CPU ray queries: the GPU ray tracers ([`gpu`]: the scene as a two-level BVH in storage
//! buffers for WGSL compute, and as hardware acceleration structures for ray queries), the
//! reference's disk cache ([`ReferenceCache`]), the radiance reference ([`trace_radiance`])
//! and the error ceilings ([`trace_ceilings`]: what the best screen-space technique could
//! reach from the g-buffer alone).
//!
//! Which crate owns what: `aograph-scene` holds the scene, its views and the CPU ray queries
//! (the BVHs, primary hits and the AO integrator `trace_reference`, which the view heuristics
//! use too); this crate builds the reference pipeline and the GPU tracers on them. Every
//! answer is the CPU tracer's: the GPU tracers test triangles with the CPU tracer's test, so
//! the two agree ray by ray up to float rounding (tests/gpu_ray_tracer/).

#![warn(missing_docs)]

pub mod cache;
mod cache_key;
pub mod ceilings;
mod error;
pub mod gpu;
pub mod radiance;
mod shader_mount;

pub use cache::{CacheKey, ReferenceCache};
pub use ceilings::{
    Ceilings, DEPTH_BREAK_RATIO, GUARD_BAND, SECOND_LAYER_SEPARATION, SEEN_SUPERSAMPLING,
    gbuffer_surface_mesh, guard_band_camera, guard_band_mesh, second_layer_mesh,
    seen_triangle_mask, seen_triangles, trace_ceilings,
};
pub use error::{TracingError, TracingResult};
pub use radiance::{BounceSurfaces, RadianceImage, trace_radiance};
pub use shader_mount::{shader_library, shader_mount};
