//! The CPU g-buffer: one primary ray per pixel centre through the BVH, giving each pixel's
//! world-space point, geometric normal and interpolated (shading) normal. It is the independent
//! check of the GPU g-buffer (`tests/gbuffer_matches_cpu.rs` compares the two on every scene)
//! and the surfaces the reference can start from without a GPU.
//!
//! Invariants: pixel (x, y) is row-major with the top row first and its ray goes through the
//! pixel centre (NDC x = (x + 0.5) / w * 2 - 1, y = 1 - (y + 0.5) / h * 2, wgpu conventions);
//! only hits between the near and far planes count (as the rasteriser clips). The rules are the
//! GPU g-buffer's (`shaders/scene/gbuffer.wgsl`), so the two can be compared pixel by pixel:
//! - the geometric normal is the hit triangle's plane normal turned to face the camera;
//! - the shading normal interpolates the triangle's world-space vertex normals (each carried by
//!   the inverse transpose, [`crate::normal_transform`], and normalised, as the vertex shader
//!   does) with the hit's barycentrics, is renormalised and turned to the side of the geometric
//!   normal (pbrt's FaceForward); where the vertex normals interpolate to zero (a mesh without
//!   normals) it is the geometric normal.
//!
//! Misses are invalid (sky) with zero point and normals and triangle `u32::MAX`.

use super::bvh::{RayQueries, TriangleBvh};
use super::scene_rays::SceneRays;
use super::{ReferenceNormals, SurfaceBuffer};
use crate::camera::Camera;
use crate::model::Scene;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Per-pixel primary hits of one view, row-major, top row first.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct CpuGBuffer {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// World-space hit points (zero on sky).
    pub points: Vec<Vec3>,
    /// The hit triangle's unit plane normal, facing the camera.
    pub geometric_normals: Vec<Vec3>,
    /// Interpolated unit vertex normals on the camera's side of the geometric normal.
    pub shading_normals: Vec<Vec3>,
    /// Index of the hit triangle in [`Scene::world_triangles`] order (`u32::MAX` on sky).
    pub triangles: Vec<u32>,
    /// Distance from the camera's eye (perspective) or image plane (orthographic) to the hit.
    pub distances: Vec<f32>,
    /// `true` where the pixel's ray hit geometry between the near and far planes; `false`
    /// is sky.
    pub valid: Vec<bool>,
}

/// One pixel's hit.
#[derive(Clone, Copy)]
struct PixelHit {
    point: Vec3,
    geometric: Vec3,
    shading: Vec3,
    triangle: u32,
    distance: f32,
}

impl CpuGBuffer {
    /// Traces the CPU g-buffer of `scene` at time `t` seen by `camera` at `width` x `height`.
    pub fn trace(scene: &Scene, camera: &Camera, width: u32, height: u32, t: f32) -> CpuGBuffer {
        Self::trace_rays(&SceneRays::new(scene, t), camera, width, height)
    }

    /// Like [`CpuGBuffer::trace`] with the scene already posed in a [`SceneRays`].
    pub fn trace_rays(rays: &SceneRays, camera: &Camera, width: u32, height: u32) -> CpuGBuffer {
        let lookup = |i: usize| Some((rays.triangle(i)?, rays.vertex_normals(i)));
        Self::trace_hits(rays, &lookup, camera, width, height, Vec2::ZERO)
    }

    /// Like [`CpuGBuffer::trace`] with a prebuilt BVH over `triangles` and their per-vertex
    /// world normals `vertex_normals` (same order; zeros where there are none), each ray
    /// moved `offset` pixels (x right, y down) from its pixel centre: a tool for finding the
    /// pixels whose centre lies within the rasteriser's sub-pixel precision of an edge.
    pub fn trace_with_bvh(
        bvh: &TriangleBvh,
        triangles: &[[Vec3; 3]],
        vertex_normals: &[[Vec3; 3]],
        camera: &Camera,
        width: u32,
        height: u32,
        offset: Vec2,
    ) -> CpuGBuffer {
        let lookup = |i: usize| {
            let normals = vertex_normals.get(i).copied().unwrap_or_default();
            Some((*triangles.get(i)?, normals))
        };
        Self::trace_hits(bvh, &lookup, camera, width, height, offset)
    }

