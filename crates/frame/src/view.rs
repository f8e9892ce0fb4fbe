//! The per-frame view block every pass of a frame may bind as `var<uniform> view: View`
//! (WGSL mirror in shaders/common/view.wgsl). Camera matrices and viewport are generic
//! rendering data, so the block lives here, shared by the g-buffer and every technique.
//!
//! Conventions: right-handed view space, the camera looks down -Z, linear depth = -z_view > 0;
//! clip depth in wgpu's 0..1 (reversed when `reversed_z == 1`).

use aograph_graph::{BufferAccess, BufferHandle, PassBuilder};
use bytemuck::{Pod, Zeroable};

/// Column-major 4x4 matrix as WGSL reads it.
pub type Mat4Cols = [[f32; 4]; 4];

/// The `View` uniform block. Matrices, then scalars and `[f32; 2]`s packed four (or two) to a
/// 16-byte row, so the Rust and WGSL layouts agree with no implicit padding.
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
    /// Output width, height in pixels.
    pub size: [f32; 2],
    /// 1/width, 1/height (one pixel in UV).
    pub inv_size: [f32; 2],
    /// Near plane distance (view-space units).
    pub near: f32,
    /// Far plane distance (view-space units); 0 = infinite.
    pub far: f32,
    /// Reversed-Z depth, 0/1 (1: near maps to clip depth 1).
    pub reversed_z: f32,
    /// Orthographic projection, 0/1 (0: perspective).
    pub orthographic: f32,
    /// Frame index (counts rendered frames, wrapping).
    pub frame_index: u32,
    /// History valid, 0/1 (1: the previous frame's history may be read).
    pub history_valid: u32,
    /// Camera cut, 0/1 (1: the camera jumped this frame).
    pub camera_cut: u32,
    /// Unused; pads the row to 16 bytes.
    pub pad0: u32,
    /// Scene time in seconds.
    pub time: f32,
    /// Frame time dt in seconds (time minus the previous frame's).
    pub dt: f32,
    /// Unused; pads the row to 16 bytes.
    pub pad1: f32,
    /// Unused; pads the row to 16 bytes.
    pub pad2: f32,
}

// Six matrices, then four 16-byte rows; any change here must be mirrored in view.wgsl.
const _: () = assert!(std::mem::size_of::<ViewUniforms>() == 6 * 64 + 4 * 16);

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
