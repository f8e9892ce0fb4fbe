#include "ao/ssdo/common.wgsl"
#include "common/finite.wgsl"
// ssdo.blur_y: the vertical half of the separable geometry-sensitive blur (ssdo_blur in
// ao/ssdo/common.wgsl), writing SSDO's outputs: accessibility (sky exactly 1), ssdo_direct and
// ssdo_indirect (linear radiance, 0 on sky; the indirect exactly 0 without the bounce).

@group(0) @binding(0) var<uniform> params: SsdoParams;
@group(0) @binding(1) var positions: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var radiance: texture_2d<f32>;
@group(0) @binding(4) var bounce: texture_2d<f32>;
@group(0) @binding(5) var ao: texture_storage_2d<r32float, write>;
@group(0) @binding(6) var ssdo_direct: texture_storage_2d<rgba16float, write>;
@group(0) @binding(7) var ssdo_indirect: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let px = vec2<i32>(id.xy);
    if (textureLoad(positions, px, 0).w < 0.5) {
        textureStore(ao, px, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        textureStore(ssdo_direct, px, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        textureStore(ssdo_indirect, px, vec4<f32>(0.0, 0.0, 0.0, 1.0));
        return;
    }
    let with_bounce = params.bounce != 0u;
    let b = ssdo_blur(positions, normals, radiance, bounce, px, vec2<i32>(0, 1), with_bounce, params.blur_plane_tolerance);
    var a = clamp(b.direct.a, 0.0, 1.0);
    a = select(1.0, a, is_finite_f32(a));
    textureStore(ao, px, vec4<f32>(a, 0.0, 0.0, 0.0));
    textureStore(ssdo_direct, px, vec4<f32>(ssdo_clean(b.direct.rgb), 1.0));
    textureStore(ssdo_indirect, px, vec4<f32>(select(vec3<f32>(0.0), ssdo_clean(b.indirect), with_bounce), 1.0));
}
