// Depth MIP prefilter block (crates/ao-passes/src/blocks/depth_prefilter.rs): XeGTAO's weighted
// 2x2 rule (specs/gtao.md §4). `src` is level l (linear depth, 0 = sky), `dst` level l + 1 of
// size ceil(size(src) / 2). Each child z_i of the in-bounds, non-sky 2x2 block gets the weight
//   w_i = saturate((r - (z_max - z_i)) / (F r)),  r = 0.75 R', z_max the farthest child,
// and the texel is sum(w_i z_i) / sum(w_i): the farthest child always weighs 1, so the sum is
// never 0. A block with a sky child is sky (0): XeGTAO's sky is the far plane, the farthest
// child, which weighs 1 while every surface more than r in front of it weighs 0. (Averaging
// the surface children instead, and rebuilding the mean at the block's centre, put a grazing
// floor's near row half a row up, in front of the floor: it occluded itself to 0.63.)

struct PrefilterParams {
    // r = 0.75 R' (view units), F r (> 0), unused, unused
    shape: vec4<f32>,
}

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: PrefilterParams;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let base = vec2<i32>(id.xy) * 2;
    var z = array<f32, 4>(0.0, 0.0, 0.0, 0.0);
    var z_max = 0.0;
    var sky = false;
    for (var k = 0; k < 4; k = k + 1) {
        let q = base + vec2<i32>(k & 1, k >> 1u);
        if (q.x < src_size.x && q.y < src_size.y) {
            z[k] = textureLoad(src, q, 0).r;
            z_max = max(z_max, z[k]);
            sky = sky || !(z[k] > 0.0);
        }
    }
    let r = params.shape.x;
    let falloff = max(params.shape.y, 1e-30);
    var sum = 0.0;
    var weights = 0.0;
    for (var k = 0; k < 4; k = k + 1) {
        if (z[k] > 0.0) {
            let w = saturate((r - (z_max - z[k])) / falloff);
            sum = sum + w * z[k];
            weights = weights + w;
        }
    }
    let v = select(0.0, sum / max(weights, 1e-30), weights > 0.0 && !sky);
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}
