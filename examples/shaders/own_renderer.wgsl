// examples/own_renderer.rs: an application's own minimal forward renderer. `vs` serves both
// passes (the depth pre-pass and shading), so both rasterise the same depths. `fs_shade`
// multiplies aograph's AO (bound as a texture) into the ambient light.

struct Camera {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;
@group(0) @binding(1) var ao: texture_2d<f32>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
};

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(position, 1.0);
    out.normal = normal;
    return out;
}

fn to_srgb(c: vec3<f32>) -> vec3<f32> {
    let x = clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(x, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * x, x <= vec3<f32>(0.0031308));
}

@fragment
fn fs_shade(in: VertexOut) -> @location(0) vec4<f32> {
    let occlusion = textureLoad(ao, vec2<i32>(in.clip.xy), 0).r;
    let n = normalize(in.normal);
    let direct = max(dot(n, -camera.light_dir.xyz), 0.0) * 0.6;
    let ambient = 0.55 * occlusion;
    let albedo = vec3<f32>(0.8, 0.78, 0.74);
    return vec4<f32>(to_srgb(albedo * (ambient + direct)), 1.0);
}
