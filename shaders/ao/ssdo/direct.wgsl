#include "common/view.wgsl"
#include "common/noise.wgsl"
#include "ao/ssdo/common.wgsl"
#include "common/finite.wgsl"
// ssdo.direct: direct light with directional occlusion (docs/techniques/ssdo.md §1.2, E1) and the
// AO-equivalent accessibility. N samples P + lambda_i omega_i of the pixel's interleaved set
// (4x4 pattern) are classified by ssdo_tap; each visible direction brings the environment
// L_in(omega_i) = ambient * (1 + g omega_i.up), or the sky's radiance (environment = "sky"),
// weighted by cos theta_i, and votes for the directional light with weight max(0, omega_i.l)^k
// (ambient only: the sky holds its sun). Output rgb = L_dir, a = accessibility
// sum V_i cos theta_i / sum cos theta_i. Choices: module docs of techniques/ssdo.rs.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: SsdoParams;
@group(0) @binding(2) var<uniform> lighting: Lighting;
@group(0) @binding(3) var positions: texture_2d<f32>;
@group(0) @binding(4) var normals: texture_2d<f32>;
@group(0) @binding(5) var albedo: texture_2d<f32>;
@group(0) @binding(6) var direct_light: texture_2d<f32>;
// Intermediates: rgba32float here, rgba16float in the `?IntermediateStorage=f16` variant
// (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var radiance: IntermediateStorage;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(radiance);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let px = vec2<i32>(id.xy);
    let pw = textureLoad(positions, px, 0);
    if (pw.w < 0.5) {
        textureStore(radiance, px, vec4<f32>(0.0, 0.0, 0.0, 1.0)); // sky: no radiance, unoccluded
        return;
    }
    let rho = textureLoad(albedo, px, 0).rgb;
    // rho * E_sun * max(0, n.l), unshadowed (the g-buffer's DirectLight).
    let sun = textureLoad(direct_light, px, 0).rgb;
    let ambient = lighting.ambient;
    let n = ssdo_normalize(textureLoad(normals, px, 0).xyz);
    if (!(dot(n, n) > 0.5)) {
        textureStore(radiance, px, vec4<f32>(ssdo_clean(rho * ambient + sun), 1.0));
        return;
    }
    let p = pw.xyz;
    let r = params.r_max;
    let frame = ssdo_frame(n);
    let set_index = interleave_4x4(id.xy);
    let ortho = view.orthographic > 0.5;
    let to_light = ssdo_normalize((view.view * vec4<f32>(-lighting.light_direction, 0.0)).xyz);
    let up = (view.view * vec4<f32>(0.0, 1.0, 0.0, 0.0)).xyz;
    let gradient = params.sky_gradient;
    let lobe = params.light_lobe;
    // environment = "sky": L_in(omega) is the sky's, in world space, and the sun is in the sky
    // (its lobe), so the g-buffer's unshadowed directional light is not added.
    let sky = params.sky == 1u;
    let to_world = mat3x3<f32>(view.inv_view[0].xyz, view.inv_view[1].xyz, view.inv_view[2].xyz);

    var sum_cos = 0.0;
    var visible_cos = 0.0;
    var env = vec3<f32>(0.0);
    var sun_weight = 0.0;
    var sun_visible = 0.0;
    let count = min(params.sample_count, 16u);
    for (var i = 0u; i < count; i = i + 1u) {
        let k = params.samples[set_index * 16u + i];
        let offset = frame * k.xyz;
        let w = ssdo_normalize(offset);
        let tap = ssdo_tap(positions, p, n, p + offset * r, view.proj, ortho, r, params.fade_start, params.bias);
        let v = 1.0 - tap.occlusion;
        let cos_t = k.w;
        // E1: (rho / pi) L_in V cos dw, with dw normalised per set (module docs).
        var l_in = ambient * max(1.0 + gradient * dot(w, up), 0.0);
        if (sky) {
            l_in = sky_radiance(lighting, ssdo_normalize(to_world * w));
        }
        env = env + l_in * (v * cos_t);
        sum_cos = sum_cos + cos_t;
        visible_cos = visible_cos + v * cos_t;
        let lw = pow(max(dot(w, to_light), 0.0), lobe);
        sun_weight = sun_weight + lw;
        sun_visible = sun_visible + lw * v;
    }
    var a = 1.0;
    var env_mean = select(ambient, sky_radiance(lighting, ssdo_normalize(to_world * n)), sky);
    if (sum_cos > 1e-6) {
        a = visible_cos / sum_cos;
        env_mean = env / sum_cos;
    }
    let sun_visibility = select(1.0, sun_visible / sun_weight, sun_weight > 1e-6);
    let l_dir = rho * env_mean + select(sun * sun_visibility, vec3<f32>(0.0), sky);
    a = accessibility_or_one(a);
    textureStore(radiance, px, vec4<f32>(ssdo_clean(l_dir), a));
}
