#include "common/view.wgsl"
#include "common/noise.wgsl"
#include "common/finite.wgsl"
// tssao.sample: k new samples per pixel continuing its Halton sequence (TSSAO Eq. 4), the
// per-frame estimator (Eq. 2), the neighbourhood test (Eq. 8) with smooth invalidation
// (§3.6.1), and the blend into the AO buffer (Eqs. 5-6). Every choice is documented in
// crates/ao-passes/src/techniques/tssao.rs; buffer layouts in blocks/temporal.rs.
//
// ao_buffer = (accessibility, n_t, Halton index, depth; negative depth = moving surface)

struct TssaoParams {
    // Samples per frame k1 (unconverged).
    k1: u32,
    // Samples per frame k2 (converged).
    k2: u32,
    // Steps per sample.
    steps: u32,
    // Visibility: 0 march, 1 point.
    visibility: u32,
    // n_t clamp on a smooth invalidation (n_smooth).
    n_smooth: u32,
    // Falloff: 0 none, 1 quadratic.
    falloff: u32,
    // Halton sequence length L.
    halton_length: u32,
    pad0: u32,
    // Convergence below which k1 samples are taken (c_spatial).
    c_spatial: f32,
    // Convergence from which the pattern rotation is off (c_rot).
    c_rot: f32,
    // Cap of the sample count n_t (n_max).
    n_max: f32,
    // R (world units).
    radius: f32,
    // Eq. 7 epsilon (relative).
    depth_epsilon: f32,
    // Eq. 8 epsilon (world units).
    neighbour_epsilon: f32,
    // Cap of the projected radius (fraction of the image height).
    max_screen_radius: f32,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: TssaoParams;
@group(0) @binding(2) var reprojected: texture_2d<f32>;
@group(0) @binding(3) var previous: texture_2d<f32>;
@group(0) @binding(4) var depth: texture_2d<f32>;
@group(0) @binding(5) var normals: texture_2d<f32>;
@group(0) @binding(6) var motion: texture_2d<f32>;
@group(0) @binding(7) var ao_buffer: texture_storage_2d<rgba32float, write>;
// Halton points 1..L (bases 2, 3, 5) mapped to the sample pattern, precomputed: xyz = the
// cosine-distributed direction in tangent space (z along the normal), w = the third
// coordinate (the step jitter). L = params.halton_length.
@group(0) @binding(8) var<uniform> halton: array<vec4<f32>, 2048>;

// Linear depth of a view-space point in the previous camera (camera-only reprojection; the
// previous projection is the current one).
fn prev_depth(v: vec3<f32>) -> f32 {
    return clip_linear_depth(view.view_to_prev_clip * vec4<f32>(v, 1.0), view);
}

// Position in the previous view of the surface at pixel `q` (view-space point `v`), from the
// g-buffer's 3D motion: prev_uv = uv + m.xy at the previous depth m.z (the camera-only depth
// where the g-buffer has none).
fn prev_position(q: vec2<i32>, v: vec3<f32>) -> vec3<f32> {
    let m = textureLoad(motion, q, 0);
    let d = select(prev_depth(v), m.z, m.z > 0.0);
    return view_position(pixel_uv(q, view) + m.xy, max(d, 1e-6), view);
}

struct Visibility {
    // D(t) at the blocked point, 0 when the segment is free.
    occlusion: f32,
    // Pixel of the surface the sample ends on (the blocking one, or the one under s_i), and
    // whether there is one (on screen, not sky).
    texel: vec2<i32>,
    has_texel: bool,
}

// V(p, s_i) along the segment o -> o + r w, tested at `steps` points t_j = r (j + 1 - u) / steps,
// the last one at t = r ("march"); or, the paper's single test ("point"), at s_i = o + r (1 - u) w
// alone: a point uniformly distributed along the direction, which weighs an occluder at distance
// d by 1 - d / r (the paper's "linear falloff", §4).
fn visibility(o: vec3<f32>, c0: vec4<f32>, w: vec3<f32>, r: f32, u: f32, size: vec2<i32>) -> Visibility {
    var out: Visibility;
    out.occlusion = 0.0;
    out.has_texel = false;
    let point = params.visibility == 1u;
    let steps = select(clamp(params.steps, 1u, 8u), 1u, point);
    // Clip coordinates are affine along the segment: c0 = proj * o, plus t times this.
    let cd = view.proj * vec4<f32>(w, 0.0);
    for (var j = 0u; j < steps; j = j + 1u) {
        // The last point sits at R itself: an occluder anywhere along a wall-like depth
        // buffer leaves it behind the surface, so hits up to R all count (binary mode).
        let t = select(r * (f32(j) + 1.0 - u) / f32(steps), r, j + 1u == steps && !point);
        let zq = -(o.z + w.z * t);
        let c = c0 + cd * t;
        if (view.orthographic < 0.5 && !(zq > 1e-6 && c.w > 1e-6)) {
            break; // behind the camera: unoccluding
        }
        let ndc = c.xy / c.w;
        let uq = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
        if (!(all(uq >= vec2<f32>(0.0)) && all(uq < vec2<f32>(1.0)))) {
            break; // off screen: unoccluding
        }
        let texel = clamp(vec2<i32>(floor(uq * vec2<f32>(size))), vec2<i32>(0), size - 1);
        let zs = textureLoad(depth, texel, 0).x;
        if (!(zs > 0.0) || zs > 1e30) {
            continue; // sky in front of nothing
        }
        out.texel = texel;
        out.has_texel = true;
        if (zs < zq * (1.0 - 1e-4)) {
            // The depth buffer lies in front of the point; it blocks only if that surface is
            // within 2R of p (the paper's distance rejection, §4).
            let s = view_position(pixel_uv(texel, view), zs, view);
            if (length(s - o) < 2.0 * params.radius) {
                let tr = t / max(r, 1e-30);
                out.occlusion = select(1.0, max(1.0 - tr * tr, 0.0), params.falloff == 1u);
                return out;
            }
        }
    }
    return out;
}

// Entry points: `main` for scenes where nothing moves (Eq. 8 is identically satisfied there,
// spec §14, and is compiled out), `main_dynamic` where the g-buffer has motion vectors.
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    sample_pixel(id.xy, false);
}

