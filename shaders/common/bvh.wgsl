// Ray traversal of the scene's two-level BVH (crates/tracing/src/gpu: layout and build).
// The including pass binds the three buffers by these names (graph inputs scene_bvh.*).
//   nodes: TLAS at [0, tlas_len), then every BLAS; inner node: children at first, first + 1;
//          leaf: count primitives from first (TLAS: instance records, BLAS: triangles).
//   instances: world-to-object rows and the BLAS root of each placed instance.
//   triangles: world- or object-space vertices in leaf order.
// Traversal: fixed stacks (TLAS_STACK, BLAS_STACK; the build rejects deeper trees), children
// tested before descending, the nearer entered first and the farther pushed; a popped node is
// re-tested against the shrunken t_max. `any_hit` returns at the first hit (visibility rays).
// The triangle test is obvhs 0.3's Moller-Trumbore (the CPU reference's): e1 = v0 - v1,
// e2 = v2 - v0, n = e1 x e2, c = v0 - o, r = d x c, u = (r.e2)/det, v = (r.e1)/det,
// w = 1 - u - v, a hit when det != 0 and none of u, v, w has its sign bit set, t = (n.c)/det
// in [t_min, t_max]. Rays into an instance are transformed, not renormalised, so t stays in
// world units.

struct BvhNode {
    min: vec3<f32>,
    first: u32,
    max: vec3<f32>,
    count: u32,
}

struct BvhInstance {
    row0: vec4<f32>,
    row1: vec4<f32>,
    row2: vec4<f32>,
    blas_root: u32,
    instance: u32,
    // 1 when the instance moves (animated or skinned).
    moving: u32,
    pad1: u32,
}

struct BvhTriangle {
    v0: vec3<f32>,
    primitive: u32,
    v1: vec3<f32>,
    pad0: u32,
    v2: vec3<f32>,
    pad1: u32,
}

@group(0) @binding(12) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(13) var<storage, read> bvh_instances: array<BvhInstance>;
@group(0) @binding(14) var<storage, read> bvh_triangles: array<BvhTriangle>;

const TLAS_STACK: u32 = 64u;
const BLAS_STACK: u32 = 64u;
// No hit (t of a miss).
const BVH_MISS: f32 = 3.0e38;

struct BvhHit {
    // Distance along the world direction; BVH_MISS when nothing was hit.
    t: f32,
    // Placed-instance record and triangle (index into bvh_triangles) of the hit;
    // triangle = BVH_MISS_INDEX on a miss.
    instance: u32,
    triangle: u32,
}

// obvhs's triangle test; BVH_MISS when missed.
fn bvh_triangle_t(tri: BvhTriangle, o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    let e1 = tri.v0 - tri.v1;
    let e2 = tri.v2 - tri.v0;
    let n = cross(e1, e2);
    let c = tri.v0 - o;
    let r = cross(d, c);
    let det = dot(n, d);
    if (det == 0.0) {
        return BVH_MISS;
    }
    let inv_det = 1.0 / det;
    let u = dot(r, e2) * inv_det;
    let v = dot(r, e1) * inv_det;
    let w = 1.0 - u - v;
    let signs = (bitcast<u32>(u) | bitcast<u32>(v) | bitcast<u32>(w)) & 0x80000000u;
    if (signs != 0u) {
        return BVH_MISS;
    }
    let t = dot(n, c) * inv_det;
    if (t >= t_min && t <= t_max) {
        return t;
    }
    return BVH_MISS;
}

// Entry distance of the ray into the node's box within [t_min, t_max], BVH_MISS when it
// misses. The exit is widened by 2 gamma_3 (PBRT's conservative slab test) so rounding never
// culls a box whose triangle the ray hits.
fn bvh_box_entry(node: BvhNode, o: vec3<f32>, inv_d: vec3<f32>, t_min: f32, t_max: f32) -> f32 {
    let t0 = (node.min - o) * inv_d;
    let t1 = (node.max - o) * inv_d;
    let near = min(t0, t1);
    let far = max(t0, t1);
    let enter = max(max(near.x, near.y), max(near.z, t_min));
    let exit = min(min(far.x, far.y), min(far.z, t_max)) * 1.0000004;
    if (enter <= exit && node.min.x <= node.max.x) {
        return enter;
    }
    return BVH_MISS;
}

// 1/d with zero (and tiny) components replaced by a huge value of the same sign, so the slab
// test never computes 0 * inf.
fn bvh_safe_inverse(d: vec3<f32>) -> vec3<f32> {
    let tiny = abs(d) < vec3<f32>(1e-20);
    let s = select(vec3<f32>(1.0), vec3<f32>(-1.0), d < vec3<f32>(0.0));
    return 1.0 / select(d, s * 1e-20, tiny);
}

// Both levels' traversal stack (TLAS_STACK = BLAS_STACK).
alias BvhStack = array<u32, BLAS_STACK>;

// At inner node with children `l`, `l + 1`: the child to enter next (the nearer one the ray
// reaches within t_max), pushing the farther when both are reached; BVH_MISS_INDEX if none.
fn bvh_descend(l: u32, o: vec3<f32>, inv_d: vec3<f32>, t_min: f32, t_max: f32,
               stack: ptr<function, BvhStack>, sp: ptr<function, u32>) -> u32 {
    let tl = bvh_box_entry(bvh_nodes[l], o, inv_d, t_min, t_max);
    let tr = bvh_box_entry(bvh_nodes[l + 1u], o, inv_d, t_min, t_max);
    if (tl != BVH_MISS && tr != BVH_MISS) {
        let near_left = tl <= tr;
        (*stack)[*sp] = select(l, l + 1u, near_left);
        *sp += 1u;
        return select(l + 1u, l, near_left);
    } else if (tl != BVH_MISS) {
        return l;
    } else if (tr != BVH_MISS) {
        return l + 1u;
    }
    return BVH_MISS_INDEX;
}

