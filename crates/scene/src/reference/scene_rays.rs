//! A posed scene as a two-level BVH for the CPU's rays: one object-space BVH per mesh that
//! several rigid instances share, a world-space BVH over everything else (meshes placed once,
//! skinned instances, transforms too large or singular to invert), and a top level over those
//! parts. A scene of 1,900 copies of one mesh costs one 4,000-triangle build instead of a
//! 7.6-million-triangle one, and no flattened triangle list.
//!
//! Invariant: every query answers exactly what [`TriangleBvh`] over
//! [`Scene::world_triangles`] answers, distance for distance (only which of two triangles at
//! the same distance is reported may differ). That holds because the shared meshes' BVHs only
//! choose candidates: each candidate is tested as its world-space triangle, made with the same
//! arithmetic as `world_triangles` (the instance matrix's `transform_point3`), against the
//! same world-space ray ([`TriangleBvh::ray`]'s lead and all); their boxes are padded (`padded_box`) so
//! rounding in the object-space ray cannot drop a candidate. Hits report the triangle's index
//! in `world_triangles` order, so per-triangle lists (normals, albedo) index as before.
//! A scene without shared meshes is a single world-space [`TriangleBvh`], built as before.

use super::bvh::{RayHitRecord, RayQueries, TriangleBvh, is_traceable, padded_box};
use crate::model::{Mesh, Scene};
use crate::pose::Pose;
use glam::{Mat3, Mat4, Vec3, Vec3A};
use obvhs::aabb::Aabb as ObvhsAabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};
use obvhs::ray::{Ray, RayHit};
use obvhs::triangle::Triangle;
use std::collections::HashMap;

/// An obvhs 8-wide BVH over padded boxes; primitive `k` of a leaf is box
/// `primitive_indices[k]`.
struct CandidateBvh {
    bvh: Option<CwBvh>,
}

impl CandidateBvh {
    fn build(boxes: &[ObvhsAabb]) -> CandidateBvh {
        if boxes.is_empty() {
            return CandidateBvh { bvh: None };
        }
        let mut bvh2 = PlocBuilder::with_capacity(boxes.len()).build(
            PlocSearchDistance::Medium,
            boxes,
            (0..boxes.len() as u32).collect(),
            SortPrecision::U64,
            3,
        );
        ReinsertionOptimizer::default().run(&mut bvh2, 0.05, None);
        CandidateBvh {
            bvh: Some(bvh2_to_cwbvh(&bvh2, 3, true, false)),
        }
    }

    /// The nearest `t` `test` returns for the candidates along `ray`, and the candidate.
    fn closest(&self, ray: Ray, mut test: impl FnMut(&Ray, usize) -> f32) -> Option<(f32, usize)> {
        let bvh = self.bvh.as_ref()?;
        let mut hit = RayHit::none();
        let found = bvh.ray_traverse(ray, &mut hit, |ray, id| {
            test(ray, bvh.primitive_indices[id] as usize)
        });
        (found && hit.t.is_finite()).then(|| {
            (
                hit.t,
                bvh.primitive_indices[hit.primitive_id as usize] as usize,
            )
        })
    }

    /// Whether `test` reports a hit within the ray's interval for some candidate.
    fn any(&self, ray: Ray, mut test: impl FnMut(&Ray, usize) -> f32) -> bool {
        self.bvh.as_ref().is_some_and(|bvh| {
            !bvh.ray_traverse_miss(ray, |ray, id| test(ray, bvh.primitive_indices[id] as usize))
        })
    }
}

/// A mesh several rigid instances share: its traceable triangles in object space, their
/// vertex normals, and a BVH choosing candidates among them.
struct SharedMesh {
    /// Object-space corners, in `valid_triangles` order (untraceable ones included, so the
    /// position is the primitive's number).
    triangles: Vec<[Vec3; 3]>,
    /// Object-space vertex normals (zero where the mesh has none).
    normals: Vec<[Vec3; 3]>,
    candidates: CandidateBvh,
    /// Object-space box of the traceable triangles.
    bounds: (Vec3, Vec3),
}

