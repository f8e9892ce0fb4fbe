#include "common/view.wgsl"
#include "common/gbuffer.wgsl"
#include "common/noise.wgsl"
#include "common/finite.wgsl"
// ssao.ao: classic normal-oriented hemisphere SSAO (the Crytek/Blizzard baseline of
// docs/techniques/mssao.md §9.1). N kernel points (units of R, z along the normal) are rotated by the
// pixel's entry of a 4x4 tile of 16 rotations, placed around the pixel's view-space point,
// projected, and counted as occluded when the depth buffer lies in front of them (by more than
// the bias), weighted by a range check. Output: raw accessibility 1 - occluded / N.
// Choices (module docs of techniques/ssao.rs): tangent-plane-relative depth test, radius cap.

struct SsaoParams {
    // Sample count N.
    samples: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
    // R (world units).
    radius: f32,
    // Depth bias (fraction of R).
    bias: f32,
    // Cap of the projected radius (fraction of the image height).
    max_screen_radius: f32,
    pad3: f32,
    // Tangent-space offsets in units of R (z >= 0 along the normal).
    kernel: array<vec4<f32>, 64>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: SsaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
// The raw accessibility is an intermediate: the `?IntermediateStorage=f16` variant of this file
// writes it at half precision (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(4) var ao: IntermediateStorage;

// Linear depth at which the ray through `uv` meets the plane through `o` with normal `n`, or
// -1 where the plane is edge-on or behind the camera. view_position is affine in depth for
// both projections, so the ray is a + (b - a) (t - 1).
fn plane_depth(uv: vec2<f32>, o: vec3<f32>, n: vec3<f32>) -> f32 {
    let a = view_position(uv, 1.0, view);
    let d = view_position(uv, 2.0, view) - a;
    let den = dot(n, d);
    if (!(abs(den) > 1e-4 * length(d))) {
        return -1.0;
    }
    let t = 1.0 + dot(n, o - a) / den;
    return select(-1.0, t, t > 0.0 && t < 1e30);
}

fn accessibility(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(depth));
    let rc = load_receiver(depth, normals, p, view);
    if (!rc.valid) {
        return 1.0; // sky or no normal
    }
    let z = rc.z;
    let n = rc.n;
    let o = rc.p;

    // Projected radius, capped (R shrinks to match); under one pixel there is nothing to test.
    let ppu = pixels_per_unit(z, view);
    let r_px = min(params.radius * ppu, params.max_screen_radius * view.size.y);
    if (!(r_px >= 1.0)) {
        return 1.0;
    }
    let r = r_px / ppu;
    let bias = params.bias * r;

    // Rotation k of the 4x4 tile (Bayer order): every 4x4 window holds all 16 once. Half-step
    // angles and the kernel mirrored (y negated) for k mod 8 >= 4 make the image mirror-
    // covariant (module docs of techniques/ssao.rs).
    // With temporal accumulation the index advances by one a frame, so every pixel takes all
    // 16 rotations over 16 frames (the set stays mirror-closed).
    let k_rot = (interleave_4x4(vec2<u32>(p)) + noise_frame(view.frame_index)) % 16u;
    let angle = 6.2831853 * (f32(k_rot) + 0.5) / 16.0;
    let y_sign = select(1.0, -1.0, (k_rot % 8u) >= 4u);
    let rv = vec3<f32>(cos(angle), sin(angle), 0.0);
    var t = rv - n * dot(rv, n);
    if (length(t) < 1e-3) {
        let rv2 = vec3<f32>(-rv.y, rv.x, 0.0);
        t = rv2 - n * dot(rv2, n);
    }
    t = normalize(t);
    let b = cross(n, t);

    let count = clamp(params.samples, 1u, 64u);
    var occlusion = 0.0;
    for (var i = 0u; i < count; i = i + 1u) {
        let k = params.kernel[i].xyz;
        let s = o + (t * k.x + b * (y_sign * k.y) + n * k.z) * r;
        let zs = -s.z;
        if (view.orthographic < 0.5 && !(zs > 1e-6)) {
            continue; // behind the camera
        }
        let us = project_uv(s, view);
        if (any(us < vec2<f32>(0.0)) || any(us >= vec2<f32>(1.0))) {
            continue; // off screen: unoccluding
        }
        let q = clamp(vec2<i32>(floor(us * vec2<f32>(size))), vec2<i32>(0), size - 1);
        let zq = textureLoad(depth, q, 0).x;
        if (!(zq > 0.0)) {
            continue; // sky: unoccluding
        }
        // A surface on or below the receiver's tangent plane cannot lie in front of a sample
        // above it (a line from the eye, which is above the plane, crosses it once). Where
        // q's pixel straddles the plane's horizon, the sample's ray can miss the plane while
        // q's centre ray meets it, and the depth test below would see the plane itself in
        // front of the sample (a plane 89.9 degrees to the view came out 0.85 at 97x61).
        if (dot(n, view_position(pixel_uv(q, view), zq, view) - o) <= bias) {
            continue;
        }
        // Depth test relative to the receiver's tangent plane along each ray (exact for
        // planes; the classic z_q < z_s - bias when s lies on a pixel centre).
        let tq = plane_depth(pixel_uv(q, view), o, n);
        let ts = plane_depth(us, o, n);
        var occluded = zq < zs - bias;
        if (tq > 0.0 && ts > 0.0) {
            occluded = (tq - zq) > (ts - zs) + bias;
        }
        // Range check: an occluder more than R away in depth contributes nothing.
        let range = 1.0 - smoothstep(0.5 * r, r, abs(z - zq));
        occlusion = occlusion + select(0.0, range, occluded);
    }
    let a = 1.0 - occlusion / f32(count);
    return accessibility_or_one(a);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    textureStore(ao, p, vec4<f32>(accessibility(p), 0.0, 0.0, 0.0));
}
