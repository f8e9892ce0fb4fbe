//! The scene model: meshes, materials, instances, light, camera, and the queries the renderer
//! and the reference ray tracer ask of them (the world-space ones, which pose the instances at a
//! time, are in pose.rs).
//!
//! Invariants the loaders and procedural builders keep (and the queries tolerate when a caller
//! breaks them): mesh indices form a triangle list (`indices.len() % 3 == 0`) whose entries are
//! below `positions.len()`; `normals` is empty or has one unit normal per position; positions are
//! finite; `Instance::transform` equals the instance's transform at t = 0; `Mesh::skin_weights`
//! is empty or has one entry per position, and an instance with a skin draws a mesh with
//! weights (else the skin is ignored and the instance is rigid). Queries skip out-of-range
//! indices and instances instead of panicking.

use crate::animation::Animation;
use crate::bounds::Aabb;
use crate::camera::{Camera, CameraMotion};
use crate::skin::{JointWeights, Skin};
use glam::{Mat4, Vec3};

/// An indexed triangle mesh in its own (object) space.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Mesh {
    /// A human-readable name, used in messages.
    pub name: String,
    /// Vertex positions in object space, finite (scene units once the instance transform is
    /// applied).
    pub positions: Vec<Vec3>,
    /// One unit normal per position (may be empty for geometry only used by the ray tracer).
    pub normals: Vec<Vec3>,
    /// Triangle list, counter-clockwise front faces.
    pub indices: Vec<u32>,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// One skinning influence set per position (glTF JOINTS_0 / WEIGHTS_0), or empty for a
    /// rigid mesh. Used only by instances that carry a [`Skin`].
    pub skin_weights: Vec<JointWeights>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Triangles in object space; triangles with an out-of-range index are skipped.
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.indices.chunks_exact(3).filter_map(|tri| {
            let a = *self.positions.get(tri[0] as usize)?;
            let b = *self.positions.get(tri[1] as usize)?;
            let c = *self.positions.get(tri[2] as usize)?;
            Some([a, b, c])
        })
    }

    /// Per-vertex object-space normals of [`Mesh::triangles`] (the same triangles, in the same
    /// order); a vertex without a normal gets zero, as the g-buffer uploads it.
    pub fn triangle_normals(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        let normal = |i: u32| self.normals.get(i as usize).copied().unwrap_or(Vec3::ZERO);
        self.indices
            .chunks_exact(3)
            .filter(|tri| tri.iter().all(|&i| (i as usize) < self.positions.len()))
            .map(move |tri| [normal(tri[0]), normal(tri[1]), normal(tri[2])])
    }

    /// Object-space bounds of the referenced vertices.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.triangles().flatten())
    }

    /// Triangles whose corners are all in range, as index triples (the order of
    /// [`Mesh::triangles`]).
    pub fn valid_triangles(&self) -> impl Iterator<Item = [usize; 3]> + '_ {
        let n = self.positions.len();
        self.indices
            .chunks_exact(3)
            .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
            .filter(move |t| t.iter().all(|&i| i < n))
    }
}

/// Surface appearance; AO needs none of it, shading and SSDO use the colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Linear RGBA base colour.
    pub base_color: [f32; 4],
}

impl Default for Material {
    fn default() -> Self {
        Material {
            base_color: [0.8, 0.8, 0.8, 1.0],
        }
    }
}

/// One placement of a mesh in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Object-to-world transform at t = 0 (the only one when `animation` is `None`).
    pub transform: Mat4,
    /// Object-to-world transform over time, if the instance moves.
    pub animation: Option<Animation>,
    /// A stand-in for an unbounded surface (a procedural scene's 1000-unit floor or wall): it
    /// is drawn and traced like any geometry but has no size of its own, so it is left out of
    /// [`Scene::content_bounds`] (framing and the automatic radius). glTF instances never are.
    pub backdrop: bool,
    /// The skeleton deforming the mesh, if it is skinned: its vertices then follow the skin's
    /// joints and `transform` / `animation` are not used (glTF ignores a skinned node's own
    /// transform).
    pub skin: Option<Skin>,
}

