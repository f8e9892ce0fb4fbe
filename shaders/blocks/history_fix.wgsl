#include "common/history_denoise_params.wgsl"
#include "common/finite.wgsl"
#include "common/view.wgsl"
#include "common/same_surface.wgsl"
// blocks/history_denoise `<prefix>.history_fix` (crates/ao-passes/src/blocks/history_denoise.rs):
// per pixel, the accessibility, its variance and the spatial filter's radius that the
// a-trous passes (blocks/atrous_denoise.wgsl) use.
//   n = frames in the pixel's history (the temporal block's history.y), m1 = the running mean
//   (accumulated), m2 = the running mean of A^2 (history.z).
//   - variance of the mean = v / n, v = the pixels' own temporal variances max(m2 - m1^2, 0)
//     (SVGF's temporal moments) averaged over the 3x3 neighbourhood on the same surface;
//   - n < fix_frames (a new or disoccluded pixel; REBLUR's history fix, SVGF's spatial
//     variance): a sparse 5x5 gather at `fix_stride` pixels over the same surface (plane and
//     normal weights) with each tap weighted by its own history length, so a disoccluded pixel
//     borrows converged neighbours' values; the pixel's value moves towards the gather by
//     (fix_frames - n) / (fix_frames - 1), and the variance is the largest of the temporal
//     one, the gather's spatial variance and the 3x3 neighbours' pooled moments'.
//   radius (pixels) = base_radius * mix(hit_floor, 1, nearest hit / R) / (1 + shrink (n - 1)):
//   wide on a new pixel, shrinking as the mean converges (REBLUR's 1 / (1 + k N)), narrower
//   where occluders are close (contact shadows are sharp).
// guide = (variance, radius, n, nearest hit / R). Sky: accessibility 1, guide 0.


@group(0) @binding(0) var<uniform> params: HistoryDenoiseParams;
@group(0) @binding(1) var accumulated: texture_2d<f32>;
@group(0) @binding(2) var history: texture_2d<f32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var hits: texture_2d<f32>;
@group(0) @binding(6) var dst: texture_storage_2d<r32float, write>;
@group(0) @binding(7) var guide: texture_storage_2d<rgba16float, write>;
@group(0) @binding(8) var<uniform> view: View;

// Weight of tap q (depth zq, normal nq) for centre point p with normal n: the same surface
// (common/same_surface.wgsl).
fn surface_weight(p: vec3<f32>, n: vec3<f32>, q: vec3<f32>, zq: f32, nq: vec3<f32>) -> f32 {
    if (!is_surface(zq)) {
        return 0.0;
    }
    return exp(-plane_distance(p, n, q, params.plane_tolerance)) * facing_weight(dot(n, nq));
}

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
        textureStore(guide, p, vec4<f32>(0.0));
        return;
    }
    // Points rebuilt from linear depth at pixel centres (4 bytes a tap, not a 16-byte
    // position), in the view block's own pixel grid.
    let to_view = pixel_to_view(view, view.inv_size);
    let centre = pixel_view_position(to_view, vec2<f32>(p) + 0.5, zc);
    let nc = textureLoad(normals, p, 0).xyz;
    let a = clamp(textureLoad(accumulated, p, 0).x, 0.0, 1.0);
    let h = textureLoad(history, p, 0);
    let n = max(select(1.0, h.y, is_finite_f32(h.y)), 1.0);

    // Over the 3x3 neighbourhood on the same surface: the nearest hit, so one lucky ray does
    // not decide the radius, and the mean of the pixels' own temporal variances m2 - m1^2
    // (SVGF filters its variance spatially too: over a few frames of one ray, one pixel's
    // samples often all agree although its mean is far from converged). Each pixel's own
    // variance, not the variance of the pooled moments: differences between the pixels'
    // means are signal, not noise.
    var hit = 1.0;
    var temporal_variance = 0.0;
    var pooled_m1 = 0.0;
    var pooled_m2 = 0.0;
    var msum = 0.0;
    for (var j = -1; j <= 1; j++) {
        for (var i = -1; i <= 1; i++) {
            let q = p + vec2<i32>(i, j);
            if (any(q < vec2<i32>(0)) || any(q >= size)) {
                continue;
            }
            let zq = textureLoad(depth, q, 0).x;
            let w = surface_weight(centre, nc, pixel_view_position(to_view, vec2<f32>(q) + 0.5, zq),
                                   zq, textureLoad(normals, q, 0).xyz);
            if (w > 0.0) {
                // history.x is the accumulated value the temporal block also output.
                let hq = textureLoad(history, q, 0);
                let m1 = clamp(hq.x, 0.0, 1.0);
                let m2 = clamp(select(0.0, hq.z, is_finite_f32(hq.z)), 0.0, 1.0);
                temporal_variance += w * max(m2 - m1 * m1, 0.0);
                pooled_m1 += w * m1;
                pooled_m2 += w * m2;
                msum += w;
                if (params.has_hits > 0.5) {
                    hit = min(hit, textureLoad(hits, q, 0).y);
                }
            }
        }
    }
    // The centre weighs about 1 (its own normal, f16-rounded); the floor keeps a degenerate
    // normal from dividing by zero.
    msum = max(msum, 1e-6);
    temporal_variance = temporal_variance / msum;
    let pooled_variance = max(pooled_m2 / msum - (pooled_m1 / msum) * (pooled_m1 / msum), 0.0);
    let radius = params.base_radius * mix(params.hit_floor, 1.0, clamp(hit, 0.0, 1.0))
        / (1.0 + params.shrink * (n - 1.0));

    var value = a;
    var variance = temporal_variance / n;
    if (n < params.fix_frames) {
        var sum = 0.0;
        var sum2 = 0.0;
        var wsum = 0.0;
        let stride = i32(params.fix_stride);
        for (var j = -2; j <= 2; j++) {
            for (var i = -2; i <= 2; i++) {
                let q = p + vec2<i32>(i, j) * stride;
                if (any(q < vec2<i32>(0)) || any(q >= size)) {
                    continue;
                }
                let zq = textureLoad(depth, q, 0).x;
                let pq = pixel_view_position(to_view, vec2<f32>(q) + 0.5, zq);
                let hq = textureLoad(history, q, 0);
                let w = surface_weight(centre, nc, pq, zq, textureLoad(normals, q, 0).xyz)
                    * max(hq.y, 1.0);
                if (w > 0.0) {
                    let aq = clamp(hq.x, 0.0, 1.0);
                    sum += w * aq;
                    sum2 += w * aq * aq;
                    wsum += w;
                }
            }
        }
        if (wsum > 0.0) {
            let mean = sum / wsum;
            let t = (params.fix_frames - n) / max(params.fix_frames - 1.0, 1.0);
            value = mix(a, mean, clamp(t, 0.0, 1.0));
            // Spatial variance while the history is short (SVGF): the gather's and the 3x3
            // pooled moments', whichever is larger.
            variance = max(variance, max(max(sum2 / wsum - mean * mean, 0.0), pooled_variance));
        }
    }
    textureStore(dst, p, vec4<f32>(clamp(value, 0.0, 1.0), 0.0, 0.0, 0.0));
    textureStore(guide, p, vec4<f32>(variance, radius, n, hit));
}
