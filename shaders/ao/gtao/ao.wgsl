#include "common/view.wgsl"
#include "common/gbuffer.wgsl"
#include "common/finite.wgsl"
#include "common/horizon.wgsl"
#include "common/edges.wgsl"
// gtao.ao: ground-truth AO's slice estimator as XeGTAO computes it (specs/gtao.md §1-§3,
// equation numbers G2-G6 are the spec's). Per pixel, S slices at angles φ_k = π (k + ξ0) / S;
// in each, T steps per side find the horizon cosines c± (G3), with XeGTAO's falloff pulling a
// distant sample towards the tangent horizon c_low± = cos(γ ± π/2). The inner integral is
// analytic and cosine-weighted (G5):
//   a(h) = (cos γ + 2 h sin γ - cos(2h - γ)) / 4,  â = a(h-) + a(h+),
// weighted by the projected normal's length ‖n_p‖ (mixed with 1 by the 0.05 fudge), and the
// slices are averaged (G6): divided by S (XeGTAO, "slice-count") or by the same sum for an
// open hemisphere, Σ ‖n_p‖ (cos γ + γ sin γ) ("unoccluded", the default; the technique's docs
// say why). Then XeGTAO's small-radius fade, the final power, the 0.03 floor.
// Writes the raw accessibility (clamped to [0, 1.5] when a denoiser follows: XeGTAO averages
// before clamping, spec §12; to [0, 1] when this pass is the output) and the depth-edge
// weights for blocks/edge_denoise.wgsl.

