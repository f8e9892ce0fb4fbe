#include "ao/gtao/estimator.wgsl"
#include "common/edges.wgsl"
// gtao.ao with `bent_normals = true`: as ao/gtao/ao.wgsl, and the bent normal (XeGTAO's
// Algorithm 2, spec §1.5) in view space, xyz unit, w the pass's raw accessibility; 0 on sky.

alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
@group(0) @binding(9) var edges: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(10) var bent: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let est = estimate(p);
    let a = finite_or(est.a, 1.0);
    var e = vec4<f32>(0.0);
    var b = vec4<f32>(0.0);
    if (textureLoad(depth0, p, 0).r > 0.0) {
        e = depth_edges(depth0, p);
        b = vec4<f32>(select(vec3<f32>(0.0, 0.0, 1.0), est.bent, is_finite_vec3(est.bent)), a);
    }
    textureStore(ao, p, vec4<f32>(a, 0.0, 0.0, 0.0));
    textureStore(edges, p, e);
    textureStore(bent, p, b);
}
