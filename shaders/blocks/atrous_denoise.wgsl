#include "common/history_denoise_params.wgsl"
#include "common/view.wgsl"
#include "common/same_surface.wgsl"
// blocks/history_denoise `<prefix>.atrous<k>` (crates/ao-passes/src/blocks/history_denoise.rs):
// one a-trous iteration (SVGF, Schied et al. 2017, Eqs. 1-5) at tap spacing `step` = 2^(k-1):
// a 3x3 B-spline kernel (1/4, 1/2, 1/4) times
//   - a Gaussian of the tap's distance in pixels with the pixel's own radius from the guide
//     (blocks/history_fix.wgsl), so the filter narrows as the history grows and a pixel whose
//     radius is below half the step keeps its value (the iteration is skipped there);
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
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(6) var<uniform> view: View;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<i32>(textureDimensions(dst));
    let p = vec2<i32>(id.xy);
    if (p.x >= size.x || p.y >= size.y) {
        return;
    }
    let zc = textureLoad(depth, p, 0).x;
    if (!is_surface(zc)) {
        textureStore(dst, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    // Points rebuilt from linear depth at pixel centres (4 bytes a tap, not a 16-byte
    // position), in the view block's own pixel grid.
    let to_view = pixel_to_view(view, view.inv_size);
    let centre = pixel_view_position(to_view, vec2<f32>(p) + 0.5, zc);
    let a = textureLoad(src, p, 0).x;
    let g = textureLoad(guide, p, 0);
    let radius = g.y;
    if (!(radius * 2.0 >= params.step)) {
        textureStore(dst, p, vec4<f32>(clamp(a, 0.0, 1.0), 0.0, 0.0, 0.0));
        return;
    }
    let nc = textureLoad(normals, p, 0).xyz;
    let sigma = params.sigma_ao * sqrt(max(g.x, 0.0)) + 1e-4;
    let step = i32(params.step);
    let inv_two_r2 = 1.0 / (2.0 * radius * radius);
    let inv_sigma = 1.0 / sigma;
    var sum = 0.0;
    var wsum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let q = p + vec2<i32>(i, j) * step;
            if (any(q < vec2<i32>(0)) || any(q >= size)) {
                continue;
            }
            let zq = textureLoad(depth, q, 0).x;
            if (!is_surface(zq)) {
                continue;
            }
            let pq = pixel_view_position(to_view, vec2<f32>(q) + 0.5, zq);
            let aq = textureLoad(src, q, 0).x;
            let kernel = (0.5 - 0.25 * f32(abs(i))) * (0.5 - 0.25 * f32(abs(j)));
            let d2 = f32(i * i + j * j) * params.step * params.step;
            let plane = plane_distance(centre, nc, pq, params.plane_tolerance);
            let facing = facing_weight(dot(nc, textureLoad(normals, q, 0).xyz));
            // The distance, plane and value weights' exponentials in one.
            let w = kernel * facing
                * exp(-(d2 * inv_two_r2 + plane + abs(a - aq) * inv_sigma));
            sum += w * aq;
            wsum += w;
        }
    }
    // The centre weighs about 1/4 (its own normal, f16-rounded); a degenerate normal keeps
    // the pixel's value.
    let filtered = select(a, sum / wsum, wsum > 0.0);
    textureStore(dst, p, vec4<f32>(clamp(filtered, 0.0, 1.0), 0.0, 0.0, 0.0));
}
