#include "common/view.wgsl"
#include "common/finite.wgsl"
// tssao.filter: the adaptive convergence-aware spatial filter (TSSAO Eqs. 9-10), evaluated
// as written over the F x F footprint (the paper applies it separably in x and y; one 2D pass
// is exact and costs a single load for the converged pixels, where the filter is off):
//   A(p) = sum g(|p - x|) conv(x) A(x) / sum g(|p - x|) conv(x),
// g a Gaussian of the world-space distance, conv(x) = min(n_t, n_max) / n_max from the AO
// buffer, and the footprint shrunk by s(p) = max(c_adaptive - conv(p), 0) / c_adaptive: the
// tap at offset (i, j) weighs c(i) c(j), c(k) = clamp(s h + 0.5 - |k|, 0, 1), so at s = 0 the
// pixel is passed through unchanged.

struct FilterParams {
    // Half width h = (F - 1) / 2.
    half_width: i32,
    pad0: i32,
    pad1: i32,
    pad2: i32,
    // Gaussian sigma (world units).
    sigma: f32,
    // Convergence from which the filter is off (c_adaptive).
    c_adaptive: f32,
    // Cap of the sample count n_t (n_max).
    n_max: f32,
    pad3: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: FilterParams;
@group(0) @binding(2) var ao_buffer: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size_u = textureDimensions(dst);
    if (id.x >= size_u.x || id.y >= size_u.y) { return; }
    let size = vec2<i32>(size_u);
    let p = vec2<i32>(id.xy);
    let z = textureLoad(depth, p, 0).x;
    if (!(z > 0.0) || z > 1e30) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0)); // sky
        return;
    }
    let n_max = max(params.n_max, 1.0);
    let centre = textureLoad(ao_buffer, p, 0);
    let a_p = select(1.0, clamp(centre.x, 0.0, 1.0), centre.x == centre.x);
    let c_adaptive = max(params.c_adaptive, 1e-6);
    let s = max(c_adaptive - clamp(centre.y, 0.0, n_max) / n_max, 0.0) / c_adaptive; // Eq. 10
    let h = clamp(params.half_width, 0, 4);
    if (!(s > 0.0) || h == 0) {
        textureStore(dst, p, vec4<f32>(a_p, 0.0, 0.0, 0.0));
        return;
    }
    let o = view_position(pixel_uv(p, view), z, view);
    let inv_sigma = 1.0 / max(params.sigma, 1e-6);
    let reach = s * f32(h) + 0.5;
    var sum = 0.0;
    var wsum = 0.0;
    for (var j = -h; j <= h; j = j + 1) {
        let cj = clamp(reach - abs(f32(j)), 0.0, 1.0);
        for (var i = -h; i <= h; i = i + 1) {
            let tap = cj * clamp(reach - abs(f32(i)), 0.0, 1.0);
            let q = p + vec2<i32>(i, j);
            if (!(tap > 0.0) || any(q < vec2<i32>(0)) || any(q >= size)) {
                continue;
            }
            let zq = textureLoad(depth, q, 0).x;
            if (!(zq > 0.0) || zq > 1e30) {
                continue; // sky carries no AO
            }
            let x = view_position(pixel_uv(q, view), zq, view);
            let d = length(x - o) * inv_sigma;
            let v = textureLoad(ao_buffer, q, 0);
            let w = tap * exp(-0.5 * d * d) * clamp(v.y, 0.0, n_max) / n_max; // Eq. 9
            sum = sum + w * clamp(v.x, 0.0, 1.0);
            wsum = wsum + w;
        }
    }
    var a = a_p;
    if (wsum > 0.0) {
        a = sum / wsum;
    }
    textureStore(dst, p, vec4<f32>(select(a_p, clamp(a, 0.0, 1.0), is_finite_f32(a)), 0.0, 0.0, 0.0));
}
