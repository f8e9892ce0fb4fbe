#include "common/view.wgsl"
#include "common/noise.wgsl"
#include "ao/ssdo/common.wgsl"
// ssdo.indirect: one indirect bounce (docs/techniques/ssdo.md §2, E2). The same samples and verdicts as
// ssdo.direct; every blocker is a sender patch of area A_s (E3) at the projected point Q with
// the normal and the pass-1 radiance L_pixel of its pixel:
//   L_ind = sum (rho / pi) L_pixel (1 - V_i) A_s cos theta_s cos theta_r / max(d_i, clamp)^2
// cos theta_s = max(0, n_s.(P - Q)/d) drops back-facing senders, cos theta_r = max(0, n.(Q - P)/d)
// senders in the receiver's negative half-space.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: SsdoParams;
@group(0) @binding(2) var positions: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var albedo: texture_2d<f32>;
@group(0) @binding(5) var radiance: texture_2d<f32>;
// Intermediates: rgba32float here, rgba16float in the `?IntermediateStorage=f16` variant
// (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var indirect: IntermediateStorage;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(indirect);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let px = vec2<i32>(id.xy);
    let pw = textureLoad(positions, px, 0);
    let n = ssdo_normalize(textureLoad(normals, px, 0).xyz);
    if (pw.w < 0.5 || !(dot(n, n) > 0.5)) {
        textureStore(indirect, px, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let p = pw.xyz;
    let r = params.r_max;
    let clamp_d = params.distance_clamp;
    let frame = ssdo_frame(n);
    let set_index = interleave_4x4(id.xy);
    let ortho = view.orthographic > 0.5;

    var gathered = vec3<f32>(0.0);
    let count = min(params.sample_count, 16u);
    for (var i = 0u; i < count; i = i + 1u) {
        let k = params.samples[set_index * 16u + i];
        let tap = ssdo_tap(positions, p, n, p + (frame * k.xyz) * r, view.proj, ortho, r, params.fade_start, params.bias);
        if (tap.occlusion > 0.0) {
            let t = tap.surface - p;
            let d = length(t);
            if (d > 1e-6) {
                let dir = t / d;
                let n_s = ssdo_normalize(textureLoad(normals, tap.pixel, 0).xyz);
                let cos_s = max(dot(n_s, -dir), 0.0);
                let cos_r = max(dot(n, dir), 0.0);
                let dc = max(d, clamp_d);
                let l_pixel = textureLoad(radiance, tap.pixel, 0).rgb;
                gathered = gathered + l_pixel * (tap.occlusion * cos_s * cos_r / (dc * dc));
            }
        }
    }
    let rho = textureLoad(albedo, px, 0).rgb;
    let l_ind = rho * (params.sender_area / 3.14159265) * gathered;
    textureStore(indirect, px, vec4<f32>(ssdo_clean(l_ind), 1.0));
}
