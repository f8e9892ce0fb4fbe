#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO AO at the finest level 0 (Tables 3 and 4, Eqs. 5-11): the fixed 16-point Poisson disk
// of radius R = min(r_max, r_0) gives (sum, N); the blurred tuple of level 1 is bilaterally
// upsampled (Fig. 9, Eqs. 8-9); Eq. 10 folds them together and Eq. 11 turns the result into the
// output accessibility 1 - AO_final = (1 - AO_max)(1 - AO_average). No blur at this level.
// Sky pixels are exactly 1.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<u32>;
@group(0) @binding(4) var coarse_ao: texture_2d<f32>;
@group(0) @binding(5) var coarse_depth: texture_2d<f32>;
@group(0) @binding(6) var coarse_normals: texture_2d<u32>;
@group(0) @binding(7) var accessibility: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(accessibility);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let c = vec2<i32>(id.xy);
    let grid = mssao_grid(view, 0u);
    let s = mssao_surface(depth, normals, grid, c);
    if (!s.valid) {
        textureStore(accessibility, c, vec4<f32>(1.0, 0.0, 0.0, 0.0));
        return;
    }
    let r0 = params.d_max * pixels_per_unit(-s.p.z, view);
    let radius = mssao_kernel_radius(r0, 0u, params.r_max);
    let near = mssao_near_poisson(depth, grid, c, s, radius, params.d_max);
    let far = mssao_upsample(coarse_ao, coarse_depth, coarse_normals, mssao_grid(view, 0u + 1u), c, s, params.normal_power, params.depth_power, params.upsampling);
    let a = mssao_accessibility(mssao_combine(near, far));
    textureStore(accessibility, c, vec4<f32>(a, 0.0, 0.0, 0.0));
}
