// Edge-aware denoiser block (crates/ao-passes/src/blocks/edge_denoise.rs): one pass of XeGTAO's
// 3x3 filter (docs/techniques/gtao.md §6). `edges` holds the four edge weights (left, right, top, bottom;
// 1 = same surface, 0 = a depth edge) that the AO pass wrote, quantised to q / 3.
//   1. Symmetrise: each of the centre's edges times the neighbour's opposite edge.
//   2. Leak: if the four sum below 1.5, add 0.5 (1.5 - sum) / 1.5 to each, then saturate
//      (XeGTAO: leak threshold 2.5 of 4, strength 0.5), so an isolated pixel still blurs a bit.
//   3. Weights: the centre's blur beta, the 4 edges for the cross, and for each diagonal
//      0.425 x (the edge products along its two L-shaped paths).
//   4. Output = weighted mean; on the last pass clamped to [0, 1] (XeGTAO's x1.5 undoes its UNORM
//      packing; the AO here is stored as float, unscaled).
// Sky (depth 0) writes 1; sky taps and taps past the border weigh 0, even after the leak.

struct DenoiseParams {
    // Blur beta (centre weight).
    beta: f32,
    // 1.0 on the last pass, 0.0 before.
    last_pass: f32,
    pad0: f32,
    pad1: f32,
}

@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var edges: texture_2d<f32>;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var<uniform> params: DenoiseParams;
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(4) var dst: IntermediateStorage;

// XeGTAO's diagonal weight, 0.85 x 0.5.
const DIAGONAL_WEIGHT: f32 = 0.425;
// XeGTAO's leak threshold (of 4 edges) and strength.
const LEAK_THRESHOLD: f32 = 2.5;
const LEAK_STRENGTH: f32 = 0.5;

fn edges_at(q: vec2<i32>, size: vec2<i32>) -> vec4<f32> {
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return vec4<f32>(0.0); // past the border: no neighbour
    }
    return textureLoad(edges, q, 0);
}

// The AO at neighbour q, or 0 with weight 0 where q is sky or past the border: the leak must
// not pull in values that are no surface (XeGTAO has no sky; here sky is depth 0).
fn tap(q: vec2<i32>, size: vec2<i32>, w: f32) -> vec2<f32> {
    if (any(q < vec2<i32>(0)) || any(q >= size) || !(textureLoad(depth, q, 0).r > 0.0)) {
        return vec2<f32>(0.0);
    }
    return vec2<f32>(w * textureLoad(src, q, 0).r, w);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) { return; }
    if (!(textureLoad(depth, p, 0).r > 0.0)) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let l = edges_at(p + vec2<i32>(-1, 0), size);
    let r = edges_at(p + vec2<i32>(1, 0), size);
    let t = edges_at(p + vec2<i32>(0, -1), size);
    let b = edges_at(p + vec2<i32>(0, 1), size);
    // 1. Symmetrise (x = left, y = right, z = top, w = bottom).
    var e = edges_at(p, size) * vec4<f32>(l.y, r.x, t.w, b.z);
    // 2. Leak.
    let leak = saturate(4.0 - LEAK_THRESHOLD - dot(e, vec4<f32>(1.0))) / (4.0 - LEAK_THRESHOLD);
    e = saturate(e + leak * LEAK_STRENGTH);
    // 3. Diagonal weights along the two L-shaped paths (raw neighbour edges).
    let w_tl = DIAGONAL_WEIGHT * (e.x * l.z + e.z * t.x);
    let w_tr = DIAGONAL_WEIGHT * (e.z * t.y + e.y * r.z);
    let w_bl = DIAGONAL_WEIGHT * (e.w * b.x + e.x * l.w);
    let w_br = DIAGONAL_WEIGHT * (e.y * r.w + e.w * b.y);
    let beta = params.beta;
    var acc = vec2<f32>(beta * textureLoad(src, p, 0).r, beta);
    acc = acc + tap(p + vec2<i32>(-1, 0), size, e.x) + tap(p + vec2<i32>(1, 0), size, e.y);
    acc = acc + tap(p + vec2<i32>(0, -1), size, e.z) + tap(p + vec2<i32>(0, 1), size, e.w);
    acc = acc + tap(p + vec2<i32>(-1, -1), size, w_tl) + tap(p + vec2<i32>(1, -1), size, w_tr);
    acc = acc + tap(p + vec2<i32>(-1, 1), size, w_bl) + tap(p + vec2<i32>(1, 1), size, w_br);
    var v = acc.x / max(acc.y, 1e-30);
    if (params.last_pass > 0.5) {
        v = saturate(v);
    }
    textureStore(dst, p, vec4<f32>(v, 0.0, 0.0, 0.0));
}