    /// The g-buffer of the rays `rays` answers, `lookup` giving a hit triangle's world corners
    /// and vertex normals.
    fn trace_hits(
        rays: &(impl RayQueries + ?Sized),
        lookup: &(impl Fn(usize) -> Option<([Vec3; 3], [Vec3; 3])> + Sync),
        camera: &Camera,
        width: u32,
        height: u32,
        offset: Vec2,
    ) -> CpuGBuffer {
        let aspect = width as f32 / height.max(1) as f32;
        let w = width as usize;
        let pixels: Vec<Option<PixelHit>> = (0..w * height as usize)
            .into_par_iter()
            .map(|i| {
                let ndc = Vec2::new(
                    ((i % w) as f32 + 0.5 + offset.x) / width as f32 * 2.0 - 1.0,
                    1.0 - ((i / w) as f32 + 0.5 + offset.y) / height as f32 * 2.0,
                );
                let ray = camera.primary_ray(ndc, aspect);
                let hit = rays.closest_hit(ray.origin, ray.direction, ray.t_min, ray.t_max)?;
                let (triangle, normals) = lookup(hit.triangle)?;
                let point = ray.origin + ray.direction * hit.distance;
                let (geometric, shading) =
                    surface_normals(triangle, normals, point, ray.direction)?;
                Some(PixelHit {
                    point,
                    geometric,
                    shading,
                    triangle: hit.triangle as u32,
                    distance: hit.distance,
                })
            })
            .collect();
        let mut out = CpuGBuffer {
            width,
            height,
            ..Default::default()
        };
        for hit in pixels {
            let hit = hit.unwrap_or(PixelHit {
                point: Vec3::ZERO,
                geometric: Vec3::ZERO,
                shading: Vec3::ZERO,
                triangle: u32::MAX,
                distance: 0.0,
            });
            out.points.push(hit.point);
            out.geometric_normals.push(hit.geometric);
            out.shading_normals.push(hit.shading);
            out.triangles.push(hit.triangle);
            out.distances.push(hit.distance);
            out.valid.push(hit.triangle != u32::MAX);
        }
        out
    }

    /// The points and the chosen normals, as the reference takes them.
    pub fn surfaces(&self, normals: ReferenceNormals) -> SurfaceBuffer {
        SurfaceBuffer {
            width: self.width,
            height: self.height,
            points: self.points.clone(),
            normals: match normals {
                ReferenceNormals::Geometric => self.geometric_normals.clone(),
                ReferenceNormals::Shading => self.shading_normals.clone(),
            },
            valid: self.valid.clone(),
        }
    }
}

/// The geometric and shading normals at `point` on `triangle` (with per-vertex world
/// normals `vertex_normals`, zeros where there are none) seen along `view_direction`, by the
/// g-buffer's rules (see the module docs); `None` for a zero-area triangle.
pub fn surface_normals(
    triangle: [Vec3; 3],
    vertex_normals: [Vec3; 3],
    point: Vec3,
    view_direction: Vec3,
) -> Option<(Vec3, Vec3)> {
    let [a, b, c] = triangle;
    let plane = (b - a).cross(c - a).try_normalize()?;
    let geometric = if plane.dot(view_direction) > 0.0 {
        -plane
    } else {
        plane
    };
    let shading = interpolate_normal(vertex_normals, barycentrics(triangle, point))
        .map_or(geometric, |s| if s.dot(geometric) < 0.0 { -s } else { s });
    Some((geometric, shading))
}

/// Barycentric coordinates of `p` (on or near the plane of `tri`) in `tri`.
fn barycentrics([a, b, c]: [Vec3; 3], p: Vec3) -> Vec3 {
    // Sub-triangle areas along the triangle's normal (Ericson, Real-Time Collision Detection
    // 3.4): exact for points in the plane, a projection onto it otherwise.
    let n = (b - a).cross(c - a);
    let area = n.length_squared();
    if area.is_nan() || area <= 0.0 {
        return Vec3::new(1.0, 0.0, 0.0);
    }
    let u = (c - b).cross(p - b).dot(n) / area;
    let v = (a - c).cross(p - c).dot(n) / area;
    Vec3::new(u, v, 1.0 - u - v)
}

/// The renormalised barycentric blend of three vertex normals, or `None` when it is (nearly)
/// zero, the GPU's test (`length(s) > 1e-20`).
fn interpolate_normal(normals: [Vec3; 3], weights: Vec3) -> Option<Vec3> {
    let s = normals[0] * weights.x + normals[1] * weights.y + normals[2] * weights.z;
    (s.length() > 1e-20)
        .then(|| s.normalize())
        .filter(|s| s.is_finite())
}

