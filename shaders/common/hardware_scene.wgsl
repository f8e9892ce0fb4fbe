enable wgpu_ray_query;
// The scene as acceleration structures (crates/tracing/src/gpu/hardware.rs), at the
// compute BVH's binding numbers (common/bvh.wgsl: 12-14): the TLAS, the placed instances' rows
// (the TLAS custom index) and the primitive table mapping a BLAS primitive back to the mesh's
// valid-triangle order. A file including this must include it before anything else: WGSL's
// `enable` comes first (the shader library hoists it to line 1 otherwise).

struct HardwareInstance {
    // Index into Scene::instances.
    instance: u32,
    // Where its BLAS's primitives start in hw_primitives.
    primitive_offset: u32,
    // 1 when the instance is animated or has a moving skin, else 0.
    moving: u32,
    pad: u32,
}

@group(0) @binding(12) var scene: acceleration_structure;
@group(0) @binding(13) var<storage, read> hw_instances: array<HardwareInstance>;
@group(0) @binding(14) var<storage, read> hw_primitives: array<u32>;

// The committed hit of a ray (opaque geometry) in [t_min, t_max]; any hit when `any`.
fn hardware_trace(origin: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32, any: bool)
    -> RayIntersection {
    var flags = RAY_FLAG_FORCE_OPAQUE;
    if (any) {
        flags = flags | RAY_FLAG_TERMINATE_ON_FIRST_HIT;
    }
    var rq: ray_query;
    rayQueryInitialize(&rq, scene, RayDesc(flags, 0xffu, t_min, t_max, origin, d));
    rayQueryProceed(&rq);
    return rayQueryGetCommittedIntersection(&rq);
}
