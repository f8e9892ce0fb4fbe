//! The reference cache's key: a 128-bit FNV-1a hash of everything a cached image depends on
//! and nothing else (the surfaces, the triangles, R, rays and mode, and the code that traced
//! it: the CPU integrator's source, or the GPU tracers' Rust and WGSL as compiled in).
//!
//! Invariant: a changed input changes the key (up to hash collisions); the progress setting,
//! which changes no value, is not hashed.

use aograph_scene::environment::SkyEnvironment;
use aograph_scene::reference::{ReferenceParams, SurfaceBuffer};
use glam::Vec3;
use std::fmt;

/// The code whose output the cache stores: any edit to it changes every key. (The obvhs
/// version is pinned by Cargo.lock; the BVH's own tests and the brute-force comparison check
/// that it changes no result.)
const TRACER_SOURCES: [&str; 3] = aograph_scene::reference::INTEGRATOR_SOURCES;

/// The radiance estimator's code (with the tracer's, [`TRACER_SOURCES`]).
const RADIANCE_SOURCES: [&str; 2] = [
    include_str!("radiance.rs"),
    aograph_scene::environment::SKY_SOURCE,
];

/// 128-bit FNV-1a hasher over explicit byte sequences (stable across platforms and Rust
/// versions, unlike `std::hash`).
#[derive(Clone, Copy, Debug)]
struct Fnv1a128(u128);

impl Fnv1a128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;

    fn new() -> Self {
        Fnv1a128(Self::OFFSET)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u128::from(b);
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }

    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }

    fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }

    fn vec3(&mut self, v: Vec3) {
        self.f32(v.x);
        self.f32(v.y);
        self.f32(v.z);
    }
}

/// Identifies one reference result; shown as 32 hex digits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey(pub u128);

impl fmt::Display for CacheKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:032x}", self.0)
    }
}

impl CacheKey {
    /// The key of the reference traced from `surfaces` against `triangles` with `params`.
    pub fn new(
        triangles: &[[Vec3; 3]],
        surfaces: &SurfaceBuffer,
        params: &ReferenceParams,
    ) -> CacheKey {
        let mut h = Fnv1a128::new();
        for source in TRACER_SOURCES {
            h.u32(source.len() as u32);
            h.bytes(source.as_bytes());
        }
        h.u32(triangles.len() as u32);
        for tri in triangles {
            tri.iter().for_each(|v| h.vec3(*v));
        }
        h.u32(surfaces.width);
        h.u32(surfaces.height);
        for list in [&surfaces.points, &surfaces.normals] {
            h.u32(list.len() as u32);
            list.iter().for_each(|v| h.vec3(*v));
        }
        h.u32(surfaces.valid.len() as u32);
        surfaces.valid.iter().for_each(|v| h.bytes(&[u8::from(*v)]));
        h.f32(params.radius);
        h.u32(params.rays_per_pixel);
        h.u32(params.mode as u32);
        CacheKey(h.0)
    }
}

impl CacheKey {
    /// The key of the same reference traced by the GPU tracer: [`CacheKey::new`]'s, the
    /// tracer's name and its shaders' sources (a CPU-traced entry is never taken for a GPU one,
    /// nor one from older shaders).
    pub fn gpu_traced(self) -> CacheKey {
        self.traced_by(b"gpu", &gpu_tracer_sources())
    }

    /// The key of the same reference traced by the GPU tracer's hardware backend (its own
    /// name and shaders: its results agree with the others statistically, not bit for bit).
    pub fn hardware_traced(self) -> CacheKey {
        self.traced_by(b"hardware", &hardware_tracer_sources())
    }

    fn traced_by(self, tracer: &[u8], sources: &[&str]) -> CacheKey {
        let mut h = Fnv1a128::new();
        h.bytes(&self.0.to_le_bytes());
        h.bytes(tracer);
        for source in sources {
            h.u32(source.len() as u32);
            h.bytes(source.as_bytes());
        }
        CacheKey(h.0)
    }
}

/// The GPU tracer's shaders, and the Rust that builds the scene it traces and runs it (a
/// change to how the BVH is built changes its images as surely as a shader edit), hashed into
/// its keys.
/// The WGSL file at `path` (relative to shaders/), as the shader crate embeds it.
fn wgsl(path: &str) -> &'static str {
    let top = path.split('/').next().unwrap_or_default();
    aograph_shaders::folder(top)
        .and_then(|files| files.iter().find(|(p, _)| *p == path))
        .map(|(_, source)| *source)
        .expect("the tracer's shaders are embedded (aograph-shaders' tables)")
}

pub(crate) fn gpu_tracer_sources() -> Vec<&'static str> {
    vec![
        include_str!("gpu/scene_bvh.rs"),
        include_str!("gpu/flat_bvh.rs"),
        include_str!("gpu/gpu_bvh.rs"),
        include_str!("gpu/gpu_reference.rs"),
        include_str!("gpu/trace_scene.rs"),
        wgsl("common/bvh.wgsl"),
        wgsl("common/scene_hit.wgsl"),
        wgsl("common/scene_trace.wgsl"),
        wgsl("common/ao_ray_dirs.wgsl"),
        wgsl("common/ao_rays.wgsl"),
        wgsl("raytrace/reference.wgsl"),
    ]
}

/// The hardware backend's shaders and the Rust that builds its acceleration structures and runs
/// it, hashed into its keys.
pub(crate) fn hardware_tracer_sources() -> Vec<&'static str> {
    vec![
        include_str!("gpu/hardware.rs"),
        // Its bottom levels take their triangles from `traceable_mesh_triangles` there.
        include_str!("gpu/scene_bvh.rs"),
        include_str!("gpu/gpu_reference.rs"),
        include_str!("gpu/trace_scene.rs"),
        wgsl("common/hardware_scene.wgsl"),
        wgsl("common/scene_hit.wgsl"),
        wgsl("common/scene_trace_hardware.wgsl"),
        wgsl("common/ao_ray_dirs.wgsl"),
        wgsl("common/ao_rays.wgsl"),
        wgsl("raytrace/reference.wgsl"),
    ]
}

/// A directory of cached reference images.
impl CacheKey {
    /// The key of a radiance reference: everything [`CacheKey::new`] covers, plus the
    /// radiance code, the sky, and every triangle's and pixel's albedo.
    pub fn radiance(
        triangles: &[[Vec3; 3]],
        surfaces: &SurfaceBuffer,
        params: &ReferenceParams,
        triangle_albedo: &[Vec3],
        pixel_albedo: &[Vec3],
        sky: &SkyEnvironment,
    ) -> CacheKey {
        let mut h = Fnv1a128(CacheKey::new(triangles, surfaces, params).0);
        h.bytes(b"radiance");
        for source in RADIANCE_SOURCES {
            h.u32(source.len() as u32);
            h.bytes(source.as_bytes());
        }
        for list in [triangle_albedo, pixel_albedo] {
            h.u32(list.len() as u32);
            list.iter().for_each(|v| h.vec3(*v));
        }
        for v in [
            sky.zenith,
            sky.horizon,
            sky.ground,
            sky.sun_direction,
            sky.sun_irradiance,
        ] {
            h.vec3(v);
        }
        h.f32(sky.sun_exponent);
        CacheKey(h.0)
    }
}
