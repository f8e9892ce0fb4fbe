// A user pass: shows accessibility as a warm-to-cool false-colour image.
@group(0) @binding(0) var ao: texture_2d<f32>;
@group(0) @binding(1) var image: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(ao);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let a = clamp(textureLoad(ao, vec2<i32>(id.xy), 0).r, 0.0, 1.0);
    let c = mix(vec3<f32>(0.1, 0.1, 0.45), vec3<f32>(1.0, 0.95, 0.85), a);
    textureStore(image, vec2<i32>(id.xy), vec4<f32>(c, 1.0));
}
