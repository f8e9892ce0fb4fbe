//! The scene as acceleration structures, a frame input: the TLAS and its two tables (layout in
//! shaders/common/hardware_scene.wgsl, built by `aograph_scene::ray_tracing::HardwareSceneAs`),
//! which a technique tracing rays on the hardware backend declares
//! ([`SceneAccelerationInputs`], from `AoBuildContext::scene_trace`) and whoever runs the graph
//! builds, updates per frame and binds. A graph that declares none gets none built.

use aograph_graph::{AccelerationStructureHandle, BufferHandle};

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
