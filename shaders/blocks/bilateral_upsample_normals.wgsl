#include "common/blur.wgsl"
// Bilateral upsampling block with normals (crates/ao-passes/src/blocks/bilateral_upsample.rs):
// as bilateral_upsample.wgsl, each tap also weighted by max(0, n_p . n_i)^normal_power.
@group(0) @binding(0) var ao: texture_2d<f32>;
@group(0) @binding(1) var depth_low: texture_2d<f32>;
@group(0) @binding(2) var depth_full: texture_2d<f32>;
@group(0) @binding(3) var normals_low: texture_2d<f32>;
@group(0) @binding(4) var normals_full: texture_2d<f32>;
@group(0) @binding(5) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(6) var<uniform> params: UpsampleParams;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    let z_p = textureLoad(depth_full, p, 0).r;
    if (!(z_p > 0.0)) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let n_p = unit_normal(textureLoad(normals_full, p, 0));
    let lo = vec2<i32>(textureDimensions(ao));
    let f = upsample_footprint(p, params.factor);
    var z = vec4<f32>(0.0);
    var a = vec4<f32>(1.0);
    var n = vec4<f32>(1.0);
    for (var i = 0u; i < 4u; i = i + 1u) {
        let q = footprint_tap(f, i, lo);
        z[i] = textureLoad(depth_low, q, 0).r;
        a[i] = textureLoad(ao, q, 0).r;
        n[i] = normal_weight(n_p, unit_normal(textureLoad(normals_low, q, 0)), params.normal_power);
    }
    let v = upsample_combine(z_p, z, a, n, f.bilinear, params.depth_sigma);
    textureStore(dst, p, vec4<f32>(v, 0.0, 0.0, 0.0));
}
