#include "common/view.wgsl"
// Half-resolution g-buffer, view-space positions (Rgba32Float, w = 1 on geometry, 0 on sky):
// rebuilt from the half depth at each half texel's centre through the half view block
// (blocks/half_view.wgsl), so a position and its depth describe the same point, the one the
// selection moved to the block's centre.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let z = textureLoad(depth, p, 0).r;
    if (!(z > 0.0)) {
        textureStore(dst, p, vec4<f32>(0.0));
        return;
    }
    textureStore(dst, p, vec4<f32>(view_position(pixel_uv(p, view), z, view), 1.0));
}
