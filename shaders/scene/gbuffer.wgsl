#include "common/view.wgsl"
#include "common/normal_oct.wgsl"
// The g-buffer pass: rasterises every instance and writes the channels the graph requested
// (outputs without a colour target are discarded by the pipeline). Sky keeps the clear
// values: linear depth 0, normal.w = 0, position.w = 0, motion 0, normal_oct 0.

struct Instance {
    model: mat4x4<f32>,
    prev_model: mat4x4<f32>,
    // Carries object-space normals to world space: sign(det M) cof(M) of the model's linear
    // part M, the inverse transpose up to a positive factor (crates/scene/src/normal_transform.rs,
    // the rule the CPU g-buffer uses too). Exact under non-uniform scale, shear and mirroring.
    normal_model: mat3x3<f32>,
    color: vec4<f32>,
    // A skinned instance's first entry in `palette` and its joint count (both 0 when rigid);
    // the model matrices are then unused (glTF ignores a skinned node's transform).
    palette_first: u32,
    joint_count: u32,
    pad0: u32,
    pad1: u32,
}

// One joint's skinning matrix, world(t) * inverse_bind, now and at the previous frame
// (crates/scene/src/skin.rs).
struct JointPalette {
    current: mat4x4<f32>,
    previous: mat4x4<f32>,
}

struct Light {
    // World-space direction the light travels (unit).
    direction: vec3<f32>,
    pad0: f32,
    // Linear RGB colour times intensity.
    color: vec3<f32>,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<uniform> light: Light;
// Every skinned instance's palette, one after another (one unused entry when nothing is skinned).
@group(0) @binding(3) var<storage, read> palette: array<JointPalette>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) prev_clip: vec4<f32>,
    @location(4) cur_clip: vec4<f32>,
    @location(5) world_normal: vec3<f32>,
}

// A vertex placed by `model` now and `prev_model` at the previous frame; `normal_model` carries
// its normal (see Instance).
fn place(position: vec3<f32>, normal: vec3<f32>, model: mat4x4<f32>, prev_model: mat4x4<f32>,
         normal_model: mat3x3<f32>, color: vec4<f32>) -> VsOut {
    let world = model * vec4<f32>(position, 1.0);
    let prev_world = prev_model * vec4<f32>(position, 1.0);
    let vp = view.view * world;
    // Normalised per vertex, then interpolated and renormalised per fragment. A mesh without
    // normals uploads zero normals: its fragments fall back to the geometric normal.
    let wn = normalize_safe_or_zero(normal_model * normal);
    var out: VsOut;
    out.clip = view.proj * vp;
    out.cur_clip = out.clip;
    out.view_pos = vp.xyz;
    out.view_normal = (view.view * vec4<f32>(wn, 0.0)).xyz;
    out.world_normal = wn;
    out.color = color;
    out.prev_clip = view.prev_view_proj * prev_world;
    return out;
}

@vertex
fn vs(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @builtin(instance_index) ii: u32) -> VsOut {
    let inst = instances[ii];
    return place(position, normal, inst.model, inst.prev_model, inst.normal_model, inst.color);
}

// sign(det M) cof(M) of m's linear part: crates/scene/src/normal_transform.rs's rule.
fn normal_matrix(m: mat4x4<f32>) -> mat3x3<f32> {
    let c0 = m[0].xyz;
    let c1 = m[1].xyz;
    let c2 = m[2].xyz;
    let cofactor = mat3x3<f32>(cross(c1, c2), cross(c2, c0), cross(c0, c1));
    return cofactor * select(1.0, -1.0, dot(c0, cross(c1, c2)) < 0.0);
}

// Linear blend skinning (glTF 2.0 3.7.3.3): the vertex's matrix is sum_k w_k palette[j_k], summed
// in k order as the CPU does (JointWeights::blend), now and at the previous frame.
@vertex
fn vs_skinned(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>,
              @location(2) joints: vec4<u32>, @location(3) weights: vec4<f32>,
              @builtin(instance_index) ii: u32) -> VsOut {
    let inst = instances[ii];
    var model = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    var prev_model = model;
    let last = arrayLength(&palette) - 1u;
    for (var k = 0u; k < 4u; k += 1u) {
        // The importer keeps joints below the skin's count; one past it is skipped, as the CPU
        // skips it, and min() keeps every read inside the buffer.
        let w = select(weights[k], 0.0, joints[k] >= inst.joint_count);
        let j = palette[min(inst.palette_first + joints[k], last)];
        model += j.current * w;
        prev_model += j.previous * w;
    }
    return place(position, normal, model, prev_model, normal_matrix(model), inst.color);
}

