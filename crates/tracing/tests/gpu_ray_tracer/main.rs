//! The GPU ray tracer against the CPU one (`TriangleBvh` over `Scene::world_triangles`), ray by
//! ray: random triangle soups (instanced under rotations, non-uniform scales and mirrors) and
//! every procedural scene, closest-hit and any-hit. Hit or miss must agree on >= 99.99% of
//! rays and distances within 1e-5 relative. The only expected disagreements are rays grazing a
//! triangle edge within float rounding: the GPU tests an instanced ray in object space, the CPU
//! the transformed triangle in world space, so the two round differently there; every
//! disagreement is printed with its barycentric margin to show it is such a ray.
//! Then: the BVH work per frame (static: none; moving instances: the top level only; a
//! skinned mesh: its refit), the GPU after updates against the CPU at the new time, and the
//! GPU reference against the CPU reference (statistically: within 4 standard errors).
//!
//! Files: `batch.rs` (rays against the CPU on both backends, the structures' work per frame),
//! `reference.rs` (the GPU reference against the CPU's); the soups, rays and comparisons they
//! share are here.

mod batch;
mod reference;

use std::sync::Arc;

use aograph_graph::{GpuContext, ShaderLibrary};
use aograph_scene::{Mesh, Scene, SceneBuilder, TriangleBvh};
use aograph_tracing::gpu::{GpuRayBatch, GpuRayHit, GpuSceneBvh, HitQuery, TraceRay};
use glam::{Mat4, Quat, Vec3};

fn shaders() -> ShaderLibrary {
    aograph_tracing::shader_library().unwrap()
}

/// A small deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vec(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        lo + (hi - lo) * Vec3::new(self.next(), self.next(), self.next())
    }
    fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.vec(Vec3::splat(-1.0), Vec3::ONE);
            if let Some(d) = v.try_normalize().filter(|_| v.length_squared() <= 1.0) {
                return d;
            }
        }
    }
}

fn soup(rng: &mut Rng, triangles: usize, extent: f32, size: f32) -> Mesh {
    let mut positions = Vec::new();
    for _ in 0..triangles {
        let c = rng.vec(Vec3::splat(-extent), Vec3::splat(extent));
        for _ in 0..3 {
            positions.push(c + rng.vec(Vec3::splat(-size), Vec3::splat(size)));
        }
    }
    Mesh {
        name: "soup".into(),
        indices: (0..positions.len() as u32).collect(),
        positions,
        normals: Vec::new(),
        material: 0,
        skin_weights: Vec::new(),
    }
}

/// Rays from random points in `bounds` grown by a fifth of its diagonal on every axis (so no
/// origin lies exactly on a flat scene's plane, where a hit at t = 0 = t_min is a tie either
/// tracer may break), two in three aimed at a point of the box, the others anywhere; t_max infinite for a third, else random within the
/// diagonal; t_min 0 or a little more.
fn random_rays(rng: &mut Rng, lo: Vec3, hi: Vec3, count: usize) -> Vec<TraceRay> {
    let diagonal = (hi - lo).length();
    let pad = Vec3::splat(diagonal * 0.2);
    (0..count)
        .map(|i| {
            let origin = rng.vec(lo - pad, hi + pad);
            // Two rays in three aim at a point of the scene's box, the rest anywhere.
            let direction = if i % 3 == 2 {
                rng.direction()
            } else {
                (rng.vec(lo, hi) - origin)
                    .try_normalize()
                    .unwrap_or(Vec3::Y)
            };
            TraceRay {
                origin: origin.into(),
                t_min: if i % 5 == 0 { 1e-3 * diagonal } else { 0.0 },
                direction: direction.into(),
                t_max: if i % 3 == 0 {
                    f32::INFINITY
                } else {
                    rng.next() * diagonal
                },
            }
        })
        .collect()
}

struct Agreement {
    rays: usize,
    /// Rays the CPU finds a hit for (closest-hit queries).
    hits: usize,
    hit_disagreements: usize,
    distance_disagreements: usize,
}

/// Traces `rays` both ways at scene time `t` and counts disagreements.
fn compare(
    gpu: &Arc<GpuContext>,
    batch: &GpuRayBatch,
    bvh: &GpuSceneBvh,
    scene: &Scene,
    t: f32,
    rays: &[TraceRay],
    label: &str,
) -> Agreement {
    let _ = gpu;
    let trace = |query| batch.trace(bvh, rays, query, 1).unwrap();
    compare_traced(&trace, scene, t, rays, label)
}

