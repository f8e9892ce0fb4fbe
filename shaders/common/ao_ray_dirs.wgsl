// The reference's AO rays without a tracer (mirror of crates/scene/src/reference/sampling.rs
// and tracer.rs): per-pixel scramble, the scrambled 2D Sobol point, Malley's cosine-weighted
// hemisphere in Duff et al.'s tangent frame, the origin offset. common/ao_rays.wgsl traces them
// against the scene with common/scene_trace.wgsl (the compute BVH, or ray queries in a shader's
// `RayTracer=hardware` variant).
fn rays_hash(x_in: u32) -> u32 {
    var x = x_in;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// Per-pixel scramble masks (sampling.rs pixel_scramble).
fn rays_pixel_scramble(pixel: u32) -> vec2<u32> {
    let a = rays_hash(pixel ^ 0x9e3779b9u);
    return vec2<u32>(a, rays_hash(a ^ 0x85ebca6bu));
}

fn rays_sobol_second(index_in: u32) -> u32 {
    var index = index_in;
    var result = 0u;
    var v = 1u << 31u;
    while (index != 0u) {
        if ((index & 1u) != 0u) {
            result ^= v;
        }
        index >>= 1u;
        v ^= v >> 1u;
    }
    return result;
}

fn rays_unit_float(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

// Point `index` of the scrambled 2D Sobol sequence.
fn rays_sobol_2d(index: u32, scramble: vec2<u32>) -> vec2<f32> {
    return vec2<f32>(
        rays_unit_float(reverseBits(index) ^ scramble.x),
        rays_unit_float(rays_sobol_second(index) ^ scramble.y),
    );
}

// Malley's method: cosine-weighted around +z, z > 0.
fn rays_cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let r = sqrt(u.x);
    let phi = 6.28318530717958647 * u.y;
    let z = sqrt(max(1.0 - u.x, 1e-12));
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// Sign of z as copysign(1, z) (negative zero gives -1, as on the CPU).
fn rays_sign(z: f32) -> f32 {
    return bitcast<f32>((bitcast<u32>(z) & 0x80000000u) | bitcast<u32>(1.0));
}

// World direction of a local hemisphere direction around unit normal n (Duff et al. 2017).
fn rays_to_world(n: vec3<f32>, local: vec3<f32>) -> vec3<f32> {
    let sign = rays_sign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bt = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    return t * local.x + bt * local.y + n * local.z;
}

fn rays_offset_epsilon(p: vec3<f32>, radius: f32) -> f32 {
    let a = abs(p);
    return 1e-4 * radius + 4e-6 * max(a.x, max(a.y, a.z));
}

// True for a finite value (not NaN or +-inf).
fn rays_finite3(v: vec3<f32>) -> bool {
    let bits = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(bits != vec3<u32>(0x7f800000u));
}
