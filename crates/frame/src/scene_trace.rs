//! What a ray-tracing pass traces against: the compute BVH ([`SceneBvhInputs`]) or the
//! acceleration structures ([`SceneAccelerationInputs`]). A pass's shader is written once
//! against shaders/common/scene_trace.wgsl; [`SceneTraceInputs::shader`] names the variant for
//! the backend and [`SceneTraceInputs::bind`] binds that backend's three globals, so a
//! technique states its passes once for both.
//!
//! Invariant: the shader named and the globals bound are of the same backend.

use aograph_graph::{BufferAccess, PassBuilder};

use crate::shader_mount::ray_tracer_variant;

use crate::scene_acceleration::SceneAccelerationInputs;
use crate::scene_bvh::SceneBvhInputs;

/// The scene a ray-tracing pass reads, on one backend of the GPU tracer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneTraceInputs {
    /// The two-level BVH in storage buffers (common/bvh.wgsl), traversed by compute shaders.
    Compute(SceneBvhInputs),
    /// The TLAS and its tables (common/hardware_scene.wgsl), traversed by ray queries.
    Hardware(SceneAccelerationInputs),
}

impl SceneTraceInputs {
    /// The variant of `file` (which includes common/scene_trace.wgsl) for this backend.
    pub fn shader(&self, file: &str) -> String {
        ray_tracer_variant(file, matches!(self, Self::Hardware(_)))
    }
    /// Binds the backend's scene globals of `pass`.
    pub fn bind(&self, pass: &mut PassBuilder<'_>) {
        let read = BufferAccess::StorageRead;
        match *self {
            Self::Compute(bvh) => {
                pass.read_buffer("bvh_nodes", read, bvh.nodes)
                    .read_buffer("bvh_instances", read, bvh.instances)
                    .read_buffer("bvh_triangles", read, bvh.triangles);
            }
            Self::Hardware(a) => {
                pass.read_acceleration_structure("scene", a.tlas)
                    .read_buffer("hw_instances", read, a.instances)
                    .read_buffer("hw_primitives", read, a.primitives);
            }
        }
    }
}
