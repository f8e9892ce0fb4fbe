// A batch of arbitrary rays against the scene (crates/tracing/src/gpu/ray_batch.rs): the
// compute BVH, or the acceleration structures in the `RayTracer=hardware` variant;
// what the GPU-vs-CPU tests and the rays-per-second bench run. One invocation per ray; the
// batch is laid out over a 2D dispatch when it exceeds 65535 workgroups in x.
#include "common/scene_trace.wgsl"

struct TraceRay {
    origin: vec3<f32>,
    t_min: f32,
    direction: vec3<f32>,
    t_max: f32,
}

struct TraceParams {
    count: u32,
    // 1: any-hit (visibility), 0: closest hit.
    any_hit: u32,
    // Invocations per row of the 2D dispatch.
    row: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: TraceParams;
@group(0) @binding(1) var<storage, read> rays: array<TraceRay>;
// Per ray: (t, scene instance, primitive, 1) on a hit, bit patterns in y and z; (0, 0, 0, 0)
// on a miss.
@group(0) @binding(2) var<storage, read_write> results: array<vec4<u32>>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * params.row;
    if (i >= params.count) {
        return;
    }
    let ray = rays[i];
    let hit = scene_trace(ray.origin, ray.direction, ray.t_min, ray.t_max, params.any_hit != 0u);
    if (!hit.hit) {
        results[i] = vec4<u32>(0u);
        return;
    }
    results[i] = vec4<u32>(bitcast<u32>(hit.t), hit.instance, hit.primitive, 1u);
}
