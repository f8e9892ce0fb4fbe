// aograph-web: the page's own pre-pass (an application's, not aograph's g-buffer). It draws
// the scene's triangles into a reversed-Z Depth32Float buffer and writes each fragment's
// world-space normal, xyz as signed values in Rgba16Float: what aograph-embed reads as
// `NormalsInput { space: World, encoding: Xyz }`.

struct Camera {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
    // x: 0 shaded, 1 AO only (shade.wgsl); yzw unused.
    mode: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;

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

@fragment
fn fs_normals(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Seen from behind, a surface faces the other way.
    let n = normalize(in.normal) * select(-1.0, 1.0, front);
    return vec4<f32>(n, 1.0);
}