struct GBuffer {
    @location(0) linear_depth: f32,
    @location(1) normal: vec4<f32>,
    @location(2) position: vec4<f32>,
    @location(3) albedo: vec4<f32>,
    @location(4) direct_light: vec4<f32>,
    // (prev_uv - uv, previous linear depth, unused): 3D motion.
    @location(5) motion: vec4<f32>,
    // The normal again, compact (common/normal_oct.wgsl): written where a technique asks.
    @location(6) normal_oct: u32,
}

fn clip_to_uv(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / max(abs(c.w), 1e-30) * sign(c.w + 1e-30);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

// The direction from the surface towards the eye (view space).
fn to_eye(view_pos: vec3<f32>) -> vec3<f32> {
    return select(normalize(-view_pos), vec3<f32>(0.0, 0.0, 1.0), view.orthographic > 0.5);
}

// The triangle's geometric normal from the position derivatives, turned to face the eye
// (two-sided surfaces). Helper invocations of a 2x2 quad extrapolate the same triangle's plane,
// so the derivatives lie in that plane and the cross product is its normal.
fn geometric_normal(view_pos: vec3<f32>) -> vec3<f32> {
    let g = normalize_safe(cross(dpdx(view_pos), dpdy(view_pos)));
    return select(g, -g, dot(g, to_eye(view_pos)) < 0.0);
}

fn shade(in: VsOut, n: vec3<f32>) -> GBuffer {
    var wn = normalize((view.inv_view * vec4<f32>(n, 0.0)).xyz);
    var g: GBuffer;
    g.linear_depth = max(-in.view_pos.z, 1e-30);
    g.normal = vec4<f32>(n, 1.0);
    g.normal_oct = normal_oct_encode(n);
    g.position = vec4<f32>(in.view_pos, 1.0);
    g.albedo = vec4<f32>(in.color.rgb, 1.0);
    let ndl = max(dot(wn, -light.direction), 0.0);
    g.direct_light = vec4<f32>(in.color.rgb * light.color * ndl, 1.0);
    g.motion = vec4<f32>(
        clip_to_uv(in.prev_clip) - clip_to_uv(in.cur_clip),
        max(clip_linear_depth(in.prev_clip, view), 0.0),
        0.0,
    );
    return g;
}

// Interpolated (shading) normals, turned to the side of the geometric normal that faces the
// eye (pbrt's FaceForward(ns, ng)), so a shading normal leaning away from the eye near a
// silhouette keeps its surface's side. Zero-length normals fall back to the geometric normal.
@fragment
fn fs_smooth(in: VsOut) -> GBuffer {
    let g = geometric_normal(in.view_pos);
    let s = in.view_normal;
    if (!(length(s) > 1e-20)) {
        return shade(in, g);
    }
    let n = normalize(s);
    return shade(in, select(n, -n, dot(n, g) < 0.0));
}

// Face (geometric) normals, as MSSAO and the reference (by default) use.
@fragment
fn fs_face(in: VsOut) -> GBuffer {
    return shade(in, geometric_normal(in.view_pos));
}

// The second depth layer (gbuffer.second_layer; Mara, McGuire, Nowrouzezahrai, Luebke 2016,
// "Deep G-Buffers", §2): the first layer's linear depth this frame, and the minimum separation
// Δ (view units) a second-layer surface keeps behind it.
@group(1) @binding(0) var first_layer: texture_2d<f32>;
override SECOND_LAYER_SEPARATION: f32 = 0.0;

// Keeps a fragment only at least Δ behind the first layer (more than the first layer itself
// when Δ = 0); the depth test then leaves the nearest such surface. Its linear depth is
// computed as `shade` computes the first layer's, so Δ = 0 compares like with like.
@fragment
fn fs_second_layer(in: VsOut) -> @location(0) f32 {
    let first = textureLoad(first_layer, vec2<i32>(in.clip.xy), 0).r;
    let z = max(-in.view_pos.z, 1e-30);
    if (!(first > 0.0) || z <= first + SECOND_LAYER_SEPARATION) {
        discard;
    }
    return z;
}

fn normalize_safe_or_zero(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 1e-30) {
        return v / l;
    }
    return vec3<f32>(0.0);
}

// A degenerate derivative cross product (a triangle seen exactly edge-on) faces the eye.
fn normalize_safe(v: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if (l > 1e-30) {
        return v / l;
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}
