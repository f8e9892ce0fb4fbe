#include "common/view.wgsl"
#include "common/gbuffer.wgsl"
#include "common/noise.wgsl"
#include "common/finite.wgsl"
#include "common/horizon.wgsl"
// hbao.ao: horizon-based AO as docs/techniques/pyramid-hbao.md §1 states it. For each of D azimuth
// directions (evenly spaced, rotated by a per-pixel random angle) march S depth samples out to
// the projected radius R_px; the horizon h(θ) is the highest elevation above the tangent plane
// (sin α = n · V / |V|, less the g-buffer normals' rounding: common/horizon.wgsl) among
// samples closer than R, r(θ) its distance.
//   W(θ) = max(0, 1 - r(θ)/R)                        (Eq. 4)
//   A    = 1 - (1/D) Σ_d W(θ_d) sin h(θ_d)           (Eq. 5, Monte Carlo over θ)
// No tangent-angle term (spec §1.3). Output: raw accessibility, blurred by hbao.blur_x/_y.
// The original HBAO (Bavoil et al. 2008, preset "bavoil-2008"): per-sample attenuation,
//   AO(θ) = Σ_i W(r_i) (sin h_i - sin h_(i-1)) over the samples that raise the horizon, with the
//   horizon starting at the angle bias above the tangent plane, divided by 1 - sin(bias).

struct HbaoParams {
    // Directions D.
    directions: u32,
    // Steps S per direction.
    steps: u32,
    // Attenuation: 0 at the horizon, 1 per sample.
    per_sample: u32,
    pad0: u32,
    // R (world units).
    radius: f32,
    // Cap of the projected radius (fraction of the image height).
    max_screen_radius: f32,
    // sin(angle bias).
    sin_bias: f32,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: HbaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
// Raw accessibility: an intermediate when blurred (the `?IntermediateStorage=f16` variant of this
// file writes it at half precision; crates/graph/src/shader/variant.rs, "Storage-precision variants"),
// else the output.
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(4) var ao: IntermediateStorage;

fn accessibility(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth));
    let rc = load_receiver(depth, normals, p, view);
    if (!rc.valid) {
        return 1.0; // sky or no normal
    }
    let z = rc.z;
    let n = rc.n;
    let o = rc.p;

    // R_screen (§3.1): R projected to pixels, capped (R shrinks to match).
    let ppu = pixels_per_unit(z, view);
    let r_px = min(params.radius * ppu, params.max_screen_radius * view.size.y);
    if (!(r_px >= 1.0)) {
        return 1.0; // no neighbour within R
    }
    let r = r_px / ppu;
    let dirs = clamp(params.directions, 1u, 64u);
    let steps = clamp(params.steps, 1u, 128u);
    let step_px = (r_px - 1.0) / f32(steps);
    // Per-pixel random rotation of the directions and start offset of the march.
    // With temporal accumulation both advance by the R2 sequence's step each frame (a
    // low-discrepancy walk over the frames of the running mean).
    let frame = f32(noise_frame(view.frame_index));
    let rotation = fract(hash_pixel(vec2<u32>(p), 0x9e3779b9u) + frame * 0.7548776662);
    let jitter = fract(hash_pixel(vec2<u32>(p), 0x85ebca6bu) + frame * 0.5698402910);
    let centre = vec2<f32>(p) + 0.5;
    let eps = 1e-4 * z;

    let per_sample = params.per_sample == 1u;
    let sin_bias = clamp(params.sin_bias, 0.0, 0.99);
    var sum = 0.0;
    for (var d = 0u; d < dirs; d = d + 1u) {
        let theta = 6.2831853 * (f32(d) + rotation) / f32(dirs);
        let dir = vec2<f32>(cos(theta), sin(theta));
        var sin_h = sin_bias; // horizon starts at the (biased) tangent plane
        var r_h = r;          // W(r) = 0 until a sample rises above it
        var rises = 0.0;      // Σ W(r_i) (sin h_i - sin h_(i-1)), per-sample attenuation
        for (var i = 0u; i < steps; i = i + 1u) {
            let sp = centre + dir * (1.0 + (f32(i) + jitter) * step_px);
            if (any(sp < vec2<f32>(0.0)) || any(sp >= vec2<f32>(size))) {
                break; // off screen: the rest of the march is too
            }
            let q = vec2<i32>(floor(sp));
            if (all(q == p)) {
                continue;
            }
            let zq = textureLoad(depth, q, 0).x;
            if (!(zq > 0.0)) {
                continue; // sky does not occlude
            }
            let v = view_position(pixel_uv(q, view), zq, view) - o;
            let dist = length(v);
            if (!(dist > eps) || dist >= r) {
                continue; // beyond R: W = 0 (Eq. 4)
            }
            let sin_a = sin_elevation(n, v, dist); // less the normals' rounding
            if (sin_a > sin_h) {
                rises = rises + max(0.0, 1.0 - dist / r) * (sin_a - sin_h);
                sin_h = sin_a;
                r_h = dist;
            }
        }
        // W(θ) sin h(θ), Eqs. 4-5; or the per-sample sum. Both over 1 - sin(bias).
        let horizon = max(0.0, 1.0 - r_h / r) * (sin_h - sin_bias);
        sum = sum + select(horizon, rises, per_sample);
    }
    let a = 1.0 - sum / (f32(dirs) * (1.0 - sin_bias));
    return accessibility_or_one(a);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    textureStore(ao, p, vec4<f32>(accessibility(p), 0.0, 0.0, 0.0));
}