impl Instance {
    /// A static instance.
    pub fn fixed(mesh: usize, transform: Mat4) -> Instance {
        Instance {
            mesh,
            transform,
            animation: None,
            backdrop: false,
            skin: None,
        }
    }

    /// An animated instance; `transform` is set to the animation's t = 0 pose.
    pub fn animated(mesh: usize, animation: Animation) -> Instance {
        Instance {
            mesh,
            transform: animation.matrix_at(0.0),
            animation: Some(animation),
            backdrop: false,
            skin: None,
        }
    }

    /// A skinned instance of `mesh` (whose vertices carry [`JointWeights`]).
    pub fn skinned(mesh: usize, skin: Skin) -> Instance {
        Instance {
            skin: Some(skin),
            ..Instance::fixed(mesh, Mat4::IDENTITY)
        }
    }

    /// The skin that deforms this instance's `mesh`: its own, when the mesh has one weight set
    /// per vertex (the one rule the CPU and the GPU g-buffer use to pick skinning).
    pub fn skin_for<'a>(&'a self, mesh: &Mesh) -> Option<&'a Skin> {
        self.skin.as_ref().filter(|_| {
            !mesh.skin_weights.is_empty() && mesh.skin_weights.len() == mesh.positions.len()
        })
    }

    /// Object-to-world transform at time `t` (seconds).
    pub fn transform_at(&self, t: f32) -> Mat4 {
        match &self.animation {
            Some(animation) => animation.matrix_at(t),
            None => self.transform,
        }
    }

    /// True when the transform, or the skin's joints, change over time.
    pub fn is_moving(&self) -> bool {
        self.animation.as_ref().is_some_and(Animation::is_moving)
            || self.skin.as_ref().is_some_and(Skin::is_moving)
    }

    /// The instance's animation length in seconds (its transform's or its skin's, whichever
    /// is longer; 0 when it does not move).
    pub fn duration(&self) -> f32 {
        let own = self.animation.as_ref().map_or(0.0, Animation::duration);
        let skin = self.skin.as_ref().map_or(0.0, Skin::duration);
        own.max(skin)
    }
}

/// A light infinitely far away.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in (from the light towards the scene).
    pub direction: Vec3,
    /// Linear RGB colour.
    pub color: [f32; 3],
    /// Multiplier on `color` (illuminance, arbitrary units).
    pub intensity: f32,
}

impl Default for DirectionalLight {
    /// Warm white sunlight from above, slightly from the front left.
    fn default() -> Self {
        DirectionalLight {
            direction: Vec3::new(0.35, -1.0, -0.45).normalize(),
            color: [1.0, 0.96, 0.9],
            intensity: 3.0,
        }
    }
}

/// Ambient light applied everywhere (the term AO darkens).
pub const DEFAULT_AMBIENT: [f32; 3] = [0.25, 0.27, 0.3];

/// A camera the scene file names (a glTF camera node), selectable by name or index.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCamera {
    /// The node's name, else the camera's, else "camera N" (N its index).
    pub name: String,
    /// The camera at t = 0.
    pub camera: Camera,
    /// How it moves (an animated node), if it does.
    pub motion: Option<CameraMotion>,
}

/// Everything needed to render a frame and to ray trace its reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The geometry, each mesh in its own object space; drawn only through `instances`.
    pub meshes: Vec<Mesh>,
    /// Materials that [`Mesh::material`] indexes.
    pub materials: Vec<Material>,
    /// Placements of meshes in the world; a mesh may be placed any number of times, and one
    /// that is never placed is neither drawn nor traced.
    pub instances: Vec<Instance>,
    /// The default camera at t = 0: the file's first camera, a procedural scene's own, or an
    /// automatic view (`crate::views`).
    pub camera: Camera,
    /// How the camera moves, if it does.
    pub camera_motion: Option<CameraMotion>,
    /// Every camera the file defines, in the order of the node walk (empty for procedural
    /// scenes and files without cameras).
    pub cameras: Vec<NamedCamera>,
    /// The sun: shading's direct light and the direction of the sky's sun lobe.
    pub light: DirectionalLight,
    /// Linear RGB ambient light.
    pub ambient: [f32; 3],
}

