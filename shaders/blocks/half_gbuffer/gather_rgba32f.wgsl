// Half-resolution g-buffer, an Rgba32Float channel (motion, positions): the sample the
// selection kept
// (blocks/half_gbuffer/select.wgsl, `choice` = x + 2y of the 2x2 block).

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var choice: texture_2d<u32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let k = textureLoad(choice, p, 0).r;
    let q = min(2 * p + vec2<i32>(i32(k & 1u), i32(k >> 1u)), vec2<i32>(textureDimensions(src)) - 1);
    textureStore(dst, p, textureLoad(src, q, 0));
}
