#include "common/slices.wgsl"
// GTAO's estimator (docs/techniques/gtao.md §1-§3, G2-G6 the spec's numbers), shared by the AO pass
// (ao/gtao/ao.wgsl) and its variant that also writes bent normals (ao/gtao/ao_bent.wgsl). Per
// pixel, S slices at angles φ_k = π (k + ξ0) / S; in each, T steps per side find the horizon
// cosines c± (G3), with XeGTAO's falloff pulling a distant sample towards the tangent horizon
// c_low± = cos(γ ± π/2). The inner integral is analytic and cosine-weighted (G5):
//   a(h) = (cos γ + 2 h sin γ - cos(2h - γ)) / 4,  â = a(h-) + a(h+),
// weighted by the projected normal's length ‖n_p‖ (mixed with 1 by the 0.05 fudge), and the
// slices are averaged (G6): divided by S (XeGTAO, "slice-count") or by the same sum for an
// open hemisphere, Σ ‖n_p‖ (cos γ + γ sin γ) ("unoccluded", the default; the technique's docs
// say why). Then XeGTAO's small-radius fade, the final power, the 0.03 floor. The raw
// accessibility is clamped to [0, 1.5] when a denoiser follows (XeGTAO averages before
// clamping, spec §12), to [0, 1] when the AO pass is the output.

struct GtaoParams {
    // Slices S.
    slices: u32,
    // Steps T per side.
    steps: u32,
    // 1: this pass is the output; 0: a denoiser follows.
    is_output: u32,
    // Normalisation: 0 slice count, 1 unoccluded.
    normalization: u32,
    // R' = R x radius multiplier (view units).
    effect_radius: f32,
    // Falloff range F (fraction of R').
    falloff_range: f32,
    // Sample distribution power.
    sample_distribution_power: f32,
    // Thin-occluder compensation.
    thin_occluder_compensation: f32,
    // Final value power.
    final_value_power: f32,
    // Depth MIP sampling offset.
    depth_mip_offset: f32,
    // Projected-normal fudge.
    normal_fudge: f32,
    pad0: f32,
}

@group(0) @binding(1) var<uniform> params: GtaoParams;

// XeGTAO: "disallow total occlusion", after the final power.
const VISIBILITY_FLOOR: f32 = 0.03;

// The estimate at pixel p: accessibility (clamped as `gtao.ao` writes it) and XeGTAO's bent
// normal (Algorithm 2, spec §1.5; view space, unit; the pixel's own normal on sky or when
// nothing was sampled).
struct Estimate {
    a: f32,
    bent: vec3<f32>,
}