/// [`compare`] for any GPU tracer: `trace` answers `rays` for a query.
fn compare_traced(
    trace: &dyn Fn(HitQuery) -> Vec<Option<GpuRayHit>>,
    scene: &Scene,
    t: f32,
    rays: &[TraceRay],
    label: &str,
) -> Agreement {
    let cpu = TriangleBvh::new(&scene.world_triangles(t));
    let closest = trace(HitQuery::Closest);
    let any = trace(HitQuery::Any);
    let mut a = Agreement {
        rays: rays.len() * 2,
        hits: 0,
        hit_disagreements: 0,
        distance_disagreements: 0,
    };
    for (i, r) in rays.iter().enumerate() {
        let (o, d) = (Vec3::from(r.origin), Vec3::from(r.direction));
        let want = cpu.closest_hit(o, d, r.t_min, r.t_max);
        a.hits += want.is_some() as usize;
        match (want, closest[i]) {
            (Some(w), Some(g)) => {
                // Relative 1e-5 of the larger of the distance and the origin's magnitude:
                // float points are known to their coordinates' ulp (6e-8 relative), and both
                // tracers round there, the CPU restarting each ray `lead` behind its origin
                // (reference/bvh.rs), the GPU moving it into object space. A larger
                // difference is a different triangle hit (edge-grazing rays; printed).
                let scale = w.distance.abs().max(o.abs().max_element());
                let rel = (w.distance - g.distance).abs() / scale.max(1e-30);
                if rel > 1e-5 {
                    a.distance_disagreements += 1;
                    eprintln!(
                        "{label}: ray {i} distance cpu {} gpu {} (rel {rel:e})",
                        w.distance, g.distance
                    );
                }
            }
            (None, None) => {}
            (w, g) => {
                a.hit_disagreements += 1;
                eprintln!("{label}: ray {i} {r:?}: cpu {w:?}, gpu {g:?}");
            }
        }
        let want_any = cpu.any_hit(o, d, r.t_min, r.t_max);
        if want_any != any[i].is_some() {
            a.hit_disagreements += 1;
            eprintln!("{label}: ray {i} any-hit cpu {want_any}, gpu {:?}", any[i]);
        }
    }
    a
}

fn assert_agrees(a: &Agreement, label: &str) {
    eprintln!(
        "{label}: {} rays, {} closest hits; {} hit/miss and {} distance disagreements",
        a.rays, a.hits, a.hit_disagreements, a.distance_disagreements
    );
    // The comparison means something only where rays hit things.
    assert!(
        a.hits * 4 >= a.rays / 2,
        "{label}: only {} of {} rays hit",
        a.hits,
        a.rays / 2
    );
    // 99.99% of rays: at most one disagreement in 10 000 (see the module docs for which).
    assert!(
        a.hit_disagreements * 10_000 <= a.rays,
        "{label}: hit/miss differs on {} of {} rays",
        a.hit_disagreements,
        a.rays
    );
    assert!(
        a.distance_disagreements * 10_000 <= a.rays,
        "{label}: distance differs by more than 1e-5 on {} of {} rays",
        a.distance_disagreements,
        a.rays
    );
}

/// Two random triangle soups placed five times: identity, rotation with non-uniform scale, a
/// mirror, a tiny and a large copy.
fn instanced_soups(rng: &mut Rng) -> Scene {
    let mut b = SceneBuilder::new();
    let dense = b.mesh(soup(rng, 3000, 2.0, 0.3));
    let sparse = b.mesh(soup(rng, 400, 5.0, 1.0));
    // Identity, rotation + non-uniform scale, a mirror, a tiny and a large copy.
    b.place(dense, Mat4::IDENTITY);
    b.place(
        dense,
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.0, 0.5, 2.0),
            Quat::from_rotation_y(0.7) * Quat::from_rotation_x(-0.3),
            Vec3::new(4.0, 0.0, -1.0),
        ),
    );
    b.place(
        dense,
        Mat4::from_translation(Vec3::new(-4.0, 1.0, 0.0))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    );
    b.place(sparse, Mat4::from_scale(Vec3::splat(0.01)));
    b.place(
        sparse,
        Mat4::from_translation(Vec3::new(0.0, 8.0, 0.0)) * Mat4::from_scale(Vec3::splat(3.0)),
    );
    b.build(aograph_scene::Camera::perspective(
        Vec3::new(0.0, 2.0, 12.0),
        Vec3::ZERO,
        0.8,
        0.1,
        100.0,
    ))
}

fn gpu_and_batch() -> Option<(Arc<GpuContext>, GpuRayBatch)> {
    let gpu = aograph_graph::test_gpu()?;
    let batch = GpuRayBatch::new(gpu.clone(), &shaders()).unwrap();
    Some((gpu, batch))
}

/// The device and the ray batch, when the device has ray queries (the batch then has its
/// hardware pipeline); without them the hardware tests skip (saying so), unless
/// AOGRAPH_REQUIRE_RAY_QUERY=1 (CI) makes that a failure.
fn hardware_batch() -> Option<(Arc<GpuContext>, GpuRayBatch)> {
    let gpu = aograph_graph::test_gpu()?;
    if !gpu.has_ray_queries() {
        let why = format!(
            "{} ({}) has no ray queries: scripts/ensure-vulkan.sh installs a lavapipe with them",
            gpu.info.name, gpu.info.driver_info
        );
        assert!(
            std::env::var("AOGRAPH_REQUIRE_RAY_QUERY").as_deref() != Ok("1"),
            "AOGRAPH_REQUIRE_RAY_QUERY=1 but {why}"
        );
        eprintln!("skipping the hardware tracer: {why}");
        return None;
    }
    let batch = GpuRayBatch::new(gpu.clone(), &shaders()).unwrap();
    Some((gpu, batch))
}
