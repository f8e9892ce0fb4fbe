#include "common/view.wgsl"
#include "common/finite.wgsl"
// blocks/temporal `<prefix>.reproject`: reverse reprojection of the AO history (TSSAO Eq. 3,
// MSSAO Eq. 12) and the disocclusion test (TSSAO Eq. 7, MSSAO Eq. 13). Layouts of `history`
// and `reprojected`, and every choice below, are documented in
// crates/ao-passes/src/blocks/temporal.rs.
//
// reprojected = (previous accessibility, bilinear over the 2x2 texels that pass Eq. 7;
//                n_t of the nearest passing texel, 0 when invalid;
//                history.z of the passing texel with the largest weight (the sequence index,
//                or the second moment; the nearest texel's on disocclusion);
//                flags: 1 = history valid here, 2 = the pixel is moving)

struct ReprojectParams {
    // Eq. 7's relative depth tolerance.
    epsilon: f32,
    // 1 when `motion` holds the g-buffer's motion vectors (prev_uv = uv + motion).
    has_motion: u32,
    // Motion differing from the camera-only reprojection by more pixels than this = moving.
    moving_pixels: f32,
    _pad: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: ReprojectParams;
@group(0) @binding(2) var history: texture_2d<f32>;
@group(0) @binding(3) var linear_depth: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var motion: texture_2d<f32>;
@group(0) @binding(6) var reprojected: texture_storage_2d<rgba32float, write>;

// UV (y down) of a clip-space point.
fn clip_uv(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / max(abs(c.w), 1e-30) * sign(c.w + 1e-30);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// Linear depth of a point in the previous camera's clip space (same projection as now).
fn clip_depth(c: vec4<f32>) -> f32 {
    return clip_linear_depth(c, view);
}

// Linear depth at which the ray through `uv` meets the plane through `o` with normal `n`, or
// -1 where the plane is edge-on or behind the camera. The ray is a + (t - 1) d: view_position
// is affine in depth, with d = a for a perspective camera and (0, 0, -1) for an orthographic one.
fn plane_depth(uv: vec2<f32>, o: vec3<f32>, n: vec3<f32>) -> f32 {
    let a = view_position(uv, 1.0, view);
    let d = select(a, vec3<f32>(0.0, 0.0, -1.0), view.orthographic > 0.5);
    let den = dot(n, d);
    if (!(abs(den) > 1e-4 * length(d))) {
        return -1.0;
    }
    let t = 1.0 + dot(n, o - a) / den;
    return select(-1.0, t, t > 0.0 && t < 1e30);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(reprojected);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let z = textureLoad(linear_depth, p, 0).x;
    if (!(z > 0.0) || z > 1e30) {
        textureStore(reprojected, p, vec4<f32>(1.0, 0.0, 0.0, 0.0)); // sky: nothing to carry
        return;
    }
    let uv = pixel_uv(p, view);
    let pv = view_position(uv, z, view);

    // Eq. 3: the camera-only reprojection gives the previous depth d_new (and prev_uv for
    // static geometry); where the g-buffer has motion, prev_uv and the previous depth are the
    // surface's own (3D motion: its previous transform through the previous camera).
    let c = view.view_to_prev_clip * vec4<f32>(pv, 1.0);
    var d_new = clip_depth(c);
    let uv_cam = clip_uv(c);
    var prev_uv = uv_cam;
    var moving = false;
    if (params.has_motion != 0u) {
        let m = textureLoad(motion, p, 0);
        prev_uv = uv + m.xy;
        moving = length((prev_uv - uv_cam) * view.size) > params.moving_pixels
            || (m.z > 0.0 && abs(1.0 - m.z / max(d_new, 1e-30)) > 0.25 * params.epsilon);
        if (m.z > 0.0) {
            d_new = m.z;
        }
    }
    let flag_moving = select(0.0, 2.0, moving);

    let in_front = d_new > 0.0 && d_new < 1e30 && (view.orthographic > 0.5 || c.w > 0.0);
    let on_screen = all(prev_uv >= vec2<f32>(0.0)) && all(prev_uv <= vec2<f32>(1.0));
    if (view.history_valid == 0u || !in_front || !on_screen) {
        // No history, behind the previous camera, or off screen last frame: invalid.
        textureStore(reprojected, p, vec4<f32>(1.0, 0.0, 0.0, flag_moving));
        return;
    }

    // The current point and its tangent plane in the previous view: inv_proj *
    // view_to_prev_clip = prev_view * inv_view when the projection is unchanged.
    let p_old = view_position(prev_uv, d_new, view);
    let nc = textureLoad(normals, p, 0).xyz;
    let nr = (view.inv_proj * (view.view_to_prev_clip * vec4<f32>(nc, 0.0))).xyz;
    let nl = length(nr);
    let n_old = select(vec3<f32>(0.0), nr / nl, nl > 1e-20);

    // The 2x2 texels around prev_uv: bilinear weights, Eq. 7 against the tangent plane.
    let hs = vec2<i32>(textureDimensions(history));
    let f = prev_uv * vec2<f32>(hs) - 0.5;
    let base = vec2<i32>(floor(f));
    let fr = f - floor(f);
    var sum = 0.0;
    var wsum = 0.0;
    var best_w = 0.0;
    var best = vec4<f32>(0.0);
    var nearest_w = -1.0;
    var nearest = vec4<f32>(0.0);
    for (var j = 0; j < 4; j = j + 1) {
        let o = vec2<i32>(j & 1, j >> 1u);
        let q = clamp(base + o, vec2<i32>(0), hs - 1);
        let w = select(1.0 - fr.x, fr.x, o.x == 1) * select(1.0 - fr.y, fr.y, o.y == 1);
        let h = textureLoad(history, q, 0);
        if (w > nearest_w) {
            nearest_w = w;
            nearest = h;
        }
        let d_old = abs(h.w);
        if (!(w > 1e-6) || !(d_old > 0.0)) {
            continue; // no weight, or sky / nothing there last frame
        }
        var d_exp = d_new;
        let tq = plane_depth(pixel_uv(q, view), p_old, n_old);
        if (tq > 0.0 && abs(tq / d_new - 1.0) < 0.5) {
            d_exp = tq;
        }
        if (abs(1.0 - d_exp / d_old) < params.epsilon) { // Eq. 7
            sum = sum + w * h.x;
            wsum = wsum + w;
            if (w > best_w) {
                best_w = w;
                best = h;
            }
        }
    }
    let index = select(0.0, max(nearest.z, 0.0), nearest.z == nearest.z && nearest.z < 1e30);
    if (!(wsum > 0.0)) {
        // Disocclusion: the sequence index runs on, n_t restarts at 0.
        textureStore(reprojected, p, vec4<f32>(1.0, 0.0, index, flag_moving));
        return;
    }
    let a = clamp(sum / wsum, 0.0, 1.0);
    let n = clamp(best.y, 0.0, 1e9);
    let best_index = select(index, max(best.z, 0.0), best.z == best.z && best.z < 1e30);
    textureStore(reprojected, p, vec4<f32>(select(1.0, a, is_finite_f32(a)), select(0.0, n, is_finite_f32(n)), best_index, 1.0 + flag_moving));
}
