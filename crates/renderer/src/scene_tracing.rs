//! The scene as the renderer's ray-tracing passes read it: the BVH buffers (compute backend)
//! and the acceleration structures (hardware backend), each built the first time a graph
//! declares it (`DeclaredInputs`), imported into the executor under the names the graph binds,
//! and moved to each frame's time before the frame runs. A static scene builds once and does
//! no per-frame work; moving instances rebuild the TLAS; moving skins rebuild their BLAS.
//!
//! Invariant: what the executor binds under the import names is the structure built for the
//! current scene, moved to the time of the frame about to execute.

use std::sync::Arc;

use aograph_ao::DeclaredInputs;
use aograph_frame::{
    BVH_INSTANCES_BUFFER, BVH_NODES_BUFFER, BVH_TRIANGLES_BUFFER, SCENE_AS_INSTANCES_BUFFER,
    SCENE_AS_PRIMITIVES_BUFFER, SCENE_TLAS,
};
use aograph_graph::{Executor, GpuContext};
use aograph_scene::Scene;
use aograph_scene::ray_tracing::{AsWork, GpuSceneBvh, HardwareSceneAs};

use crate::error::RenderResult;

/// The scene's ray-tracing structures on the device, each `None` until a graph asks for it.
#[derive(Default)]
pub(crate) struct SceneTracing {
    /// The compute backend's BVH.
    pub bvh: Option<GpuSceneBvh>,
    /// The hardware backend's BLAS and TLAS.
    pub acceleration: Option<HardwareSceneAs>,
}

impl SceneTracing {
    /// Builds what `declared` asks for and has not been built, binds it in `exec`, and moves
    /// everything built to `time`.
    pub fn update(
        &mut self,
        gpu: &Arc<GpuContext>,
        exec: &mut Executor,
        scene: &Scene,
        declared: &DeclaredInputs,
        time: f32,
    ) -> RenderResult<()> {
        if declared.scene_bvh.is_some() {
            match &mut self.bvh {
                Some(bvh) => {
                    bvh.update(scene, time)?;
                }
                None => {
                    let bvh = GpuSceneBvh::new(gpu.clone(), scene, time)?;
                    exec.import_buffer(BVH_NODES_BUFFER, bvh.nodes.clone());
                    exec.import_buffer(BVH_INSTANCES_BUFFER, bvh.instances.clone());
                    exec.import_buffer(BVH_TRIANGLES_BUFFER, bvh.triangles.clone());
                    self.bvh = Some(bvh);
                }
            }
        }
        if declared.scene_acceleration.is_some() {
            match &mut self.acceleration {
                Some(a) => {
                    a.update(gpu, scene, time)?;
                }
                None => {
                    let a = HardwareSceneAs::build(gpu, scene, time)?;
                    exec.import_acceleration_structure(SCENE_TLAS, a.tlas.clone());
                    exec.import_buffer(SCENE_AS_INSTANCES_BUFFER, a.instances.clone());
                    exec.import_buffer(SCENE_AS_PRIMITIVES_BUFFER, a.primitives.clone());
                    self.acceleration = Some(a);
                }
            }
        }
        Ok(())
    }

    /// What the last update of the acceleration structures did (`None` before one is built).
    pub fn acceleration_work(&self) -> Option<AsWork> {
        self.acceleration.as_ref().map(|a| a.work)
    }
}
