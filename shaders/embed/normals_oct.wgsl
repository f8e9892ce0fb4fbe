#include "common/normal_oct.wgsl"
// Embedding input adapter: the view-space normals channel (Rgba16Float) in aograph's compact
// octahedral encoding (R32Uint, shaders/common/normal_oct.wgsl), for techniques that read that.

@group(0) @binding(0) var normals: texture_2d<f32>;
@group(0) @binding(1) var normals_oct: texture_storage_2d<r32uint, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(normals_oct);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let n = textureLoad(normals, p, 0);
    // Sky (w = 0) stores 0: readers find sky from linear depth.
    let bits = select(0u, normal_oct_encode(n.xyz), n.w > 0.5);
    textureStore(normals_oct, p, vec4<u32>(bits, 0u, 0u, 0u));
}
