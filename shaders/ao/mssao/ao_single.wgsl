#include "common/view.wgsl"
#include "common/mssao.wgsl"
// MSSAO with one level (n = 1): the finest level is also the coarsest, so the 16-point Poisson
// disk's (sum, N) is the whole tuple (Eq. 10 with AO_far = 0) and Eq. 11 gives the output
// accessibility (1 - mean)^2. Sky pixels are exactly 1.

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: MssaoParams;
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<u32>;
@group(0) @binding(4) var accessibility: texture_storage_2d<r32float, write>;

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
    let a = mssao_accessibility(mssao_combine(near, vec3<f32>(0.0)));
    textureStore(accessibility, c, vec4<f32>(a, 0.0, 0.0, 0.0));
}