// `next`, or when it is BVH_MISS_INDEX the first popped node still within reach (t_max may
// have shrunk since it was pushed); BVH_MISS_INDEX when the stack runs out.
fn bvh_pop(next: u32, o: vec3<f32>, inv_d: vec3<f32>, t_min: f32, t_max: f32,
           stack: ptr<function, BvhStack>, sp: ptr<function, u32>) -> u32 {
    var n = next;
    while (n == BVH_MISS_INDEX && *sp > 0u) {
        *sp -= 1u;
        let candidate = (*stack)[*sp];
        if (bvh_box_entry(bvh_nodes[candidate], o, inv_d, t_min, t_max) != BVH_MISS) {
            n = candidate;
        }
    }
    return n;
}

// Traverses one BLAS from `root` with an object-space ray; updates `hit` (closest so far) and
// returns true when `any_hit` found a hit.
fn bvh_traverse_blas(root: u32, o: vec3<f32>, d: vec3<f32>, t_min: f32, any_hit: bool,
                     instance: u32, hit: ptr<function, BvhHit>) -> bool {
    let inv_d = bvh_safe_inverse(d);
    var stack: BvhStack;
    var sp = 0u;
    if (bvh_box_entry(bvh_nodes[root], o, inv_d, t_min, (*hit).t) == BVH_MISS) {
        return false;
    }
    var index = root;
    loop {
        let node = bvh_nodes[index];
        var next = BVH_MISS_INDEX;
        if (node.count > 0u) {
            for (var k = node.first; k < node.first + node.count; k++) {
                let t = bvh_triangle_t(bvh_triangles[k], o, d, t_min, (*hit).t);
                if (t != BVH_MISS) {
                    (*hit).t = t;
                    (*hit).instance = instance;
                    (*hit).triangle = k;
                    if (any_hit) {
                        return true;
                    }
                }
            }
        } else {
            next = bvh_descend(node.first, o, inv_d, t_min, (*hit).t, &stack, &sp);
        }
        next = bvh_pop(next, o, inv_d, t_min, (*hit).t, &stack, &sp);
        if (next == BVH_MISS_INDEX) {
            return false;
        }
        index = next;
    }
    return false;
}

const BVH_MISS_INDEX: u32 = 0xffffffffu;

// The world-space ray `o + t d`, t in [t_min, t_max], against the whole scene: the closest hit
// (or, with `any_hit`, the first found).
// As the CPU tracer (reference/bvh.rs `TriangleBvh::ray`), the ray starts `lead` behind its
// origin and t is shifted by it: a surface through the origin itself (a point on a crease,
// offset along one face's normal, lies on the other face's plane) is then a crossing at
// t = lead that both tracers round alike (hit or not by the last bit, half the time each),
// instead of a t = 0 tie the GPU would always count and the CPU only half the time.
fn bvh_trace(o_in: vec3<f32>, d: vec3<f32>, t_min_in: f32, t_max_in: f32, any_hit: bool) -> BvhHit {
    let a = abs(o_in);
    let lead = 2e-4 + 1e-6 * max(a.x, max(a.y, a.z)) + max(-t_min_in, 0.0);
    let o = o_in - d * lead;
    let t_min = t_min_in + lead;
    let t_max = t_max_in + lead;
    var result = bvh_trace_from(o, d, t_min, t_max, any_hit);
    if (result.triangle != BVH_MISS_INDEX) {
        result.t -= lead;
    }
    return result;
}

fn bvh_trace_from(o: vec3<f32>, d: vec3<f32>, t_min: f32, t_max: f32, any_hit: bool) -> BvhHit {
    // t_max bounds the search; `triangle` stays BVH_MISS_INDEX until something is hit.
    var hit = BvhHit(min(t_max, BVH_MISS), 0u, BVH_MISS_INDEX);
    let inv_d = bvh_safe_inverse(d);
    var stack: BvhStack;
    var sp = 0u;
    if (bvh_box_entry(bvh_nodes[0], o, inv_d, t_min, hit.t) == BVH_MISS) {
        return BvhHit(BVH_MISS, 0u, BVH_MISS_INDEX);
    }
    var index = 0u;
    loop {
        let node = bvh_nodes[index];
        var next = BVH_MISS_INDEX;
        if (node.count > 0u) {
            for (var k = node.first; k < node.first + node.count; k++) {
                let inst = bvh_instances[k];
                let m = mat3x4<f32>(inst.row0, inst.row1, inst.row2);
                let lo = vec4<f32>(o, 1.0) * m;
                let ld = vec4<f32>(d, 0.0) * m;
                if (bvh_traverse_blas(inst.blas_root, lo, ld, t_min, any_hit, k, &hit)) {
                    return hit;
                }
            }
        } else {
            next = bvh_descend(node.first, o, inv_d, t_min, hit.t, &stack, &sp);
        }
        next = bvh_pop(next, o, inv_d, t_min, hit.t, &stack, &sp);
        if (next == BVH_MISS_INDEX) {
            break;
        }
        index = next;
    }
    if (hit.triangle == BVH_MISS_INDEX) {
        return BvhHit(BVH_MISS, 0u, BVH_MISS_INDEX);
    }
    return hit;
}
