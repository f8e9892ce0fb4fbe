//! The scene's ray-tracing BVH as a frame input: three storage buffers (nodes, instances,
//! triangles; layout in shaders/common/bvh.wgsl, built by `aograph_scene::ray_tracing`), which
//! a technique that traces rays declares ([`SceneBvhInputs`], from
//! `AoBuildContext::scene_bvh`) and whoever runs the graph binds. A graph that declares none
//! gets no BVH built or uploaded.

use aograph_graph::BufferHandle;

/// Import names of the BVH's buffers.
pub const BVH_NODES_BUFFER: &str = "scene_bvh.nodes";
pub const BVH_INSTANCES_BUFFER: &str = "scene_bvh.instances";
pub const BVH_TRIANGLES_BUFFER: &str = "scene_bvh.triangles";

/// The graph's handles of the imported BVH buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBvhInputs {
    pub nodes: BufferHandle,
    pub instances: BufferHandle,
    pub triangles: BufferHandle,
}
