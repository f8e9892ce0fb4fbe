// blocks/temporal `<prefix>.zero_motion`: a 1x1 stand-in for the g-buffer's motion channel on
// scenes without motion vectors. The temporal shaders declare a `motion` binding always and
// never read it when `has_motion` is 0; this pass only gives the binding a written texture.
@group(0) @binding(0) var dst: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(dst, vec2<i32>(id.xy), vec4<f32>(0.0));
}
