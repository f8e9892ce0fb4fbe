#include "common/view.wgsl"
// Half-resolution g-buffer, the selection (crates/ao-passes/src/blocks/half_resolution.rs): for
// each half-size texel p, the 2x2 block of full pixels 2p + (0..1, 0..1) (those inside the
// image). The rule: the block's nearest surface (smallest positive linear depth; sky sorts
// last) is kept, with its normal, and its depth is moved to the block's centre, full pixel
// corner 2p + 1, along its tangent plane (the depth where the ray through the centre meets
// the plane through the sample with its normal), so a plane stays on itself at half
// resolution. Where the plane is edge-on to that ray (or the move exceeds half the depth) the
// sample's own depth is kept. Writes the half depth (0 = sky), the normal (w = 1 on geometry,
// 0 on sky, as the g-buffer's) and which of the four was kept (0..3, x + 2y), for the gather
// passes that copy the other channels of the same sample.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var half_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var half_normals: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var choice: texture_storage_2d<r32uint, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(half_depth);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let full = vec2<i32>(textureDimensions(depth));
    var best = 3.0e38;
    var pick = 0u;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let q = 2 * p + vec2<i32>(i32(k & 1u), i32(k >> 1u));
        let inside = all(q < full);
        let z = textureLoad(depth, min(q, full - 1), 0).r;
        if (inside && z > 0.0 && z < best) {
            best = z;
            pick = k;
        }
    }
    textureStore(choice, p, vec4<u32>(pick, 0u, 0u, 0u));
    if (!(best < 3.0e38)) {
        textureStore(half_depth, p, vec4<f32>(0.0));
        textureStore(half_normals, p, vec4<f32>(0.0));
        return;
    }
    let q = 2 * p + vec2<i32>(i32(pick & 1u), i32(pick >> 1u));
    let nw = textureLoad(normals, q, 0);
    let s = view_position(pixel_uv(q, view), best, view);
    // The ray through the block's centre: the point at depth 1 on it (perspective: X = t r),
    // or (r.xy, -t) for an orthographic camera.
    let r = view_position(vec2<f32>(2 * p + 1) * view.inv_size, 1.0, view);
    var t = best;
    let n = nw.xyz;
    if (view.orthographic > 0.5) {
        if (abs(n.z) > 1e-6) {
            t = (dot(n.xy, r.xy) - dot(n, s)) / n.z;
        }
    } else {
        let d = dot(n, r);
        if (abs(d) > 1e-12) {
            t = dot(n, s) / d;
        }
    }
    let z = select(best, t, t > 0.0 && abs(t / best - 1.0) < 0.5);
    textureStore(half_depth, p, vec4<f32>(z, 0.0, 0.0, 0.0));
    textureStore(half_normals, p, nw);
}
