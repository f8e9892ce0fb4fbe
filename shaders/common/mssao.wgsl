#include "common/view.wgsl"
#include "common/normal_oct.wgsl"
// MSSAO (Hoang & Low, "Efficient screen-space approach to high-quality multi-scale ambient
// occlusion", The Visual Computer 2012): the math every MSSAO pass shares. Equation numbers are
// the paper's; docs/techniques/mssao.md records them. Self-contained (no globals): the pass files
// include this after common/view.wgsl and pass their textures in.
//
// Conventions: level 0 is the finest (the paper's Res_1). Every level stores linear depth
// (R32Float, 0 on sky) and the view-space unit normal, octahedral in one u32
// (common/normal_oct.wgsl): 8 bytes a texel instead of 24 for an Rgba32Float position and an
// Rgba16Float normal. A texel's view-space position is rebuilt from its depth at its centre
// (`mssao_texel_centre`), and downsampling stores the depth its chosen surface has there
// (`mssao_plane_depth`), so a plane stays on itself at every level. "AO" is occlusion, 1 - k_A, as in the
// paper; the tuple textures hold (max of per-level means, raw sum, sample count).


// Mirror of `MssaoUniform` in crates/ao-passes/src/techniques/mssao/passes.rs (48 bytes).
struct MssaoParams {
    // Pyramid level this pass works at (0 = finest).
    level: u32,
    // 1: the 3x3 blur also weighs by Eqs. 8-9 (the prose's "bilateral"); 0: Table 4's weights only.
    bilateral_blur: u32,
    // Fig. 8's upsampling: 0 nearest, 1 bilinear, 2 bilateral (the paper's).
    upsampling: u32,
    pad1: u32,
    // d_max: the AO radius of influence in view units (= the shared radius R).
    d_max: f32,
    // r_max: kernel radius cap in pixels of the level (Eq. 5).
    r_max: f32,
    // d_threshold: depth range of a 2x2 block above which downsampling keeps one sub-pixel.
    d_threshold: f32,
    // t_n, t_z: exponents of the normal (Eq. 8) and depth (Eq. 9) weights.
    normal_power: f32,
    depth_power: f32,
    pad2: f32,
    pad3: f32,
    pad4: f32,
}

// One g-buffer texel of some level.
struct MssaoSurface {
    p: vec3<f32>,
    n: vec3<f32>,
    valid: bool,
}

// Where one level's texels lie: the full-resolution pixel-to-view map, the level's texel
// size in full-resolution pixels (2^l) and the full resolution.
struct MssaoGrid {
    to_view: PixelToView,
    scale: f32,
    full: vec2<f32>,
}

// `full` is the level-0 image's extent in its own texels: view.size, which a half-resolution
// view block (blocks/half_view.wgsl) gives as W / 2, so rounded up: the half image's last texel
// at an odd size is its block's, centred on full pixel corner 2p + 1 like every other.
fn mssao_grid(view: View, level: u32) -> MssaoGrid {
    return MssaoGrid(pixel_to_view(view, view.inv_size), f32(1u << level), ceil(view.size));
}

// The centre, in full-resolution pixels, of the pixels texel c covers: [c 2^l, (c + 1) 2^l)
// within the image (the last texel of an odd size covers fewer).
fn mssao_texel_centre(g: MssaoGrid, c: vec2<i32>) -> vec2<f32> {
    let lo = vec2<f32>(c) * g.scale;
    return 0.5 * (lo + min(lo + g.scale, g.full));
}

// Geometry: a positive, finite depth (0 marks sky; NaN fails both tests).
fn mssao_is_geometry(z: f32) -> bool {
    return z > 0.0 && z < 3.0e38;
}

// The view-space position of texel c of a level with depth z: rebuilt at the texel's centre.
fn mssao_position(g: MssaoGrid, c: vec2<i32>, z: f32) -> vec3<f32> {
    return pixel_view_position(g.to_view, mssao_texel_centre(g, c), z);
}

// The depth where the line of sight through texel c's centre meets the plane through p with
// normal n; 0 where it misses the plane in front of the camera (parallel, or non-finite).
fn mssao_plane_depth(g: MssaoGrid, c: vec2<i32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    // r: the point at depth 1 on the line (perspective: X = t r has depth t); for an
    // orthographic camera X = (r.xy, -t).
    let r = pixel_view_position(g.to_view, mssao_texel_centre(g, c), 1.0);
    var t: f32;
    if (g.to_view.perspective > 0.5) {
        t = dot(n, p) / dot(n, r);
    } else {
        t = (dot(n.xy, r.xy) - dot(n, p)) / n.z;
    }
    return select(0.0, t, t > 0.0 && t < 3.0e38);
}

