#include "common/view.wgsl"
#include "common/gbuffer.wgsl"
#include "common/finite.wgsl"
#include "common/horizon.wgsl"
#include "common/noise.wgsl"
// What the slice-based techniques (ao/gtao, ao/vbao) share (docs/techniques/gtao.md §1.2, §2, §5; vbao.md
// §2 takes them unchanged): their inputs, the receiver's set-up, XeGTAO's noise and sample
// placement, depth taps on the prefiltered MIPs (blocks/depth_prefilter.wgsl) and the slice
// geometry. Bindings 0, 2-7 and 11 are declared here; the including file declares 1 (its
// parameters), 8 (the raw accessibility) and 9 (the denoiser's edges).

@group(0) @binding(0) var<uniform> view: View;
// The prefiltered depth MIPs; depth0 is the g-buffer's linear depth.
@group(0) @binding(2) var depth0: texture_2d<f32>;
@group(0) @binding(3) var depth1: texture_2d<f32>;
@group(0) @binding(4) var depth2: texture_2d<f32>;
@group(0) @binding(5) var depth3: texture_2d<f32>;
@group(0) @binding(6) var depth4: texture_2d<f32>;
@group(0) @binding(7) var normals: texture_2d<f32>;
// The second depth layer (GBufferChannel::SecondLayerDepth: the nearest surface at least Δ
// behind the first; Mara, McGuire, Nowrouzezahrai, Luebke 2016), read only when SECOND_LAYER
// is set (`layers = 2`); a one-layer plan binds depth0 here and never reads it.
@group(0) @binding(11) var second_layer: texture_2d<f32>;
override SECOND_LAYER: bool = false;

const PI: f32 = 3.14159265;
const HALF_PI: f32 = 1.57079633;
// XeGTAO: taps closer than this many pixels to the centre are not taken (s_min = 1.3 / r_px).
const PIXEL_TOO_CLOSE: f32 = 1.3;
// XeGTAO: the centre's depth is pulled towards the camera by this factor (fp32), against
// self-occlusion.
const CENTRE_DEPTH_BIAS: f32 = 0.99999;
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
    t.p = view_position(centre * view.inv_size, z, view);
    return t;
}

// GTAO's inner integral's antiderivative at angle h from V (G5): ∫ cos(θ - γ)|sin θ| dθ over
// [h1, h2] on one side of V is the difference of this at the two ends (negated below V).
fn inner_arc(h: f32, gamma: f32, cos_gamma: f32, sin_gamma: f32) -> f32 {
    return (cos_gamma + 2.0 * h * sin_gamma - cos(2.0 * h - gamma)) * 0.25;
}

// The receiver: pixel, unit normal, view-space point (with XeGTAO's centre bias), view vector,
// R' in pixels and its noise.
struct Centre {
    valid: bool,
    p: vec2<i32>,
    n: vec3<f32>,
    pos: vec3<f32>,
    v: vec3<f32>,
    r_px: f32,
    noise: vec2<f32>,
}

// Invalid on sky, without a normal, or where R' covers no neighbour (under 1.3 pixels).
fn centre_of(p: vec2<i32>, effect_radius: f32) -> Centre {
    var c: Centre;
    c.valid = false;
    let rc = load_receiver(depth0, normals, p, view);
    if (!rc.valid) {
        return c;
    }
    c.p = p;
    c.n = rc.n;
    c.pos = view_position(pixel_uv(p, view), rc.z * CENTRE_DEPTH_BIAS, view);
    c.v = normalize(-c.pos);
    c.r_px = effect_radius * pixels_per_unit(rc.z, view);
    // Noise (spec §5): R2 over the Hilbert index; XeGTAO's temporal term (288 (frame mod 64))
    // only when the output is accumulated (TEMPORAL_NOISE, common/noise.wgsl).
    let index = hilbert_index(vec2<u32>(p)) + 288u * (noise_frame(view.frame_index) % 64u);
    c.noise = fract(vec2<f32>(0.5) + f32(index) * R2);
    c.valid = c.r_px >= PIXEL_TOO_CLOSE;
    return c;
}

