#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO low-pass filter of a level's tuple before it is upsampled (Sec. 4.5, Table 4): a 3x3
// blur with weights w_g = 1 / ((dx + 1)(dy + 1)) (1, 1/2, 1/4), applied to all three channels and
// normalised by the sum of weights (Table 4 omits the division; without it the max channel would
// exceed 1). The prose calls the filter bilateral, so by default each weight is also multiplied
// by Eq. 8 and Eq. 9 between the centre and the neighbour (`bilateral_blur`). Sky neighbours and
// off-screen taps get no weight; sky centres write (0, 0, 0).

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<u32>;
@group(0) @binding(4) var src: texture_2d<f32>;
// The tuple is an intermediate: rgba32float here, rgba16float in the `?IntermediateStorage=f16`
// variant (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var dst: IntermediateStorage;

// The workgroup's 8x8 texels and a one-texel ring: depth and decoded normal, each read and
// decoded once per workgroup (100 decodes for 64 texels instead of 9 a texel; decoding, with
// its normalisation, costs more than the loads on SIMD CPU drivers). Out-of-image texels are
// stored with depth 0, so they drop out as sky taps do.
const TILE: u32 = 10u;
var<workgroup> tile_z: array<f32, 100>;
var<workgroup> tile_n: array<vec3<f32>, 100>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) li: u32, @builtin(workgroup_id) wg: vec3<u32>) {
    let size = textureDimensions(dst);
    let isize = vec2<i32>(size);
    let origin = vec2<i32>(wg.xy) * 8 - vec2<i32>(1);
    for (var k = li; k < TILE * TILE; k = k + 64u) {
        let t = origin + vec2<i32>(i32(k % TILE), i32(k / TILE));
        let q = mssao_depth_normal(depth, normals, clamp(t, vec2<i32>(0), isize - vec2<i32>(1)));
        tile_z[k] = select(0.0, q.z, mssao_in_bounds(t, isize));
        tile_n[k] = q.n;
    }
    workgroupBarrier();
    if (id.x >= size.x || id.y >= size.y) { return; }
    let c = vec2<i32>(id.xy);
    let local = vec2<i32>(id.xy) - origin;
    let z = tile_z[u32(local.y) * TILE + u32(local.x)];
    let n = tile_n[u32(local.y) * TILE + u32(local.x)];
    if (!mssao_is_geometry(z)) {
        textureStore(dst, c, vec4<f32>(0.0));
        return;
    }
    var sum = vec3<f32>(0.0);
    var wsum = 0.0;
    for (var dy = -1; dy <= 1; dy = dy + 1) {
        for (var dx = -1; dx <= 1; dx = dx + 1) {
            let k = u32(local.y + dy) * TILE + u32(local.x + dx);
            let qz = tile_z[k];
            if (!mssao_is_geometry(qz)) {
                continue; // sky or off the image
            }
            var w = 1.0 / (f32(abs(dx) + 1) * f32(abs(dy) + 1));
            if (params.bilateral_blur != 0u) {
                w = w * mssao_bilateral_weight(n, z, tile_n[k], qz, params.normal_power, params.depth_power);
            }
            sum = sum + w * textureLoad(src, c + vec2<i32>(dx, dy), 0).xyz;
            wsum = wsum + w;
        }
    }
    // The centre always has weight 1 (Eqs. 8-9 give 1 for itself), so wsum >= 1.
    textureStore(dst, c, vec4<f32>(sum / max(wsum, 1e-30), 0.0));
}
