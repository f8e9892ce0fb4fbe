//! A bounding volume hierarchy over world-space triangles, for the reference and primary rays.
//!
//! Built with `obvhs` (PLOC build, reinsertion optimisation, converted to an 8-wide compressed
//! BVH traversed with SIMD node tests). Triangles are stored in BVH leaf order for cache
//! locality; hits report the caller's original triangle index. Triangles no ray can hit
//! (a non-finite vertex, zero area, or a coordinate beyond 1e15) are left out: they would
//! break the builder (overflowing or zero box areas) and change no result.
//! obvhs 0.3's CWBVH node test skips every box the ray leaves before t = 1e-4 (an absolute
//! constant), which would lose occluders closer than 1e-4 world units: fatal for small scenes
//! and for points on a crease. Every query therefore starts its ray a `lead` distance behind the
//! origin (more than that constant, and more than a few float ulps of the origin's coordinates)
//! and shifts t_min/t_max by the same amount, so hits at any t >= t_min are found; reported
//! distances are measured from the caller's origin again. Directions are canonicalised so no
//! component is negative zero, which obvhs 0.3's traversal mishandles (found by the
//! brute-force comparison). Invariants: an empty triangle set
//! gives a BVH every ray misses; rays with a non-finite origin or direction miss instead of
//! reaching obvhs (whose debug assertions would panic).

use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;

/// Largest coordinate magnitude kept: beyond it, box areas in the BVH builder overflow f32.
const MAX_COORDINATE: f32 = 1e15;

/// Relative padding of a BVH's primitive boxes: far above f32 rounding (6e-8) of a
/// transformed point, far below any gap a BVH separates.
const BOX_PADDING: f32 = 1e-5;

/// The box from `min` to `max` grown by [`BOX_PADDING`] of its size and of its distance from
/// the origin, so no box is flat and rounding cannot move a primitive outside it.
pub(super) fn padded_box(min: Vec3, max: Vec3) -> Aabb {
    let pad = BOX_PADDING * ((max - min).max_element() + min.abs().max(max.abs()).max_element());
    Aabb::new(Vec3A::from(min - pad), Vec3A::from(max + pad))
}

/// True for triangles a ray can hit: finite, within `MAX_COORDINATE` (1e15), non-zero area.
/// (Zero-area triangles are invisible to rays anyway, and their flat boxes break obvhs 0.3's
/// wide-BVH conversion.)
pub fn is_traceable(triangle: &[Vec3; 3]) -> bool {
    let [a, b, c] = *triangle;
    let in_range = |v: Vec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
    in_range(a) && in_range(b) && in_range(c) && (b - a).cross(c - a).length_squared() > 0.0
}

/// The nearest intersection along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHitRecord {
    /// Distance along the (unit) ray direction.
    pub distance: f32,
    /// Index of the triangle in the slice given to [`TriangleBvh::new`].
    pub triangle: usize,
}

/// The two ray queries the reference, the CPU g-buffer and the view probes ask, whatever
/// structure answers them: [`TriangleBvh`] over a triangle list, or
/// [`super::SceneRays`] over a posed scene's instances. Distances are along the (unit)
/// direction, in scene units; a hit's `triangle` is its index in the triangle list the
/// structure stands for.
pub trait RayQueries: Sync {
    /// The nearest hit with distance in `t_min..=t_max`.
    fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<RayHitRecord>;
    /// True when any triangle is hit with distance in `t_min..=t_max`.
    fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool;
}

