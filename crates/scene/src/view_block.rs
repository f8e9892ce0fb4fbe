//! Fills the graph's `ViewUniforms` block from a scene's camera at a time: matrices, the
//! previous frame's view-projection (for reprojection and motion), viewport and depth range.

use aograph_frame::{ViewMatrices, ViewUniforms};
use aograph_graph::Extent;

use crate::camera::{Camera, Projection};

/// Per-frame view inputs.
#[derive(Clone, Copy, Debug)]
pub struct ViewFrame {
    /// This frame's camera: the view and projection matrices, near/far and depth convention.
    pub camera: Camera,
    /// The previous frame's camera, giving `prev_view_proj` for reprojection and motion
    /// (pass `camera` again when there is no previous frame).
    pub prev_camera: Camera,
    /// Output size in pixels; also sets the projection's aspect ratio.
    pub output: Extent,
    /// Frames rendered so far, wrapping; temporal techniques vary their noise with it.
    pub frame_index: u32,
    /// Whether the previous frame's history textures hold valid data to reuse.
    pub history_valid: bool,
    /// The camera jumped this frame, so temporal techniques should drop their history.
    pub camera_cut: bool,
    /// Scene time in seconds.
    pub time: f32,
    /// This frame's time minus the previous frame's, in seconds.
    pub dt: f32,
}

/// The `View` block for a frame.
pub fn view_uniforms(f: &ViewFrame) -> ViewUniforms {
    let aspect = f.output.width.max(1) as f32 / f.output.height.max(1) as f32;
    let (reversed_z, orthographic) = match f.camera.projection {
        Projection::Perspective {
            reversed_z_infinite,
            ..
        } => (reversed_z_infinite, false),
        Projection::Orthographic { .. } => (false, true),
    };
    ViewUniforms::from_matrices(&ViewMatrices {
        view: f.camera.view(),
        proj: f.camera.projection(aspect),
        prev_view_proj: f.prev_camera.view_projection(aspect),
        near: f.camera.near(),
        far: f.camera.far(),
        reversed_z,
        orthographic,
        width: f.output.width,
        height: f.output.height,
        frame_index: f.frame_index,
        history_valid: f.history_valid,
        camera_cut: f.camera_cut,
        time: f.time,
        dt: f.dt,
    })
}
