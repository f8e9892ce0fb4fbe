//! The scene as the renderer's ray-tracing passes read it: the BVH buffers (compute backend)
//! and the acceleration structures (hardware backend), each built the first time a graph
//! declares it (the frame inputs `SceneBvh`, `SceneAcceleration`), bound per plan behind the
//! handles the graph declared, and moved to each frame's time before the frame runs. A static
//! scene builds once and does no per-frame work; moving instances rebuild the TLAS; moving
//! skins rebuild their BLAS.
//!
//! Invariant: what a plan binds behind those handles is the structure built for the current
//! scene, moved to the time of the frame about to execute.

use std::sync::Arc;

use aograph_frame::{
    DeclaredInputs, InputBindings, SceneAcceleration, SceneAccelerationResources, SceneBvh,
    SceneBvhBuffers,
};
use aograph_graph::GpuContext;
use aograph_scene::Scene;
use aograph_tracing::gpu::{AsWork, GpuSceneBvh, HardwareSceneAs};

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
    /// Builds what `declared` asks for and has not been built, and moves everything built to
    /// `time`. Returns whether something was built (to supply: [`Self::supply`]).
    pub fn update(
        &mut self,
        gpu: &Arc<GpuContext>,
        scene: &Scene,
        declared: &DeclaredInputs,
        time: f32,
    ) -> RenderResult<bool> {
        let mut built = false;
        if declared.contains::<SceneBvh>() {
            match &mut self.bvh {
                Some(bvh) => {
                    bvh.update(scene, time)?;
                }
                None => {
                    self.bvh = Some(GpuSceneBvh::new(gpu.clone(), scene, time)?);
                    built = true;
                }
            }
        }
        if declared.contains::<SceneAcceleration>() {
            match &mut self.acceleration {
                Some(a) => {
                    a.update(gpu, scene, time)?;
                }
                None => {
                    self.acceleration = Some(HardwareSceneAs::build(gpu, scene, time)?);
                    built = true;
                }
            }
        }
        Ok(built)
    }

    /// Supplies what is built to `inputs`, for every plan declaring it.
    pub fn supply(&self, inputs: &mut InputBindings) {
        if let Some(bvh) = &self.bvh {
            inputs.set::<SceneBvh>(SceneBvhBuffers {
                nodes: bvh.nodes.clone(),
                instances: bvh.instances.clone(),
                triangles: bvh.triangles.clone(),
            });
        }
        if let Some(a) = &self.acceleration {
            inputs.set::<SceneAcceleration>(SceneAccelerationResources {
                tlas: a.tlas.clone(),
                instances: a.instances.clone(),
                primitives: a.primitives.clone(),
            });
        }
    }

    /// What the last update of the acceleration structures did (`None` before one is built).
    pub fn acceleration_work(&self) -> Option<AsWork> {
        self.acceleration.as_ref().map(|a| a.work)
    }
}
