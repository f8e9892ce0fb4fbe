//! The scene as acceleration structures, a frame input: the TLAS and its two tables (layout in
//! shaders/common/hardware_scene.wgsl, built by `aograph_tracing::gpu::HardwareSceneAs`),
//! which a technique tracing rays on the hardware backend declares
//! ([`SceneAccelerationInputs`], from `AoBuildContext::scene_trace`) and whoever runs the graph
//! builds, updates per frame and binds. A graph that declares none gets none built.

use aograph_graph::{
    AccelerationStructureHandle, BufferDesc, BufferHandle, CompiledGraph, Executor, GraphBuilder,
    GraphResult,
};

use crate::frame_input::FrameInput;

/// Import name of the scene's top-level acceleration structure.
pub const SCENE_TLAS: &str = "scene_as.tlas";
/// Import name of the placed instances' rows (the TLAS custom index names one).
pub const SCENE_AS_INSTANCES_BUFFER: &str = "scene_as.instances";
/// Import name of the primitive table (a BLAS primitive back to the mesh's triangle order).
pub const SCENE_AS_PRIMITIVES_BUFFER: &str = "scene_as.primitives";

/// The graph's handles of the imported acceleration structures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneAccelerationInputs {
    /// The TLAS, imported as [`SCENE_TLAS`] (`scene` in hardware_scene.wgsl).
    pub tlas: AccelerationStructureHandle,
    /// Instance rows, imported as [`SCENE_AS_INSTANCES_BUFFER`] (`hw_instances`).
    pub instances: BufferHandle,
    /// Primitive table, imported as [`SCENE_AS_PRIMITIVES_BUFFER`] (`hw_primitives`).
    pub primitives: BufferHandle,
}

/// The acceleration structures' device objects, as their owner binds them
/// (`aograph_tracing::gpu::HardwareSceneAs` builds them).
#[derive(Clone, Debug)]
pub struct SceneAccelerationResources {
    /// Bound behind [`SceneAccelerationInputs::tlas`].
    pub tlas: wgpu::Tlas,
    /// Bound behind [`SceneAccelerationInputs::instances`].
    pub instances: wgpu::Buffer,
    /// Bound behind [`SceneAccelerationInputs::primitives`].
    pub primitives: wgpu::Buffer,
}

/// The scene's acceleration structures as a frame input (`AoBuildContext::scene_trace` on the
/// hardware backend).
pub struct SceneAcceleration;

impl FrameInput for SceneAcceleration {
    const NAME: &'static str = "the scene's acceleration structures";
    type Handles = SceneAccelerationInputs;
    type Resources = SceneAccelerationResources;
    fn declare(b: &mut GraphBuilder) -> SceneAccelerationInputs {
        let desc = BufferDesc { size: 16 };
        SceneAccelerationInputs {
            tlas: b.import_acceleration_structure(SCENE_TLAS),
            instances: b.import_buffer(SCENE_AS_INSTANCES_BUFFER, desc),
            primitives: b.import_buffer(SCENE_AS_PRIMITIVES_BUFFER, desc),
        }
    }
    fn bind(
        exec: &mut Executor,
        plan: &CompiledGraph,
        h: SceneAccelerationInputs,
        r: &SceneAccelerationResources,
    ) -> GraphResult<()> {
        exec.bind_import_acceleration_structure(plan, h.tlas, r.tlas.clone())?;
        exec.bind_import_buffer(plan, h.instances, r.instances.clone())?;
        exec.bind_import_buffer(plan, h.primitives, r.primitives.clone())
    }
}
