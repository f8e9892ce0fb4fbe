#include "common/view.wgsl"
#include "common/ao_rays.wgsl"
#include "common/edges.wgsl"
// rtao.trace: N of the reference's rays per pixel (common/ao_rays.wgsl) against the scene's
// BVH, from the g-buffer's point and normal taken to world space; frame f traces rays
// [f N, (f + 1) N) of the pixel's sequence (params.sequence = 1), so frames accumulated by the
// temporal block continue one low-discrepancy sequence; writes 1 - mean occlusion, the
// depth-edge weights for blocks/edge_denoise.wgsl, and in `changed` r = 1 where a ray hit
// moving geometry (the temporal block then keeps a short history there: blocks/temporal.rs
// ChangeMask) and g = the nearest hit's distance over R (1: no ray hit), which sets the
// history denoiser's radius (blocks/history_denoise.rs).

struct RtaoParams {
    rays: u32,
    // 0 binary, 1 obscurance.
    mode: u32,
    // 1: advance the sequence every frame; 0: the same rays every frame.
    sequence: u32,
    pad0: u32,
    radius: f32,
    pad1: f32,
    pad2: f32,
    pad3: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: RtaoParams;
@group(0) @binding(2) var positions: texture_2d<f32>;
@group(0) @binding(3) var normals: texture_2d<f32>;
@group(0) @binding(4) var depth: texture_2d<f32>;
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
@group(0) @binding(9) var edges: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(10) var changed: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy);
    let position = textureLoad(positions, p, 0);
    let normal = textureLoad(normals, p, 0).xyz;
    var e = vec4<f32>(0.0);
    var accessibility = 1.0;
    var moving_hit = 0.0;
    var nearest = 1.0;
    let world_p = (view.inv_view * vec4<f32>(position.xyz, 1.0)).xyz;
    let world_n = (view.inv_view * vec4<f32>(normal, 0.0)).xyz;
    let len = length(world_n);
    if (position.w > 0.5 && rays_finite3(world_p) && rays_finite3(world_n) && len > 0.0
        && len < 3.0e38) {
        e = depth_edges(depth, p);
        let n = world_n * (1.0 / len);
        let pixel = id.y * size.x + id.x;
        let scramble = rays_pixel_scramble(pixel);
        let first = select(0u, view.frame_index * params.rays, params.sequence == 1u);
        var sum = 0.0;
        for (var i = 0u; i < params.rays; i++) {
            let s = rays_sample_hit(world_p, n, scramble, first + i, params.radius, params.mode);
            sum += s.x;
            moving_hit = max(moving_hit, s.y);
            nearest = min(nearest, s.z);
        }
        accessibility = clamp(1.0 - sum / f32(params.rays), 0.0, 1.0);
    }
    textureStore(ao, p, vec4<f32>(accessibility, 0.0, 0.0, 0.0));
    textureStore(edges, p, e);
    textureStore(changed, p, vec4<f32>(moving_hit, nearest, 0.0, 0.0));
}