/// Casts one ray per pixel centre of a `width` x `height` image from `camera` into the scene
/// at time `t`: the points and geometric normals of the CPU g-buffer (see [`CpuGBuffer`]).
pub fn primary_hits(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
    t: f32,
) -> SurfaceBuffer {
    CpuGBuffer::trace(scene, camera, width, height, t).surfaces(ReferenceNormals::Geometric)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Mesh;
    use crate::scene_builder::SceneBuilder;
    use glam::Mat4;

    /// One triangle in the plane z = 0 whose vertex normals lean apart, seen from +Z.
    fn leaning_triangle(transform: Mat4) -> Scene {
        let mut b = SceneBuilder::new();
        let m = b.material([0.5; 3]);
        let lean = |x: f32, y: f32| Vec3::new(x, y, 1.0).normalize();
        b.add(
            Mesh {
                name: "tri".into(),
                positions: vec![
                    Vec3::new(-1.0, -1.0, 0.0),
                    Vec3::new(1.0, -1.0, 0.0),
                    Vec3::new(0.0, 1.0, 0.0),
                ],
                normals: vec![lean(-0.5, -0.5), lean(0.5, -0.5), lean(0.0, 0.5)],
                indices: vec![0, 1, 2],
                material: m,
                skin_weights: Vec::new(),
            },
            transform,
        );
        b.build(Camera::perspective(
            Vec3::new(0.0, 0.0, 5.0),
            Vec3::ZERO,
            0.8,
            0.1,
            100.0,
        ))
    }

    #[test]
    fn centre_pixel_hits_the_plane_with_both_normals() {
        let scene = leaning_triangle(Mat4::IDENTITY);
        let g = CpuGBuffer::trace(&scene, &scene.camera, 9, 9, 0.0);
        let i = 4 * 9 + 4;
        assert!(g.valid[i]);
        assert!(g.points[i].length() < 1e-5, "{}", g.points[i]);
        assert!((g.distances[i] - 5.0).abs() < 1e-5);
        assert_eq!(g.geometric_normals[i], Vec3::Z);
        // At the origin the barycentrics are (0.25, 0.25, 0.5): the blend of the leaning
        // normals, renormalised.
        let lean = |x: f32, y: f32| Vec3::new(x, y, 1.0).normalize();
        let want =
            (lean(-0.5, -0.5) * 0.25 + lean(0.5, -0.5) * 0.25 + lean(0.0, 0.5) * 0.5).normalize();
        assert!((g.shading_normals[i] - want).length() < 1e-5);
        assert!(!g.valid[0], "the corner pixel misses the triangle");
        assert_eq!(g.triangles[0], u32::MAX);
    }

    #[test]
    fn normals_face_the_camera_from_behind_and_under_mirroring() {
        // Seen from -Z, both normals turn to -Z's side; a mirror in X keeps them there.
        for transform in [
            Mat4::from_rotation_y(std::f32::consts::PI),
            Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))
                * Mat4::from_rotation_y(std::f32::consts::PI),
        ] {
            let scene = leaning_triangle(transform);
            let g = CpuGBuffer::trace(&scene, &scene.camera, 9, 9, 0.0);
            let i = 4 * 9 + 4;
            assert!(
                g.geometric_normals[i].z > 0.999,
                "{}",
                g.geometric_normals[i]
            );
            assert!(g.shading_normals[i].z > 0.9, "{}", g.shading_normals[i]);
        }
    }

    #[test]
    fn mesh_without_normals_shades_with_the_geometric_normal() {
        let mut scene = leaning_triangle(Mat4::IDENTITY);
        scene.meshes[0].normals.clear();
        let g = CpuGBuffer::trace(&scene, &scene.camera, 9, 9, 0.0);
        let i = 4 * 9 + 4;
        assert_eq!(g.shading_normals[i], g.geometric_normals[i]);
    }

    #[test]
    fn barycentrics_reproduce_the_point() {
        let tri = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(2.0, 0.0, 1.0),
            Vec3::new(0.0, 3.0, 1.0),
        ];
        let p = Vec3::new(0.5, 1.0, 1.0);
        let w = barycentrics(tri, p);
        let back = tri[0] * w.x + tri[1] * w.y + tri[2] * w.z;
        assert!((back - p).length() < 1e-6 && (w.x + w.y + w.z - 1.0).abs() < 1e-6);
    }
}
