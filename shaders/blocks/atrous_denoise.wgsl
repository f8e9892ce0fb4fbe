#include "common/history_denoise_params.wgsl"
// blocks/history_denoise `<prefix>.atrous<k>` (crates/ao-passes/src/blocks/history_denoise.rs):
// one a-trous iteration (SVGF, Schied et al. 2017, Eqs. 1-5) at tap spacing `step` = 2^(k-1):
// a 3x3 B-spline kernel (1/4, 1/2, 1/4) times
//   - a Gaussian of the tap's distance in pixels with the pixel's own radius from the guide
//     (blocks/history_fix.wgsl), so the filter narrows as the history grows and a pixel whose
//     radius is below a third of the step keeps its value (the iteration is skipped there);
//   - the same surface: exp(-plane distance / (tolerance * distance to the camera)) and
//     max(n.n_q, 0)^64 (SVGF's sigma_n = 128, halved for a 3x3 kernel);
//   - the AO difference over the pixel's standard deviation: exp(-|a_p - a_q| / (sigma_ao
//     sqrt(variance) + 1e-4)) (SVGF's luminance weight, Eq. 5), so a converged pixel (small
//     variance) averages only what equals it.
// Sky writes 1 and is never a tap; the output is a convex combination of inputs, clamped to
// [0, 1].


@group(0) @binding(0) var<uniform> params: HistoryDenoiseParams;
@group(0) @binding(1) var src: texture_2d<f32>;
@group(0) @binding(2) var guide: texture_2d<f32>;
@group(0) @binding(3) var positions: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var dst: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) {
        return;
    }
    let centre = textureLoad(positions, p, 0);
    if (centre.w < 0.5) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let a = textureLoad(src, p, 0).x;
    let g = textureLoad(guide, p, 0);
    let radius = g.y;
    if (!(radius * 3.0 >= params.step)) {
        textureStore(dst, p, vec4<f32>(clamp(a, 0.0, 1.0), 0.0, 0.0, 0.0));
        return;
    }
    let nc = textureLoad(normals, p, 0).xyz;
    let sigma = params.sigma_ao * sqrt(max(g.x, 0.0)) + 1e-4;
    let to_camera = max(length(centre.xyz), 1e-20);
    let step = i32(params.step);
    var sum = 0.0;
    var wsum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let q = p + vec2<i32>(i, j) * step;
            if (any(q < vec2<i32>(0)) || any(q >= size)) {
                continue;
            }
            let pq = textureLoad(positions, q, 0);
            if (pq.w < 0.5) {
                continue;
            }
            let aq = textureLoad(src, q, 0).x;
            let kernel = (0.5 - 0.25 * f32(abs(i))) * (0.5 - 0.25 * f32(abs(j)));
            let d2 = f32(i * i + j * j) * params.step * params.step;
            let distance_w = exp(-d2 / (2.0 * radius * radius));
            let plane = abs(dot(nc, pq.xyz - centre.xyz)) / (params.plane_tolerance * to_camera);
            let facing = pow(max(dot(nc, textureLoad(normals, q, 0).xyz), 0.0), 64.0);
            let value_w = exp(-abs(a - aq) / sigma);
            let w = kernel * distance_w * exp(-plane) * facing * value_w;
            sum += w * aq;
            wsum += w;
        }
    }
    // The centre always weighs (kernel 1/4, every other factor 1), so wsum > 0.
    textureStore(dst, p, vec4<f32>(clamp(sum / wsum, 0.0, 1.0), 0.0, 0.0, 0.0));
}
