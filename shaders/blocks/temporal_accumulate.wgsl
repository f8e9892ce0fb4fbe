#include "common/finite.wgsl"
// blocks/temporal `<prefix>.accumulate`: blends this frame's accessibility with the
// reprojected history and writes the new history and the accumulated output.
// mode 0 (Average): TSSAO Eqs. 5-6 with one sample per frame,
//   A = (n_t A_prev + A) / (n_t + 1), n_t+1 = min(n_t + 1, n_max); the same running mean of
//   A^2 (the second moment, for the per-pixel variance SVGF's temporal moments give) is kept
//   in the history's z;
// mode 1 (FixedBlend): MSSAO Eq. 14, A = k A_prev + (1 - k) A where the history is valid
//   (k = 0 where it is not, Table 5).
// With a change mask (changed_n_max > 0, mode 0 only): where `changed` marks the pixel or its
//   surface moves, n_t is capped at changed_n_max - 1 before the blend (ChangeMask in
//   temporal.rs).
// Layouts: crates/ao-passes/src/blocks/temporal.rs.

struct AccumulateParams {
    mode: u32,
    n_max: f32,
    // Weight of the previous value in mode 1.
    k: f32,
    // Cap of n_t at changed pixels; 0: no mask (then `changed` is not read).
    changed_n_max: f32,
}

@group(0) @binding(0) var<uniform> params: AccumulateParams;
@group(0) @binding(1) var current: texture_2d<f32>;
@group(0) @binding(2) var reprojected: texture_2d<f32>;
@group(0) @binding(3) var linear_depth: texture_2d<f32>;
@group(0) @binding(4) var history: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var accumulated: texture_storage_2d<r32float, write>;
@group(0) @binding(6) var changed: texture_2d<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(accumulated);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let z = textureLoad(linear_depth, p, 0).x;
    if (!(z > 0.0) || z > 1e30) {
        textureStore(history, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        textureStore(accumulated, p, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let c = textureLoad(current, p, 0).x;
    let a = select(1.0, clamp(c, 0.0, 1.0), c == c);
    let r = textureLoad(reprojected, p, 0);
    let flags = u32(max(r.w, 0.0) + 0.5);
    let valid = (flags & 1u) != 0u;
    let moving = (flags & 2u) != 0u;
    var out = a;
    var n = 1.0;
    var moment = a * a;
    if (params.mode == 0u) {
        var nt = select(0.0, r.y, valid);
        if (params.changed_n_max > 0.0 && (moving || textureLoad(changed, p, 0).x > 0.5)) {
            nt = min(nt, params.changed_n_max - 1.0);
        }
        out = (nt * r.x + a) / (nt + 1.0); // Eq. 5, k = 1
        let previous_moment = select(0.0, clamp(r.z, 0.0, 1.0), nt > 0.0 && is_finite_f32(r.z));
        moment = (nt * previous_moment + a * a) / (nt + 1.0);
        n = min(nt + 1.0, params.n_max); // Eq. 6
    } else if (valid) {
        out = params.k * r.x + (1.0 - params.k) * a; // MSSAO Eq. 14
    }
    out = select(a, clamp(out, 0.0, 1.0), is_finite_f32(out));
    let z_out = select(0.0, moment, params.mode == 0u);
    textureStore(history, p, vec4<f32>(out, n, z_out, select(z, -z, moving)));
    textureStore(accumulated, p, vec4<f32>(out, 0.0, 0.0, 0.0));
}
