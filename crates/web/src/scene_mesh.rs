//! A scene's triangles as the page draws them: every placed mesh at t = 0 in world space, one
//! vertex per corner with its normal (the mesh's own, or the face's where it has none).
//!
//! Invariant: a vertex's normal is its mesh's own, moved to world space by the scene's rule
//! (`aograph_scene::normal_transform`); only a vertex without one takes its face's.

use aograph_scene::Scene;
use glam::Vec3;

/// One vertex: world-space position and unit normal.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// World-space position.
    pub position: [f32; 3],
    /// World-space unit normal.
    pub normal: [f32; 3],
}

/// Every triangle of a scene, in world space.
#[derive(Clone, Debug, Default)]
pub struct SceneMesh {
    /// Three per triangle.
    pub vertices: Vec<Vertex>,
}

impl SceneMesh {
    /// `scene`'s placed meshes at time `t`.
    pub fn of(scene: &Scene, t: f32) -> Self {
        let mut vertices = Vec::with_capacity(3 * scene.triangle_count());
        for instance in &scene.instances {
            let Some(mesh) = scene.meshes.get(instance.mesh) else {
                continue;
            };
            let pose = instance.pose(mesh, t);
            let positions = pose.positions(mesh);
            let normals = pose.normals(mesh);
            for tri in mesh.valid_triangles() {
                let p = tri.map(|i| positions[i]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                for i in tri {
                    let n = normals.get(i).copied().unwrap_or(Vec3::ZERO);
                    let n = if n == Vec3::ZERO { face } else { n };
                    vertices.push(Vertex {
                        position: positions[i].into(),
                        normal: n.into(),
                    });
                }
            }
        }
        Self { vertices }
    }
}
