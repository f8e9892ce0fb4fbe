//! The crate's one error type, [`TracingError`]: the GPU tracers' own failures (a device
//! operation, a missing feature, a BVH over the device's limits) and the scene crate's errors
//! passed through.
//!
//! Invariant: every message says what is wrong and what to do (trace fewer meshes, use the CPU
//! tracer, ...); nothing in this crate panics on user input.

use aograph_scene::SceneError;

/// Everything that can go wrong tracing a scene's reference or building its GPU structures.
#[derive(Debug, thiserror::Error)]
pub enum TracingError {
    /// A scene, parameter or file error of the scene crate, passed through unchanged.
    #[error(transparent)]
    Scene(#[from] SceneError),

    /// A GPU operation (a pipeline, a dispatch, a readback) failed.
    #[error("GPU error while {what}: {message}")]
    Gpu {
        /// What was being done, as a gerund phrase, e.g. "reading ray tracing results back".
        what: &'static str,
        /// wgpu's error text.
        message: String,
    },

    /// A device feature the request needs is missing (e.g. ray queries for the hardware
    /// tracer).
    #[error("{what} cannot run on this device: {detail}")]
    Unsupported {
        /// What was asked for, e.g. "the hardware ray tracer".
        what: String,
        /// What the device lacks and has, and what to do instead.
        detail: String,
    },

    /// The scene's BVH does not fit one of the device's storage-buffer limits.
    #[error(
        "the scene's BVH does not fit this device: its {buffer} buffer is {size} bytes (the whole \
         BVH {total} bytes), over the device's limit of {limit} bytes ({limit_name}); trace fewer \
         or decimated meshes, or use a device with larger limits"
    )]
    BvhTooLarge {
        /// Which buffer is too large: "node", "instance" or "triangle".
        buffer: &'static str,
        /// That buffer's size in bytes.
        size: u64,
        /// The three buffers' sizes together, in bytes.
        total: u64,
        /// The limit it exceeds, in bytes: the smaller of the two limits named below.
        limit: u64,
        /// The `wgpu::Limits` field that limit comes from: `max_storage_buffer_binding_size` or
        /// `max_buffer_size`.
        limit_name: &'static str,
    },

    /// A GPU tracer's input or output buffer over the device's storage-buffer limit.
    #[error(
        "the GPU tracer's {what} need {size} bytes, over this device's storage-buffer limit of \
         {limit} bytes: trace a smaller image or batch, or use the CPU tracer \
         ([reference] tracer = \"cpu\")"
    )]
    OverDeviceLimit {
        /// What the buffer holds, plural, e.g. "rays" or "surface points".
        what: &'static str,
        /// The buffer's size in bytes.
        size: u64,
        /// The device's largest storage binding (and buffer), in bytes.
        limit: u64,
    },

    /// A BVH level deeper than the GPU traversal's fixed stack.
    #[error(
        "the scene's {level}-level BVH is {depth} nodes deep, over the GPU traversal stack of \
         {limit}: the geometry is too degenerate to trace (split the mesh or remove stacked \
         duplicate triangles)"
    )]
    BvhTooDeep {
        /// Which level is too deep: "top" (over instances) or "bottom" (over one mesh's
        /// triangles).
        level: &'static str,
        /// That tree's depth, in nodes from root to deepest leaf.
        depth: u32,
        /// The traversal stack size for that level, the deepest tree the GPU can walk.
        limit: u32,
    },
}

/// Results of this crate.
pub type TracingResult<T> = Result<T, TracingError>;
