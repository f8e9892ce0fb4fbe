// Test helper: copies the red channel of any float texture into a buffer of f32, row-major,
// so a test reads exactly what a shader sampling the texture with textureLoad reads (bevy's
// own SSAO texture has no COPY_SRC usage; a copy could not read it).
@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> values: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(source);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    values[id.y * size.x + id.x] = textureLoad(source, vec2<i32>(id.xy), 0).r;
}
