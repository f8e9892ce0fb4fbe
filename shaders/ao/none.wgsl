// `none`: accessibility 1 everywhere (the cost floor).
@group(0) @binding(0) var ao: texture_storage_2d<r32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(ao, vec2<i32>(id.xy), vec4<f32>(1.0, 0.0, 0.0, 0.0));
}
