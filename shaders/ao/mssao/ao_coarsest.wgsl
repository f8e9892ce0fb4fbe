#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO AO at the coarsest level n - 1 (Table 3, Eqs. 5-7): the interleaved every-other-pixel
// kernel of radius R = min(r_max, r_0 / 2^l). Nothing is upsampled into this level, so the tuple
// is Eq. 10 with AO_far = (0, 0, 0): (sum / N, sum, N). Sky texels write (0, 0, 0).

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<u32>;
// The tuple is an intermediate: rgba32float here, rgba16float in the `?IntermediateStorage=f16`
// variant (crates/graph/src/shader/variant.rs, "Storage-precision variants").
alias IntermediateStorage = texture_storage_2d<rgba32float, write>;
@group(0) @binding(4) var ao: IntermediateStorage;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let c = vec2<i32>(id.xy);
    let grid = mssao_grid(view, params.level);
    let s = mssao_surface(depth, normals, grid, c);
    if (!s.valid) {
        textureStore(ao, c, vec4<f32>(0.0));
        return;
    }
    let r0 = params.d_max * pixels_per_unit(-s.p.z, view);
    let radius = mssao_kernel_radius(r0, params.level, params.r_max);
    let near = mssao_near_interleaved(depth, grid, c, s, radius, params.d_max);
    textureStore(ao, c, vec4<f32>(mssao_combine(near, vec3<f32>(0.0)), 0.0));
}
