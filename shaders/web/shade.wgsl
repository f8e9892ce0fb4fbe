// aograph-web: the page's shading, drawn into the canvas after aograph's AO. A full-screen
// triangle reads the pre-pass's normals and aograph's AO texel for texel: shaded is
// albedo * (ambient * AO + direct), AO-only shows the AO as grey. The canvas format is not
// sRGB on the web, so the shader encodes sRGB itself.

struct Camera {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
    mode: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var normals: texture_2d<f32>;
@group(0) @binding(2) var ao: texture_2d<f32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

fn to_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}

@fragment
fn fs(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(pixel.xy);
    let occlusion = textureLoad(ao, p, 0).r;
    let n4 = textureLoad(normals, p, 0);
    if (camera.mode.x > 0.5) {
        return vec4<f32>(to_srgb(vec3<f32>(occlusion)), 1.0);
    }
    if (n4.w == 0.0) {
        // Nothing drawn here: the sky.
        return vec4<f32>(to_srgb(vec3<f32>(0.55, 0.65, 0.8)), 1.0);
    }
    let n = normalize(n4.xyz);
    let direct = max(dot(n, -camera.light_dir.xyz), 0.0) * 0.6;
    let ambient = 0.55 * occlusion;
    let albedo = vec3<f32>(0.8, 0.78, 0.74);
    return vec4<f32>(to_srgb(albedo * (ambient + direct)), 1.0);
}
