#include "common/finite.wgsl"
// ssao.blur: the classic 4x4 box blur that removes the 4x4 rotation pattern of ssao.ao, made
// centred: offsets -2..2 on each axis weighted 1/2, 1, 1, 1, 1/2, so every phase of the 4-pixel
// pattern gets the same weight (the two ends share one) as in a 4x4 box, without the box's
// half-pixel shift, which made the image differ from its mirror. Taps on sky are left out of
// the average; sky pixels are exactly 1.

@group(0) @binding(0) var raw: texture_2d<f32>;
@group(0) @binding(1) var depth: texture_2d<f32>;
@group(0) @binding(2) var ao: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    var a = 1.0;
    if (textureLoad(depth, p, 0).x > 0.0) {
        let last = vec2<i32>(textureDimensions(raw)) - 1;
        var sum = 0.0;
        var n = 0.0;
        for (var dy = -2; dy <= 2; dy = dy + 1) {
            for (var dx = -2; dx <= 2; dx = dx + 1) {
                let q = clamp(p + vec2<i32>(dx, dy), vec2<i32>(0), last);
                let w = select(1.0, 0.5, abs(dx) == 2) * select(1.0, 0.5, abs(dy) == 2);
                if (textureLoad(depth, q, 0).x > 0.0) {
                    sum = sum + w * textureLoad(raw, q, 0).x;
                    n = n + w;
                }
            }
        }
        a = clamp(sum / max(n, 1.0), 0.0, 1.0);
        a = select(1.0, a, is_finite_f32(a));
    }
    textureStore(ao, p, vec4<f32>(a, 0.0, 0.0, 0.0));
}
