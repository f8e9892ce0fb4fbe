// Shared by the separable blur and upsampling blocks (crates/ao-passes/src/blocks/): the
// blur constants (Rust mirror: blocks::BlurUniform) and the bilateral weight terms.

struct BlurParams {
    // Tap offset per step: (1, 0) horizontal, (0, 1) vertical.
    axis: vec2<i32>,
    // Taps on each side: the kernel is k = -radius..radius.
    radius: i32,
    // Relative depth tolerance sigma_z (0 = no depth term).
    depth_sigma: f32,
    // Exponent of the normal term (0 = no normal term).
    normal_power: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
    // Normalised one-sided Gaussian weights w[|k|], packed four per vec4.
    weights: array<vec4<f32>, 8>,
}

// The spatial Gaussian weight of offset k, w[|k|] = exp(-k^2 / (2 sigma^2)) / sum (computed on
// the CPU), is read straight from the uniform block, `params.weights[|k| / 4][|k| % 4]`, in each
// shader: a helper taking the block by value copied all of it (160 bytes) into every tap,
// which made the blurs four times slower per load than the AO passes on lavapipe.

// Depth term exp(-(dz / (sigma_z * z_p))^2 / 2): relative, so the tolerance scales with the
// distance; 1 when sigma_z is 0 (term off).
fn depth_weight(z_p: f32, z_q: f32, sigma_z: f32) -> f32 {
    if (sigma_z <= 0.0) { return 1.0; }
    let d = (z_q - z_p) / max(sigma_z * z_p, 1e-20);
    return exp(-0.5 * min(d * d, 80.0));
}

// Normal term max(0, n_p . n_q)^power; 1 when power is 0 (term off).
fn normal_weight(n_p: vec3<f32>, n_q: vec3<f32>, power: f32) -> f32 {
    if (power <= 0.0) { return 1.0; }
    let c = dot(n_p, n_q);
    // pow(0, y) goes through log2(0): return the limit directly.
    if (!(c > 1e-6)) { return 0.0; }
    return pow(min(c, 1.0), power);
}

// A g-buffer normal made unit length; zero on sky or a degenerate normal.
fn unit_normal(n: vec4<f32>) -> vec3<f32> {
    let l = length(n.xyz);
    if (n.w < 0.5 || !(l > 1e-6)) { return vec3<f32>(0.0); }
    return n.xyz / l;
}

// Bilateral upsampling (crates/ao-passes/src/blocks/bilateral_upsample.rs).
struct UpsampleParams {
    // Full-resolution pixels per low-resolution texel (integer, >= 1).
    factor: f32,
    depth_sigma: f32,
    normal_power: f32,
    pad0: f32,
}

// The 2x2 low-resolution footprint of full-resolution pixel p: tap (0, 0) and bilinear weights
// of the taps (0,0), (1,0), (0,1), (1,1) in x, y, z, w.
struct Footprint {
    base: vec2<i32>,
    bilinear: vec4<f32>,
}

fn upsample_footprint(p: vec2<i32>, factor: f32) -> Footprint {
    // Low-res texel x covers full-res [x f, (x + 1) f): its centre is at (x + 0.5) f.
    let u = (vec2<f32>(p) + 0.5) / factor - 0.5;
    let b = floor(u);
    let t = u - b;
    var f: Footprint;
    f.base = vec2<i32>(b);
    f.bilinear = vec4<f32>((1.0 - t.x) * (1.0 - t.y), t.x * (1.0 - t.y), (1.0 - t.x) * t.y, t.x * t.y);
    return f;
}

// Tap i (0..3) of a footprint, clamped to the low-resolution image.
fn footprint_tap(f: Footprint, i: u32, size: vec2<i32>) -> vec2<i32> {
    let q = f.base + vec2<i32>(i32(i & 1u), i32(i >> 1u));
    return clamp(q, vec2<i32>(0), size - 1);
}

// w_i = bilinear_i * depth term_i * normal term n_i, over non-sky taps. When no tap agrees
// (sum of weights <= 1e-4) the tap of nearest depth is taken (nearest-depth upsampling);
// with no non-sky tap at all the result is 1 (nothing known to occlude).
fn upsample_combine(z_p: f32, z: vec4<f32>, ao: vec4<f32>, n: vec4<f32>, bilinear: vec4<f32>, depth_sigma: f32) -> f32 {
    var sum = 0.0;
    var wsum = 0.0;
    var best = 1.0;
    var best_dz = 3.0e38;
    for (var i = 0u; i < 4u; i = i + 1u) {
        if (!(z[i] > 0.0)) { continue; }
        let w = bilinear[i] * depth_weight(z_p, z[i], depth_sigma) * n[i];
        sum = sum + w * ao[i];
        wsum = wsum + w;
        let dz = abs(z[i] - z_p);
        if (dz < best_dz) {
            best_dz = dz;
            best = ao[i];
        }
    }
    if (wsum > 1e-4) {
        return sum / wsum;
    }
    return best;
}
