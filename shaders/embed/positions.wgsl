#include "common/view.wgsl"
// Embedding input adapter: view-space positions (Rgba32Float, w = 1 on geometry, 0 on sky)
// from linear depth, through the projection's x and y rows (common/view.wgsl view_position).

@group(0) @binding(0) var linear_depth: texture_2d<f32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var positions: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(positions);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let z = textureLoad(linear_depth, p, 0).r;
    if (z <= 0.0) {
        textureStore(positions, p, vec4<f32>(0.0));
        return;
    }
    textureStore(positions, p, vec4<f32>(view_position(pixel_uv(p, view), z, view), 1.0));
}
