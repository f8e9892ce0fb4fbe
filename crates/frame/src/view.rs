//! The per-frame view block every pass of a frame may bind as `var<uniform> view: View`
//! (WGSL mirror in shaders/common/view.wgsl). Camera matrices and viewport are generic
//! rendering data, so the block lives here, shared by the g-buffer and every technique.
//!
//! Conventions: right-handed view space, the camera looks down -Z, linear depth = -z_view > 0;
//! clip depth in wgpu's 0..1 (reversed when `reversed_z == 1`).

use aograph_graph::{BufferAccess, BufferHandle, PassBuilder};

use crate::frame_input::{BufferBlock, BufferInput};
use bytemuck::{Pod, Zeroable};
use glam::Mat4;

/// Column-major 4x4 matrix as WGSL reads it.
pub type Mat4Cols = [[f32; 4]; 4];

/// The `View` uniform block. Matrices, then scalars and `[f32; 2]`s packed four (or two) to a
/// 16-byte row, so the Rust and WGSL layouts agree with no implicit padding.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ViewUniforms {
    /// World to view space (right-handed, the camera looking down -Z).
    pub view: Mat4Cols,
    /// View to clip space (wgpu's 0..1 depth, reversed when `reversed_z` is 1).
    pub proj: Mat4Cols,
    /// Clip to view space: the inverse of `proj` (the identity when `proj` is singular).
    pub inv_proj: Mat4Cols,
    /// View to world space: the inverse of `view` (the identity when `view` is singular).
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

aograph_graph::uniform_layout!(ViewUniforms {
    view,
    proj,
    inv_proj,
    inv_view,
    prev_view_proj,
    view_to_prev_clip,
    size,
    inv_size,
    near,
    far,
    reversed_z,
    orthographic,
    frame_index,
    history_valid,
    camera_cut,
    pad0,
    time,
    dt,
    pad1,
    pad2
});

// Six matrices, then four 16-byte rows; any change here must be mirrored in view.wgsl.
const _: () = assert!(std::mem::size_of::<ViewUniforms>() == 6 * 64 + 4 * 16);

impl ViewUniforms {
    /// The block's 448 bytes, in the WGSL `View` layout, for the buffer imported as
    /// [`VIEW_BUFFER`].
    pub fn bytes(&self) -> &[u8] {
        bytemuck::bytes_of(self)
    }

    /// The block of one frame: the matrices are inverted here (a singular one becomes the
    /// identity), `view_to_prev_clip` is `prev_view_proj * inverse(view)`, and an infinite far
    /// plane is stored as 0. The one place the block is filled, for aograph's own cameras
    /// (`aograph_scene::view_block`) and an application's matrices (the embedding API) alike.
    pub fn from_matrices(f: &ViewMatrices) -> Self {
        let inv = |m: Mat4| {
            let i = m.inverse();
            if i.is_finite() { i } else { Mat4::IDENTITY }
        };
        let (w, h) = (f.width.max(1), f.height.max(1));
        Self {
            view: f.view.to_cols_array_2d(),
            proj: f.proj.to_cols_array_2d(),
            inv_proj: inv(f.proj).to_cols_array_2d(),
            inv_view: inv(f.view).to_cols_array_2d(),
            prev_view_proj: f.prev_view_proj.to_cols_array_2d(),
            view_to_prev_clip: (f.prev_view_proj * inv(f.view)).to_cols_array_2d(),
            size: [f.width as f32, f.height as f32],
            inv_size: [1.0 / w as f32, 1.0 / h as f32],
            near: f.near,
            far: if f.far.is_finite() { f.far } else { 0.0 },
            reversed_z: f.reversed_z as u32 as f32,
            orthographic: f.orthographic as u32 as f32,
            frame_index: f.frame_index,
            history_valid: f.history_valid as u32,
            camera_cut: f.camera_cut as u32,
            pad0: 0,
            time: f.time,
            dt: f.dt,
            pad1: 0.0,
            pad2: 0.0,
        }
    }
}

/// What one frame's [`ViewUniforms`] are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewMatrices {
    /// World to view space (right-handed, looking down -Z).
    pub view: Mat4,
    /// View to clip space (wgpu's 0..1 depth).
    pub proj: Mat4,
    /// The previous frame's `proj * view`.
    pub prev_view_proj: Mat4,
    /// Near plane distance (positive).
    pub near: f32,
    /// Far plane distance; infinity for an infinite far plane.
    pub far: f32,
    /// Near maps to clip depth 1.
    pub reversed_z: bool,
    /// Orthographic projection (false: perspective).
    pub orthographic: bool,
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Counts rendered frames, wrapping; temporal techniques vary their noise with it.
    pub frame_index: u32,
    /// The previous frame's history may be read.
    pub history_valid: bool,
    /// The camera jumped this frame.
    pub camera_cut: bool,
    /// Scene time in seconds.
    pub time: f32,
    /// This frame's time minus the previous frame's, in seconds.
    pub dt: f32,
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

impl BufferBlock for ViewUniforms {
    const NAME: &'static str = "the View block";
    const IMPORT: &'static str = VIEW_BUFFER;
}

/// The frame's `View` block as a frame input: every frame graph declares it (the g-buffer and
/// every technique read it) and its owner binds the buffer it writes each frame.
pub type ViewBlock = BufferInput<ViewUniforms>;
