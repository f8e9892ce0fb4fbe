//! A bounding volume hierarchy over world-space triangles, for the reference and primary rays.
//!
//! Built with `obvhs` (PLOC build, reinsertion optimisation, converted to an 8-wide compressed
//! BVH traversed with SIMD node tests). Triangles are stored in BVH leaf order for cache
//! locality; hits report the caller's original triangle index.
//! obvhs 0.3's CWBVH node test skips every box the ray leaves before t = 1e-4 (an absolute
//! constant), which would lose occluders closer than 1e-4 world units: fatal for small scenes
//! and for points on a crease. Every query therefore starts its ray a `lead` distance behind the
//! origin (more than that constant, and more than a few float ulps of the origin's coordinates)
//! and shifts t_min/t_max by the same amount, so hits at any t >= t_min are found; reported
//! distances are measured from the caller's origin again. Invariants: triangles with a
//! non-finite vertex are left out (they could never be hit meaningfully); an empty triangle set
//! gives a BVH every ray misses; rays with a non-finite origin or direction miss instead of
//! reaching obvhs (whose debug assertions would panic).

use glam::{Vec3, Vec3A};
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;

/// The nearest intersection along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHitRecord {
    /// Distance along the (unit) ray direction.
    pub distance: f32,
    /// Index of the triangle in the slice given to [`TriangleBvh::new`].
    pub triangle: usize,
}

/// A BVH over triangles, answering closest-hit and any-hit queries.
pub struct TriangleBvh {
    bvh: Option<CwBvh>,
    /// Triangles in BVH primitive order.
    triangles: Vec<Triangle>,
    /// For each entry of `triangles`, its index in the caller's slice.
    original_index: Vec<u32>,
}

impl TriangleBvh {
    /// Builds the BVH over `triangles` (world space).
    pub fn new(triangles: &[[Vec3; 3]]) -> TriangleBvh {
        let (kept, kept_index): (Vec<Triangle>, Vec<u32>) = triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.iter().all(|v| v.is_finite()))
            .map(|(i, t)| {
                let [v0, v1, v2] = t.map(Vec3A::from);
                (Triangle { v0, v1, v2 }, i as u32)
            })
            .unzip();
        if kept.is_empty() {
            return TriangleBvh {
                bvh: None,
                triangles: Vec::new(),
                original_index: Vec::new(),
            };
        }
        let mut bvh2 = PlocBuilder::with_capacity(kept.len()).build(
            PlocSearchDistance::Medium,
            &kept,
            (0..kept.len() as u32).collect(),
            SortPrecision::U64,
            3,
        );
        ReinsertionOptimizer::default().run(&mut bvh2, 0.05, None);
        let bvh = bvh2_to_cwbvh(&bvh2, 3, true, false);
        let triangles = bvh
            .primitive_indices
            .iter()
            .map(|&i| kept[i as usize])
            .collect();
        let original_index = bvh
            .primitive_indices
            .iter()
            .map(|&i| kept_index[i as usize])
            .collect();
        TriangleBvh {
            bvh: Some(bvh),
            triangles,
            original_index,
        }
    }

    /// Number of triangles in the BVH.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The obvhs ray for the query, started `lead` behind `origin` (see the module docs), and
    /// the lead; `None` for unusable input.
    fn ray(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Option<(Ray, f32)> {
        let usable = origin.is_finite()
            && direction.is_finite()
            && direction != Vec3::ZERO
            && t_min.is_finite()
            && !t_max.is_nan()
            && t_min <= t_max;
        if !usable {
            return None;
        }
        let lead = 2e-4 + 1e-6 * origin.abs().max_element() + (-t_min).max(0.0);
        let start = origin - direction * lead;
        Some((
            Ray::new(start.into(), direction.into(), t_min + lead, t_max + lead),
            lead,
        ))
    }

    /// The nearest triangle hit with distance in `t_min..=t_max` along `direction` (unit
    /// length, so distances are in scene units).
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<RayHitRecord> {
        let bvh = self.bvh.as_ref()?;
        let (ray, lead) = Self::ray(origin, direction, t_min, t_max)?;
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut hit, |ray, id| self.triangles[id].intersect(ray));
        (found && hit.t.is_finite()).then(|| RayHitRecord {
            distance: hit.t - lead,
            triangle: self.original_index[hit.primitive_id as usize] as usize,
        })
    }

    /// True when any triangle is hit with distance in `t_min..=t_max`.
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        let (Some(bvh), Some((ray, _))) = (
            self.bvh.as_ref(),
            Self::ray(origin, direction, t_min, t_max),
        ) else {
            return false;
        };
        !bvh.ray_traverse_miss(ray, |ray, id| self.triangles[id].intersect(ray))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square_at_z(z: f32) -> Vec<[Vec3; 3]> {
        let (a, b, c, d) = (
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(1.0, -1.0, z),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(-1.0, 1.0, z),
        );
        vec![[a, b, c], [a, c, d]]
    }

    #[test]
    fn closest_hit_reports_distance_and_original_triangle() {
        let mut tris = unit_square_at_z(-5.0);
        tris.push([Vec3::new(0.0, 0.0, f32::NAN), Vec3::X, Vec3::Y]);
        tris.extend(unit_square_at_z(-2.0));
        let bvh = TriangleBvh::new(&tris);
        assert_eq!(bvh.triangle_count(), 4);
        let hit = bvh
            .closest_hit(Vec3::new(0.2, 0.1, 0.0), Vec3::NEG_Z, 0.0, f32::INFINITY)
            .unwrap();
        assert!((hit.distance - 2.0).abs() < 1e-6);
        assert!(hit.triangle >= 3);
        assert!(bvh.any_hit(Vec3::ZERO, Vec3::NEG_Z, 0.0, 2.5));
        assert!(!bvh.any_hit(Vec3::ZERO, Vec3::NEG_Z, 0.0, 1.5));
        assert!(!bvh.any_hit(Vec3::ZERO, Vec3::Z, 0.0, 100.0));
    }

    #[test]
    fn hits_closer_than_obvhs_node_epsilon_are_found() {
        let bvh = TriangleBvh::new(&unit_square_at_z(-1e-6));
        let hit = bvh.closest_hit(Vec3::ZERO, Vec3::NEG_Z, 0.0, 1.0).unwrap();
        assert!((hit.distance - 1e-6).abs() < 1e-9, "{}", hit.distance);
        // Behind the origin, within a negative t_min.
        let hit = bvh
            .closest_hit(Vec3::new(0.0, 0.0, -2e-6), Vec3::NEG_Z, -2e-6, 1.0)
            .unwrap();
        assert!(hit.distance < 0.0);
        assert!(!bvh.any_hit(Vec3::new(0.0, 0.0, -2e-6), Vec3::NEG_Z, 0.0, 1.0));
    }

    #[test]
    fn empty_and_single_triangle_bvhs_work() {
        let empty = TriangleBvh::new(&[]);
        assert!(empty.closest_hit(Vec3::ZERO, Vec3::X, 0.0, 1.0).is_none());
        let one = TriangleBvh::new(&unit_square_at_z(-1.0)[..1]);
        assert!(one.any_hit(Vec3::new(0.5, -0.5, 0.0), Vec3::NEG_Z, 0.0, 2.0));
        assert!(!one.any_hit(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::NEG_Z, 0.0, 2.0));
    }
}
