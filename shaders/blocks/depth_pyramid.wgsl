// Depth pyramid block (crates/ao-passes/src/blocks/depth_pyramid.rs): one level from the
// previous one. `src` is level l (linear depth, 0 = sky), `dst` is level l + 1 of size
// ceil(size(src) / factor). Only in-bounds texels count; an all-sky block is 0.
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;

// Pyramid HBAO (spec §2.2, §7): mean of the 3x3 block (3x + i, 3y + j), i, j in 0..3, over its
// in-bounds texels. A block holding sky and geometry takes its centre texel (3x + 1, 3y + 1,
// clamped into the image) instead: the AO pass rebuilds a coarse texel at the block's centre,
// and the mean of the geometry texels alone lies elsewhere (on a plane meeting the horizon,
// nearer than the plane at the centre: above it, occluding). A sky centre makes the texel sky.
@compute @workgroup_size(8, 8)
fn average_3x3(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let base = vec2<i32>(id.xy) * 3;
    var sum = 0.0;
    var n = 0u;
    var sky = 0u;
    for (var j = 0; j < 3; j = j + 1) {
        for (var i = 0; i < 3; i = i + 1) {
            let q = base + vec2<i32>(i, j);
            if (q.x >= src_size.x || q.y >= src_size.y) { continue; }
            let z = textureLoad(src, q, 0).r;
            if (z > 0.0) {
                sum = sum + z;
                n = n + 1u;
            } else {
                sky = sky + 1u;
            }
        }
    }
    var v = select(0.0, sum / f32(max(n, 1u)), n > 0u);
    if (n > 0u && sky > 0u) {
        let centre = textureLoad(src, min(base + vec2<i32>(1), src_size - 1), 0).r;
        v = select(0.0, centre, centre > 0.0);
    }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}

// Nearest (min) or farthest (max) non-sky texel of the 2x2 block (2x + i, 2y + j).
fn reduce_2x2(id: vec2<u32>, farthest: bool) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let base = vec2<i32>(id) * 2;
    var lo = 3.0e38;
    var hi = 0.0;
    var n = 0u;
    for (var j = 0; j < 2; j = j + 1) {
        for (var i = 0; i < 2; i = i + 1) {
            let q = base + vec2<i32>(i, j);
            if (q.x >= src_size.x || q.y >= src_size.y) { continue; }
            let z = textureLoad(src, q, 0).r;
            if (z > 0.0) {
                lo = min(lo, z);
                hi = max(hi, z);
                n = n + 1u;
            }
        }
    }
    let v = select(select(lo, hi, farthest), 0.0, n == 0u);
    textureStore(dst, vec2<i32>(id), vec4<f32>(v, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn min_2x2(@builtin(global_invocation_id) id: vec3<u32>) {
    reduce_2x2(id.xy, false);
}

@compute @workgroup_size(8, 8)
fn max_2x2(@builtin(global_invocation_id) id: vec3<u32>) {
    reduce_2x2(id.xy, true);
}
