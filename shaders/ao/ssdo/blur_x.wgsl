#include "ao/ssdo/common.wgsl"
// ssdo.blur_x: the horizontal half of the separable geometry-sensitive blur (ssdo_blur in
// ao/ssdo/common.wgsl) of the raw direct radiance + accessibility and the raw indirect
// radiance. Without the bounce (params.bounce = 0) `bounce` is not read and the indirect is 0.

@group(0) @binding(0) var<uniform> params: SsdoParams;
@group(0) @binding(1) var positions: texture_2d<f32>;
@group(0) @binding(2) var normals: texture_2d<f32>;
@group(0) @binding(3) var radiance: texture_2d<f32>;
@group(0) @binding(4) var bounce: texture_2d<f32>;
// Intermediates: rgba32float here, rgba16float in the `?IntermediateStorage=f16` variant
// (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var direct_x: IntermediateStorage;
@group(0) @binding(6) var indirect_x: IntermediateStorage;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(direct_x);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let px = vec2<i32>(id.xy);
    let b = ssdo_blur(positions, normals, radiance, bounce, px, vec2<i32>(1, 0), params.bounce != 0u, params.blur_plane_tolerance);
    textureStore(direct_x, px, b.direct);
    textureStore(indirect_x, px, vec4<f32>(b.indirect, 1.0));
}
