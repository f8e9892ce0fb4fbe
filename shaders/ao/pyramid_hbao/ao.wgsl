#include "common/view.wgsl"
#include "common/noise.wgsl"
#include "common/pyramid.wgsl"
#include "common/horizon.wgsl"
// Pyramid HBAO, the AO pass (crates/ao-passes/src/techniques/pyramid_hbao.rs; spec
// /work/shared/specs/pyramid_hbao.md §2.3-2.5, pseudo-code §7). Per pixel P: D directions;
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
    // Levels L (level 0 included), directions D, reads per level.
    levels: u32,
    directions: u32,
    step_count: u32,
    pad0: u32,
}

@group(0) @binding(0) var<uniform> view: View;
@group(0) @binding(1) var<uniform> params: Params;
// Level 0: the full-resolution linear depth (0 = sky); levels 1..4 of the 3x3-average
// pyramid. Slots past L - 1 are bound to some level and never read.
@group(0) @binding(2) var depth: texture_2d<f32>;
@group(0) @binding(3) var depth1: texture_2d<f32>;
@group(0) @binding(4) var depth2: texture_2d<f32>;
@group(0) @binding(5) var depth3: texture_2d<f32>;
@group(0) @binding(6) var depth4: texture_2d<f32>;
@group(0) @binding(7) var normals: texture_2d<f32>;
// Raw AO: an intermediate when blurred (the `?intermediate=r16float` variant of this file
// writes it at half precision; crates/graph/src/shader.rs, "Variants"), else the output.
alias IntermediateStorage = texture_storage_2d<r32float, write>;
@group(0) @binding(8) var ao: IntermediateStorage;

const TAU: f32 = 6.283185307179586;

// One direction's march state, carried from level to level.
struct March {
    // Receiver: view-space position, normal, pixel centre, 1 / full size.
    o: vec3<f32>,
    n: vec3<f32>,
    pc: vec2<f32>,
    inv_size: vec2<f32>,
    dir: vec2<f32>,
    // Distance marched (full-res pixels), step, level scale K^l, best W * sin (Eq. 8).
    t: f32,
    step: f32,
    scale: f32,
    a_max: f32,
    eps: f32,
    pixel_world: f32,
    done: bool,
}

// step_count reads on one pyramid level. The level's texture is a parameter (not a switch in
// the loop), so each call site reads exactly one texture: on SIMD CPUs such as lavapipe a
// switch over textures executes every case.
fn march_level(tex: texture_2d<f32>, l: u32, m: ptr<function, March>, edges: ptr<function, PyramidEdges>, full: vec2<i32>) {
    for (var i = 0u; i < params.step_count; i = i + 1u) {
        (*m).t = (*m).t + (*m).step;
        let q = (*m).pc + (*m).dir * (*m).t;
        if (any(q < vec2<f32>(0.0)) || any(q >= vec2<f32>(full))) { (*m).done = true; return; }
        if (ray_distance((*m).o, q * (*m).inv_size) >= params.radius + (*m).scale * (*m).pixel_world) { (*m).done = true; return; }
        let tx = min(vec2<i32>(floor(q / (*m).scale)), (*edges).last[l]);
        let zs = textureLoad(tex, tx, 0).r;
        if (!(zs > 0.0)) { continue; }
        let c = pyramid_texel_centre(edges, tx, l, (*m).scale);
        let v = view_position(c * (*m).inv_size, zs, view) - (*m).o;
        let r = length(v);
        if (r < (*m).eps) { continue; }
        // Eq. 8: the max over samples of W(r) * sin(alpha), W(r) = max(0, 1 - r/R); sin(alpha)
        // less the g-buffer normals' rounding (common/horizon.wgsl).
        let w = max(0.0, 1.0 - r / params.radius);
        (*m).a_max = max((*m).a_max, w * max(0.0, sin_elevation((*m).n, v, r) - params.sin_bias));
    }
    // Next level: the step and the texel footprint both grow by K.
    (*m).step = (*m).step * params.factor;
    (*m).scale = (*m).scale * params.factor;
}

fn ray_distance(o: vec3<f32>, uv: vec2<f32>) -> f32 {
    let r = view_position(uv, 1.0, view);
    if (view.near_far.w > 0.5) {
        return length(r.xy - o.xy);
    }
    return length(cross(o, r)) / max(length(r), 1e-30);
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
    let n = nw.xyz / nl;
    let inv_size = 1.0 / vec2<f32>(full);
    let pc = vec2<f32>(p) + 0.5;
    let o = view_position(pc * inv_size, z, view);
    // Spec §6.3: |V| below eps is P aliased onto itself; skip it.
    let eps = 1e-4 * z;
    // World size of one full-resolution pixel at P, for the early-out slack.
    let pixel_world = 1.0 / max(pixels_per_unit(z, view), 1e-30);
    let levels = clamp(params.levels, 1u, 5u);
    let k = params.factor;
    var edges = pyramid_edges(full, i32(k), levels);

    // Spec §2.5: per-pixel rotation from a low-discrepancy dither (R2 sequence over pixels,
    // a blue-noise-like pattern) instead of a 32x32 blue-noise texture; per-direction jitter
    // u_d and start-step multiplier xi_d from a hash tiled every 32 pixels.
    let rotation = fract(0.7548776662 * f32(p.x) + 0.5698402910 * f32(p.y));
    let tile = vec2<u32>(p) % vec2<u32>(32u);
    let dirs = max(params.directions, 1u);
    var occlusion = 0.0;
    for (var d = 0u; d < dirs; d = d + 1u) {
        // theta_d = 2 pi (rotation + (d + u_d) / D): random, stratified directions (§2.5).
        let u = hash_pixel(tile, 2u * d);
        let theta = TAU * (rotation + (f32(d) + u) / f32(dirs));
        let dir = vec2<f32>(cos(theta), sin(theta));
        // xi_d in [0.5, 1.5): the random start-step multiplier of §2.5.
        var m: March;
        m.o = o;
        m.n = n;
        m.pc = pc;
        m.inv_size = inv_size;
        m.dir = dir;
        m.t = 0.0;
        m.step = params.initial_step * (0.5 + hash_pixel(tile, 2u * d + 1u));
        m.scale = 1.0;
        m.a_max = 0.0;
        m.eps = eps;
        m.pixel_world = pixel_world;
        m.done = false;
        march_level(depth, 0u, &m, &edges, full);
        if (levels > 1u && !m.done) { march_level(depth1, 1u, &m, &edges, full); }
        if (levels > 2u && !m.done) { march_level(depth2, 2u, &m, &edges, full); }
        if (levels > 3u && !m.done) { march_level(depth3, 3u, &m, &edges, full); }
        if (levels > 4u && !m.done) { march_level(depth4, 4u, &m, &edges, full); }
        let a_max = m.a_max;
        occlusion = occlusion + a_max;
    }
    // Step 3 (§2.3): AO(P) = 1 - (1/D) sum_d A(theta_d).
    store(p, clamp(1.0 - occlusion / f32(dirs), 0.0, 1.0));
}
