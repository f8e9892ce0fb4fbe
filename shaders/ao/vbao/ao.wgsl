#include "common/slices.wgsl"
#include "common/edges.wgsl"
// vbao.ao: visibility-bitmask AO (Therrien, Levesque, Gilet 2023; docs/techniques/vbao.md, V1-V6 are the
// spec's numbers) on GTAO's slices, steps, MIPs and noise (common/slices.wgsl). Per slice, N
// sectors spread uniformly in angle over the π-wide arc centred on the projected normal, one
// bit each. Every tap is a surface of constant thickness T: it occludes the arc between its
// front Δ_f = S - P and its back Δ_b = Δ_f - T V (V1), mapped to sector coordinates by
//   t = saturate((σ θ - γ) / π + 1/2)                                        (V2)
// (σ = +1 on the +ω side, θ the angle from V; the /π on both θ and γ is the one bevy lacked
// until #25334), and the sectors it covers are set (V3): by their centres (round both ends, the
// default: unbiased, spec §10) or by any touch (ceil, the blog's shipped rule). Per slice
//   uniform (V4, the blog's rule):  v = 1 - popcount(b) / N,  A = mean over slices;
//   cosine  (V6):  each set sector k hides w_k = ∫ cos(ϑ - γ)|sin ϑ| dϑ over its span, weighted
//                  by ‖n_p‖, and A = 1 - Σ hidden / Σ ‖n_p‖ (cos γ + γ sin γ), GTAO's measure.
// Then the final power and 0.03 floor (bevy). No falloff (spec §6); taps farther than R' from P
// are dropped when `clip` is on (spec §9, the reference's hard radius).

struct VbaoParams {
    // Slices S.
    slices: u32,
    // Steps T per side.
    steps: u32,
    pad0: u32,
    // Sectors N.
    sectors: u32,
    // R' (view units).
    effect_radius: f32,
    // Thickness T (view units).
    thickness: f32,
    // Sample distribution power.
    sample_distribution_power: f32,
    // Depth MIP sampling offset.
    depth_mip_offset: f32,
    // Final value power.
    final_value_power: f32,
    // Weighting: 1.0 cosine, 0.0 uniform.
    cosine_weighting: f32,
    // Sector rounding: 1.0 centre, 0.0 ceil.
    centre_rounding: f32,
    // 1.0: taps farther than R' are dropped.
    clip_to_radius: f32,
}

@group(0) @binding(1) var<uniform> params: VbaoParams;
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
@group(0) @binding(9) var edges: texture_storage_2d<rgba8unorm, write>;

// bevy: "disallow total occlusion".
const VISIBILITY_FLOOR: f32 = 0.03;

// Bits [start, start + count) of a u32, clipped to 32 bits; 0 when count is 0 (a plain
// 0xFFFFFFFF >> (32 - count) would shift by 32 there, spec §5).
fn sector_mask(start: u32, count: u32) -> u32 {
    let s = min(start, 32u);
    let c = min(count, 32u - s);
    if (c == 0u) {
        return 0u;
    }
    let ones = select((1u << c) - 1u, 0xFFFFFFFFu, c == 32u);
    return ones << s;
}

// V2: the sector coordinate of a tap direction at angle θ from V on side σ.
fn sector_coordinate(sigma: f32, cos_theta: f32, gamma: f32) -> f32 {
    return saturate((sigma * acos(clamp(cos_theta, -1.0, 1.0)) - gamma) / PI + 0.5);
}

// V6: what sector k of n hides, ∫ cos(ϑ - γ)|sin ϑ| dϑ over ϑ in [γ - π/2 + kπ/n, + π/n],
// split at ϑ = 0 where |sin ϑ| changes sign.
fn sector_weight(k: u32, n: u32, s: Slice) -> f32 {
    let a = s.gamma - HALF_PI + f32(k) * PI / f32(n);
    let b = a + PI / f32(n);
    let lo = min(b, 0.0);
    let hi = max(a, 0.0);
    var w = 0.0;
    if (a < 0.0) {
        w = w + inner_arc(a, s.gamma, s.cos_gamma, s.sin_gamma)
            - inner_arc(lo, s.gamma, s.cos_gamma, s.sin_gamma);
    }
    if (b > 0.0) {
        w = w + inner_arc(b, s.gamma, s.cos_gamma, s.sin_gamma)
            - inner_arc(hi, s.gamma, s.cos_gamma, s.sin_gamma);
    }
    return max(w, 0.0);
}

