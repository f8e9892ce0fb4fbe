// The AO reference on the GPU (crates/tracing/src/gpu/gpu_reference.rs): per pixel, the
// CPU reference's rays (common/ao_rays.wgsl) and its estimator: A = 1 - mean occlusion,
// standard error sqrt(s^2 / N) with s^2 the unbiased sample variance. Sky and pixels whose
// point or normal is unusable give (1, 0). One band of rows per dispatch.
#include "common/ao_rays.wgsl"

struct ReferenceParams {
    width: u32,
    height: u32,
    rays: u32,
    // 0 binary, 1 obscurance.
    mode: u32,
    radius: f32,
    // First row of this band.
    row_start: u32,
    rows: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> params: ReferenceParams;
// xyz: world point, w: 1 valid, 0 sky.
@group(0) @binding(1) var<storage, read> points: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> normals: array<vec4<f32>>;
// (accessibility, standard error) per pixel of the whole image.
@group(0) @binding(3) var<storage, read_write> result: array<vec2<f32>>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let y = params.row_start + id.y;
    if (id.x >= params.width || id.y >= params.rows || y >= params.height) {
        return;
    }
    let pixel = y * params.width + id.x;
    let point = points[pixel];
    let raw_n = normals[pixel].xyz;
    let len = length(raw_n);
    if (point.w < 0.5 || !rays_finite3(point.xyz) || !rays_finite3(raw_n) || len == 0.0
        || !(len < 3.0e38)) {
        result[pixel] = vec2<f32>(1.0, 0.0);
        return;
    }
    // glam's try_normalize: times the reciprocal length.
    let n = raw_n * (1.0 / len);
    let scramble = rays_pixel_scramble(pixel);
    var sum = 0.0;
    var sum_squares = 0.0;
    for (var i = 0u; i < params.rays; i++) {
        let o = rays_occlusion(point.xyz, n, scramble, i, params.radius, params.mode);
        sum += o;
        sum_squares += o * o;
    }
    let count = f32(params.rays);
    let mean = sum / count;
    var variance = 0.0;
    if (params.rays > 1u) {
        variance = max((sum_squares - count * mean * mean) / (count - 1.0), 0.0);
    }
    result[pixel] = vec2<f32>(clamp(1.0 - mean, 0.0, 1.0), sqrt(variance / count));
}
