// Embedding output: the technique's accessibility (R32Float) into the application's format
// (R8Unorm, R16Float or R32Float), as a colour target: core WebGPU cannot store r8unorm or
// r16float from a compute shader, but every one of them is renderable. Clamped to [0, 1].

@group(0) @binding(0) var ao: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let a = textureLoad(ao, vec2<i32>(frag.xy), 0).r;
    return vec4<f32>(clamp(a, 0.0, 1.0), 0.0, 0.0, 1.0);
}
