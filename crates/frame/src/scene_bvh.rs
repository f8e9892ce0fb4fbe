//! The scene's ray-tracing BVH as a frame input: three storage buffers (nodes, instances,
//! triangles; layout in shaders/common/bvh.wgsl, built by `aograph_tracing::gpu`), which
//! a technique that traces rays declares ([`SceneBvhInputs`], from
//! `AoBuildContext::scene_bvh`) and whoever runs the graph binds. A graph that declares none
//! gets no BVH built or uploaded.

use aograph_graph::{BufferDesc, BufferHandle, CompiledGraph, Executor, GraphBuilder, GraphResult};

use crate::frame_input::FrameInput;

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

/// The BVH's three device buffers, as its owner binds them (`aograph_tracing::gpu`
/// builds them).
#[derive(Clone, Debug)]
pub struct SceneBvhBuffers {
    /// Bound behind [`SceneBvhInputs::nodes`].
    pub nodes: wgpu::Buffer,
    /// Bound behind [`SceneBvhInputs::instances`].
    pub instances: wgpu::Buffer,
    /// Bound behind [`SceneBvhInputs::triangles`].
    pub triangles: wgpu::Buffer,
}

/// The scene's BVH as a frame input (`AoBuildContext::scene_bvh`).
pub struct SceneBvh;

impl FrameInput for SceneBvh {
    const NAME: &'static str = "the scene's BVH";
    type Handles = SceneBvhInputs;
    type Resources = SceneBvhBuffers;
    fn declare(b: &mut GraphBuilder) -> SceneBvhInputs {
        // Sizes are the device's business (the BVH is checked against its limits when built).
        let desc = BufferDesc { size: 32 };
        SceneBvhInputs {
            nodes: b.import_buffer(BVH_NODES_BUFFER, desc),
            instances: b.import_buffer(BVH_INSTANCES_BUFFER, desc),
            triangles: b.import_buffer(BVH_TRIANGLES_BUFFER, desc),
        }
    }
    fn bind(
        exec: &mut Executor,
        plan: &CompiledGraph,
        h: SceneBvhInputs,
        r: &SceneBvhBuffers,
    ) -> GraphResult<()> {
        exec.bind_import_buffer(plan, h.nodes, r.nodes.clone())?;
        exec.bind_import_buffer(plan, h.instances, r.instances.clone())?;
        exec.bind_import_buffer(plan, h.triangles, r.triangles.clone())
    }
}