fn mssao_surface(depth: texture_2d<f32>, normals: texture_2d<u32>, g: MssaoGrid, c: vec2<i32>) -> MssaoSurface {
    let z = textureLoad(depth, c, 0).x;
    let valid = mssao_is_geometry(z);
    let p = mssao_position(g, c, select(1.0, z, valid));
    let n = normal_oct_decode(textureLoad(normals, c, 0).x);
    return MssaoSurface(p, n, valid);
}

// A texel's linear depth and normal only, for the filters (Eqs. 8-9 weigh by nothing else):
// no position to rebuild.
struct MssaoDepthNormal {
    z: f32,
    n: vec3<f32>,
    valid: bool,
}

fn mssao_depth_normal(depth: texture_2d<f32>, normals: texture_2d<u32>, c: vec2<i32>) -> MssaoDepthNormal {
    let z = textureLoad(depth, c, 0).x;
    return MssaoDepthNormal(z, normal_oct_decode(textureLoad(normals, c, 0).x), mssao_is_geometry(z));
}

fn mssao_in_bounds(c: vec2<i32>, size: vec2<i32>) -> bool {
    return all(c >= vec2<i32>(0)) && all(c < size);
}

// Eqs. 6-7 for one sample: rho(d) * clamp(n . normalize(q - p), 0, 1), with
// rho(d) = 1 - min(1, (d / d_max)^2). A sample at p itself (d ~ 0, common after the median
// downsampling) contributes 0 and is not normalised.
fn mssao_sample_ao(p: vec3<f32>, n: vec3<f32>, q: vec3<f32>, d_max: f32) -> f32 {
    let v = q - p;
    let d = length(v);
    if (!(d > 1e-6 * d_max)) {
        return 0.0;
    }
    let cos_t = clamp(dot(n, v / d), 0.0, 1.0);
    let x = d / d_max;
    let rho = 1.0 - min(1.0, x * x);
    return rho * cos_t;
}

// Eq. 5 with the spec's erratum (0-based level index): r_l = r_0 / 2^l, R_l = min(r_max, r_l),
// where r_0 = s d_max / (2 z tan(alpha / 2)) = d_max * pixels_per_unit(z) is d_max projected at
// the finest level.
fn mssao_kernel_radius(r0: f32, level: u32, r_max: f32) -> f32 {
    return min(r_max, r0 / f32(1u << level));
}

// One tap of the neighbourhood: (ao, counted). Off-screen taps are skipped (the g-buffer has no
// data there); sky taps count as unoccluding samples (nothing is there).
fn mssao_tap(depth: texture_2d<f32>, g: MssaoGrid, size: vec2<i32>, c: vec2<i32>, p: vec3<f32>, n: vec3<f32>, d_max: f32) -> vec2<f32> {
    if (!mssao_in_bounds(c, size)) {
        return vec2<f32>(0.0);
    }
    let z = textureLoad(depth, c, 0).x;
    if (!mssao_is_geometry(z)) {
        return vec2<f32>(0.0, 1.0);
    }
    return vec2<f32>(mssao_sample_ao(p, n, mssao_position(g, c, z), d_max), 1.0);
}

// Coarse levels (Sec. 4.3, Fig. 6 left): every other pixel of the (2 R + 1)^2 kernel, i.e. the
// odd offsets +-1, +-3, +-5 (36 of 121 taps at R = 5) with |o.x|, |o.y| <= R. Returns
// (un-normalised sum of Eq. 6, sample count N).
//
// The paper's kernel takes ring k (the taps with max(|o.x|, |o.y|) = k) exactly when R >= k, so
// its tap set, and with it the mean sum / N, jumps where R crosses 1, 3 or 5: a surface whose
// R_l = r_0 / 2^l sits near 3 or 5 texels switches from 4 to 16 or from 16 to 36 taps, and a
// camera step of 0.1 units changed the mean of a wall by 0.15 (docs/results/output-sizes.md,
// "At every output size"). Here ring k enters with weight w_k(R) = clamp((R - k) / 2 + 1, 0, 1),
// rising over (k - 2, k]; ring 1 over (0, 1]. At odd R (R = r_max = 5 included) every ring the
// paper takes has weight 1 and no other ring is present, so the kernel is the paper's there;
// between, the sum and N move continuously with R. The weights count in N as fractions.
fn mssao_ring_weight(k: i32, radius: f32) -> f32 {
    if (k == 1) {
        return clamp(radius, 0.0, 1.0);
    }
    return clamp((radius - f32(k)) * 0.5 + 1.0, 0.0, 1.0);
}

