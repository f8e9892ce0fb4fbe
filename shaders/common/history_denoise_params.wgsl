// The uniform both passes of blocks/history_denoise read (crates/ao-passes/src/blocks/
// history_denoise.rs, `HistoryDenoiseUniform`): radius in pixels on a new pixel, its shrink
// with history length, the AO weight's sigma, the plane tolerance (relative to the distance
// to the camera), this a-trous iteration's tap spacing, the history fix's frame count and
// stride, the radius factor at the closest hits, and whether a hit-distance texture is bound.
struct HistoryDenoiseParams {
    base_radius: f32,
    shrink: f32,
    sigma_ao: f32,
    plane_tolerance: f32,
    step: f32,
    fix_frames: f32,
    fix_stride: f32,
    hit_floor: f32,
    has_hits: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}
