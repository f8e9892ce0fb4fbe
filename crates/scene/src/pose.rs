//! Where a placed mesh's vertices go at one time: one matrix for a rigid instance, or a skin's
//! palette blended per vertex (`crate::skin`). The CPU's world-space geometry (the reference's
//! triangles, the CPU g-buffer's normals, bounds) goes through here: the [`Scene`] queries at a
//! time `t` live in this module, the model (`crate::model`) knows nothing of poses. The GPU
//! g-buffer applies the same rules in `shaders/scene/gbuffer.wgsl`. Invariant: positions and
//! normals come back one per mesh vertex, normals unit or zero, never NaN from a degenerate
//! transform.

use crate::bounds::Aabb;
use crate::model::{Instance, Mesh, Scene};
use crate::normal_transform::{normal_matrix, transform_normal};
use glam::{Mat3, Mat4, Vec3};

/// Where a placed mesh's vertices go at one time: one matrix for all, or a skin's palette
/// blended per vertex by the mesh's [`crate::skin::JointWeights`].
pub enum Pose {
    /// One object-to-world matrix for every vertex (a rigid instance).
    Rigid(Mat4),
    /// The skin's joint matrices at the time, blended per vertex by its weights.
    Skinned(Vec<Mat4>),
}

impl Pose {
    /// The object-to-world matrix of vertex `vertex` of `mesh` (a vertex without weights under
    /// a skin gets zero, which `Instance::pose` never produces: it picks a skin only for a mesh
    /// with weights).
    pub fn vertex_matrix(&self, mesh: &Mesh, vertex: usize) -> Mat4 {
        match self {
            Pose::Rigid(m) => *m,
            Pose::Skinned(palette) => mesh
                .skin_weights
                .get(vertex)
                .map_or(Mat4::ZERO, |w| w.blend(palette)),
        }
    }

    /// Every vertex of `mesh` in world space.
    pub fn positions(&self, mesh: &Mesh) -> Vec<Vec3> {
        match self {
            Pose::Rigid(m) => mesh
                .positions
                .iter()
                .map(|p| m.transform_point3(*p))
                .collect(),
            Pose::Skinned(_) => (mesh.positions.iter().enumerate())
                .map(|(i, p)| self.vertex_matrix(mesh, i).transform_point3(*p))
                .collect(),
        }
    }

    /// Every vertex normal of `mesh` in world space (unit, zero where a vertex has none or the
    /// transform flattens it), by the rule of [`crate::normal_transform`].
    pub fn normals(&self, mesh: &Mesh) -> Vec<Vec3> {
        let rigid = match self {
            Pose::Rigid(m) => Some(normal_matrix(*m)),
            Pose::Skinned(_) => None,
        };
        (0..mesh.positions.len())
            .map(|i| {
                let Some(n) = mesh.normals.get(i) else {
                    return Vec3::ZERO;
                };
                match rigid {
                    Some(nm) => rigid_normal(nm, *n),
                    None => transform_normal(self.vertex_matrix(mesh, i), *n).unwrap_or(Vec3::ZERO),
                }
            })
            .collect()
    }

    /// World-space bounds of `mesh`: the object bounds' box transformed for a rigid pose, the
    /// posed referenced vertices' box for a skinned one.
    pub fn bounds(&self, mesh: &Mesh) -> Aabb {
        match self {
            Pose::Rigid(m) => mesh.bounds().transformed(m),
            Pose::Skinned(_) => {
                let world = self.positions(mesh);
                Aabb::from_points(
                    mesh.indices
                        .iter()
                        .filter_map(|&i| world.get(i as usize).copied()),
                )
            }
        }
    }
}

/// Object-space normal `n` in world space under normal matrix `normal_matrix` (unit; zero when
/// the transform flattens it): the rule every rigid instance's normals follow.
pub fn rigid_normal(normal_matrix: Mat3, n: Vec3) -> Vec3 {
    (normal_matrix * n)
        .try_normalize()
        .filter(|v| v.is_finite())
        .unwrap_or(Vec3::ZERO)
}

