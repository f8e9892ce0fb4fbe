#include "common/blur.wgsl"
// Gaussian blur block with a depth input, one axis (crates/ao-passes/src/blocks/gaussian_blur.rs):
// sky pixels (depth 0) write 1 and sky taps are left out; with depth_sigma > 0 each tap is
// also weighted by the relative depth term (common/blur.wgsl). Weights are renormalised over
// the taps used; the centre tap of a non-sky pixel always counts, so the sum is > 0.
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_2d<f32>;
// r32float; the first pass of a blur at a technique's half intermediate precision uses the
// `?IntermediateStorage=f16` variant (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(2) var dst: IntermediateStorage;
@group(0) @binding(3) var<uniform> params: BlurParams;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    let z_p = textureLoad(depth, p, 0).r;
    if (!(z_p > 0.0)) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    var sum = 0.0;
    var wsum = 0.0;
    for (var k = -params.radius; k <= params.radius; k = k + 1) {
        let q = p + params.axis * k;
        if (any(q < vec2<i32>(0)) || any(q >= size)) { continue; }
        let z_q = textureLoad(depth, q, 0).r;
        if (!(z_q > 0.0)) { continue; }
        let w = params.weights[u32(abs(k)) / 4u][u32(abs(k)) % 4u] * depth_weight(z_p, z_q, params.depth_sigma);
        sum = sum + w * textureLoad(src, q, 0).r;
        wsum = wsum + w;
    }
    textureStore(dst, p, vec4<f32>(sum / max(wsum, 1e-30), 0.0, 0.0, 0.0));
}