impl Scene {
    /// The camera at time `t` (seconds).
    pub fn camera_at(&self, t: f32) -> Camera {
        match &self.camera_motion {
            Some(motion) => motion.camera_at(&self.camera, t),
            None => self.camera,
        }
    }

    /// True when some instance or the camera moves over time.
    pub fn is_animated(&self) -> bool {
        self.instances.iter().any(Instance::is_moving)
            || self
                .camera_motion
                .as_ref()
                .is_some_and(CameraMotion::is_moving)
    }

    /// True when nothing moves: no moving instance and no moving camera (so no motion vectors
    /// are needed and one reference image serves every frame).
    pub fn is_static(&self) -> bool {
        !self.is_animated()
    }

    /// Longest animation cycle or keyframe range in seconds (0 for a static scene).
    pub fn duration(&self) -> f32 {
        let instances = self.instances.iter().map(Instance::duration);
        let camera = match &self.camera_motion {
            Some(CameraMotion::Orbit { period, .. }) => period.max(0.0),
            Some(CameraMotion::Node(animation)) => animation.duration(),
            None => 0.0,
        };
        instances.fold(camera, f32::max)
    }

    /// Checks the invariants every loader and builder keeps (module docs): at least one
    /// triangle; triangle lists with in-range indices; finite positions; normals absent or one
    /// finite unit normal per position; instances and meshes referring to existing meshes and
    /// materials; finite transforms. The error names the first broken one.
    pub fn check_invariants(&self) -> Result<(), String> {
        if self.triangle_count() == 0 {
            return Err("no triangles".into());
        }
        for (i, m) in self.meshes.iter().enumerate() {
            if m.indices.len() % 3 != 0 {
                return Err(format!(
                    "mesh {i}: {} indices, not a triangle list",
                    m.indices.len()
                ));
            }
            if let Some(bad) = m.indices.iter().find(|&&x| x as usize >= m.positions.len()) {
                return Err(format!(
                    "mesh {i}: index {bad} of {} positions",
                    m.positions.len()
                ));
            }
            if !m.positions.iter().all(|p| p.is_finite()) {
                return Err(format!("mesh {i}: a position is not finite"));
            }
            if !(m.normals.is_empty() || m.normals.len() == m.positions.len()) {
                return Err(format!(
                    "mesh {i}: {} normals for {} positions",
                    m.normals.len(),
                    m.positions.len()
                ));
            }
            if let Some(n) = m
                .normals
                .iter()
                .find(|n| !(n.is_finite() && (n.length() - 1.0).abs() < 1e-3))
            {
                return Err(format!("mesh {i}: normal {n} is not a finite unit vector"));
            }
            if !(m.skin_weights.is_empty() || m.skin_weights.len() == m.positions.len()) {
                return Err(format!(
                    "mesh {i}: {} skin weights for {} positions",
                    m.skin_weights.len(),
                    m.positions.len()
                ));
            }
            if m.material >= self.materials.len() {
                return Err(format!(
                    "mesh {i}: material {} of {}",
                    m.material,
                    self.materials.len()
                ));
            }
        }
        for (i, inst) in self.instances.iter().enumerate() {
            if inst.mesh >= self.meshes.len() {
                return Err(format!(
                    "instance {i}: mesh {} of {}",
                    inst.mesh,
                    self.meshes.len()
                ));
            }
            if !inst.transform.is_finite() {
                return Err(format!("instance {i}: transform is not finite"));
            }
            if let Some(skin) = &inst.skin {
                let joints = skin.joints.len();
                let weights = &self.meshes[inst.mesh].skin_weights;
                if let Some(w) = weights
                    .iter()
                    .find(|w| w.joints.iter().any(|&j| j as usize >= joints))
                {
                    return Err(format!(
                        "instance {i}: joint index in {:?} of a skin with {joints} joints",
                        w.joints
                    ));
                }
                if skin.joints.iter().any(|j| !j.inverse_bind.is_finite()) {
                    return Err(format!(
                        "instance {i}: an inverse bind matrix is not finite"
                    ));
                }
            }
        }
        Ok(())
    }