impl SharedMesh {
    fn new(mesh: &Mesh) -> SharedMesh {
        let triangles: Vec<[Vec3; 3]> = mesh
            .valid_triangles()
            .map(|t| t.map(|i| mesh.positions[i]))
            .collect();
        let normals = mesh
            .valid_triangles()
            .map(|t| t.map(|i| mesh.normals.get(i).copied().unwrap_or(Vec3::ZERO)))
            .collect();
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        let boxes: Vec<ObvhsAabb> = triangles
            .iter()
            .map(|t| {
                let (min, max) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
                if is_traceable(t) {
                    (lo, hi) = (lo.min(min), hi.max(max));
                }
                padded_box(min, max)
            })
            .collect();
        SharedMesh {
            candidates: CandidateBvh::build(&boxes),
            triangles,
            normals,
            bounds: (lo, hi),
        }
    }
}

/// Where an instance's triangles live.
enum Placement {
    /// In the world-space part, from this position of `world_triangles`.
    World { start: usize },
    /// A shared mesh under a rigid transform.
    Shared {
        mesh: usize,
        matrix: Mat4,
        inverse: Mat4,
        normal_matrix: Mat3,
    },
}

/// One placed instance: its first triangle's index in `world_triangles` order, how many it
/// has, and where they live.
struct Placed {
    first: usize,
    count: usize,
    placement: Placement,
}

/// A part the top level chooses among: the world-space BVH, or one shared instance.
#[derive(Clone, Copy)]
enum Part {
    World,
    Instance(usize),
}

/// The scene at one time, ready for world-space ray queries (see the module docs).
pub struct SceneRays {
    placed: Vec<Placed>,
    shared: Vec<SharedMesh>,
    /// The world-space part's triangles and vertex normals, in the order of its instances.
    world_triangles: Vec<[Vec3; 3]>,
    world_normals: Vec<[Vec3; 3]>,
    world: TriangleBvh,
    parts: Vec<Part>,
    /// `None` when the world part is all there is.
    top: Option<CandidateBvh>,
}

/// A rigid transform the shared path can take: finite, invertible, and keeping the mesh
/// within the coordinates [`TriangleBvh`] keeps.
fn shareable(matrix: Mat4, object: (Vec3, Vec3)) -> Option<Mat4> {
    let inverse = matrix.inverse();
    let world = crate::bounds::Aabb {
        min: object.0,
        max: object.1,
    }
    .transformed(&matrix);
    let in_range = |v: Vec3| v.is_finite() && v.abs().max_element() <= 1e15;
    (matrix.is_finite()
        && inverse.is_finite()
        && matrix.determinant() != 0.0
        && in_range(world.min)
        && in_range(world.max))
    .then_some(inverse)
}

