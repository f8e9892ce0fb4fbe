#include "common/blur.wgsl"
// Bilateral blur block, one axis (crates/ao-passes/src/blocks/bilateral_blur.rs):
//   w(q) = G_sigma(k) * exp(-((z_q - z_p) / (sigma_z z_p))^2 / 2) * max(0, n_p . n_q)^power
//   out(p) = sum_q w(q) src(q) / sum_q w(q)
// over in-bounds, non-sky taps q = p + k axis. Sky pixels write 1. The centre tap has weight
// G(0) > 0 (its depth and normal terms are 1), so the sum is > 0.
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
// r32float; the first pass of a blur at a technique's half intermediate precision uses the
// `?IntermediateStorage=f16` variant (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(3) var dst: IntermediateStorage;
@group(0) @binding(4) var<uniform> params: BlurParams;

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
    let n_p = unit_normal(textureLoad(normals, p, 0));
    var sum = 0.0;
    var wsum = 0.0;
    for (var k = -params.radius; k <= params.radius; k = k + 1) {
        let q = p + params.axis * k;
        if (any(q < vec2<i32>(0)) || any(q >= size)) { continue; }
        let z_q = textureLoad(depth, q, 0).r;
        if (!(z_q > 0.0)) { continue; }
        var w = params.weights[u32(abs(k)) / 4u][u32(abs(k)) % 4u] * depth_weight(z_p, z_q, params.depth_sigma);
        if (k != 0) {
            w = w * normal_weight(n_p, unit_normal(textureLoad(normals, q, 0)), params.normal_power);
        }
        sum = sum + w * textureLoad(src, q, 0).r;
        wsum = wsum + w;
    }
    textureStore(dst, p, vec4<f32>(sum / max(wsum, 1e-30), 0.0, 0.0, 0.0));
}