impl RayQueries for TriangleBvh {
    fn closest_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<RayHitRecord> {
        TriangleBvh::closest_hit(self, o, d, t_min, t_max)
    }
    fn any_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        TriangleBvh::any_hit(self, o, d, t_min, t_max)
    }
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
        Self::with_indices(triangles, 0..triangles.len() as u32)
    }

    /// Builds the BVH over `triangles`, a hit on `triangles[k]` reporting the `k`-th of
    /// `indices` (a triangle's number in a longer list the caller keeps).
    pub(super) fn with_indices(
        triangles: &[[Vec3; 3]],
        indices: impl IntoIterator<Item = u32>,
    ) -> TriangleBvh {
        let (kept, kept_index): (Vec<Triangle>, Vec<u32>) = triangles
            .iter()
            .zip(indices)
            .filter(|(t, _)| is_traceable(t))
            .map(|(t, i)| {
                let [v0, v1, v2] = t.map(Vec3A::from);
                (Triangle { v0, v1, v2 }, i)
            })
            .unzip();
        if kept.is_empty() {
            return TriangleBvh {
                bvh: None,
                triangles: Vec::new(),
                original_index: Vec::new(),
            };
        }
        // Padded boxes: obvhs 0.3's wide nodes lose hits in subtrees of zero extent along
        // an axis (coplanar axis-aligned triangles; tests/bvh_matches_brute_force.rs).
        let boxes: Vec<Aabb> = kept
            .iter()
            .map(|t| {
                let [a, b, c] = [t.v0, t.v1, t.v2].map(Vec3::from);
                padded_box(a.min(b).min(c), a.max(b).max(c))
            })
            .collect();
        let mut bvh2 = PlocBuilder::with_capacity(kept.len()).build(
            PlocSearchDistance::Medium,
            &boxes,
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
    /// the lead; `None` for unusable input. [`super::BruteForceTracer`] asks the same rays.
    pub(super) fn ray(origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Option<(Ray, f32)> {
        let usable = origin.is_finite()
            && direction.is_finite()
            && direction != Vec3::ZERO
            && t_min.is_finite()
            && !t_max.is_nan()
            && t_min <= t_max;
        if !usable {
            return None;
        }
        // A negative-zero component (-Vec3::X is (-1, -0, -0)) makes obvhs 0.3's wide-node
        // test miss boxes the ray plainly enters (its octant comes from the sign bit, its
        // inverse direction is -inf): adding +0 turns -0 into +0 and changes nothing else.
        let direction = direction + Vec3::ZERO;
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
        let (ray, lead) = Self::ray(origin, direction, t_min, t_max)?;
        let (t, triangle) = self.closest_on(ray)?;
        Some(RayHitRecord {
            distance: t - lead,
            triangle,
        })
    }

    /// True when any triangle is hit with distance in `t_min..=t_max`.
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        Self::ray(origin, direction, t_min, t_max).is_some_and(|(ray, _)| self.any_on(ray))
    }

    /// The nearest hit of an already prepared ray ([`TriangleBvh::ray`]): its `t` on that ray
    /// and the triangle's caller index.
    pub(super) fn closest_on(&self, ray: Ray) -> Option<(f32, usize)> {
        let bvh = self.bvh.as_ref()?;
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut hit, |ray, id| self.triangles[id].intersect(ray));
        (found && hit.t.is_finite()).then(|| {
            (
                hit.t,
                self.original_index[hit.primitive_id as usize] as usize,
            )
        })
    }

    /// Whether a prepared ray hits anything within its interval.
    pub(super) fn any_on(&self, ray: Ray) -> bool {
        self.bvh.as_ref().is_some_and(|bvh| {
            !bvh.ray_traverse_miss(ray, |ray, id| self.triangles[id].intersect(ray))
        })
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
    fn degenerate_inputs_build_without_panicking() {
        let point = [Vec3::ONE; 3];
        let _ = TriangleBvh::new(&vec![point; 1000]);

        let same = TriangleBvh::new(&vec![[Vec3::ZERO, Vec3::X, Vec3::Y]; 1000]);
        assert!(same.any_hit(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z, 0.0, 2.0));
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let _ = TriangleBvh::new(&vec![line; 100]);
        let huge = [
            Vec3::splat(-1e30),
            Vec3::new(1e30, -1e30, 0.0),
            Vec3::splat(1e30),
        ];
        let bvh = TriangleBvh::new(&[huge, [Vec3::ZERO, Vec3::X, Vec3::Y]]);

        let _ = bvh.closest_hit(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z, 0.0, f32::INFINITY);
        let mut many: Vec<[Vec3; 3]> = (0..5000)
            .map(|i| {
                let p = Vec3::new(
                    (i % 17) as f32,
                    (i % 5) as f32 * 1e-7,
                    (i / 17) as f32 * 1e-3,
                );
                [p, p + Vec3::X * 1e-6, p + Vec3::Z * 1e-6]
            })
            .collect();
        many.push(point);
        let _ = TriangleBvh::new(&many);
    }

    #[test]
    fn random_triangle_soups_build_and_trace() {
        let mut state = 0x1234_5678_u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        for round in 0..ROUNDS {
            let scale = 10f32.powf(next() * 12.0 - 6.0);
            let count = 1 + (next() * 300.0) as usize;
            let snap = round % 3 == 0;
            let mut tris: Vec<[Vec3; 3]> = (0..count)
                .map(|_| {
                    let mut p = || {
                        let v = Vec3::new(next(), next(), next()) * scale;
                        if snap {
                            (v * 4.0 / scale).round() * scale / 4.0
                        } else {
                            v
                        }
                    };
                    [p(), p(), p()]
                })
                .collect();
            if round % 5 == 0 {
                let copy = tris[0];
                tris.extend(std::iter::repeat_n(copy, 40));
            }
            let bvh = TriangleBvh::new(&tris);
            let origin = Vec3::splat(0.5 * scale);
            let direction = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            if let Some(direction) = direction.try_normalize() {
                let _ = bvh.closest_hit(origin, direction, 0.0, f32::INFINITY);
                let _ = bvh.any_hit(origin, direction, 0.0, scale);
            }
        }
    }
    const ROUNDS: usize = 200;

    #[test]
    fn empty_and_single_triangle_bvhs_work() {
        let empty = TriangleBvh::new(&[]);
        assert!(empty.closest_hit(Vec3::ZERO, Vec3::X, 0.0, 1.0).is_none());
        let one = TriangleBvh::new(&unit_square_at_z(-1.0)[..1]);
        assert!(one.any_hit(Vec3::new(0.5, -0.5, 0.0), Vec3::NEG_Z, 0.0, 2.0));
        assert!(!one.any_hit(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::NEG_Z, 0.0, 2.0));
    }
}
