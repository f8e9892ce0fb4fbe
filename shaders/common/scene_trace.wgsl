// One ray against the scene, as every GPU tracer asks it (the reference's AO rays, rtao, the
// ray batch): here against the compute BVH (common/bvh.wgsl). Its twin,
// common/scene_trace_hardware.wgsl, answers the same question with ray queries; a shader's
// `RayTracer=hardware` variant (crates/graph/src/shader/variant.rs) includes that one in this
// one's place, so a shader is written once for both backends.
#include "common/bvh.wgsl"
#include "common/scene_hit.wgsl"

// The nearest hit in [t_min, t_max], or any hit when `any` (visibility).
fn scene_trace(origin: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32, any: bool) -> SceneHit {
    let hit = bvh_trace(origin, d, t_min, t_max, any);
    var out: SceneHit;
    out.hit = hit.triangle != BVH_MISS_INDEX;
    if (!out.hit) {
        return out;
    }
    out.t = hit.t;
    out.instance = bvh_instances[hit.instance].instance;
    out.primitive = bvh_triangles[hit.triangle].primitive;
    out.moving = bvh_instances[hit.instance].moving;
    return out;
}