// Slice k of `slices` (G2): its screen direction ω (pixels, y down, length R'), the projected
// normal's length, the signed angle γ from V to it, and the tangent horizons' cosines on the
// +ω side (cos(γ + π/2)) and the -ω side (cos(γ - π/2)).
struct Slice {
    omega: vec2<f32>,
    n_len: f32,
    gamma: f32,
    cos_gamma: f32,
    sin_gamma: f32,
    low_pos: f32,
    low_neg: f32,
}

fn slice_of(c: Centre, k: u32, slices: u32) -> Slice {
    var s: Slice;
    let phi = PI * (f32(k) + c.noise.x) / f32(slices);
    s.omega = vec2<f32>(cos(phi), -sin(phi)) * c.r_px;
    let dir = vec3<f32>(cos(phi), sin(phi), 0.0); // ω's view-space twin (y up)
    let ortho = dir - dot(dir, c.v) * c.v;
    let axis = normalize(cross(ortho, c.v));
    let n_p = c.n - axis * dot(c.n, axis);
    s.n_len = length(n_p);
    s.cos_gamma = saturate(dot(n_p, c.v) / max(s.n_len, 1e-4));
    s.gamma = select(-1.0, 1.0, dot(ortho, n_p) >= 0.0) * acos(s.cos_gamma);
    s.sin_gamma = sin(s.gamma);
    s.low_pos = cos(s.gamma + HALF_PI);
    s.low_neg = cos(s.gamma - HALF_PI);
    return s;
}

// Step j of `steps` in slice k (spec §2): XeGTAO's R1 jitter, distribution power and s_min,
// the offset rounded to whole pixels, and the depth MIP log2(|offset|) - `mip_offset`.
struct Step {
    offset: vec2<i32>,
    mip: u32,
}

fn step_of(c: Centre, s: Slice, k: u32, j: u32, steps: u32, power: f32, mip_offset: f32) -> Step {
    var st: Step;
    let jitter = fract(c.noise.y + f32(k + j * steps) * GOLDEN);
    let t = pow((f32(j) + jitter) / f32(steps), power) + PIXEL_TOO_CLOSE / c.r_px;
    let offset_px = t * s.omega;
    st.mip = u32(clamp(round(log2(length(offset_px)) - mip_offset), 0.0, 4.0));
    st.offset = vec2<i32>(round(offset_px));
    return st;
}

// The tap of step `st` on side `side` (0: +ω, 1: -ω), as the vector from the receiver.
// Invalid off screen and on sky (no data, no occlusion), and within the g-buffer normals'
// rounding of the tangent plane (common/horizon.wgsl: the plane itself, not occlusion).
struct Sample {
    valid: bool,
    delta: vec3<f32>,
    dist: f32,
}

fn sample_of(c: Centre, st: Step, side: u32) -> Sample {
    var smp: Sample;
    smp.valid = false;
    let size = vec2<i32>(textureDimensions(depth0));
    let q = c.p + select(-st.offset, st.offset, side == 0u);
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return smp;
    }
    return sample_from(c, depth_tap(st.mip, q));
}

// A tap's point as a sample of receiver c (invalid on sky, or on the tangent plane or below).
fn sample_from(c: Centre, tap: Tap) -> Sample {
    var smp: Sample;
    smp.valid = false;
    if (!(tap.z > 0.0) || !is_finite_f32(tap.z)) {
        return smp;
    }
    smp.delta = tap.p - c.pos;
    smp.dist = length(smp.delta);
    smp.valid = smp.dist > 0.0 && sin_elevation(c.n, smp.delta, smp.dist) > 0.0;
    return smp;
}

// The second layer under step `st`'s tap on `side`, at the tap's own full-resolution pixel;
// z = 0 off screen and where the layer holds no surface.
fn second_layer_tap(c: Centre, st: Step, side: u32) -> Tap {
    var t: Tap;
    t.z = 0.0;
    t.p = vec3<f32>(0.0);
    let size = vec2<i32>(textureDimensions(second_layer));
    let q = c.p + select(-st.offset, st.offset, side == 0u);
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return t;
    }
    let z = textureLoad(second_layer, q, 0).r;
    if (!(z > 0.0) || !is_finite_f32(z)) {
        return t;
    }
    t.z = z;
    t.p = view_position(pixel_uv(q, view), z, view);
    return t;
}