impl SceneRays {
    /// `scene` posed at time `t`.
    pub fn new(scene: &Scene, t: f32) -> SceneRays {
        // Meshes with two or more rigid instances get an object-space BVH.
        let mut rigid_uses: HashMap<usize, usize> = HashMap::new();
        for instance in &scene.instances {
            if let Some(mesh) = scene.meshes.get(instance.mesh)
                && instance.skin_for(mesh).is_none()
            {
                *rigid_uses.entry(instance.mesh).or_default() += 1;
            }
        }
        let mut shared_index: HashMap<usize, usize> = HashMap::new();
        let mut shared = Vec::new();
        let mut placed = Vec::new();
        let (mut world_triangles, mut world_normals, mut world_index) =
            (Vec::new(), Vec::new(), Vec::new());
        let mut first = 0;
        for instance in &scene.instances {
            let Some(mesh) = scene.meshes.get(instance.mesh) else {
                continue;
            };
            let pose = instance.pose(mesh, t);
            let count = mesh.valid_triangles().count();
            let sharing = match pose {
                Pose::Rigid(matrix) if rigid_uses.get(&instance.mesh).is_some_and(|&n| n > 1) => {
                    let index = *shared_index.entry(instance.mesh).or_insert_with(|| {
                        shared.push(SharedMesh::new(mesh));
                        shared.len() - 1
                    });
                    shareable(matrix, shared[index].bounds).map(|inverse| (index, matrix, inverse))
                }
                _ => None,
            };
            let placement = match sharing {
                Some((mesh, matrix, inverse)) => Placement::Shared {
                    mesh,
                    matrix,
                    inverse,
                    normal_matrix: crate::normal_transform::normal_matrix(matrix),
                },
                None => {
                    let start = world_triangles.len();
                    let positions = pose.positions(mesh);
                    let normals = pose.normals(mesh);
                    for tri in mesh.valid_triangles() {
                        world_triangles.push(tri.map(|i| positions[i]));
                        world_normals.push(tri.map(|i| normals[i]));
                    }
                    world_index.extend((first..first + count).map(|i| i as u32));
                    Placement::World { start }
                }
            };
            placed.push(Placed {
                first,
                count,
                placement,
            });
            first += count;
        }
        let world = TriangleBvh::with_indices(&world_triangles, world_index);
        let mut parts = Vec::new();
        let mut boxes = Vec::new();
        if world.triangle_count() > 0 {
            let (lo, hi) = world_triangles
                .iter()
                .filter(|t| is_traceable(t))
                .flatten()
                .fold(
                    (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                    |(lo, hi), v| (lo.min(*v), hi.max(*v)),
                );
            parts.push(Part::World);
            boxes.push(padded_box(lo, hi));
        }
        for (i, p) in placed.iter().enumerate() {
            if let Placement::Shared { mesh, matrix, .. } = p.placement {
                let (lo, hi) = shared[mesh].bounds;
                if lo.cmple(hi).all() {
                    let object = crate::bounds::Aabb { min: lo, max: hi };
                    let world = object.transformed(&matrix);
                    parts.push(Part::Instance(i));
                    boxes.push(padded_box(world.min, world.max));
                }
            }
        }
        let only_world = parts.iter().all(|p| matches!(p, Part::World));
        SceneRays {
            top: (!only_world).then(|| CandidateBvh::build(&boxes)),
            placed,
            shared,
            world_triangles,
            world_normals,
            world,
            parts,
        }
    }

    /// Number of triangles the scene places (the length of `world_triangles`).
    pub fn triangle_count(&self) -> usize {
        self.placed.last().map_or(0, |p| p.first + p.count)
    }

    /// The instance holding triangle `triangle` (in `world_triangles` order), and the
    /// triangle's number within it.
    fn locate(&self, triangle: usize) -> Option<(&Placed, usize)> {
        let k = self
            .placed
            .partition_point(|p| p.first + p.count <= triangle);
        let p = self.placed.get(k)?;
        (triangle >= p.first).then_some((p, triangle - p.first))
    }

    /// World-space corners of triangle `triangle`, as `Scene::world_triangles` has them.
    pub fn triangle(&self, triangle: usize) -> Option<[Vec3; 3]> {
        let (p, k) = self.locate(triangle)?;
        Some(match &p.placement {
            Placement::World { start } => self.world_triangles[start + k],
            Placement::Shared { mesh, matrix, .. } => {
                self.shared[*mesh].triangles[k].map(|v| matrix.transform_point3(v))
            }
        })
    }

    /// World-space unit vertex normals of triangle `triangle`, as
    /// `Scene::world_vertex_normals` has them (zero where there are none).
    pub fn vertex_normals(&self, triangle: usize) -> [Vec3; 3] {
        let Some((p, k)) = self.locate(triangle) else {
            return [Vec3::ZERO; 3];
        };
        match &p.placement {
            Placement::World { start } => self.world_normals[start + k],
            Placement::Shared {
                mesh,
                normal_matrix,
                ..
            } => self.shared[*mesh].normals[k].map(|n| {
                if n == Vec3::ZERO {
                    return Vec3::ZERO;
                }
                crate::pose::rigid_normal(*normal_matrix, n)
            }),
        }
    }

    /// The world-space `t` of the nearest hit on shared instance `placed` along the prepared
    /// world ray `ray` (within its interval), and the triangle's `world_triangles` index.
    fn closest_on_instance(&self, placed: usize, ray: &Ray) -> Option<(f32, usize)> {
        let p = &self.placed[placed];
        let Placement::Shared {
            mesh,
            matrix,
            inverse,
            ..
        } = &p.placement
        else {
            return None;
        };
        let mesh = &self.shared[*mesh];
        let local = object_ray(ray, inverse);
        let (t, k) = mesh.candidates.closest(local, |local, k| {
            world_triangle(&mesh.triangles[k], matrix).map_or(f32::INFINITY, |tri| {
                let mut world = *ray;
                world.tmax = local.tmax;
                tri.intersect(&world)
            })
        })?;
        Some((t, p.first + k))
    }

    fn any_on_instance(&self, placed: usize, ray: &Ray) -> bool {
        let Placement::Shared {
            mesh,
            matrix,
            inverse,
            ..
        } = &self.placed[placed].placement
        else {
            return false;
        };
        let mesh = &self.shared[*mesh];
        mesh.candidates.any(object_ray(ray, inverse), |_, k| {
            world_triangle(&mesh.triangles[k], matrix)
                .map_or(f32::INFINITY, |tri| tri.intersect(ray))
        })
    }
}

/// The world-space triangle of object-space corners `corners` under `matrix`, `None` when no
/// ray can hit it ([`is_traceable`]: as the flat BVH leaves it out).
fn world_triangle(corners: &[Vec3; 3], matrix: &Mat4) -> Option<Triangle> {
    let world = corners.map(|v| matrix.transform_point3(v));
    is_traceable(&world).then(|| {
        let [v0, v1, v2] = world.map(Vec3A::from);
        Triangle { v0, v1, v2 }
    })
}

/// The world ray `ray` in an instance's object space: the same `t` marks the same point, so the
/// direction is transformed, not renormalised.
fn object_ray(ray: &Ray, inverse: &Mat4) -> Ray {
    let origin = inverse.transform_point3(Vec3::from(ray.origin));
    // +0 turns a negative-zero component into +0 (see `TriangleBvh::ray`).
    let direction = inverse.transform_vector3(Vec3::from(ray.direction)) + Vec3::ZERO;
    Ray::new(origin.into(), direction.into(), ray.tmin, ray.tmax)
}

impl RayQueries for SceneRays {
    fn closest_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> Option<RayHitRecord> {
        SceneRays::closest_hit(self, o, d, t_min, t_max)
    }
    fn any_hit(&self, o: Vec3, d: Vec3, t_min: f32, t_max: f32) -> bool {
        SceneRays::any_hit(self, o, d, t_min, t_max)
    }
}

impl SceneRays {
    /// The nearest hit with distance in `t_min..=t_max` along `direction` (unit length, so
    /// distances are in scene units); its triangle is numbered in `world_triangles` order.
    pub fn closest_hit(
        &self,
        origin: Vec3,
        direction: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<RayHitRecord> {
        let Some(top) = &self.top else {
            return self.world.closest_hit(origin, direction, t_min, t_max);
        };
        let (ray, lead) = TriangleBvh::ray(origin, direction, t_min, t_max)?;
        let mut triangle = 0;
        let (t, _) = top.closest(ray, |ray, part| {
            let found = match self.parts[part] {
                Part::World => self.world.closest_on(*ray),
                Part::Instance(placed) => self.closest_on_instance(placed, ray),
            };
            match found {
                Some((t, k)) if t < ray.tmax => {
                    triangle = k;
                    t
                }
                _ => f32::INFINITY,
            }
        })?;
        Some(RayHitRecord {
            distance: t - lead,
            triangle,
        })
    }

    /// True when any triangle is hit with distance in `t_min..=t_max`.
    pub fn any_hit(&self, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> bool {
        let Some(top) = &self.top else {
            return self.world.any_hit(origin, direction, t_min, t_max);
        };
        let Some((ray, _)) = TriangleBvh::ray(origin, direction, t_min, t_max) else {
            return false;
        };
        top.any(ray, |ray, part| {
            let hit = match self.parts[part] {
                Part::World => self.world.any_on(*ray),
                Part::Instance(placed) => self.any_on_instance(placed, ray),
            };
            if hit {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            }
        })
    }
}
