//! Where a placed mesh's vertices go at one time: one matrix for a rigid instance, or a skin's
//! palette blended per vertex (`crate::skin`). The CPU's world-space geometry (the reference's
//! triangles, the CPU g-buffer's normals, bounds) goes through here; the GPU g-buffer applies
//! the same rules in `shaders/scene/gbuffer.wgsl`. Invariant: positions and normals come back
//! one per mesh vertex, normals unit or zero, never NaN from a degenerate transform.

use crate::bounds::Aabb;
use crate::model::Mesh;
use crate::normal_transform::{normal_matrix, transform_normal};
use glam::{Mat4, Vec3};

/// Where a placed mesh's vertices go at one time: one matrix for all, or a skin's palette
/// blended per vertex by the mesh's [`crate::skin::JointWeights`].
pub(crate) enum Pose {
    Rigid(Mat4),
    Skinned(Vec<Mat4>),
}

impl Pose {
    /// The object-to-world matrix of vertex `vertex` of `mesh` (a vertex without weights under
    /// a skin gets zero, which `Instance::pose` never produces: it picks a skin only for a mesh
    /// with weights).
    pub(crate) fn vertex_matrix(&self, mesh: &Mesh, vertex: usize) -> Mat4 {
        match self {
            Pose::Rigid(m) => *m,
            Pose::Skinned(palette) => mesh
                .skin_weights
                .get(vertex)
                .map_or(Mat4::ZERO, |w| w.blend(palette)),
        }
    }

    /// Every vertex of `mesh` in world space.
    pub(crate) fn positions(&self, mesh: &Mesh) -> Vec<Vec3> {
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
    pub(crate) fn normals(&self, mesh: &Mesh) -> Vec<Vec3> {
        let rigid = match self {
            Pose::Rigid(m) => Some(normal_matrix(*m)),
            Pose::Skinned(_) => None,
        };
        (0..mesh.positions.len())
            .map(|i| {
                let Some(n) = mesh.normals.get(i) else {
                    return Vec3::ZERO;
                };
                let world = match rigid {
                    Some(nm) => (nm * *n).try_normalize().filter(|v| v.is_finite()),
                    None => transform_normal(self.vertex_matrix(mesh, i), *n),
                };
                world.unwrap_or(Vec3::ZERO)
            })
            .collect()
    }

    /// World-space bounds of `mesh`: the object bounds' box transformed for a rigid pose, the
    /// posed referenced vertices' box for a skinned one.
    pub(crate) fn bounds(&self, mesh: &Mesh) -> Aabb {
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
