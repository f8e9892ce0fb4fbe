// gtao.multibounce: GTAO's multi-bounce fit (docs/techniques/gtao.md §7), per colour channel with the
// g-buffer's albedo ρ:  A' = max(A, ((a A + b) A + c) A),
//   a = 2.0404 ρ - 0.3324,  b = -4.7951 ρ + 0.6417,  c = 2.7552 ρ + 0.6903.
// An extra output for shading; the comparison with the reference uses A itself. Sky stays 1.

@group(0) @binding(0) var accessibility: texture_2d<f32>;
@group(0) @binding(1) var albedo: texture_2d<f32>;
@group(0) @binding(2) var dst: texture_storage_2d<rgba16float, write>;

fn multibounce(a: f32, rho: vec3<f32>) -> vec3<f32> {
    let ca = 2.0404 * rho - 0.3324;
    let cb = -4.7951 * rho + 0.6417;
    let cc = 2.7552 * rho + 0.6903;
    return max(vec3<f32>(a), ((ca * a + cb) * a + cc) * a);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let a = textureLoad(accessibility, p, 0).r;
    let rho = saturate(textureLoad(albedo, p, 0).rgb);
    textureStore(dst, p, vec4<f32>(multibounce(a, rho), a));
}
