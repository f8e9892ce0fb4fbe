// Depth MIP prefilter block (crates/ao-passes/src/blocks/depth_prefilter.rs): XeGTAO's weighted
// 2x2 rule (docs/techniques/gtao.md §4). `src` is level l (linear depth, 0 = sky), `dst` level l + 1 of
// size ceil(size(src) / 2). Each child z_i of the in-bounds, non-sky 2x2 block gets the weight
//   w_i = saturate((r - (z_max - z_i)) / (F r)),  r = 0.75 R', z_max the farthest child,
// and the texel is sum(w_i z_i) / sum(w_i): the farthest child always weighs 1, so the sum is
// never 0. A block with a sky child is sky (0): XeGTAO's sky is the far plane, the farthest
// child, which weighs 1 while every surface more than r in front of it weighs 0. (Averaging
// the surface children instead, and rebuilding the mean at the block's centre, put a grazing
// floor's near row half a row up, in front of the floor: it occluded itself to 0.63.)

struct PrefilterParams {
    // r = 0.75 R' (view units).
    radius: f32,
    // Falloff range F r (view units, > 0).
    falloff: f32,
    pad0: f32,
    pad1: f32,
}

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: PrefilterParams;
@group(0) @binding(2) var dst: texture_storage_2d<r32float, write>;

// One child: its depth clamped-loaded, and whether it is in the image.
fn child(base: vec2<i32>, k: vec2<i32>, src_size: vec2<i32>) -> vec2<f32> {
    let q = base + k;
    let z = textureLoad(src, min(q, src_size - vec2<i32>(1)), 0).r;
    return vec2<f32>(z, select(0.0, 1.0, all(q < src_size)));
}

// The child's weighted depth and weight (0 for out-of-image and sky children).
fn weigh(c: vec2<f32>, z_max: f32, r: f32, falloff: f32) -> vec2<f32> {
    let w = select(0.0, saturate((r - (z_max - c.x)) / falloff), c.y > 0.5 && c.x > 0.0);
    return vec2<f32>(w * c.x, w);
}

// Branch-free: the four children loaded (clamped) and masked, no array indexed at run time.
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let base = vec2<i32>(id.xy) * 2;
    let c0 = child(base, vec2<i32>(0, 0), src_size);
    let c1 = child(base, vec2<i32>(1, 0), src_size);
    let c2 = child(base, vec2<i32>(0, 1), src_size);
    let c3 = child(base, vec2<i32>(1, 1), src_size);
    let inside = vec4<f32>(c0.y, c1.y, c2.y, c3.y) > vec4<f32>(0.5);
    let z = vec4<f32>(c0.x, c1.x, c2.x, c3.x);
    let zi = select(vec4<f32>(0.0), z, inside);
    let z_max = max(max(zi.x, zi.y), max(zi.z, zi.w));
    let sky = any(inside & !(z > vec4<f32>(0.0)));
    let r = params.radius;
    let falloff = max(params.falloff, 1e-30);
    let t = weigh(c0, z_max, r, falloff) + weigh(c1, z_max, r, falloff)
        + weigh(c2, z_max, r, falloff) + weigh(c3, z_max, r, falloff);
    let v = select(0.0, t.x / max(t.y, 1e-30), t.y > 0.0 && !sky);
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}