impl Instance {
    /// Where `mesh` (this instance's) goes at time `t`.
    pub fn pose(&self, mesh: &Mesh, t: f32) -> Pose {
        match self.skin_for(mesh) {
            Some(skin) => Pose::Skinned(skin.palette(t)),
            None => Pose::Rigid(self.transform_at(t)),
        }
    }
}

/// The scene's posed, world-space queries: every one walks the instances through their
/// pose at a time (one matrix, or a skin's palette blended per vertex).
impl Scene {
    /// World-space bounds at t = 0.
    pub fn bounds(&self) -> Aabb {
        self.bounds_at(0.0)
    }

    /// World-space bounds at t = 0 of everything but backdrops (see [`Instance::backdrop`]):
    /// the extent of what the scene is about. Empty when the scene is only backdrops.
    pub fn content_bounds(&self) -> Aabb {
        self.instances
            .iter()
            .filter(|instance| !instance.backdrop)
            .filter_map(|instance| {
                let mesh = self.meshes.get(instance.mesh)?;
                let pose = match instance.skin_for(mesh) {
                    Some(skin) => Pose::Skinned(skin.palette(0.0)),
                    None => Pose::Rigid(instance.transform),
                };
                Some(pose.bounds(mesh))
            })
            .fold(Aabb::EMPTY, Aabb::union)
    }

    /// Every instance whose mesh exists, with that mesh and its pose at time `t`: the walk
    /// the bounds, counts and world-space triangle lists below share.
    fn placed_meshes(&self, t: f32) -> impl Iterator<Item = (&Mesh, Pose)> {
        self.instances.iter().filter_map(move |instance| {
            let mesh = self.meshes.get(instance.mesh)?;
            Some((mesh, instance.pose(mesh, t)))
        })
    }

    /// World-space bounds at time `t`.
    pub fn bounds_at(&self, t: f32) -> Aabb {
        self.placed_meshes(t)
            .map(|(mesh, pose)| pose.bounds(mesh))
            .fold(Aabb::EMPTY, Aabb::union)
    }

    /// Every instance's triangles in world space at time `t` (skins deformed), for the
    /// reference ray tracer.
    pub fn world_triangles(&self, t: f32) -> Vec<[Vec3; 3]> {
        let mut out = Vec::with_capacity(self.triangle_count());
        for (mesh, pose) in self.placed_meshes(t) {
            let world = pose.positions(mesh);
            out.extend(mesh.valid_triangles().map(|tri| tri.map(|i| world[i])));
        }
        out
    }

    /// The mesh of instance `instance` posed at time `t`, in world space (skin deformed,
    /// transform applied; vertices without a normal get none): a still copy for exporters.
    /// `None` when the instance or its mesh does not exist.
    pub fn posed_mesh(&self, instance: usize, t: f32) -> Option<Mesh> {
        let inst = self.instances.get(instance)?;
        let mesh = self.meshes.get(inst.mesh)?;
        let pose = inst.pose(mesh, t);
        let normals = if mesh.normals.len() == mesh.positions.len() {
            pose.normals(mesh)
                .into_iter()
                .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
                .collect()
        } else {
            Vec::new()
        };
        Some(Mesh {
            name: mesh.name.clone(),
            positions: pose.positions(mesh),
            normals,
            indices: mesh.indices.clone(),
            material: mesh.material,
            skin_weights: Vec::new(),
        })
    }

    /// Per-vertex world-space unit normals of [`Scene::world_triangles`] at time `t`, in the
    /// same order: each vertex normal carried by its instance's normal matrix (the inverse
    /// transpose, see [`crate::normal_transform`]) and renormalised, the rule the GPU g-buffer's
    /// vertex shader applies. Vertices without a usable normal get zero.
    pub fn world_vertex_normals(&self, t: f32) -> Vec<[Vec3; 3]> {
        let mut out = Vec::with_capacity(self.triangle_count());
        for (mesh, pose) in self.placed_meshes(t) {
            let world = pose.normals(mesh);
            out.extend(mesh.valid_triangles().map(|tri| tri.map(|i| world[i])));
        }
        out
    }
}