fn mssao_near_interleaved(depth: texture_2d<f32>, g: MssaoGrid, c: vec2<i32>, s: MssaoSurface, radius: f32, d_max: f32) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(depth));
    var acc = vec2<f32>(0.0);
    if (!(radius > 0.0)) {
        return acc;
    }
    // The outermost ring with a weight: the largest odd k < R + 2.
    let k = min((i32(ceil((radius + 1.0) * 0.5)) * 2) - 1, MSSAO_MAX_RING);
    for (var oy = -k; oy <= k; oy = oy + 2) {
        for (var ox = -k; ox <= k; ox = ox + 2) {
            let w = mssao_ring_weight(max(abs(ox), abs(oy)), radius);
            acc = acc + w * mssao_tap(depth, g, size, c + vec2<i32>(ox, oy), s.p, s.n, d_max);
        }
    }
    return acc;
}

// The outermost ring a radius within r_max's range (at most 8) can weigh: 9 (w_9 > 0 above 7).
const MSSAO_MAX_RING: i32 = 9;

// The finest level's fixed, unrotated 16-point Poisson disk (Sec. 4.3, Fig. 6 right). The paper
// prints no coordinates: these come from Mitchell's best-candidate algorithm in the unit disk
// (minimum distance 0.465, centroid within 0.02 of the origin).
const MSSAO_POISSON: array<vec2<f32>, 16> = array<vec2<f32>, 16>(
    vec2<f32>(0.1177, -0.1292), vec2<f32>(-0.9247, 0.2728), vec2<f32>(-0.0589, 0.9798), vec2<f32>(-0.5662, -0.7433),
    vec2<f32>(0.8773, 0.4504), vec2<f32>(0.8872, -0.4327), vec2<f32>(0.2211, -0.9547), vec2<f32>(-0.3048, 0.3436),
    vec2<f32>(0.2877, 0.4300), vec2<f32>(-0.4884, -0.1777), vec2<f32>(-0.6826, 0.7173), vec2<f32>(0.5895, -0.0524),
    vec2<f32>(-0.9586, -0.2593), vec2<f32>(0.4495, 0.8898), vec2<f32>(-0.0859, -0.5837), vec2<f32>(0.3782, -0.5166),
);

// Finest level: the Poisson disk scaled by R and rounded to texels. A point that rounds onto the
// shaded pixel itself is not a neighbour and is skipped. Returns (sum, N) as above.
fn mssao_near_poisson(depth: texture_2d<f32>, g: MssaoGrid, c: vec2<i32>, s: MssaoSurface, radius: f32, d_max: f32) -> vec2<f32> {
    let size = vec2<i32>(textureDimensions(depth));
    var acc = vec2<f32>(0.0);
    if (!(radius >= 1.0)) {
        return acc;
    }
    var disk = MSSAO_POISSON;
    for (var i = 0u; i < 16u; i = i + 1u) {
        let o = vec2<i32>(round(disk[i] * radius));
        if (all(o == vec2<i32>(0))) {
            continue;
        }
        acc = acc + mssao_tap(depth, g, size, c + o, s.p, s.n, d_max);
    }
    return acc;
}

// x^e for x in [0, 1], e >= 0, never NaN (pow(0, 0) = 1 here, pow(0, e > 0) = 0).
fn mssao_pow01(x: f32, e: f32) -> f32 {
    return exp2(e * log2(max(x, 1e-30)));
}

// Eq. 8 times Eq. 9: ((n . n_i + 1) / 2)^t_n * (1 / (1 + |z_i - z|))^t_z, with z positive
// linear depth.
fn mssao_bilateral_weight(n: vec3<f32>, z: f32, ni: vec3<f32>, zi: f32, t_n: f32, t_z: f32) -> f32 {
    let wn = mssao_pow01(clamp((dot(n, ni) + 1.0) * 0.5, 0.0, 1.0), t_n);
    let wz = mssao_pow01(1.0 / (1.0 + abs(zi - z)), t_z);
    return wn * wz;
}

