#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO downsampling, one pyramid level (Sec. 4.2, Table 2): each texel of level l takes the four
// sub-pixels of level l - 1, sorted by positive linear depth z0 <= z1 <= z2 <= z3. If every
// sub-pixel lies within d_threshold of the median's plane (through the mean of the middle two,
// with their renormalised mean normal), depth and normal are the means of the middle two (the
// paper's "median"); otherwise the second-nearest sub-pixel is kept as it is. Table 2 tests the
// depth range z3 - z0 instead, which a plane seen at a grazing angle exceeds at coarse levels,
// so the rule then depended on the distance to the camera (crates/ao-passes/src/techniques/
// mssao.rs, "At every output size"); on a plane both branches give the same texel. Normals follow the
// same sorted indices and are renormalised (falling back to n1 when n1 + n2 ~ 0). Sky sub-pixels
// sort last (infinite depth), so a block with at least two geometry sub-pixels stays geometry.
// Odd sizes: the level is ceil(size / 2); the 2x2 fetch is clamped at the border.
// Each level keeps depth and an octahedral normal (common/mssao.wgsl, "Conventions"). Where the
// paper keeps the mean position of the two sub-pixels (or the second-nearest's), the depth
// kept is that of the plane through that position with the kept normal, at the new texel's
// centre, within the block's geometry depths: positions rebuilt at texel centres then lie on
// the surface (exactly, for a plane) at every level. A block with sky whose centre looks past
// its surface is sky.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var src_depth: texture_2d<f32>;
@group(0) @binding(3) var src_normals: texture_2d<u32>;
@group(0) @binding(4) var dst_depth: texture_storage_2d<r32float, write>;
@group(0) @binding(5) var dst_normals: texture_storage_2d<r32uint, write>;

const SKY_DEPTH: f32 = 3.0e38;

// A sub-pixel: its depth (sky: SKY_DEPTH), its index in the 2x2 block, its normal code.
struct SubPixel {
    z: f32,
    i: u32,
    n: u32,
    // The source texel (clamped into the source level).
    c: vec2<i32>,
}

// The order of the sort: by depth, then by index (so equal depths keep the block's order, as
// a stable sort would; the keys are distinct, so any correct sorting network gives that order).
fn sub_less(a: SubPixel, b: SubPixel) -> bool {
    return a.z < b.z || (a.z == b.z && a.i < b.i);
}

fn sub_min(a: SubPixel, b: SubPixel) -> SubPixel {
    if (sub_less(b, a)) { return b; }
    return a;
}

fn sub_max(a: SubPixel, b: SubPixel) -> SubPixel {
    if (sub_less(b, a)) { return a; }
    return b;
}

fn load_sub_pixel(base: vec2<i32>, i: u32, src_max: vec2<i32>) -> SubPixel {
    let c = min(base + vec2<i32>(i32(i & 1u), i32(i >> 1u)), src_max);
    let d = textureLoad(src_depth, c, 0).x;
    return SubPixel(select(SKY_DEPTH, d, mssao_is_geometry(d)), i, textureLoad(src_normals, c, 0).x, c);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst_depth);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_max = vec2<i32>(textureDimensions(src_depth)) - vec2<i32>(1);
    let base = vec2<i32>(id.xy) * 2;
    let a = load_sub_pixel(base, 0u, src_max);
    let b = load_sub_pixel(base, 1u, src_max);
    let c = load_sub_pixel(base, 2u, src_max);
    let d = load_sub_pixel(base, 3u, src_max);
    // The four sorted by a sorting network (0,1)(2,3), (0,2)(1,3), (1,2): no array indexed at
    // run time (on SIMD CPU drivers such an array lives in per-lane memory).
    let t0 = sub_min(a, b);
    let t1 = sub_max(a, b);
    let t2 = sub_min(c, d);
    let t3 = sub_max(c, d);
    let s0 = sub_min(t0, t2);
    let s3 = sub_max(t1, t3);
    let m1 = sub_min(t1, t3);
    let m2 = sub_max(t0, t2);
    let s1 = sub_min(m1, m2);
    let s2 = sub_max(m1, m2);
    let dst_c = vec2<i32>(id.xy);
    if (s1.z >= SKY_DEPTH) {
        // Fewer than two geometry sub-pixels: this texel is sky.
        textureStore(dst_depth, dst_c, vec4<f32>(0.0));
        textureStore(dst_normals, dst_c, vec4<u32>(0u));
        return;
    }
    let src_grid = mssao_grid(view, params.level - 1u);
    let p1 = mssao_position(src_grid, s1.c, s1.z);
    let n1 = normal_oct_decode(s1.n);
    var p = p1;
    var nv = n1;
    var n = s1.n;
    var depth = s1.z;
    // The median candidate: the mean of the two middle sub-pixels and their renormalised normal.
    let p2 = mssao_position(src_grid, s2.c, s2.z);
    let sum = n1 + normal_oct_decode(s2.n);
    let l = length(sum);
    let p_med = 0.5 * (p1 + p2);
    let n_med = select(n1, sum / max(l, 1e-30), l > 1e-6);
    var spread = 3.0e38;
    if (s3.z < SKY_DEPTH) {
        let p0 = mssao_position(src_grid, s0.c, s0.z);
        let p3 = mssao_position(src_grid, s3.c, s3.z);
        spread = max(max(abs(dot(n_med, p0 - p_med)), abs(dot(n_med, p1 - p_med))),
                     max(abs(dot(n_med, p2 - p_med)), abs(dot(n_med, p3 - p_med))));
    }
    if (spread <= params.d_threshold) {
        // A continuous surface: the mean of the two middle sub-pixels.
        depth = 0.5 * (s1.z + s2.z);
        p = p_med;
        if (l > 1e-6) {
            nv = n_med;
            n = normal_oct_encode(nv);
        }
    }
    // What the centre's line of sight meets: the kept surface's plane, within the block's
    // geometry depths [s0, hi] (beyond them, the nearest or farthest child); where it passes
    // behind every geometry child (or misses the plane) in a block with sky, the sky.
    let hi = select(s1.z, select(s2.z, s3.z, s3.z < SKY_DEPTH), s2.z < SKY_DEPTH);
    let t = mssao_plane_depth(mssao_grid(view, params.level), dst_c, p, nv);
    if (s3.z >= SKY_DEPTH && !(t > 0.0 && t <= hi)) {
        textureStore(dst_depth, dst_c, vec4<f32>(0.0));
        textureStore(dst_normals, dst_c, vec4<u32>(0u));
        return;
    }
    depth = select(depth, clamp(t, s0.z, hi), t > 0.0);
    textureStore(dst_depth, dst_c, vec4<f32>(depth, 0.0, 0.0, 0.0));
    textureStore(dst_normals, dst_c, vec4<u32>(n, 0u, 0u, 0u));
}
