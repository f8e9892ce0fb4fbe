#include "common/hardware_scene.wgsl"
// The reference's AO rays (common/ao_ray_dirs.wgsl) traced with ray queries against the
// scene's acceleration structures: the same rays_sample / rays_occlusion as
// common/ao_rays.wgsl, so a shader including that file runs on the hardware tracer as its
// `RayTracer=hardware` variant (crates/graph/src/shader/variant.rs), which includes this one in
// its place.
#include "common/ao_ray_dirs.wgsl"

// Occlusion of ray `index` of a pixel (scrambled by `scramble`) from surface point p with
// unit normal n, mode 0 binary, 1 obscurance; and 1 in y when the occluder moves.
fn rays_sample(p: vec3<f32>, n: vec3<f32>, scramble: vec2<u32>, index: u32, radius: f32,
               mode: u32) -> vec2<f32> {
    let origin = p + n * rays_offset_epsilon(p, radius);
    let d = rays_to_world(n, rays_cosine_hemisphere(rays_sobol_2d(index, scramble)));
    let hit = hardware_trace(origin, d, 0.0, radius, mode == 0u);
    if (hit.kind == RAY_QUERY_INTERSECTION_NONE) {
        return vec2<f32>(0.0);
    }
    let moving = f32(hw_instances[hit.instance_custom_data].moving);
    if (mode == 0u) {
        return vec2<f32>(1.0, moving);
    }
    let x = hit.t / radius;
    return vec2<f32>(1.0 - min(1.0, x * x), moving);
}

// The occlusion of `rays_sample` alone.
fn rays_occlusion(p: vec3<f32>, n: vec3<f32>, scramble: vec2<u32>, index: u32, radius: f32,
                  mode: u32) -> f32 {
    return rays_sample(p, n, scramble, index, radius, mode).x;
}
