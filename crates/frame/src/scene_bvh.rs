//! The scene's ray-tracing BVH as a frame input: three storage buffers (nodes, instances,
//! triangles; layout in shaders/common/bvh.wgsl, built by `aograph_scene::ray_tracing`), which
//! a technique that traces rays declares ([`SceneBvhInputs`], from
//! `AoBuildContext::scene_bvh`) and whoever runs the graph binds. A graph that declares none
//! gets no BVH built or uploaded.

use aograph_graph::BufferHandle;

/// Import name of the BVH's node buffer (the top level, then every bottom level).
pub const BVH_NODES_BUFFER: &str = "scene_bvh.nodes";
/// Import name of the BVH's instance buffer (one record per placed mesh instance).
pub const BVH_INSTANCES_BUFFER: &str = "scene_bvh.instances";
/// Import name of the BVH's triangle buffer (vertices in leaf order).
pub const BVH_TRIANGLES_BUFFER: &str = "scene_bvh.triangles";

/// The graph's handles of the imported BVH buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBvhInputs {
    /// Nodes, imported as [`BVH_NODES_BUFFER`]: the top-level tree first, then every
    /// bottom-level one (`BvhNode` in bvh.wgsl).
    pub nodes: BufferHandle,
    /// Placed instances, imported as [`BVH_INSTANCES_BUFFER`]: world-to-object rows, the root
    /// of the instance's bottom-level tree and whether it moves (`BvhInstance`).
    pub instances: BufferHandle,
    /// Triangles, imported as [`BVH_TRIANGLES_BUFFER`]: three vertices each, in leaf order
    /// (`BvhTriangle`).
    pub triangles: BufferHandle,
}
