//! The scene's BVH on the device: [`SceneBvh`]'s three arrays in storage buffers, checked
//! against the device's limits before anything is allocated, and kept current by uploading
//! only what an update rewrote (nothing at all for a static scene).
//!
//! Invariant: the buffers keep their size for the scene's lifetime (updates rewrite in place),
//! so a graph binding them never needs rebinding; each holds at least one element (wgpu has no
//! zero-size bindings), and element 0 of an empty BVH is a node or record no ray uses.

use crate::error::TracingError;
use std::sync::Arc;

use aograph_graph::GpuContext;
use bytemuck::Pod;

use super::gpu_io::buffer_of;
use super::limits::check_bvh_fits;
use super::scene_bvh::{BvhUpdate, BvhWork, SceneBvh};
use aograph_scene::model::Scene;

/// Graph import names of the three buffers (the rtao technique declares them; whoever runs
/// the graph binds [`GpuSceneBvh`]'s buffers under them).
pub use aograph_frame::{BVH_INSTANCES_BUFFER, BVH_NODES_BUFFER, BVH_TRIANGLES_BUFFER};

/// The BVH of one scene on one device.
pub struct GpuSceneBvh {
    /// The CPU copy, always at the time of the last successful [`GpuSceneBvh::update`].
    pub bvh: SceneBvh,
    /// Storage buffer of [`SceneBvh::nodes`] (`BvhNode` array), bound as [`BVH_NODES_BUFFER`].
    pub nodes: wgpu::Buffer,
    /// Storage buffer of [`SceneBvh::instances`], bound as [`BVH_INSTANCES_BUFFER`].
    pub instances: wgpu::Buffer,
    /// Storage buffer of [`SceneBvh::triangles`], bound as [`BVH_TRIANGLES_BUFFER`].
    pub triangles: wgpu::Buffer,
    gpu: Arc<GpuContext>,
    /// Everything done since creation, the first build included.
    pub work: BvhWork,
    /// Bytes written to the buffers since creation.
    pub bytes_uploaded: u64,
}

fn storage_buffer<T: Pod>(gpu: &GpuContext, label: &str, items: &[T]) -> wgpu::Buffer {
    buffer_of(
        gpu,
        label,
        items,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    )
}

impl GpuSceneBvh {
    /// Builds `scene`'s BVH at time `t` and uploads it; a BVH over the device's limits is a
    /// [`TracingError::BvhTooLarge`] before any buffer is made.
    pub fn new(gpu: Arc<GpuContext>, scene: &Scene, t: f32) -> Result<GpuSceneBvh, TracingError> {
        let (bvh, work) = SceneBvh::build(scene, t)?;
        let sizes = bvh.sizes();
        check_bvh_fits(&sizes, &gpu.device.limits())?;
        Ok(GpuSceneBvh {
            nodes: storage_buffer(&gpu, "bvh.nodes", &bvh.nodes),
            instances: storage_buffer(&gpu, "bvh.instances", &bvh.instances),
            triangles: storage_buffer(&gpu, "bvh.triangles", &bvh.triangles),
            bvh,
            gpu,
            work,
            bytes_uploaded: sizes.total(),
        })
    }

    /// Moves the BVH to time `t`, uploading only what changed; returns what was done.
    pub fn update(&mut self, scene: &Scene, t: f32) -> Result<BvhWork, TracingError> {
        let BvhUpdate {
            work,
            nodes,
            instances,
            triangles,
        } = self.bvh.update(scene, t)?;
        for r in nodes {
            self.bytes_uploaded += write(&self.gpu, &self.nodes, &self.bvh.nodes, r);
        }
        if let Some(r) = instances {
            self.bytes_uploaded += write(&self.gpu, &self.instances, &self.bvh.instances, r);
        }
        for r in triangles {
            self.bytes_uploaded += write(&self.gpu, &self.triangles, &self.bvh.triangles, r);
        }
        self.work += work;
        Ok(work)
    }
}

/// Writes `items[range]` to `buffer` at its offset; returns the bytes written.
fn write<T: Pod>(
    gpu: &GpuContext,
    buffer: &wgpu::Buffer,
    items: &[T],
    range: std::ops::Range<usize>,
) -> u64 {
    let size = std::mem::size_of::<T>();
    let bytes: &[u8] = bytemuck::cast_slice(&items[range.clone()]);
    if bytes.is_empty() {
        return 0;
    }
    gpu.queue
        .write_buffer(buffer, (range.start * size) as u64, bytes);
    bytes.len() as u64
}
