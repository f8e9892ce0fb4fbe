#include "common/finite.wgsl"
#include "common/view.wgsl"
// Reading the g-buffer's receiver point (needs common/view.wgsl): linear depth (0 = sky) and
// view-space normals (w = 0 on sky), as every technique's per-pixel set-up does.

struct Receiver {
    // False on sky or where the normal is missing: the pixel is unoccluded.
    valid: bool,
    // Linear view depth (> 0).
    z: f32,
    // View-space position and unit normal.
    p: vec3<f32>,
    n: vec3<f32>,
}

fn load_receiver(depth: texture_2d<f32>, normals: texture_2d<f32>, px: vec2<i32>, view: View) -> Receiver {
    var r: Receiver;
    r.valid = false;
    let z = textureLoad(depth, px, 0).x;
    // Bit-pattern tests first (common/finite.wgsl): a NaN or infinite depth or normal is no
    // receiver, whatever a compiler assumes about float comparisons.
    if (!is_finite_f32(z) || !(z > 0.0) || z > 1e30) {
        return r; // sky
    }
    let nw = textureLoad(normals, px, 0);
    let nl = length(nw.xyz);
    if (!is_finite_vec3(nw.xyz) || nw.w < 0.5 || !(nl > 1e-6)) {
        return r;
    }
    r.valid = true;
    r.z = z;
    r.n = nw.xyz / nl;
    r.p = view_position(pixel_uv(px, view), z, view);
    return r;
}
