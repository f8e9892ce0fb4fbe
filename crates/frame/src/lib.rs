//! What the g-buffer node (aograph-scene) and the AO techniques (aograph-ao-passes) share, on top of
//! the render graph, without depending on each other: the g-buffer's channels (a technique
//! states which it reads; the g-buffer writes only those), the frame inputs (the per-frame `View`
//! block every pass may bind, the scene's lighting block and ray-tracing BVH a technique
//! declares when it reads them), the compact normal encoding's CPU side ([`normal_oct`]), and the precision of AO
//! intermediates (a shader variant the graph offers generically: see [`intermediate_shader`]),
//! and the WGSL all of them include (shaders/common/, [`shader_mount`]).
//!
//! `aograph-graph` knows none of this: it is a render graph, not an AO renderer.
//!
//! # Example
//!
//! A technique's channel set, and one frame's `View` block from a camera's matrices (no GPU
//! needed for either):
//!
//! ```
//! use aograph_frame::{GBufferChannel, GBufferChannels, ViewMatrices, ViewUniforms};
//! use glam::{Mat4, Vec3};
//!
//! // Linear depth and compact normals: what the g-buffer is asked to write.
//! let channels = GBufferChannels::none()
//!     .with(GBufferChannel::LinearDepth)
//!     .with(GBufferChannel::NormalsOct);
//! assert!(channels.contains(GBufferChannel::LinearDepth));
//! assert!(channels.has_normals()); // either encoding counts
//! assert!(!channels.contains(GBufferChannel::Albedo));
//! let names: Vec<&str> = channels.iter().map(GBufferChannel::name).collect();
//! assert_eq!(names, ["linear_depth", "normals_oct"]);
//!
//! // Right-handed view looking down -Z, wgpu's 0..1 clip depth, an infinite far plane.
//! let view = Mat4::look_at_rh(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y);
//! let proj = Mat4::perspective_infinite_rh(1.0, 16.0 / 9.0, 0.1);
//! let block = ViewUniforms::from_matrices(&ViewMatrices {
//!     view,
//!     proj,
//!     prev_view_proj: proj * view, // a still camera
//!     near: 0.1,
//!     far: f32::INFINITY,
//!     reversed_z: false,
//!     orthographic: false,
//!     width: 1280,
//!     height: 720,
//!     frame_index: 0,
//!     history_valid: false,
//!     camera_cut: false,
//!     time: 0.0,
//!     dt: 0.0,
//! });
//! assert_eq!(block.size, [1280.0, 720.0]);
//! assert_eq!(block.far, 0.0); // an infinite far plane is stored as 0
//! assert_eq!(block.bytes().len(), 448); // what the buffer imported as VIEW_BUFFER holds
//! ```

#![warn(missing_docs)]

mod channels;
mod frame_input;
mod lighting;
pub mod normal_oct;
mod precision;
mod scene_acceleration;
mod scene_bvh;
mod scene_trace;
mod shader_mount;
mod view;

pub use channels::{DepthFormat, GBufferChannel, GBufferChannels, GBufferTextures};
pub use frame_input::{BufferBlock, BufferInput, DeclaredInputs, FrameInput, InputBindings};
pub use lighting::{LIGHTING_BUFFER, LightingUniforms, SceneLighting, SkyColours};
pub use precision::{INTERMEDIATE_ALIAS, intermediate_shader};
pub use scene_acceleration::{
    SCENE_AS_INSTANCES_BUFFER, SCENE_AS_PRIMITIVES_BUFFER, SCENE_TLAS, SceneAcceleration,
    SceneAccelerationInputs, SceneAccelerationResources,
};
pub use scene_bvh::{
    BVH_INSTANCES_BUFFER, BVH_NODES_BUFFER, BVH_TRIANGLES_BUFFER, SceneBvh, SceneBvhBuffers,
    SceneBvhInputs,
};
pub use scene_trace::SceneTraceInputs;
pub use shader_mount::{
    RAY_TRACER, SCENE_TRACE, SCENE_TRACE_HARDWARE, ray_tracer_variant, shader_mount,
};
pub use view::{
    Mat4Cols, ReadsView, VIEW_BINDING, VIEW_BUFFER, ViewBlock, ViewMatrices, ViewUniforms,
};
