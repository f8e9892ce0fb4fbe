#include "common/blur.wgsl"
// Gaussian blur block, one axis (crates/ao-passes/src/blocks/gaussian_blur.rs): plain,
// no depth input. out(p) = sum_k w[k] src(p + k axis) / sum_k w[k] over in-bounds taps, so a
// constant stays constant at the borders.
@group(0) @binding(0) var src: texture_2d<f32>;
// r32float; the first pass of a blur at a technique's half intermediate precision uses the
// `?IntermediateStorage=f16` variant (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(1) var dst: IntermediateStorage;
@group(0) @binding(2) var<uniform> params: BlurParams;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    var sum = 0.0;
    var wsum = 0.0;
    for (var k = -params.radius; k <= params.radius; k = k + 1) {
        let q = p + params.axis * k;
        if (any(q < vec2<i32>(0)) || any(q >= size)) { continue; }
        let w = params.weights[u32(abs(k)) / 4u][u32(abs(k)) % 4u];
        sum = sum + w * textureLoad(src, q, 0).r;
        wsum = wsum + w;
    }
    // The centre tap is always in bounds and w[0] > 0, so wsum > 0.
    textureStore(dst, p, vec4<f32>(sum / max(wsum, 1e-30), 0.0, 0.0, 0.0));
}