struct GtaoParams {
    // slices S, steps per side T, this pass is the output (1) or a denoiser follows (0),
    // normalisation (0 slice count, 1 unoccluded)
    counts: vec4<u32>,
    // R' = R x radius multiplier (view units), falloff range F, sample distribution power,
    // thin-occluder compensation
    shape: vec4<f32>,
    // final value power, depth MIP sampling offset, projected-normal fudge, unused
    tail: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: GtaoParams;
// The prefiltered depth MIPs (blocks/depth_prefilter.wgsl); depth0 is the g-buffer's.
@group(0) @binding(2) var depth0: texture_2d<f32>;
@group(0) @binding(3) var depth1: texture_2d<f32>;
@group(0) @binding(4) var depth2: texture_2d<f32>;
@group(0) @binding(5) var depth3: texture_2d<f32>;
@group(0) @binding(6) var depth4: texture_2d<f32>;
@group(0) @binding(7) var normals: texture_2d<f32>;
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
@group(0) @binding(9) var edges: texture_storage_2d<rgba8unorm, write>;

const PI: f32 = 3.14159265;
const HALF_PI: f32 = 1.57079633;
// XeGTAO: taps closer than this many pixels to the centre are not taken (s_min = 1.3 / r_px).
const PIXEL_TOO_CLOSE: f32 = 1.3;
// XeGTAO: the centre's depth is pulled towards the camera by this factor (fp32), against
// self-occlusion.
const CENTRE_DEPTH_BIAS: f32 = 0.99999;
// XeGTAO: "disallow total occlusion", after the final power.
const VISIBILITY_FLOOR: f32 = 0.03;
// The R1 (golden ratio) step jitter and the R2 sequence's constants (spec §2, §5).
const GOLDEN: f32 = 0.6180339887;
const R2: vec2<f32> = vec2<f32>(0.75487766624669276, 0.56984029099805327);

// XeGTAO's Hilbert-curve index of (x mod 64, y mod 64), 0..4095 (spec §5).
fn hilbert_index(p: vec2<u32>) -> u32 {
    var x = p.x & 63u;
    var y = p.y & 63u;
    var index = 0u;
    for (var level = 32u; level > 0u; level = level / 2u) {
        let rx = select(0u, 1u, (x & level) > 0u);
        let ry = select(0u, 1u, (y & level) > 0u);
        index = index + level * level * ((3u * rx) ^ ry);
        if (ry == 0u) {
            if (rx == 1u) {
                x = 63u - x;
                y = 63u - y;
            }
            let t = x;
            x = y;
            y = t;
        }
    }
    return index;
}

// A depth tap: the view-space point of MIP `level`'s texel under full-resolution pixel `px`.
// Texel i of level l covers pixels [2^l i, 2^l (i + 1)) (blocks/depth_prefilter.wgsl), and its
// depth, a mean over that block, belongs at the block's centre: the point is rebuilt there,
// not at `px` (there, on a slope, the mean lies up to half a texel's depth step in front of
// the surface, and a plane occludes itself).
struct Tap {
    z: f32,
    p: vec3<f32>,
}

fn depth_tap(level: u32, px: vec2<i32>) -> Tap {
    let i = px >> vec2<u32>(level);
    var z: f32;
    switch level {
        case 0u: { z = textureLoad(depth0, i, 0).r; }
        case 1u: { z = textureLoad(depth1, i, 0).r; }
        case 2u: { z = textureLoad(depth2, i, 0).r; }
        case 3u: { z = textureLoad(depth3, i, 0).r; }
        default: { z = textureLoad(depth4, i, 0).r; }
    }
    let full = vec2<f32>(textureDimensions(depth0));
    let scale = f32(1u << level);
    let lo = vec2<f32>(i) * scale;
    let centre = 0.5 * (lo + min(lo + scale, full)); // a partial edge block's own centre
    var t: Tap;
    t.z = z;
    t.p = view_position(centre * view.viewport.zw, z, view);
    return t;
}

// The inner integral's antiderivative at horizon angle h (G5).
fn inner_arc(h: f32, gamma: f32, cos_gamma: f32, sin_gamma: f32) -> f32 {
    return (cos_gamma + 2.0 * h * sin_gamma - cos(2.0 * h - gamma)) * 0.25;
}

fn accessibility(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth0));
    let rc = load_receiver(depth0, normals, p, view);
    if (!rc.valid) {
        return 1.0; // sky or no normal
    }
    let n = rc.n;
    let centre_uv = pixel_uv(p, view);
    let pos = view_position(centre_uv, rc.z * CENTRE_DEPTH_BIAS, view);
    let v = normalize(-pos);

    let effect_radius = params.shape.x;
    let r_px = effect_radius * pixels_per_unit(rc.z, view);
    if (!(r_px >= PIXEL_TOO_CLOSE)) {
        return 1.0; // R' covers no neighbour
    }
    let slices = clamp(params.counts.x, 1u, 32u);
    let steps = clamp(params.counts.y, 1u, 32u);
    // Falloff (spec §3): w = saturate((R' - d) / (F R')) = saturate(d mul + add).
    let falloff_range = max(params.shape.y, 1e-4) * effect_radius;
    let falloff_from = effect_radius * (1.0 - max(params.shape.y, 1e-4));
    let falloff_mul = -1.0 / falloff_range;
    let falloff_add = falloff_from / falloff_range + 1.0;
    let power = params.shape.z;
    let thin = params.shape.w;
    let mip_offset = params.tail.y;
    let fudge = params.tail.z;
    let min_s = PIXEL_TOO_CLOSE / r_px;
    // Noise (spec §5): R2 over the Hilbert index; no temporal term (no TAA here).
    let noise = fract(vec2<f32>(0.5) + f32(hilbert_index(vec2<u32>(p))) * R2);

    var occluded = 0.0;
    var open = 0.0;
    for (var k = 0u; k < slices; k = k + 1u) {
        let phi = PI * (f32(k) + noise.x) / f32(slices);
        // Screen direction (y down) and its view-space twin (y up), G2.
        let omega = vec2<f32>(cos(phi), -sin(phi)) * r_px;
        let dir = vec3<f32>(cos(phi), sin(phi), 0.0);
        let ortho = dir - dot(dir, v) * v;
        let axis = normalize(cross(ortho, v));
        let n_p = n - axis * dot(n, axis);
        let n_len = length(n_p);
        let cos_gamma = saturate(dot(n_p, v) / max(n_len, 1e-4));
        let gamma = select(-1.0, 1.0, dot(ortho, n_p) >= 0.0) * acos(cos_gamma);
        let sin_gamma = sin(gamma);
        let low_pos = cos(gamma + HALF_PI); // tangent horizon on the +ω side
        let low_neg = cos(gamma - HALF_PI); // and on the -ω side
        var c_pos = low_pos;
        var c_neg = low_neg;
        for (var j = 0u; j < steps; j = j + 1u) {
            // XeGTAO's sample distribution (spec §2): R1 jitter, power, s_min.
            let jitter = fract(noise.y + f32(k + j * steps) * GOLDEN);
            let s = pow((f32(j) + jitter) / f32(steps), power) + min_s;
            let offset_px = s * omega;
            let mip = u32(clamp(round(log2(length(offset_px)) - mip_offset), 0.0, 4.0));
            let offset = vec2<i32>(round(offset_px));
            for (var side = 0u; side < 2u; side = side + 1u) {
                let q = p + select(-offset, offset, side == 0u);
                if (any(q < vec2<i32>(0)) || any(q >= size)) {
                    continue; // off screen: no data, no occlusion
                }
                let tap = depth_tap(mip, q);
                if (!(tap.z > 0.0) || !is_finite_f32(tap.z)) {
                    continue; // sky does not occlude
                }
                let delta = tap.p - pos;
                let dist = length(delta);
                if (!(dist > 0.0)) {
                    continue;
                }
                // A sample within the normals' rounding of the tangent plane is the plane
                // itself (common/horizon.wgsl), not occlusion.
                if (sin_elevation(n, delta, dist) <= 0.0) {
                    continue;
                }
                let falloff_dist = length(vec3<f32>(delta.xy, delta.z * (1.0 + thin)));
                let w = saturate(falloff_dist * falloff_mul + falloff_add);
                let c = dot(delta / dist, v);
                if (side == 0u) {
                    c_pos = max(c_pos, mix(low_pos, c, w));
                } else {
                    c_neg = max(c_neg, mix(low_neg, c, w));
                }
            }
        }
        // Horizon angles from V (G3). What a raised horizon hides, per side, is the inner
        // integral between it and the tangent horizon γ ± π/2 (G5); a side no sample raised
        // hides exactly 0, so an open slice is exactly its open value.
        let weight = mix(n_len, 1.0, fudge);
        let open_slice = cos_gamma + gamma * sin_gamma; // â at h = γ ± π/2
        var hidden = 0.0;
        if (c_pos > low_pos) {
            let h = acos(clamp(c_pos, -1.0, 1.0));
            hidden = hidden + inner_arc(gamma + HALF_PI, gamma, cos_gamma, sin_gamma)
                - inner_arc(h, gamma, cos_gamma, sin_gamma);
        }
        if (c_neg > low_neg) {
            let h = -acos(clamp(c_neg, -1.0, 1.0));
            hidden = hidden + inner_arc(gamma - HALF_PI, gamma, cos_gamma, sin_gamma)
                - inner_arc(h, gamma, cos_gamma, sin_gamma);
        }
        occluded = occluded + weight * max(hidden, 0.0);
        open = open + weight * open_slice;
    }
    // G6: 1 - hidden / open ("unoccluded"), or (open - hidden) / S (XeGTAO).
    var a = select((open - occluded) / f32(slices), 1.0 - occluded / max(open, 1e-6),
        params.counts.w == 1u);
    // XeGTAO's small-radius fade (added before its division by S).
    a = a + 0.5 * saturate((10.0 - r_px) / 100.0) / f32(slices);
    a = max(VISIBILITY_FLOOR, pow(max(a, 0.0), params.tail.x));
    return select(clamp(a, 0.0, 1.5), saturate(a), params.counts.z == 1u);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let a = accessibility(p);
    var e = vec4<f32>(0.0);
    if (textureLoad(depth0, p, 0).r > 0.0) {
        e = depth_edges(depth0, p);
    }
    textureStore(ao, p, vec4<f32>(finite_or(a, 1.0), 0.0, 0.0, 0.0));
    textureStore(edges, p, e);
}