// V2-V3: the sectors the arc between a tap's front and back covers (both as offsets from
// the receiver; v towards the viewer, sigma the side, gamma the slice's normal angle).
fn interval_bits(front: vec3<f32>, back: vec3<f32>, v: vec3<f32>, sigma: f32, gamma: f32,
                 n: u32, centres: bool) -> u32 {
    let cos_front = dot(front / max(length(front), 1e-30), v);
    let cos_back = dot(back, v) / max(length(back), 1e-30);
    let t_front = sector_coordinate(sigma, cos_front, gamma);
    let t_back = sector_coordinate(sigma, cos_back, gamma);
    let t_min = min(t_front, t_back);
    let t_max = max(t_front, t_back);
    // V3: the sectors the interval covers.
    var start: u32;
    var count: u32;
    if (centres) {
        start = u32(round(f32(n) * t_min));
        count = u32(max(round(f32(n) * t_max) - f32(start), 0.0));
    } else {
        start = u32(floor(f32(n) * t_min));
        count = u32(ceil(f32(n) * (t_max - t_min)));
    }
    return sector_mask(start, count);
}

fn accessibility(p: vec2<i32>) -> f32 {
    let effect_radius = params.effect_radius;
    let c = centre_of(p, effect_radius);
    if (!c.valid) {
        return 1.0; // sky, no normal, or R' covers no neighbour
    }
    let slices = clamp(params.slices, 1u, 32u);
    let steps = clamp(params.steps, 1u, 32u);
    let n = clamp(params.sectors, 1u, 32u);
    let thickness = params.thickness;
    let cosine = params.cosine_weighting > 0.5;
    let centres = params.centre_rounding > 0.5;
    let clip = params.clip_to_radius > 0.5;

    var set_bits = 0u;   // uniform: Σ popcount
    var hidden = 0.0;    // cosine: Σ ‖n_p‖ Σ_set w_k
    var open = 0.0;      // cosine: Σ ‖n_p‖ (cos γ + γ sin γ)
    for (var k = 0u; k < slices; k = k + 1u) {
        let s = slice_of(c, k, slices);
        var bits = 0u;
        for (var j = 0u; j < steps; j = j + 1u) {
            let st = step_of(
                c, s, k, j, steps, params.sample_distribution_power, params.depth_mip_offset);
            for (var side = 0u; side < 2u; side = side + 1u) {
                let smp = sample_of(c, st, side);
                if (!smp.valid || (clip && smp.dist > effect_radius)) {
                    continue;
                }
                // V1: the tap's front and back (T further from the viewer along V). With two
                // layers (`layers = 2`) the back is the second layer's front under the tap
                // (the first layer's real thickness), and the second layer's own surface
                // occludes its arc of thickness T too; without a second layer there, T.
                let sigma = select(-1.0, 1.0, side == 0u);
                var back = smp.delta - thickness * c.v;
                if (SECOND_LAYER) {
                    let t2 = second_layer_tap(c, st, side);
                    if (t2.z > 0.0) {
                        back = t2.p - c.pos;
                        let s2 = sample_from(c, t2);
                        if (s2.valid && !(clip && s2.dist > effect_radius)) {
                            bits = bits | interval_bits(s2.delta, s2.delta - thickness * c.v,
                                c.v, sigma, s.gamma, n, centres);
                        }
                    }
                }
                bits = bits | interval_bits(smp.delta, back, c.v, sigma, s.gamma, n, centres);
            }
        }
        set_bits = set_bits + countOneBits(bits);
        if (cosine) {
            var h = 0.0;
            for (var b = 0u; b < n; b = b + 1u) {
                if ((bits & (1u << b)) != 0u) {
                    h = h + sector_weight(b, n, s);
                }
            }
            hidden = hidden + s.n_len * h;
            open = open + s.n_len * (s.cos_gamma + s.gamma * s.sin_gamma);
        }
    }
    var a = select(1.0 - f32(set_bits) / f32(n * slices), 1.0 - hidden / max(open, 1e-6),
        cosine);
    a = max(VISIBILITY_FLOOR, pow(max(a, 0.0), params.final_value_power));
    return saturate(a);
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
