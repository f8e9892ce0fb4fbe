#include "common/hardware_scene.wgsl"
// common/scene_trace.wgsl's question answered with ray queries against the scene's
// acceleration structures (crates/tracing/src/gpu/hardware.rs): the same SceneHit for
// the same ray. Included in scene_trace.wgsl's place by a shader's `RayTracer=hardware` variant.
#include "common/scene_hit.wgsl"

// The nearest hit in [t_min, t_max], or any hit when `any` (visibility).
fn scene_trace(origin: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32, any: bool) -> SceneHit {
    let hit = hardware_trace(origin, d, t_min, t_max, any);
    var out: SceneHit;
    out.hit = hit.kind != RAY_QUERY_INTERSECTION_NONE;
    if (!out.hit) {
        return out;
    }
    let row = hw_instances[hit.instance_custom_data];
    out.t = hit.t;
    out.instance = row.instance;
    out.primitive = hw_primitives[row.primitive_offset + hit.primitive_index];
    out.moving = row.moving;
    return out;
}
