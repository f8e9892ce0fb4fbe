// The same-surface tests of blocks/history_denoise's passes (history_fix.wgsl,
// atrous_denoise.wgsl): a tap counts where it is a surface, lies near the centre's tangent
// plane and faces the same way.

// Whether linear depth z is a surface (0 marks sky).
fn is_surface(z: f32) -> bool {
    return z > 0.0 && z < 3.0e38;
}

// max(c, 0)^64 (SVGF's normal weight, sigma_n = 128 halved for a 3x3 kernel) by six squarings
// (pow is an exp and a log).
fn facing_weight(c: f32) -> f32 {
    var x = max(c, 0.0);
    x = x * x;
    x = x * x;
    x = x * x;
    x = x * x;
    x = x * x;
    return x * x;
}

// The distance of point q from the plane through p with unit normal n, over `tolerance` times
// p's distance to the camera (the plane weight is exp of minus this).
fn plane_distance(p: vec3<f32>, n: vec3<f32>, q: vec3<f32>, tolerance: f32) -> f32 {
    return abs(dot(n, q - p)) / (tolerance * max(length(p), 1e-20));
}
