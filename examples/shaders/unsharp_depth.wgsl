#include "common/view.wgsl"
// A user AO plugin: depth-buffer unsharp masking (Luft, Colditz and Deussen 2006). The
// difference between a pixel's depth and its blurred neighbourhood darkens creases.

struct Params { strength: f32, radius_px: f32, pad0: f32, pad1: f32 }

@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var<uniform> params: Params;
@group(0) @binding(3) var ao: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(depth));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    let z = textureLoad(depth, p, 0).r;
    if (z <= 0.0) {
        textureStore(ao, p, vec4<f32>(1.0));
        return;
    }
    let r = i32(clamp(params.radius_px, 1.0, 16.0));
    var sum = 0.0;
    var count = 0.0;
    for (var dy = -r; dy <= r; dy = dy + 1) {
        for (var dx = -r; dx <= r; dx = dx + 1) {
            let q = clamp(p + vec2<i32>(dx, dy), vec2<i32>(0), size - 1);
            let zq = textureLoad(depth, q, 0).r;
            if (zq > 0.0) {
                sum = sum + zq;
                count = count + 1.0;
            }
        }
    }
    // Positive where the neighbourhood is nearer than the pixel: a crease.
    let delta = max(z - sum / max(count, 1.0), 0.0) / z;
    textureStore(ao, p, vec4<f32>(clamp(1.0 - params.strength * delta, 0.0, 1.0)));
}
