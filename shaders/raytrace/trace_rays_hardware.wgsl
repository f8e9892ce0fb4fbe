enable wgpu_ray_query;
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

// Per placed instance (the TLAS custom index): its scene instance and where its BLAS's
// primitive table starts.
struct HardwareInstance {
    instance: u32,
    primitive_offset: u32,
}

@group(0) @binding(0) var<uniform> params: TraceParams;
@group(0) @binding(1) var<storage, read> rays: array<TraceRay>;
// Per ray: (t, scene instance, primitive, 1) on a hit, bit patterns in y and z; (0, 0, 0, 0)
// on a miss.
@group(0) @binding(2) var<storage, read_write> results: array<vec4<u32>>;
@group(0) @binding(3) var scene: acceleration_structure;
@group(0) @binding(4) var<storage, read> hw_instances: array<HardwareInstance>;
// Per BLAS primitive: its index among the mesh's valid triangles.
@group(0) @binding(5) var<storage, read> hw_primitives: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * params.row;
    if (i >= params.count) {
        return;
    }
    let ray = rays[i];
    var flags = RAY_FLAG_FORCE_OPAQUE;
    if (params.any_hit != 0u) {
        flags = flags | RAY_FLAG_TERMINATE_ON_FIRST_HIT;
    }
    var rq: ray_query;
    rayQueryInitialize(&rq, scene, RayDesc(flags, 0xffu, ray.t_min, ray.t_max, ray.origin, ray.direction));
    rayQueryProceed(&rq);
    let hit = rayQueryGetCommittedIntersection(&rq);
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
