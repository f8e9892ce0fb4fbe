#include "common/view.wgsl"
#include "common/noise.wgsl"
#include "common/pyramid.wgsl"
#include "common/horizon.wgsl"
// Pyramid HBAO, the AO pass (crates/ao-passes/src/techniques/pyramid_hbao.rs; spec
// docs/techniques/pyramid-hbao.md §2.3-2.5, pseudo-code §7). Per pixel P: D directions;
// along each, step_count reads per pyramid level, the step multiplied by K per level, keeping
// the max of W(r) sin(alpha) (Eq. 8); AO = 1 - mean over directions.

struct Params {
    // World-space radius R (the shared [ao] radius).
    radius: f32,
    // Initial step s0 in full-resolution pixels.
    initial_step: f32,
    // sin(angle bias); 0 = the paper's estimator (spec §6.3).
    sin_bias: f32,
    // Pyramid factor K (3).
    factor: f32,
    // Directions D (the level count L and the steps per level are pipeline constants).
    directions: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: Params;
// Level 0: the full-resolution linear depth (0 = sky); levels 1..6 of the 3x3-average
// pyramid. Slots past L - 1 are bound to some level and never read.
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var depth1: texture_2d<f32>;
@group(0) @binding(4) var depth2: texture_2d<f32>;
@group(0) @binding(5) var depth3: texture_2d<f32>;
@group(0) @binding(6) var depth4: texture_2d<f32>;
@group(0) @binding(7) var normals: texture_2d<f32>;
// Raw AO: an intermediate when blurred (the `?IntermediateStorage=f16` variant of this file
// writes it at half precision; crates/graph/src/shader/variant.rs, "Storage-precision variants"), else
// the output.
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;
// Levels 5 and 6 (texels of 243 and 729 pixels): the reach of 1920x1080 and 3840x2160.
@group(0) @binding(9) var depth5: texture_2d<f32>;
@group(0) @binding(10) var depth6: texture_2d<f32>;

const TAU: f32 = 6.283185307179586;
// Reads per direction and level (`step_count`): a pipeline constant, not a uniform, so the
// driver unrolls the march (on lavapipe a loop with a uniform bound costs 35% more).
override STEP_COUNT: u32 = 4u;
// Pyramid levels L, level 0 included (`levels`): a pipeline constant too, so the marches of
// levels the pyramid does not have are not in the pipeline at all. SIMD CPU drivers such as
// lavapipe run both sides of a branch under a mask: with L in a uniform, L = 1 cost what
// L = 5 does.
override LEVELS: u32 = 4u;

// What every sample of one pixel's march shares.
struct Receiver {
    // View-space position and unit normal of P.
    o: vec3<f32>,
    n: vec3<f32>,
    // P's pixel centre (full-resolution pixels) and the pixel-to-view map.
    pc: vec2<f32>,
    to_view: PixelToView,
    // |V|^2 below which a sample is P itself (spec §6.3), 1 / R.
    eps2: f32,
    inv_radius: f32,
}

// One direction's march, carried from level to level: the direction, how far it may go
// (the screen's edge along it), the distance marched (full-resolution pixels) and the best
// W(r) sin(alpha) so far (Eq. 8).
struct March {
    dir: vec2<f32>,
    t_exit: f32,
    t: f32,
    a_max: f32,
}

// step_count reads on one pyramid level of texels `scale` pixels wide, `step` pixels apart.
// The level's texture is a parameter (not a switch in the loop), so each call site reads
// exactly one texture: on SIMD CPUs such as lavapipe a switch over textures executes every
// case. The body has no branch: a sample off screen, on the sky or on P itself contributes 0.
fn march_level(tex: texture_2d<f32>, edge: PyramidEdge, scale: f32, step: f32, g: Receiver, m_in: March) -> March {
    var m = m_in;
    let inv_scale = 1.0 / scale; // a power of K: exact, and folded where the level is known
    for (var i = 0u; i < STEP_COUNT; i = i + 1u) {
        m.t = m.t + step;
        let q = g.pc + m.dir * m.t;
        let tx = pyramid_texel(edge, q, inv_scale);
        let zs = textureLoad(tex, tx, 0).r;
        let v = pixel_view_position(g.to_view, pyramid_texel_centre(edge, tx, scale), zs) - g.o;
        let r2 = dot(v, v);
        let r = sqrt(r2);
        // Eq. 8: the max over samples of W(r) * sin(alpha), W(r) = max(0, 1 - r/R); sin(alpha)
        // less the g-buffer normals' rounding (common/horizon.wgsl).
        let w = max(0.0, 1.0 - r * g.inv_radius);
        let a = w * max(0.0, sin_elevation(g.n, v, r) - params.sin_bias);
        let counts = zs > 0.0 && r2 >= g.eps2 && m.t < m.t_exit;
        m.a_max = max(m.a_max, select(0.0, a, counts));
    }
    return m;
}

// Whether the march can stop before a level whose first sample is `t` pixels out: that
// sample is off screen, or its line of sight passes farther than R (plus the level's texel
// size) from P. Both only grow with t along a direction (the angle between P's line of sight
// and the sample's does), so every later sample is out too. Squared, without a root: the
// distance from P to the line through the eye along r is |P x r| / |r| (perspective); for an
// orthographic camera, the distance across the view axis.
fn march_ends(g: Receiver, m: March, t: f32, scale: f32, pixel_world: f32) -> bool {
    if (t >= m.t_exit) { return true; }
    let limit = params.radius + scale * pixel_world;
    let r = pixel_view_position(g.to_view, g.pc + m.dir * t, 1.0);
    if (g.to_view.perspective < 0.5) {
        let d = r.xy - g.o.xy;
        return dot(d, d) >= limit * limit;
    }
    let c = cross(g.o, r);
    return dot(c, c) >= limit * limit * dot(r, r);
}

// The march's distance to the screen's edge along `dir` from the pixel centre `pc`.
fn screen_exit(pc: vec2<f32>, dir: vec2<f32>, full: vec2<f32>) -> f32 {
    let to_far = select(pc, full - pc, dir > vec2<f32>(0.0));
    let t = select(vec2<f32>(3.0e38), to_far / abs(dir), dir != vec2<f32>(0.0));
    return min(t.x, t.y);
}

fn store(p: vec2<i32>, v: f32) {
    textureStore(ao, p, vec4<f32>(v, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let full = vec2<i32>(textureDimensions(depth));
    let p = vec2<i32>(id.xy);
    if (p.x >= full.x || p.y >= full.y) { return; }
    // Step 1 (spec §2.4): O(P) from the linear depth (the g-buffer's depth is already Eq. 6's
    // linear z), and the full-resolution normal, read once.
    let z = textureLoad(depth, p, 0).r;
    let nw = textureLoad(normals, p, 0);
    let nl = length(nw.xyz);
    if (!(z > 0.0) || nw.w < 0.5 || !(nl > 1e-6)) {
        store(p, 1.0);
        return;
    }
    var g: Receiver;
    g.n = nw.xyz / nl;
    g.pc = vec2<f32>(p) + 0.5;
    g.to_view = pixel_to_view(view, 1.0 / vec2<f32>(full));
    g.o = pixel_view_position(g.to_view, g.pc, z);
    // Spec §6.3: |V| below eps = 1e-4 z is P aliased onto itself; skip it.
    g.eps2 = 1e-8 * z * z;
    g.inv_radius = 1.0 / params.radius;
    // World size of one full-resolution pixel at P, for the early-out slack.
    let pixel_world = 1.0 / max(pixels_per_unit(z, view), 1e-30);
    let levels = clamp(LEVELS, 1u, 7u);
    let k = params.factor;
    let ki = i32(k);
    // The levels' edge texels (common/pyramid.wgsl), once per pixel.
    let e0 = pyramid_edge0(full);
    let e1 = pyramid_next_edge(e0, vec2<i32>(textureDimensions(depth1)), ki, 1.0);
    let e2 = pyramid_next_edge(e1, vec2<i32>(textureDimensions(depth2)), ki, k);
    let e3 = pyramid_next_edge(e2, vec2<i32>(textureDimensions(depth3)), ki, k * k);
    let e4 = pyramid_next_edge(e3, vec2<i32>(textureDimensions(depth4)), ki, k * k * k);
    let e5 = pyramid_next_edge(e4, vec2<i32>(textureDimensions(depth5)), ki, k * k * k * k);
    let e6 = pyramid_next_edge(e5, vec2<i32>(textureDimensions(depth6)), ki, k * k * k * k * k);

    // Spec §2.5: per-pixel rotation from a low-discrepancy dither (R2 sequence over pixels,
    // a blue-noise-like pattern) instead of a 32x32 blue-noise texture; per-direction jitter
    // u_d and start-step multiplier xi_d from a hash tiled every 32 pixels.
    // With temporal accumulation the rotation advances by the golden ratio each frame and the
    // hash is reseeded by the frame.
    let frame = noise_frame(view.frame_index);
    let rotation = fract(0.7548776662 * f32(p.x) + 0.5698402910 * f32(p.y) + 0.6180339887 * f32(frame));
    let tile = vec2<u32>(p) % vec2<u32>(32u);
    let pixel_seed = pcg_hash(tile.x ^ pcg_hash(tile.y + frame * 0x01000193u));
    let dirs = max(params.directions, 1u);
    var occlusion = 0.0;
    for (var d = 0u; d < dirs; d = d + 1u) {
        // theta_d = 2 pi (rotation + (d + u_d) / D): random, stratified directions (§2.5).
        // One hash per direction: its high 16 bits give u_d, its low 16 bits xi_d.
        let h = pcg_hash(pixel_seed ^ (d * 0x9e3779b9u));
        let u = f32(h >> 16u) / 65536.0;
        let theta = TAU * (rotation + (f32(d) + u) / f32(dirs));
        var m: March;
        m.dir = vec2<f32>(cos(theta), sin(theta));
        m.t_exit = screen_exit(g.pc, m.dir, vec2<f32>(full));
        m.t = 0.0;
        m.a_max = 0.0;
        // xi_d in [0.5, 1.5): the random start-step multiplier of §2.5; the step and the
        // texel footprint both grow by K per level.
        let s0 = params.initial_step * (0.5 + f32(h & 0xffffu) / 65536.0);
        // Level 0 always: its first sample is under 1.5 pixels away.
        m = march_level(depth, e0, 1.0, s0, g, m);
        var step = s0 * k;
        var scale = k;
        if (levels > 1u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
            m = march_level(depth1, e1, scale, step, g, m);
            step = step * k;
            scale = scale * k;
            if (levels > 2u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
                m = march_level(depth2, e2, scale, step, g, m);
                step = step * k;
                scale = scale * k;
                if (levels > 3u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
                    m = march_level(depth3, e3, scale, step, g, m);
                    step = step * k;
                    scale = scale * k;
                    if (levels > 4u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
                        m = march_level(depth4, e4, scale, step, g, m);
                        step = step * k;
                        scale = scale * k;
                        if (levels > 5u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
                            m = march_level(depth5, e5, scale, step, g, m);
                            step = step * k;
                            scale = scale * k;
                            if (levels > 6u && !march_ends(g, m, m.t + step, scale, pixel_world)) {
                                m = march_level(depth6, e6, scale, step, g, m);
                            }
                        }
                    }
                }
            }
        }
        occlusion = occlusion + m.a_max;
    }
    // Step 3 (§2.3): AO(P) = 1 - (1/D) sum_d A(theta_d).
    store(p, clamp(1.0 - occlusion / f32(dirs), 0.0, 1.0));
}
