//! The geometry probe behind the view heuristics: the scene's triangles in a BVH, traced
//! from a point over a spread of directions to tell how enclosed it is and how much room it
//! has. Invariant: it traces the scene at t = 0, as the heuristics place views at t = 0.

use std::f32::consts::PI;

use glam::Vec3;

use super::ENCLOSED_FRACTION;
use crate::camera::Camera;
use crate::model::Scene;
use crate::reference::SceneRays;

/// 64 directions spread evenly over the sphere (a Fibonacci lattice).
pub(super) fn sphere_directions(n: usize) -> Vec<Vec3> {
    let golden = PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect()
}

/// What a point sees: the share of directions hitting geometry, the share of those hits on
/// back faces, and the nearest hit (clearance).
pub(super) struct Surroundings {
    pub(super) hit_fraction: f32,
    pub(super) back_fraction: f32,
    pub(super) clearance: f32,
}

/// Geometry the view heuristics trace against: the scene at t = 0 as a two-level BVH
/// ([`SceneRays`]: shared meshes are not flattened), and how far a probe ray reaches.
pub(super) struct Tracer {
    pub(super) rays: SceneRays,
    pub(super) reach: f32,
}

impl Tracer {
    pub(super) fn new(scene: &Scene) -> Tracer {
        let whole = scene.bounds();
        let reach = if whole.is_empty() {
            1.0
        } else {
            (2.0 * whole.diagonal()).min(1e7)
        };
        Tracer {
            rays: SceneRays::new(scene, 0.0),
            reach,
        }
    }

    /// Triangle `triangle`'s outward normal: the mean vertex normal (carried by the inverse
    /// transpose, so mirrored nodes keep it outward); the winding's normal where the mesh has
    /// none.
    fn outward(&self, triangle: usize) -> Option<Vec3> {
        let [a, b, c] = self.rays.triangle(triangle)?;
        let n = self.rays.vertex_normals(triangle);
        Some(
            (n[0] + n[1] + n[2])
                .try_normalize()
                .unwrap_or_else(|| (b - a).cross(c - a).normalize_or_zero()),
        )
    }

    /// The mean reference accessibility a coarse trace (32 x 24 pixels, 16 rays each) of
    /// `camera`'s view shows at `radius`: 1 when it sees no geometry.
    pub(super) fn mean_accessibility(&self, camera: &Camera, radius: f32) -> f32 {
        let g = crate::reference::CpuGBuffer::trace_rays(&self.rays, camera, 32, 24);
        let surfaces = g.surfaces(crate::reference::ReferenceNormals::Geometric);
        let params = crate::reference::ReferenceParams {
            radius,
            rays_per_pixel: 16,
            progress: crate::reference::ProgressMode::Never,
            ..Default::default()
        };
        let Ok(image) = crate::reference::trace_reference(&self.rays, &surfaces, &params) else {
            return 1.0;
        };
        let (sum, n) = image
            .accessibility
            .iter()
            .zip(&surfaces.valid)
            .filter(|(_, v)| **v)
            .fold((0.0f32, 0usize), |(s, n), (a, _)| (s + a, n + 1));
        if n == 0 { 1.0 } else { sum / n as f32 }
    }

    pub(super) fn surroundings(&self, p: Vec3, directions: &[Vec3]) -> Surroundings {
        let (mut hits, mut back, mut clearance) = (0usize, 0usize, f32::INFINITY);
        for &d in directions {
            if let Some(hit) = self.rays.closest_hit(p, d, 0.0, self.reach) {
                hits += 1;
                clearance = clearance.min(hit.distance);
                if self.outward(hit.triangle).is_some_and(|n| n.dot(d) > 0.0) {
                    back += 1;
                }
            }
        }
        Surroundings {
            hit_fraction: hits as f32 / directions.len().max(1) as f32,
            back_fraction: back as f32 / hits.max(1) as f32,
            clearance,
        }
    }

    pub(super) fn enclosed(&self, s: &Surroundings) -> bool {
        s.hit_fraction >= ENCLOSED_FRACTION && s.back_fraction <= 0.25
    }

    /// The first hit distance from `p` along `d`, or the tracer's reach.
    pub(super) fn free_distance(&self, p: Vec3, d: Vec3) -> f32 {
        self.rays
            .closest_hit(p, d, 0.0, self.reach)
            .map_or(self.reach, |h| h.distance)
    }
}
