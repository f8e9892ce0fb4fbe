// The elevation of a sample above a receiver's tangent plane, as the horizon-based techniques
// (hbao, pyramid-hbao) measure it: sin(alpha) = n . V / |V|, less what the g-buffer's storage
// cannot resolve. Normals are stored as Rgba16Float (crates/frame/src/channels.rs):
// every component is rounded to 11 significant bits, an error of at most 2^-11 = 4.9e-4 of
// the unit normal, so a V lying exactly in the tangent plane reads a sin(alpha) of up to that
// much either way. Without a floor the positive half counts as occlusion: a flat plane reads
// a mean accessibility of 1 - 5e-4 instead of 1 (bench, `plane`), enough to make hbao lose to
// `none` where the true occlusion is small. The floor, 1e-3, is twice the normal's rounding to
// leave room for the reconstructed positions' own; below it a sample is the plane itself.
const SIN_ELEVATION_FLOOR: f32 = 1e-3;

fn sin_elevation(n: vec3<f32>, v: vec3<f32>, dist: f32) -> f32 {
    return dot(n, v) / dist - SIN_ELEVATION_FLOOR;
}
