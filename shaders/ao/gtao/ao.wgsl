#include "ao/gtao/estimator.wgsl"
#include "common/edges.wgsl"
// gtao.ao: GTAO's estimator (ao/gtao/estimator.wgsl) at every pixel; writes the raw
// accessibility and the depth-edge weights for blocks/edge_denoise.wgsl.

alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
@group(0) @binding(9) var edges: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let a = estimate(p).a;
    var e = vec4<f32>(0.0);
    if (textureLoad(depth0, p, 0).r > 0.0) {
        e = depth_edges(depth0, p);
    }
    textureStore(ao, p, vec4<f32>(finite_or(a, 1.0), 0.0, 0.0, 0.0));
    textureStore(edges, p, e);
}
