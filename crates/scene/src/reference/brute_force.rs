//! A tracer with no acceleration structure: every ray is tested against every triangle. It is
//! the BVH's independent check (`tests/bvh_matches_brute_force.rs`): the same query rays
//! ([`TriangleBvh`]'s lead-shifted rays) and the same ray-triangle test (obvhs's Möller-Trumbore,
//! accepting t in [t_min, t_max) as the BVH traversal does), so on any ray the two must agree
//! exactly, bit for bit, on hit or miss and on the hit distance. Only the traversal, the node
//! boxes and the triangles the BVH leaves out can make them differ, which is what it checks.
//! Cost: O(triangles) per ray; meant for small soups in tests.

use super::bvh::{RayHitRecord, TriangleBvh};
use glam::{Vec3, Vec3A};
use obvhs::triangle::Triangle;

/// Every triangle, in the caller's order.
pub struct BruteForceTracer {
    triangles: Vec<Triangle>,
}

impl BruteForceTracer {
    /// Keeps every triangle of `triangles` (none is filtered out).
    pub fn new(triangles: &[[Vec3; 3]]) -> BruteForceTracer {
        BruteForceTracer {
            triangles: triangles
                .iter()
                .map(|t| {
                    let [v0, v1, v2] = t.map(Vec3A::from);
                    Triangle { v0, v1, v2 }
                })
                .collect(),
        }
    }

    /// The nearest hit with distance in `t_min..t_max` (the lowest triangle index among equal
    /// distances), as [`TriangleBvh::closest_hit`] defines it.
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<RayHitRecord> {
        let (ray, lead) = TriangleBvh::ray(origin, direction, t_min, t_max)?;
        let mut best: Option<(f32, usize)> = None;
        for (i, triangle) in self.triangles.iter().enumerate() {
            let t = triangle.intersect(&ray);
            if t < best.map_or(ray.tmax, |(b, _)| b) {
                best = Some((t, i));
            }
        }
        best.map(|(t, triangle)| RayHitRecord {
            distance: t - lead,
            triangle,
        })
    }

    /// True when any triangle is hit with distance in `t_min..t_max`.
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        let Some((ray, _)) = TriangleBvh::ray(origin, direction, t_min, t_max) else {
            return false;
        };
        self.triangles.iter().any(|t| t.intersect(&ray) < ray.tmax)
    }
}
