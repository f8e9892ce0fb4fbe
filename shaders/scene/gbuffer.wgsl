#include "common/view.wgsl"
// The g-buffer pass: rasterises every instance and writes the channels the graph requested
// (outputs without a colour target are discarded by the pipeline). Sky keeps the clear
// values: linear depth 0, normal.w = 0, position.w = 0, motion 0.

struct Instance {
    model: mat4x4<f32>,
    prev_model: mat4x4<f32>,
    color: vec4<f32>,
}

struct Light {
    // World-space direction the light travels (unit), and its colour times intensity.
    direction: vec4<f32>,
    color: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<uniform> light: Light;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) prev_clip: vec4<f32>,
    @location(4) cur_clip: vec4<f32>,
    @location(5) world_normal: vec3<f32>,
}

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @builtin(instance_index) ii: u32) -> VsOut {
    let inst = instances[ii];
    let world = inst.model * vec4<f32>(position, 1.0);
    let prev_world = inst.prev_model * vec4<f32>(position, 1.0);
    let vp = view.view * world;
    // Normals: the model's linear part applied to the normal, renormalised (exact for the
    // rotations and uniform scales scenes use; non-uniform scale is approximated).
    let wn = (inst.model * vec4<f32>(normal, 0.0)).xyz;
    var out: VsOut;
    out.clip = view.proj * vp;
    out.cur_clip = out.clip;
    out.view_pos = vp.xyz;
    out.view_normal = (view.view * vec4<f32>(wn, 0.0)).xyz;
    out.world_normal = wn;
    out.color = inst.color;
    out.prev_clip = view.prev_view_proj * prev_world;
    return out;
}

struct GBuffer {
    @location(0) linear_depth: f32,
    @location(1) normal: vec4<f32>,
    @location(2) position: vec4<f32>,
    @location(3) albedo: vec4<f32>,
    @location(4) direct_light: vec4<f32>,
    @location(5) motion: vec2<f32>,
}

fn clip_to_uv(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / max(abs(c.w), 1e-30) * sign(c.w + 1e-30);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

fn shade(in: VsOut, n_view: vec3<f32>) -> GBuffer {
    // Face the camera: two-sided surfaces.
    var n = n_view;
    let to_eye = select(normalize(-in.view_pos), vec3<f32>(0.0, 0.0, 1.0), view.near_far.w > 0.5);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    var wn = normalize((view.inv_view * vec4<f32>(n, 0.0)).xyz);
    var g: GBuffer;
    g.linear_depth = max(-in.view_pos.z, 1e-30);
    g.normal = vec4<f32>(n, 1.0);
    g.position = vec4<f32>(in.view_pos, 1.0);
    g.albedo = vec4<f32>(in.color.rgb, 1.0);
    let ndl = max(dot(wn, -light.direction.xyz), 0.0);
    g.direct_light = vec4<f32>(in.color.rgb * light.color.rgb * ndl, 1.0);
    g.motion = clip_to_uv(in.prev_clip) - clip_to_uv(in.cur_clip);
    return g;
}

// Interpolated vertex normals.
@fragment
fn fs_smooth(in: VsOut) -> GBuffer {
    var n = in.view_normal;
    let len = length(n);
    if (!(len > 1e-20)) {
        n = cross(dpdx(in.view_pos), dpdy(in.view_pos));
    }
    return shade(in, normalize_safe(n));
}

// Face (flat) normals from the position derivatives, as MSSAO needs.
@fragment
fn fs_face(in: VsOut) -> GBuffer {
    var n = cross(dpdx(in.view_pos), dpdy(in.view_pos));
    if (!(length(n) > 1e-30)) {
        n = in.view_normal;
    }
    return shade(in, normalize_safe(n));
}

fn normalize_safe(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 1e-30) {
        return v / l;
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}
