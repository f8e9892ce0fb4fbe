// Depth-edge weights for the edge-aware denoiser (blocks/edge_denoise.wgsl), as XeGTAO's AO
// pass computes them (docs/techniques/gtao.md §6). For the neighbours left, right, top, bottom:
//   delta = z_neighbour - z_centre; slope-compensated: s_LR = (delta_R - delta_L) / 2, then
//   delta_L + s_LR and delta_R - s_LR (top/bottom alike); the smaller magnitude of the raw and
//   the compensated delta is kept, so a plane at a slope is not an edge;
//   e = saturate(1.25 - |delta| / (0.011 z_centre)),
// quantised to 2 bits each, round(2.9 e) / 3, as XeGTAO packs them (R8: L*64 + R*16 + T*4 + B).
// A neighbour past the border is the centre itself (XeGTAO's clamped gather); sky (depth 0)
// differs from any surface by its whole depth, so its weight is 0.

fn depth_edges(depth: texture_2d<f32>, p: vec2<i32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(depth));
    let zc = textureLoad(depth, p, 0).r;
    let zl = textureLoad(depth, clamp(p + vec2<i32>(-1, 0), vec2<i32>(0), size - 1), 0).r;
    let zr = textureLoad(depth, clamp(p + vec2<i32>(1, 0), vec2<i32>(0), size - 1), 0).r;
    let zt = textureLoad(depth, clamp(p + vec2<i32>(0, -1), vec2<i32>(0), size - 1), 0).r;
    let zb = textureLoad(depth, clamp(p + vec2<i32>(0, 1), vec2<i32>(0), size - 1), 0).r;
    let d = vec4<f32>(zl, zr, zt, zb) - zc;
    let slope_lr = (d.y - d.x) * 0.5;
    let slope_tb = (d.w - d.z) * 0.5;
    let adjusted = d + vec4<f32>(slope_lr, -slope_lr, slope_tb, -slope_tb);
    let m = min(abs(d), abs(adjusted));
    let e = saturate(vec4<f32>(1.25) - m / (zc * 0.011));
    return round(2.9 * e) / 3.0;
}
