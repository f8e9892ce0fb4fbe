#include "common/finite.wgsl"
// SSDO (docs/techniques/ssdo.md): the blocks ssdo.direct, ssdo.indirect and ssdo.blur share. Included
// after common/view.wgsl and common/noise.wgsl; it names nothing from them, so it also
// validates on its own. Rust mirrors: SsdoUniform (techniques/ssdo/kernel.rs) and
// LightingUniforms (crates/frame/src/lighting.rs).

struct SsdoParams {
    // r_max (world units).
    r_max: f32,
    // Fade start (world units).
    fade_start: f32,
    // Depth bias (world units).
    bias: f32,
    // Sender patch area A_s = pi r_max^2 / N (E3, world units^2).
    sender_area: f32,
    // Distance clamp of E2 (scene units).
    distance_clamp: f32,
    // Light lobe exponent.
    light_lobe: f32,
    // Sky gradient.
    sky_gradient: f32,
    // Blur plane tolerance (world units).
    blur_plane_tolerance: f32,
    // Sample count N.
    sample_count: u32,
    // Bounce: 0 or 1.
    bounce: u32,
    // Environment: 0 ambient, 1 sky.
    sky: u32,
    pad0: u32,
    // 16 interleaved sets of up to 16 samples, [set * 16 + i] = (lambda_i omega_i in units of
    // r_max in the frame (t, b, n), cos theta_i)
    samples: array<vec4<f32>, 256>,
}

struct Lighting {
    // World-space unit direction the directional light travels.
    light_direction: vec3<f32>,
    pad0: f32,
    // Colour times intensity (linear RGB).
    light_color: vec3<f32>,
    pad1: f32,
    // Ambient: the constant environment radiance (linear RGB).
    ambient: vec3<f32>,
    pad2: f32,
    // The sky (environment = "sky"): zenith, horizon, ground radiance (linear RGB); the
    // world-space unit direction towards the sun and the sun lobe's exponent k; the sun lobe's
    // irradiance on a surface facing it (linear RGB).
    sky_zenith: vec3<f32>,
    pad3: f32,
    sky_horizon: vec3<f32>,
    pad4: f32,
    sky_ground: vec3<f32>,
    pad5: f32,
    sun_direction: vec3<f32>,
    sun_exponent: f32,
    sun_irradiance: vec3<f32>,
    pad6: f32,
}

// Radiance of the sky arriving from world direction `w` (unit): zenith to horizon by sqrt(y),
// horizon to ground over y in [-0.25, 0], plus the sun lobe E (k + 1) / (2 pi) max(0, w.s)^k.
// CPU mirror: aograph_scene::SkyEnvironment::radiance.
fn sky_radiance(sky: Lighting, w: vec3<f32>) -> vec3<f32> {
    var c = mix(sky.sky_horizon, sky.sky_ground, min(-w.y / 0.25, 1.0));
    if (w.y >= 0.0) {
        c = mix(sky.sky_horizon, sky.sky_zenith, sqrt(w.y));
    }
    let k = sky.sun_exponent;
    let lobe = pow(max(dot(w, sky.sun_direction), 0.0), k) * (k + 1.0) / 6.28318531;
    return c + sky.sun_irradiance * lobe;
}

// One classified sample point.
struct SsdoTap {
    // 1 - V: 0 visible, 1 a full blocker, in between inside the border fade.
    occlusion: f32,
    // The pixel the sample projects to (meaningful when occlusion > 0).
    pixel: vec2<i32>,
    // The position-buffer point at that pixel: the sender patch position Q (view space).
    surface: vec3<f32>,
}

fn ssdo_normalize(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    return select(vec3<f32>(0.0), v / l, l > 1e-20);
}

// Finite, non-negative radiance that fits in an f16 (NaN becomes 0).
fn ssdo_clean(v: vec3<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), clamp(v, vec3<f32>(0.0), vec3<f32>(65000.0)), is_finite_vec3(v));
}

// smoothstep that tolerates e0 == e1 (a step there).
fn ssdo_smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = clamp((x - e0) / max(e1 - e0, 1e-20), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Orthonormal frame (t, b, n) around unit n as matrix columns (Duff et al. 2017).
fn ssdo_frame(n: vec3<f32>) -> mat3x3<f32> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat3x3<f32>(vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3<f32>(b, s + n.y * n.y * a, -n.y), n);
}

// Distance along the eye ray (origin o, unit direction d) to the plane through `p` with normal
// `n`; -1 where the ray is (nearly) parallel to the plane or meets it behind the origin.
fn ssdo_ray_plane(o: vec3<f32>, d: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let den = dot(d, n);
    if (!(abs(den) > 1e-4)) {
        return -1.0;
    }
    let t = dot(p - o, n) / den;
    return select(-1.0, t, t > 0.0 && t < 1e30);
}

// The eye ray through view-space point `x`: origin and unit direction (from the eye in
// perspective, from the image plane along -z when orthographic).
fn ssdo_eye_origin(x: vec3<f32>, ortho: bool) -> vec3<f32> {
    return select(vec3<f32>(0.0), vec3<f32>(x.xy, 0.0), ortho);
}
fn ssdo_eye_dir(x: vec3<f32>, ortho: bool) -> vec3<f32> {
    return select(ssdo_normalize(x), vec3<f32>(0.0, 0.0, -1.0), ortho);
}