fn estimate(p: vec2<i32>) -> Estimate {
    var e: Estimate;
    e.a = 1.0;
    e.bent = vec3<f32>(0.0, 0.0, 1.0);
    let effect_radius = params.effect_radius;
    let c = centre_of(p, effect_radius);
    if (!c.valid) {
        let rc = load_receiver(depth0, normals, p, view);
        e.bent = select(e.bent, rc.n, rc.valid);
        return e; // sky, no normal, or R' covers no neighbour
    }
    let slices = clamp(params.slices, 1u, 32u);
    let steps = clamp(params.steps, 1u, 32u);
    // Falloff (spec §3): w = saturate((R' - d) / (F R')) = saturate(d mul + add).
    let falloff_range = max(params.falloff_range, 1e-4) * effect_radius;
    let falloff_from = effect_radius * (1.0 - max(params.falloff_range, 1e-4));
    let falloff_mul = -1.0 / falloff_range;
    let falloff_add = falloff_from / falloff_range + 1.0;
    let thin = params.thin_occluder_compensation;
    let fudge = params.normal_fudge;

    var occluded = 0.0;
    var open = 0.0;
    var bent = vec3<f32>(0.0);
    for (var k = 0u; k < slices; k = k + 1u) {
        let s = slice_of(c, k, slices);
        var c_pos = s.low_pos;
        var c_neg = s.low_neg;
        for (var j = 0u; j < steps; j = j + 1u) {
            let st = step_of(
                c, s, k, j, steps, params.sample_distribution_power, params.depth_mip_offset);
            for (var side = 0u; side < 2u; side = side + 1u) {
                // With two layers (`layers = 2`) the tap's second-layer surface is a horizon
                // candidate too: where the first layer lies far in front (falloff weight
                // near 0), the surface it hides may still occlude (Mara et al. 2016's AO takes
                // each tap's stronger layer).
                for (var layer = 0u; layer < select(1u, 2u, SECOND_LAYER); layer = layer + 1u) {
                    var smp: Sample;
                    if (layer == 0u) {
                        smp = sample_of(c, st, side);
                    } else {
                        smp = sample_from(c, second_layer_tap(c, st, side));
                    }
                    if (!smp.valid) {
                        continue;
                    }
                    // Horizon cosine, pulled towards the tangent horizon by the falloff (G3).
                    let delta = smp.delta;
                    let falloff_dist = length(vec3<f32>(delta.xy, delta.z * (1.0 + thin)));
                    let w = saturate(falloff_dist * falloff_mul + falloff_add);
                    let cs = dot(delta / smp.dist, c.v);
                    if (side == 0u) {
                        c_pos = max(c_pos, mix(s.low_pos, cs, w));
                    } else {
                        c_neg = max(c_neg, mix(s.low_neg, cs, w));
                    }
                }
            }
        }
        // Horizon angles from V (G3). What a raised horizon hides, per side, is the inner
        // integral between it and the tangent horizon γ ± π/2 (G5); a side no sample raised
        // hides exactly 0, so an open slice is exactly its open value.
        let weight = mix(s.n_len, 1.0, fudge);
        let open_slice = s.cos_gamma + s.gamma * s.sin_gamma; // â at h = γ ± π/2
        // Horizon angles (G3): an untouched side keeps its exact tangent angle γ ± π/2.
        let h_pos = select(s.gamma + HALF_PI, acos(clamp(c_pos, -1.0, 1.0)), c_pos > s.low_pos);
        let h_neg = select(s.gamma - HALF_PI, -acos(clamp(c_neg, -1.0, 1.0)), c_neg > s.low_neg);
        var hidden = 0.0;
        if (c_pos > s.low_pos) {
            hidden = hidden + inner_arc(s.gamma + HALF_PI, s.gamma, s.cos_gamma, s.sin_gamma)
                - inner_arc(h_pos, s.gamma, s.cos_gamma, s.sin_gamma);
        }
        if (c_neg > s.low_neg) {
            hidden = hidden + inner_arc(s.gamma - HALF_PI, s.gamma, s.cos_gamma, s.sin_gamma)
                - inner_arc(h_neg, s.gamma, s.cos_gamma, s.sin_gamma);
        }
        bent = bent + weight * slice_bent_normal(c, s, h_neg, h_pos);
        occluded = occluded + weight * max(hidden, 0.0);
        open = open + weight * open_slice;
    }
    // G6: 1 - hidden / open ("unoccluded"), or (open - hidden) / S (XeGTAO).
    var a = select((open - occluded) / f32(slices), 1.0 - occluded / max(open, 1e-6),
        params.normalization == 1u);
    // XeGTAO's small-radius fade (added before its division by S).
    a = a + 0.5 * saturate((10.0 - c.r_px) / 100.0) / f32(slices);
    a = max(VISIBILITY_FLOOR, pow(max(a, 0.0), params.final_value_power));
    e.a = select(clamp(a, 0.0, 1.5), saturate(a), params.is_output == 1u);
    let l = length(bent);
    e.bent = select(c.n, bent / l, l > 1e-12);
    return e;
}

// One slice's bent-normal contribution (XeGTAO, Algorithm 2): the cosine-weighted mean
// direction of the visible arc [h-, h+], in the slice frame (d along the slice, V towards the
// camera), rotated from view-space +z onto V. Unweighted by |n_p| (the caller weighs it).
fn slice_bent_normal(c: Centre, s: Slice, h0: f32, h1: f32) -> vec3<f32> {
    let n = s.gamma;
    let t0 = (6.0 * sin(h0 - n) - sin(3.0 * h0 - n) + 6.0 * sin(h1 - n) - sin(3.0 * h1 - n)
        + 16.0 * sin(n) - 3.0 * (sin(h0 + n) + sin(h1 + n))) / 12.0;
    let t1 = (-cos(3.0 * h0 - n) - cos(3.0 * h1 - n) + 8.0 * cos(n)
        - 3.0 * (cos(h0 + n) + cos(h1 + n))) / 12.0;
    let d = normalize(vec2<f32>(s.omega.x, -s.omega.y)); // the slice's view-space direction
    let local = vec3<f32>(d * t0, t1);
    // Rotation taking +z to V (Rodrigues with c = z x V; V.z > 0 for any visible point).
    let z = vec3<f32>(0.0, 0.0, 1.0);
    let axis = cross(z, c.v);
    let cos_a = dot(z, c.v);
    return local + cross(axis, local) + cross(axis, cross(axis, local)) / (1.0 + cos_a);
}

