//! Fills the graph's `ViewUniforms` block from a scene's camera at a time: matrices, the
//! previous frame's view-projection (for reprojection and motion), viewport and depth range.

use aograph_frame::ViewUniforms;
use aograph_graph::Extent;
use glam::Mat4;

use crate::camera::{Camera, Projection};

/// Per-frame view inputs.
#[derive(Clone, Copy, Debug)]
pub struct ViewFrame {
    pub camera: Camera,
    pub prev_camera: Camera,
    pub output: Extent,
    pub frame_index: u32,
    pub history_valid: bool,
    pub camera_cut: bool,
    pub time: f32,
    pub dt: f32,
}

/// The `View` block for a frame.
pub fn view_uniforms(f: &ViewFrame) -> ViewUniforms {
    let aspect = f.output.width.max(1) as f32 / f.output.height.max(1) as f32;
    let view = f.camera.view();
    let proj = f.camera.projection(aspect);
    let prev_vp = f.prev_camera.view_projection(aspect);
    let inv = |m: Mat4| {
        let i = m.inverse();
        if i.is_finite() { i } else { Mat4::IDENTITY }
    };
    let (reversed, ortho) = match f.camera.projection {
        Projection::Perspective {
            reversed_z_infinite,
            ..
        } => (reversed_z_infinite, false),
        Projection::Orthographic { .. } => (false, true),
    };
    let far = f.camera.far();
    ViewUniforms {
        view: view.to_cols_array_2d(),
        proj: proj.to_cols_array_2d(),
        inv_proj: inv(proj).to_cols_array_2d(),
        inv_view: inv(view).to_cols_array_2d(),
        prev_view_proj: prev_vp.to_cols_array_2d(),
        view_to_prev_clip: (prev_vp * inv(view)).to_cols_array_2d(),
        size: [f.output.width as f32, f.output.height as f32],
        inv_size: [
            1.0 / f.output.width.max(1) as f32,
            1.0 / f.output.height.max(1) as f32,
        ],
        near: f.camera.near(),
        far: if far.is_finite() { far } else { 0.0 },
        reversed_z: reversed as u32 as f32,
        orthographic: ortho as u32 as f32,
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
