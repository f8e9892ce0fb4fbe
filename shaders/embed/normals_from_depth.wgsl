#include "common/view.wgsl"
// Embedding input adapter, for an application without a normal buffer: view-space normals
// (Rgba16Float, w = 1 on geometry, 0 on sky) rebuilt from linear depth, edge-aware.
//
// Per axis the centre has two one-sided differences; the side whose surface continues through
// the centre is kept. Each side predicts the centre's depth by linear extrapolation from its
// two texels (Y. Wen, "Accurate Normal Reconstruction from Depth Buffer", 2019, the rule
// XeGTAO's and Wicked Engine's reconstructions use): a plane's 1/z is affine in screen space
// under a perspective (z itself under an orthographic projection), so on a plane the
// prediction is exact, and across a depth edge the far side's is not. The normal is the cross
// product of the kept tangents, turned towards the camera. Sky texels and the image border
// predict nothing; an axis with no usable side falls back to the other side's single
// difference, and a pixel with neither axis faces the camera.

@group(0) @binding(0) var linear_depth: texture_2d<f32>;
@group(0) @binding(1) var<uniform> view: View;
@group(0) @binding(2) var normals: texture_storage_2d<rgba16float, write>;

const NO_DEPTH: f32 = 0.0;

fn depth_at(p: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(linear_depth));
    if (any(p < vec2<i32>(0)) || any(p >= size)) { return NO_DEPTH; }
    return textureLoad(linear_depth, p, 0).r;
}

// The quantity affine in screen space on a plane.
fn affine(z: f32) -> f32 {
    return select(1.0 / z, z, view.orthographic > 0.5);
}

// Extrapolation error of one side (`s` = step towards that side): large when a texel is sky.
fn side_error(p: vec2<i32>, s: vec2<i32>, zc: f32) -> f32 {
    let z1 = depth_at(p + s);
    let z2 = depth_at(p + 2 * s);
    if (z1 <= 0.0) { return 3.0e38; }
    if (z2 <= 0.0) { return 1.0e38; }
    let predicted = 2.0 * affine(z1) - affine(z2);
    return abs(predicted - affine(zc)) / abs(affine(zc));
}

// The tangent along axis `s` (a unit pixel step): towards the better side, signed so it points
// along +s. Zero when neither neighbour is geometry.
fn tangent(p: vec2<i32>, s: vec2<i32>, zc: f32, pc: vec3<f32>) -> vec3<f32> {
    let forward = side_error(p, s, zc);
    let backward = side_error(p, -s, zc);
    if (min(forward, backward) >= 3.0e38) { return vec3<f32>(0.0); }
    if (forward <= backward) {
        let q = p + s;
        return view_position(pixel_uv(q, view), depth_at(q), view) - pc;
    }
    let q = p - s;
    return pc - view_position(pixel_uv(q, view), depth_at(q), view);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(normals);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = vec2<i32>(id.xy);
    let zc = depth_at(p);
    if (zc <= 0.0) {
        textureStore(normals, p, vec4<f32>(0.0));
        return;
    }
    let pc = view_position(pixel_uv(p, view), zc, view);
    let tx = tangent(p, vec2<i32>(1, 0), zc, pc);
    let ty = tangent(p, vec2<i32>(0, 1), zc, pc);
    // x right, y down in pixels: cross(ty, tx) points out of a surface facing the camera.
    var n = cross(ty, tx);
    let to_camera = select(-pc, vec3<f32>(0.0, 0.0, 1.0), view.orthographic > 0.5);
    let len = length(n);
    if (!(len > 1e-30)) {
        n = normalize(to_camera);
    } else {
        n = n / len;
        if (dot(n, to_camera) < 0.0) { n = -n; }
    }
    textureStore(normals, p, vec4<f32>(n, 1.0));
}