// Bilateral 2x2 upsampling (Sec. 4.5, Fig. 9, Eqs. 8-9) of the blurred tuple of the next
// coarser level to fine texel `c` with surface `s`: the four nearest coarse texels with bilinear
// weights 9/16, 3/16, 3/16, 1/16, times Eq. 8 and Eq. 9, normalised. Eq. 9's |dz| is the coarse
// point's distance from the fine surface's tangent plane, |n . (q - p)|: the depth difference
// for a surface facing the camera, but not many units along a wall seen at a grazing angle,
// where the depth difference made one coarse texel win (blocks a coarse texel wide). Coarse sky texels get no
// weight; if every bilateral weight underflows, the bilinear weights are used; if every
// coarse texel is sky, the result is (0, 0, 0): no far-field occlusion. `mode` is Fig. 8's
// comparison: 2 as described, 1 the bilinear weights alone, 0 the enclosing coarse texel
// alone (its tuple, or (0, 0, 0) where it is sky).
const MSSAO_NEAREST: u32 = 0u;
const MSSAO_BILATERAL: u32 = 2u;

fn mssao_upsample(coarse_ao: texture_2d<f32>, coarse_depth: texture_2d<f32>, coarse_normals: texture_2d<u32>, coarse_grid: MssaoGrid, c: vec2<i32>, s: MssaoSurface, t_n: f32, t_z: f32, mode: u32) -> vec3<f32> {
    let cs = vec2<i32>(textureDimensions(coarse_ao));
    let m = c / 2;
    // A fine texel centre lies a quarter coarse texel from its parent's centre, towards the
    // neighbour in direction `d`.
    let d = select(vec2<i32>(-1), vec2<i32>(1), (c & vec2<i32>(1)) == vec2<i32>(1));
    var taps = array<vec2<i32>, 4>(m, m + vec2<i32>(d.x, 0), m + vec2<i32>(0, d.y), m + d);
    var wb = array<f32, 4>(9.0 / 16.0, 3.0 / 16.0, 3.0 / 16.0, 1.0 / 16.0);
    if (mode == MSSAO_NEAREST) {
        wb = array<f32, 4>(1.0, 0.0, 0.0, 0.0);
    }
    var sum_bilateral = vec3<f32>(0.0);
    var w_bilateral = 0.0;
    var sum_bilinear = vec3<f32>(0.0);
    var w_bilinear = 0.0;
    for (var j = 0; j < 4; j = j + 1) {
        let t = clamp(taps[j], vec2<i32>(0), cs - vec2<i32>(1));
        let q = mssao_surface(coarse_depth, coarse_normals, coarse_grid, t);
        if (!q.valid || !(wb[j] > 0.0)) {
            continue;
        }
        let a = textureLoad(coarse_ao, t, 0).xyz;
        let w = wb[j] * mssao_bilateral_weight(s.n, 0.0, q.n, dot(s.n, q.p - s.p), t_n, t_z);
        sum_bilateral = sum_bilateral + w * a;
        w_bilateral = w_bilateral + w;
        sum_bilinear = sum_bilinear + wb[j] * a;
        w_bilinear = w_bilinear + wb[j];
    }
    if (mode == MSSAO_BILATERAL && w_bilateral > 1e-30) {
        return sum_bilateral / w_bilateral;
    }
    if (w_bilinear > 0.0) {
        return sum_bilinear / w_bilinear;
    }
    return vec3<f32>(0.0);
}

// Eq. 10: the tuple a level passes on, from its own (sum, N) and the upsampled tuple `far`:
// (max(sum / N, far.max), sum + far.sum, N + far.count). N = 0 gives a mean of 0.
fn mssao_combine(near: vec2<f32>, far: vec3<f32>) -> vec3<f32> {
    let mean = select(0.0, clamp(near.x / near.y, 0.0, 1.0), near.y > 0.0);
    return vec3<f32>(max(mean, far.x), near.x + far.y, near.y + far.z);
}

// Eq. 11 on the finest level's combined tuple, returned as accessibility 1 - AO_final =
// (1 - AO_max)(1 - AO_average), AO_average = sum / count (0 without samples).
fn mssao_accessibility(t: vec3<f32>) -> f32 {
    let ao_max = clamp(t.x, 0.0, 1.0);
    let ao_avg = select(0.0, clamp(t.y / t.z, 0.0, 1.0), t.z > 1e-6);
    return clamp((1.0 - ao_max) * (1.0 - ao_avg), 0.0, 1.0);
}