    /// The same scene seen from `camera` (still, whatever motion the scene's camera had).
    pub fn with_camera(&self, camera: Camera) -> Scene {
        Scene {
            camera,
            camera_motion: None,
            ..self.clone()
        }
    }

    /// Every instance whose mesh exists, with that mesh (no pose: for counts).
    fn instance_meshes(&self) -> impl Iterator<Item = &Mesh> {
        self.instances
            .iter()
            .filter_map(|instance| self.meshes.get(instance.mesh))
    }

    /// Number of triangles over all instances.
    pub fn triangle_count(&self) -> usize {
        self.instance_meshes().map(Mesh::triangle_count).sum()
    }

    /// The linear RGB albedo (material base colour) of every triangle of
    /// [`Scene::world_triangles`], in the same order; a mesh whose material index is out of
    /// range gets the default material's.
    /// Materials do not move: `_t` only mirrors [`Scene::world_triangles`]' call, and no pose
    /// is computed.
    pub fn world_triangle_albedo(&self, _t: f32) -> Vec<Vec3> {
        self.instance_meshes()
            .flat_map(|mesh| {
                let c = self
                    .materials
                    .get(mesh.material)
                    .copied()
                    .unwrap_or_default()
                    .base_color;
                std::iter::repeat_n(Vec3::new(c[0], c[1], c[2]), mesh.triangles().count())
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animation::AnimatedTransform;

    fn one_triangle_scene(animation: Option<Animation>) -> Scene {
        let mesh = Mesh {
            name: "tri".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            indices: vec![0, 1, 2, 0, 1, 7],
            material: 0,
            skin_weights: Vec::new(),
        };
        let instance = match animation {
            Some(a) => Instance::animated(0, a),
            None => Instance::fixed(0, Mat4::from_translation(Vec3::Z)),
        };
        Scene {
            meshes: vec![mesh],
            materials: vec![Material::default()],
            instances: vec![instance, Instance::fixed(5, Mat4::IDENTITY)],
            camera: Camera::perspective(Vec3::Z * 5.0, Vec3::ZERO, 1.0, 0.1, 100.0),
            camera_motion: None,
            cameras: Vec::new(),
            light: DirectionalLight::default(),
            ambient: DEFAULT_AMBIENT,
        }
    }

    #[test]
    fn world_triangles_skip_bad_indices_and_missing_meshes() {
        let scene = one_triangle_scene(None);
        let tris = scene.world_triangles(0.0);
        assert_eq!(tris.len(), 1);
        assert_eq!(tris[0][1], Vec3::new(1.0, 0.0, 1.0));
        assert!(scene.is_static());
        let normals = scene.world_vertex_normals(0.0);
        assert_eq!(normals, vec![[Vec3::Z; 3]]);
    }

    #[test]
    fn world_vertex_normals_follow_the_inverse_transpose() {
        // A 45-degree normal under scale (1, 8, 1) must become (1, 1/8, 0) normalised, not
        // (1, 8, 0) normalised as the model matrix itself would make it.
        let mut scene = one_triangle_scene(None);
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        scene.meshes[0].normals = vec![n; 3];
        scene.instances[0].transform = Mat4::from_scale(Vec3::new(1.0, 8.0, 1.0));
        let got = scene.world_vertex_normals(0.0)[0][0];
        let want = Vec3::new(1.0, 0.125, 0.0).normalize();
        assert!((got - want).length() < 1e-6, "{got}");
    }

    #[test]
    fn moving_instance_makes_scene_animated() {
        let animation = Animation::new(vec![AnimatedTransform::Oscillate {
            from: Vec3::ZERO,
            to: Vec3::X,
            period: 2.0,
        }]);
        let scene = one_triangle_scene(Some(animation));
        assert!(!scene.is_static());
        let moved = scene.world_triangles(1.0);
        assert!((moved[0][0] - Vec3::X).length() < 1e-5);
        assert_eq!(scene.instances[0].transform, Mat4::IDENTITY);
    }
}
