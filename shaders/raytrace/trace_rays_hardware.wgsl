#include "common/hardware_scene.wgsl"
// A batch of arbitrary rays against the scene's acceleration structures with ray queries
// (crates/scene/src/ray_tracing/hardware.rs): the hardware twin of raytrace/trace_rays.wgsl,
// same rays in, same answers out. One invocation per ray; geometry is opaque, so the first
// proceed commits the nearest hit (closest) or any hit (any-hit: terminate on first hit).

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
    let hit = hardware_trace(ray.origin, ray.direction, ray.t_min, ray.t_max, params.any_hit != 0u);
    if (hit.kind == RAY_QUERY_INTERSECTION_NONE) {
        results[i] = vec4<u32>(0u);
        return;
    }
    let row = hw_instances[hit.instance_custom_data];
    results[i] = vec4<u32>(
        bitcast<u32>(hit.t),
        row.instance,
        hw_primitives[row.primitive_offset + hit.primitive_index],
        1u,
    );
}
