#include "common/view.wgsl"
// Embedding input adapter: an application's hardware depth (Depth32Float, Depth24Plus or
// Depth16Unorm) to aograph's linear depth (R32Float, -z_view > 0, 0 = sky), for whatever
// convention the projection encodes: standard or reversed Z, finite or infinite far plane,
// perspective or orthographic. Only the projection's z and w rows enter (wgpu's 0..1 clip depth):
//   perspective (w = -z_view): d = P32 / lin - P22, so lin = P32 / (d + P22);
//   orthographic (w = 1):      d = P32 - P22 lin,  so lin = (P32 - d) / P22,
// with P22 = proj[2][2] and P32 = proj[3][2] (column, row). A texel at the far plane's value
// (the clear value: 1 with standard Z, 0 with reversed Z) is sky.

@group(0) @binding(0) var depth: texture_depth_2d;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var linear_depth: texture_storage_2d<r32float, write>;
// The viewport's top-left corner in depth (0, 0 without one): see adapters.rs.
@group(0) @binding(3) var<uniform> viewport: vec4<u32>;

fn linear_from_hardware(d: f32) -> f32 {
    let far_value = select(1.0, 0.0, view.reversed_z > 0.5);
    if (d == far_value) { return 0.0; }
    let p22 = view.proj[2][2];
    let p32 = view.proj[3][2];
    var lin: f32;
    if (view.orthographic > 0.5) {
        lin = (p32 - d) / p22;
    } else {
        lin = p32 / (d + p22);
    }
    // Behind the camera or not a number (a depth outside the projection's range): sky.
    return select(0.0, lin, lin > 0.0 && lin < 3.0e38);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(linear_depth);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let d = textureLoad(depth, p + vec2<i32>(viewport.xy), 0);
    textureStore(linear_depth, p, vec4<f32>(linear_from_hardware(d), 0.0, 0.0, 0.0));
}
