#include "common/view.wgsl"
// Embedding input adapter: an application's motion vectors to aograph's motion channel
// (Rgba32Float: xy = previous uv - uv, z = the surface's previous linear depth, 0 on sky).
// The application states its convention as a scale: previous uv = uv + uv_scale * m.xy
// ((1, 1) for aograph's; (-1, -1) for "current - previous"; (1/w, 1/h) or (-1/w, -1/h) for
// pixels; (0.5, -0.5) or (-0.5, 0.5) for NDC offsets, whose y points up). Motion vectors carry
// no depth: z is the previous linear depth of this point held still (the camera's motion only),
// which is what the reprojection's disocclusion test compares against.

@group(0) @binding(0) var motion_in: texture_2d<f32>;
@group(0) @binding(1) var linear_depth: texture_2d<f32>;
@group(0) @binding(2) var<uniform> view: View;
@group(0) @binding(3) var<uniform> uv_scale: vec4<f32>;
@group(0) @binding(4) var motion: texture_storage_2d<rgba32float, write>;
// The viewport's top-left corner in motion_in (0, 0 without one): see adapters.rs.
@group(0) @binding(5) var<uniform> viewport: vec4<u32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(motion);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let z = textureLoad(linear_depth, p, 0).r;
    if (z <= 0.0) {
        textureStore(motion, p, vec4<f32>(0.0));
        return;
    }
    let m = textureLoad(motion_in, p + vec2<i32>(viewport.xy), 0).xy * uv_scale.xy;
    let pv = view_position(pixel_uv(p, view), z, view);
    let prev_z = clip_linear_depth(view.view_to_prev_clip * vec4<f32>(pv, 1.0), view);
    textureStore(motion, p, vec4<f32>(m, prev_z, 0.0));
}
