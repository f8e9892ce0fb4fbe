//! CPU primary rays: one ray per pixel centre through the camera, giving the world-space
//! points and normals the reference starts from. A stand-in for the GPU g-buffer read-back,
//! used by tests and tools until that exists.
//!
//! Invariants: pixel (x, y) is row-major with the top row first and its ray goes through the
//! pixel centre (NDC x = (x + 0.5) / w * 2 - 1, y = 1 - (y + 0.5) / h * 2, wgpu conventions);
//! only hits between the near and far planes count (as the rasteriser clips); normals are the
//! hit triangle's geometric normal, flipped to face the camera; misses are invalid (sky) with
//! zero point and normal.

use super::SurfaceBuffer;
use super::bvh::TriangleBvh;
use crate::camera::Camera;
use crate::model::Scene;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Casts one ray per pixel centre of a `width` x `height` image from `camera` into the scene
/// at time `t` (builds a BVH; use [`primary_hits_with_bvh`] to share one with the reference).
pub fn primary_hits(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    t: f32,
) -> SurfaceBuffer {
    let triangles = scene.world_triangles(t);
    let bvh = TriangleBvh::new(&triangles);
    primary_hits_with_bvh(&bvh, &triangles, camera, width, height)
}

/// Like [`primary_hits`] with a prebuilt BVH over `triangles`.
pub fn primary_hits_with_bvh(
    bvh: &TriangleBvh,
    triangles: &[[Vec3; 3]],
    camera: &Camera,
    width: u32,
    height: u32,
) -> SurfaceBuffer {
    let aspect = width as f32 / height.max(1) as f32;
    let pixels: Vec<(Vec3, Vec3, bool)> = (0..width as usize * height as usize)
        .into_par_iter()
        .map(|i| {
            let (x, y) = ((i % width as usize) as f32, (i / width as usize) as f32);
            let ndc = Vec2::new(
                (x + 0.5) / width as f32 * 2.0 - 1.0,
                1.0 - (y + 0.5) / height as f32 * 2.0,
            );
            let ray = camera.primary_ray(ndc, aspect);
            let hit = bvh.closest_hit(ray.origin, ray.direction, ray.t_min, ray.t_max);
            let Some(hit) = hit else {
                return (Vec3::ZERO, Vec3::ZERO, false);
            };
            let Some([a, b, c]) = triangles.get(hit.triangle).copied() else {
                return (Vec3::ZERO, Vec3::ZERO, false);
            };
            let Some(normal) = (b - a).cross(c - a).try_normalize() else {
                return (Vec3::ZERO, Vec3::ZERO, false);
            };
            let normal = if normal.dot(ray.direction) > 0.0 {
                -normal
            } else {
                normal
            };
            (ray.origin + ray.direction * hit.distance, normal, true)
        })
        .collect();
    let mut surfaces = SurfaceBuffer {
        width,
        height,
        points: Vec::with_capacity(pixels.len()),
        normals: Vec::with_capacity(pixels.len()),
        valid: Vec::with_capacity(pixels.len()),
    };
    for (point, normal, valid) in pixels {
        surfaces.points.push(point);
        surfaces.normals.push(normal);
        surfaces.valid.push(valid);
    }
    surfaces
}
