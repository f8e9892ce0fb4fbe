// The device's texel-load rate, for the bench's roofline (crates/bench/src/roofline.rs): every thread
// loads the 7x7 neighbourhood of its pixel from an R32Float texture (49 loads, the access
// pattern of the blurs and AO kernels: neighbours, mostly in cache) and writes one sum, so the
// kernel is bound by loads, not by the single store or the additions. It is a lower bound of
// the true peak (a pass with better locality can exceed it; on lavapipe the denoisers reach
// about 90%).
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    // One clamp for the whole neighbourhood, so the loop is loads and adds only.
    let c = clamp(p, vec2<i32>(3), size - 4);
    var sum = 0.0;
    for (var y = -3; y <= 3; y = y + 1) {
        for (var x = -3; x <= 3; x = x + 1) {
            sum = sum + textureLoad(src, c + vec2<i32>(x, y), 0).r;
        }
    }
    textureStore(dst, p, vec4<f32>(sum, 0.0, 0.0, 0.0));
}
