//! The per-frame view block every pass of a frame may bind as `var<uniform> view: View`
//! (WGSL mirror in shaders/common/view.wgsl). Camera matrices and viewport are generic
//! rendering data, so the block lives here, shared by the g-buffer and every technique.
//!
//! Conventions: right-handed view space, the camera looks down -Z, linear depth = -z_view > 0;
//! clip depth in wgpu's 0..1 (reversed when `near_far[2] == 1`).

use aograph_graph::{BufferAccess, BufferHandle, PassBuilder};
use bytemuck::{Pod, Zeroable};

/// Column-major 4x4 matrix as WGSL reads it.
pub type Mat4Cols = [[f32; 4]; 4];

/// The `View` uniform block. 16-byte aligned fields only, so the Rust and WGSL layouts agree.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ViewUniforms {
    pub view: Mat4Cols,
    pub proj: Mat4Cols,
    pub inv_proj: Mat4Cols,
    pub inv_view: Mat4Cols,
    /// Previous frame's view-projection (world to previous clip space).
    pub prev_view_proj: Mat4Cols,
    /// This frame's view space to the previous frame's clip space (static-scene reprojection).
    pub view_to_prev_clip: Mat4Cols,
    /// width, height, 1/width, 1/height in pixels.
    pub viewport: [f32; 4],
    /// near, far (0 = infinite), reversed_z (0/1), orthographic (0/1).
    pub near_far: [f32; 4],
    /// frame index, history valid (0/1), camera cut (0/1), unused.
    pub frame: [u32; 4],
    /// time in seconds, frame time dt, unused, unused.
    pub time: [f32; 4],
}

impl ViewUniforms {
    pub fn bytes(&self) -> &[u8] {
        bytemuck::bytes_of(self)
    }
}

/// Name under which the view block is imported as a buffer into every graph.
pub const VIEW_BUFFER: &str = "view";

/// The WGSL name every shader gives the block (`var<uniform> view: View`).
pub const VIEW_BINDING: &str = "view";

/// Binds the frame's `View` block to a pass: the one place its WGSL name is written, so no
/// technique spells it.
pub trait ReadsView {
    /// The pass reads the View block `view` (the frame's imported buffer) as a uniform.
    fn read_view(&mut self, view: BufferHandle) -> &mut Self;
}

impl ReadsView for PassBuilder<'_> {
    fn read_view(&mut self, view: BufferHandle) -> &mut Self {
        self.read_buffer(VIEW_BINDING, BufferAccess::Uniform, view)
    }
}
