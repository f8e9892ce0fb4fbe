// The reference's AO rays, on the GPU (mirror of crates/scene/src/reference/sampling.rs and
// tracer.rs; shared by the GPU reference and the rtao technique):
//   origin = p + n eps, eps = 1e-4 R + 4e-6 max|p| (tracer.rs offset_epsilon);
//   ray i of pixel k: the 2D Sobol point i (dimension 1: bit reversal, dimension 2: the
//   x + 1 polynomial), XOR-scrambled by lowbias32 hashes of k, lifted to the hemisphere by
//   Malley's method (cosine-weighted) in Duff et al.'s tangent frame;
//   occlusion: binary, 1 for any hit in [0, R]; obscurance, 1 - min(1, (d/R)^2) for the
//   nearest hit within R.
// Traced by common/scene_trace.wgsl: the compute BVH, or ray queries in a shader's
// `RayTracer=hardware` variant.
#include "common/ao_ray_dirs.wgsl"
#include "common/scene_trace.wgsl"

// Occlusion of ray `index` of a pixel (scrambled by `scramble`) from surface point p with
// unit normal n, mode 0 binary, 1 obscurance; 1 in y when the occluder moves; in z the hit's
// distance over R (1 on a miss; in binary mode the first hit found, not always the nearest).
fn rays_sample_hit(p: vec3<f32>, n: vec3<f32>, scramble: vec2<u32>, index: u32, radius: f32,
                   mode: u32) -> vec3<f32> {
    return rays_sample_at(p, n, rays_sobol_2d(index, scramble), radius, mode);
}

// `rays_sample_hit` for the unit-square point u (lifted to the cosine-weighted hemisphere).
fn rays_sample_at(p: vec3<f32>, n: vec3<f32>, u: vec2<f32>, radius: f32, mode: u32) -> vec3<f32> {
    let origin = p + n * rays_offset_epsilon(p, radius);
    let d = rays_to_world(n, rays_cosine_hemisphere(u));
    let hit = scene_trace(origin, d, 0.0, radius, mode == 0u);
    if (!hit.hit) {
        return vec3<f32>(0.0, 0.0, 1.0);
    }
    let moving = f32(hit.moving);
    let x = clamp(hit.t / radius, 0.0, 1.0);
    if (mode == 0u) {
        return vec3<f32>(1.0, moving, x);
    }
    return vec3<f32>(1.0 - x * x, moving, x);
}

// `rays_sample_hit` without the distance.
fn rays_sample(p: vec3<f32>, n: vec3<f32>, scramble: vec2<u32>, index: u32, radius: f32,
               mode: u32) -> vec2<f32> {
    return rays_sample_hit(p, n, scramble, index, radius, mode).xy;
}

// The occlusion of `rays_sample` alone.
fn rays_occlusion(p: vec3<f32>, n: vec3<f32>, scramble: vec2<u32>, index: u32, radius: f32,
                  mode: u32) -> f32 {
    return rays_sample(p, n, scramble, index, radius, mode).x;
}
