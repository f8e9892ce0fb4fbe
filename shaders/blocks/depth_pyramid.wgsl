// Depth pyramid block (crates/ao-passes/src/blocks/depth_pyramid.rs): one level from the
// previous one. `src` is level l (linear depth, 0 = sky), `dst` is level l + 1 of size
// ceil(size(src) / factor) (the 3x3 one one more where its overhang would be odd). Only
// in-bounds texels count; an all-sky block is 0.
@group(0) @binding(0) var src: texture_2d<f32>;
@group(0) @binding(1) var dst: texture_storage_2d<r32float, write>;

// Pyramid HBAO (spec §2.2, §7): mean of the 3x3 block (3x + i - o, 3y + j - o), i, j in 0..3,
// over its in-bounds texels, o the centred grid's overhang (3m - n) / 2 per axis. A block
// holding sky and geometry takes its centre texel (3x + 1 - o, 3y + 1 - o, clamped into the
// image) instead: the AO pass rebuilds a coarse texel at the block's centre,
// and the mean of the geometry texels alone lies elsewhere (on a plane meeting the horizon,
// nearer than the plane at the centre: above it, occluding). A sky centre makes the texel sky.
@compute @workgroup_size(8, 8)
fn average_3x3(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let last = src_size - vec2<i32>(1);
    // The grid is centred (blocks/depth_pyramid.rs): o texels of overhang on each side.
    let overhang = (vec2<i32>(size) * 3 - src_size) / 2;
    let base = vec2<i32>(id.xy) * 3 - overhang;
    // Branch-free: every tap is loaded (clamped into the image) and counted by masks, so the
    // loop unrolls into straight loads (on SIMD CPU drivers a branch per tap costs more than
    // the load).
    var sum = 0.0;
    var n = 0.0;
    var sky = 0.0;
    var centre = 0.0;
    for (var j = 0; j < 3; j = j + 1) {
        for (var i = 0; i < 3; i = i + 1) {
            let q = base + vec2<i32>(i, j);
            let inside = all(q < src_size) && all(q >= vec2<i32>(0));
            let z = textureLoad(src, clamp(q, vec2<i32>(0), last), 0).r;
            let geometry = inside && z > 0.0;
            sum = sum + select(0.0, z, geometry);
            n = n + select(0.0, 1.0, geometry);
            sky = sky + select(0.0, 1.0, inside && !(z > 0.0));
            // The (1, 1) tap, clamped into the image: the block's centre texel.
            centre = select(centre, z, i == 1 && j == 1);
        }
    }
    var v = select(0.0, sum / max(n, 1.0), n > 0.0);
    if (n > 0.0 && sky > 0.0) {
        v = select(0.0, centre, centre > 0.0);
    }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(v, 0.0, 0.0, 0.0));
}

// Nearest (min) or farthest (max) non-sky texel of the 2x2 block (2x + i, 2y + j).
fn reduce_2x2(id: vec2<u32>, farthest: bool) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_size = vec2<i32>(textureDimensions(src));
    let last = src_size - vec2<i32>(1);
    let base = vec2<i32>(id) * 2;
    var lo = 3.0e38;
    var hi = 0.0;
    for (var j = 0; j < 2; j = j + 1) {
        for (var i = 0; i < 2; i = i + 1) {
            let q = base + vec2<i32>(i, j);
            let z = textureLoad(src, min(q, last), 0).r;
            let geometry = all(q < src_size) && z > 0.0;
            lo = min(lo, select(3.0e38, z, geometry));
            hi = max(hi, select(0.0, z, geometry));
        }
    }
    let v = select(select(lo, hi, farthest), 0.0, hi == 0.0);
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