@compute @workgroup_size(8, 8)
fn main_dynamic(@builtin(global_invocation_id) id: vec3<u32>) {
    sample_pixel(id.xy, true);
}

fn sample_pixel(id: vec2<u32>, dynamic: bool) {
    let size_u = textureDimensions(ao_buffer);
    if (id.x >= size_u.x || id.y >= size_u.y) { return; }
    let size = vec2<i32>(size_u);
    let p = vec2<i32>(id);
    let z = textureLoad(depth, p, 0).x;
    if (!(z > 0.0) || z > 1e30) {
        textureStore(ao_buffer, p, vec4<f32>(1.0, 0.0, 0.0, 0.0)); // sky
        return;
    }
    let rp = textureLoad(reprojected, p, 0);
    let flags = u32(max(rp.w, 0.0) + 0.5);
    let valid = (flags & 1u) != 0u;
    let moving = (flags & 2u) != 0u;
    let stored_z = select(z, -z, moving);
    let nw = textureLoad(normals, p, 0);
    let nl = length(nw.xyz);
    if (nw.w < 0.5 || !(nl > 1e-6)) {
        textureStore(ao_buffer, p, vec4<f32>(1.0, 0.0, 0.0, stored_z));
        return;
    }
    let n = nw.xyz / nl;

    // Reprojected state; invalid history (Eq. 7, off screen, cut, resize) restarts at n_t = 0.
    let n_max = max(params.n_max, 1.0);
    var nt = select(0.0, min(rp.y, n_max), valid);
    let a_prev = rp.x;
    let len = params.halton_length;
    var index = u32(clamp(rp.z, 0.0, f32(len - 1u)));
    if (!valid && rp.z == 0.0) {
        // No history here at all (first frame, cut, resize, off screen): the pixel's own
        // starting index into the sequence (§3.3.1), so pixels use different windows of it.
        index = pcg_hash(u32(p.x) ^ pcg_hash(u32(p.y) ^ 0x9e3779b9u)) & (len - 1u);
    }
    let conv = nt / n_max;
    // §3.6.2: k1 samples until converged enough, then k2.
    let k1 = clamp(params.k1, 1u, 64u);
    var k = clamp(select(params.k2, params.k1, conv < params.c_spatial), 1u, 64u);
    // §3.6.4: per-pixel pattern rotation only while conv < c_rot.
    // The rotation turns the pattern about the normal by a per-pixel angle and shifts the
    // step jitter by a per-pixel offset (a Cranley-Patterson rotation of coordinates 2, 3).
    let rotate = conv < params.c_rot;
    let angle = select(0.0, 6.2831853 * hash_pixel(vec2<u32>(p), 1u), rotate);
    let jitter = select(0.0, hash_pixel(vec2<u32>(p), 2u), rotate);

    let o = view_position(pixel_uv(p, view), z, view);
    let ppu = pixels_per_unit(z, view);
    let r_px = min(params.radius * ppu, params.max_screen_radius * view.size.y);
    let r = r_px / max(ppu, 1e-30);
    // Start 1.5 pixel footprints above the surface (self-occlusion on grazing planes).
    let start = o + n * (1.5 / max(ppu, 1e-30));

    // Tangent frame (Duff et al. 2017).
    let sgn = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sgn + n.z);
    let b = n.x * n.y * a;
    let t0 = vec3<f32>(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    let t1 = vec3<f32>(b, sgn + n.y * n.y * a, -n.y);
    let tx = t0 * cos(angle) + t1 * sin(angle);
    let ty = t1 * cos(angle) - t0 * sin(angle);
    let c0 = view.proj * vec4<f32>(start, 1.0);

    var p_old = vec3<f32>(0.0);
    if (dynamic) {
        p_old = prev_position(p, o);
    }
    var occlusion = 0.0;
    var changed = false;
    for (var i = 0u; i < k; i = i + 1u) {
        // Eq. 4: sample idx + i of the pixel's Halton sequence (bases 2, 3, 5; the table
        // starts at point 1, point 0 being the origin).
        let h = halton[(index + i) & (len - 1u)];
        // Cosine-distributed direction (Malley): the cos of Eq. 2 is in the density.
        let w = tx * h.x + ty * h.y + n * h.z;
        if (!(r_px >= 1.0)) {
            continue; // R under a pixel: nothing to test, unoccluded
        }
        let v = visibility(start, c0, w, r, fract(h.w + jitter), size);
        occlusion = occlusion + v.occlusion;

        // Eq. 8 (only where something moves): the sample's surface point s_i, in front of
        // p's tangent plane and within reach, must keep its distance to p.
        if (dynamic && v.has_texel && !changed && valid) {
            let zs = textureLoad(depth, v.texel, 0).x;
            let s = view_position(pixel_uv(v.texel, view), zs, view);
            let d = s - o;
            if (dot(d, n) > 0.0 && length(d) < 2.0 * params.radius) {
                let s_old = prev_position(v.texel, s);
                if (abs(length(d) - length(s_old - p_old)) >= params.neighbour_epsilon) {
                    changed = true;
                }
                // The previous occupant of s_i's position: moving geometry at another depth
                // there last frame means the neighbourhood changed (module docs).
                let prev_uv = pixel_uv(v.texel, view) + textureLoad(motion, v.texel, 0).xy;
                if (all(prev_uv >= vec2<f32>(0.0)) && all(prev_uv < vec2<f32>(1.0)) && view.history_valid != 0u) {
                    let hs = vec2<i32>(textureDimensions(previous));
                    let h = textureLoad(previous, clamp(vec2<i32>(floor(prev_uv * vec2<f32>(hs))), vec2<i32>(0), hs - 1), 0);
                    let zm = textureLoad(motion, v.texel, 0).z;
                    let d_prev = select(prev_depth(s), zm, zm > 0.0);
                    if (h.w < 0.0 && abs(1.0 - d_prev / -h.w) >= params.depth_epsilon) {
                        changed = true;
                    }
                }
            }
        }
        // The history just lost its weight (smooth invalidation below): take k1 samples
        // this frame already rather than from the next one (§3.6.2's adaptive sampling).
        if (changed) {
            k = max(k, k1);
        }
    }
    let a_frame = 1.0 - occlusion / f32(k);

    // §3.6.1: a neighbourhood change clamps n_t (smooth invalidation) or resets it.
    if (valid && changed) {
        nt = min(nt, f32(params.n_smooth));
    }
    let kf = f32(k);
    var a_new = (nt * a_prev + kf * a_frame) / (nt + kf); // Eq. 5
    a_new = accessibility_or_one(a_new);
    let n_new = min(nt + kf, n_max); // Eq. 6
    let index_new = f32((index + k) & (len - 1u));
    textureStore(ao_buffer, p, vec4<f32>(a_new, n_new, index_new, stored_z));
}
