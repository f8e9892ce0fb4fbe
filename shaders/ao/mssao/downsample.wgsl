#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO downsampling, one pyramid level (Sec. 4.2, Table 2): each texel of level l takes the four
// sub-pixels of level l - 1, sorted by positive linear depth z0 <= z1 <= z2 <= z3. If the depth
// range z3 - z0 is at most d_threshold, position and normal are the means of the middle two (the
// paper's "median"); otherwise the second-nearest sub-pixel is kept as it is. Normals follow the
// same sorted indices and are renormalised (falling back to n1 when n1 + n2 ~ 0). Sky sub-pixels
// sort last (infinite depth), so a block with at least two geometry sub-pixels stays geometry.
// Odd sizes: the level is ceil(size / 2); the 2x2 fetch is clamped at the border.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var src_positions: texture_2d<f32>;
@group(0) @binding(3) var src_normals: texture_2d<f32>;
@group(0) @binding(4) var dst_positions: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var dst_normals: texture_storage_2d<rgba16float, write>;

const SKY_DEPTH: f32 = 3.0e38;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst_positions);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let src_max = vec2<i32>(textureDimensions(src_positions)) - vec2<i32>(1);
    let base = vec2<i32>(id.xy) * 2;
    var pos: array<vec4<f32>, 4>;
    var nrm: array<vec4<f32>, 4>;
    var z: array<f32, 4>;
    var idx = array<u32, 4>(0u, 1u, 2u, 3u);
    for (var i = 0u; i < 4u; i = i + 1u) {
        let c = min(base + vec2<i32>(i32(i & 1u), i32(i >> 1u)), src_max);
        pos[i] = textureLoad(src_positions, c, 0);
        nrm[i] = textureLoad(src_normals, c, 0);
        let d = -pos[i].z;
        z[i] = select(SKY_DEPTH, d, pos[i].w > 0.5 && d > 0.0);
    }
    // Insertion sort of four indices by depth (stable).
    for (var i = 1u; i < 4u; i = i + 1u) {
        var j = i;
        loop {
            if (j == 0u) { break; }
            if (z[idx[j - 1u]] <= z[idx[j]]) { break; }
            let t = idx[j];
            idx[j] = idx[j - 1u];
            idx[j - 1u] = t;
            j = j - 1u;
        }
    }
    let i1 = idx[1];
    let i2 = idx[2];
    var p = pos[i1];
    var n = nrm[i1];
    if (z[i1] >= SKY_DEPTH) {
        // Fewer than two geometry sub-pixels: this texel is sky.
        p = vec4<f32>(0.0);
        n = vec4<f32>(0.0);
    } else if (z[idx[3]] - z[idx[0]] <= params.d_threshold) {
        // Table 2: small depth range, the mean of the two middle sub-pixels.
        p = vec4<f32>(0.5 * (pos[i1].xyz + pos[i2].xyz), 1.0);
        let s = nrm[i1].xyz + nrm[i2].xyz;
        let l = length(s);
        n = select(vec4<f32>(nrm[i1].xyz, 1.0), vec4<f32>(s / l, 1.0), l > 1e-6);
    } else {
        p = vec4<f32>(pos[i1].xyz, 1.0);
        n = vec4<f32>(nrm[i1].xyz, 1.0);
    }
    textureStore(dst_positions, vec2<i32>(id.xy), p);
    textureStore(dst_normals, vec2<i32>(id.xy), n);
}
