//! A bevy camera's frame in the terms aograph-embed reads: its prepass textures and matrices
//! mapped onto [`AoInputs`], once, here.
//!
//! bevy 0.20's prepass, as aograph reads it:
//! - depth: Depth32Float, reversed Z with an infinite far plane for perspective cameras
//!   (`DepthConvention` reads that off the projection), the size of the render target;
//! - normals: Rgb10a2Unorm, world space, packed as `n * 0.5 + 0.5`;
//! - motion vectors: Rg16Float, current minus previous position in uv (`uv_scale = [-1, -1]`);
//! - the projection is the one bevy's view uniform holds, so TAA's sub-pixel jitter is applied
//!   as bevy applies it; the view's viewport (physical pixels) is the rectangle AO is made for,
//!   and bevy's PBR pass reads AO at `frag_coord - viewport.xy`, so the output is that size.

use aograph_embed::{
    AoInputs, DepthInput, MotionInput, NormalEncoding, NormalSpace, NormalsInput, Viewport,
};
use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::math::Vec4Swizzles;
use bevy::render::camera::TemporalJitter;
use bevy::render::view::ExtractedView;

/// bevy's motion vectors are current minus previous, in uv: previous uv = uv - m.
pub const BEVY_MOTION_UV_SCALE: [f32; 2] = [-1.0, -1.0];

/// The AO inputs of one bevy view: its prepass depth (required), normals and motion vectors
/// (when the camera has those prepasses), its projection (jittered as bevy jitters it) and
/// view matrix, and its viewport when it covers part of the target. `None` without a depth
/// prepass.
pub fn ao_inputs<'a>(
    prepass: &'a ViewPrepassTextures,
    view: &ExtractedView,
    jitter: Option<&TemporalJitter>,
    time: f32,
) -> Option<AoInputs<'a>> {
    let depth: &wgpu::Texture = &prepass.depth.as_ref()?.texture.texture;
    let viewport = view.viewport;
    let mut projection = view.clip_from_view;
    if let Some(jitter) = jitter {
        jitter.jitter_projection(&mut projection, viewport.zw().as_vec2());
    }
    let world_to_view = view.world_from_view.to_matrix().inverse();
    // bevy's glam and aograph's may be different versions: matrices cross as column arrays.
    let mut inputs = AoInputs::from_column_arrays(
        DepthInput::Hardware(depth),
        projection.to_cols_array_2d(),
        world_to_view.to_cols_array_2d(),
    );
    inputs.normals = prepass.normal.as_ref().map(|n| NormalsInput {
        texture: &n.texture.texture,
        space: NormalSpace::World,
        encoding: NormalEncoding::PackedXyz,
    });
    inputs.motion = prepass.motion_vectors.as_ref().map(|m| MotionInput {
        texture: &m.texture.texture,
        uv_scale: BEVY_MOTION_UV_SCALE,
    });
    inputs.time = time;
    let whole =
        (viewport.x, viewport.y, viewport.z, viewport.w) == (0, 0, depth.width(), depth.height());
    if !whole {
        inputs.viewport = Some(Viewport {
            x: viewport.x,
            y: viewport.y,
            width: viewport.z,
            height: viewport.w,
        });
    }
    Some(inputs)
}
