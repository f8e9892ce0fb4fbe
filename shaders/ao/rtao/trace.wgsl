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
    // 0: the same rays every frame; 1: advance the pixel's sequence every frame; 2: blue
    // noise (every pixel the same Sobol point of the frame, shifted by its own dither offset).
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

// The pixel's offset of the blue-noise sequence: two dither masks with blue-noise spectra,
// Roberts' R2 mask (the plastic number's 2D Kronecker weights) and Jimenez's interleaved
// gradient noise, so neighbouring pixels take distant points of the unit square and the error
// left at one ray a pixel is high-frequency, which the spatial filter removes best.
fn blue_noise_offset(p: vec2<u32>) -> vec2<f32> {
    let x = f32(p.x);
    let y = f32(p.y);
    return vec2<f32>(
        fract(0.7548776662 * x + 0.5698402910 * y),
        fract(52.9829189 * fract(0.06711056 * x + 0.00583715 * y)),
    );
}

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
        let first = select(0u, view.frame_index * params.rays, params.sequence >= 1u);
        let offset = blue_noise_offset(id.xy);
        var sum = 0.0;
        for (var i = 0u; i < params.rays; i++) {
            // Blue noise: the frame's shared (unscrambled) Sobol point rotated by the pixel's
            // offset, modulo 1; each pixel's points over frames are still a rotated (0,2)
            // sequence, uniform on the square, so the rays stay cosine-distributed.
            let u = select(
                rays_sobol_2d(first + i, scramble),
                fract(rays_sobol_2d(first + i, vec2<u32>(0u)) + offset),
                params.sequence == 2u
            );
            let s = rays_sample_at(world_p, n, u, params.radius, params.mode);
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
