#include "common/blur.wgsl"
// Bilateral upsampling block, depth only (crates/ao-passes/src/blocks/bilateral_upsample.rs):
// full-resolution `dst` from low-resolution `ao`, weighting the 2x2 bilinear footprint by how
// well each low-res depth matches the full-res depth (common/blur.wgsl, upsample_combine).
@group(0) @binding(0) var ao: texture_2d<f32>;
@group(0) @binding(1) var depth_low: texture_2d<f32>;
@group(0) @binding(2) var depth_full: texture_2d<f32>;
@group(0) @binding(3) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(4) var<uniform> params: UpsampleParams;

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
    let lo = vec2<i32>(textureDimensions(ao));
    let f = upsample_footprint(p, params.factor);
    var z = vec4<f32>(0.0);
    var a = vec4<f32>(1.0);
    for (var i = 0u; i < 4u; i = i + 1u) {
        let q = footprint_tap(f, i, lo);
        z[i] = textureLoad(depth_low, q, 0).r;
        a[i] = textureLoad(ao, q, 0).r;
    }
    let v = upsample_combine(z_p, z, a, vec4<f32>(1.0), f.bilinear, params.depth_sigma);
    textureStore(dst, p, vec4<f32>(v, 0.0, 0.0, 0.0));
}
