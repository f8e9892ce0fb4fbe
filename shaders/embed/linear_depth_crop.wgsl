// Embedding input adapter: linear depth given as such (R32Float), copied out of the viewport's
// rectangle of a larger texture into an output-sized one (see adapters.rs). Without a viewport
// the given texture is read in place and this pass is not declared.

@group(0) @binding(0) var depth: texture_2d<f32>;
@group(0) @binding(1) var<uniform> viewport: vec4<u32>;
@group(0) @binding(2) var linear_depth: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(linear_depth);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let d = textureLoad(depth, p + vec2<i32>(viewport.xy), 0).r;
    textureStore(linear_depth, p, vec4<f32>(d, 0.0, 0.0, 0.0));
}