// Classifies the sample point `s` of the receiver `p` with normal `n` (view space) against the
// position buffer (docs/techniques/ssdo.md §1.4): `s` is back-projected to its pixel, the position Q there
// is read, and `s` is a blocker when projecting it onto the surface brings it nearer the viewer
// (by more than `bias`). Q lies on the ray through its pixel's centre, up to half a pixel from
// the sample's ray, which on grazing surfaces reads the receiver's own surface nearer than the
// sample; so both distances are measured from the receiver's tangent plane along their own rays
// (exact for planes, the plain test when the rays coincide; the plain test where the plane is
// edge-on). Blockers fade out between `fade_start` and `r_max` from p (§7.2). Off-screen,
// behind-camera and sky taps are visible.
fn ssdo_tap(positions: texture_2d<f32>, p: vec3<f32>, n: vec3<f32>, s: vec3<f32>, proj: mat4x4<f32>, ortho: bool, r_max: f32, fade_start: f32, bias: f32) -> SsdoTap {
    var tap: SsdoTap;
    tap.occlusion = 0.0;
    tap.pixel = vec2<i32>(0);
    tap.surface = s;
    let c = proj * vec4<f32>(s, 1.0);
    if (!(c.w > 1e-6)) {
        return tap; // behind the camera
    }
    let ndc = c.xy / c.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (!(all(uv >= vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0)))) {
        return tap; // off screen (or NaN)
    }
    let size = vec2<i32>(textureDimensions(positions));
    let q = clamp(vec2<i32>(floor(uv * vec2<f32>(size))), vec2<i32>(0), size - 1);
    let qp = textureLoad(positions, q, 0);
    if (qp.w < 0.5) {
        return tap; // sky
    }
    let sq = qp.xyz;
    // A surface on or below the receiver's tangent plane cannot block a sample above it (a
    // line from the eye, above the plane, crosses it once); without this, where q's pixel
    // straddles the plane's horizon the sample's ray misses the plane while q's centre ray
    // meets it, and the plain test sees the receiver's own plane in front of the sample (a
    // plane 89.9 degrees to the view came out 0.67 at 1x1).
    if (dot(n, sq - p) <= bias) {
        return tap;
    }
    let os = ssdo_eye_origin(s, ortho);
    let ds = ssdo_eye_dir(s, ortho);
    let oq = ssdo_eye_origin(sq, ortho);
    let dq = ssdo_eye_dir(sq, ortho);
    // Distances to the viewer along each ray, and the heights above the receiver's plane.
    let t_s = dot(s - os, ds);
    let t_q = dot(sq - oq, dq);
    let plane_s = ssdo_ray_plane(os, ds, p, n);
    let plane_q = ssdo_ray_plane(oq, dq, p, n);
    var nearer = t_s - t_q;
    if (plane_s > 0.0 && plane_q > 0.0) {
        nearer = (plane_q - t_q) - (plane_s - t_s);
    }
    tap.pixel = q;
    tap.surface = sq;
    if (nearer > bias) {
        tap.occlusion = 1.0 - ssdo_smoothstep(fade_start, r_max, length(sq - p));
    }
    return tap;
}

// The blurred radiance (rgb) and accessibility (a), and the blurred indirect radiance.
struct SsdoBlurred {
    direct: vec4<f32>,
    indirect: vec3<f32>,
}

// One axis of the separable geometry-sensitive blur (docs/techniques/ssdo.md §3.1, [Segovia et al.
// 2006]) at pixel `px` along `axis`: 5 taps weighted [1/2, 1, 1, 1, 1/2] (each residue of the
// 4x4 interleave pattern weighs the same, centred) times (n.n_j)^8 and
// 1 - |n.(P_j - P)| / tolerance; sky taps are left out, the centre always counts. `bounce` is
// read only when `with_bounce`.
fn ssdo_blur(positions: texture_2d<f32>, normals: texture_2d<f32>, radiance: texture_2d<f32>, bounce: texture_2d<f32>, px: vec2<i32>, axis: vec2<i32>, with_bounce: bool, tolerance: f32) -> SsdoBlurred {
    var out: SsdoBlurred;
    out.direct = textureLoad(radiance, px, 0);
    out.indirect = vec3<f32>(0.0);
    if (with_bounce) {
        out.indirect = textureLoad(bounce, px, 0).rgb;
    }
    let pw = textureLoad(positions, px, 0);
    if (pw.w < 0.5) {
        return out;
    }
    let n = ssdo_normalize(textureLoad(normals, px, 0).xyz);
    let last = vec2<i32>(textureDimensions(positions)) - 1;
    let tol = max(tolerance, 1e-20);
    var sum_w = 1.0;
    for (var k = -2; k <= 2; k = k + 1) {
        let q = px + axis * k;
        if (k == 0 || any(q < vec2<i32>(0)) || any(q > last)) {
            continue;
        }
        let qp = textureLoad(positions, q, 0);
        if (qp.w < 0.5) {
            continue;
        }
        let qn = ssdo_normalize(textureLoad(normals, q, 0).xyz);
        let w = select(1.0, 0.5, abs(k) == 2) * pow(max(dot(n, qn), 0.0), 8.0) * max(1.0 - abs(dot(qp.xyz - pw.xyz, n)) / tol, 0.0);
        if (w > 0.0) {
            out.direct = out.direct + w * textureLoad(radiance, q, 0);
            if (with_bounce) {
                out.indirect = out.indirect + w * textureLoad(bounce, q, 0).rgb;
            }
            sum_w = sum_w + w;
        }
    }
    out.direct = out.direct / sum_w;
    out.indirect = out.indirect / sum_w;
    return out;
}
