//! Assembles a [`Scene`] piece by piece: materials, meshes and their placements.
//!
//! Invariant: every index the builder hands out (material, mesh) refers to an entry it holds,
//! and a mesh added with [`SceneBuilder::add`] gets a valid material index, so a built scene
//! never has a dangling reference.

use crate::animation::Animation;
use crate::camera::Camera;
use crate::model::{DEFAULT_AMBIENT, DirectionalLight, Instance, Material, Mesh, Scene};
use glam::Mat4;

/// Collects materials, meshes and instances, then [`SceneBuilder::build`]s a [`Scene`].
#[derive(Clone, Debug, Default)]
pub struct SceneBuilder {
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    instances: Vec<Instance>,
}

impl SceneBuilder {
    /// An empty builder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an opaque material of linear RGB `color`; returns its index.
    pub fn material(&mut self, color: [f32; 3]) -> usize {
        self.materials.push(Material {
            base_color: [color[0], color[1], color[2], 1.0],
        });
        self.materials.len() - 1
    }

    /// Adds a mesh (its material index is clamped to an existing material, creating a default
    /// material if there is none); returns its index.
    pub fn mesh(&mut self, mut mesh: Mesh) -> usize {
        if self.materials.is_empty() {
            self.materials.push(Material::default());
        }
        mesh.material = mesh.material.min(self.materials.len() - 1);
        self.meshes.push(mesh);
        self.meshes.len() - 1
    }

    /// Places mesh `mesh` (an index from [`SceneBuilder::mesh`]) with a fixed transform.
    pub fn place(&mut self, mesh: usize, transform: Mat4) {
        self.instances.push(Instance::fixed(mesh, transform));
    }

    /// Places mesh `mesh` with a transform over time.
    pub fn place_animated(&mut self, mesh: usize, animation: Animation) {
        self.instances.push(Instance::animated(mesh, animation));
    }

    /// Adds `mesh` and places it once; returns the mesh index.
    pub fn add(&mut self, mesh: Mesh, transform: Mat4) -> usize {
        let index = self.mesh(mesh);
        self.place(index, transform);
        index
    }

    /// Adds `mesh` as a backdrop (a stand-in for an unbounded floor or wall, see
    /// [`Instance::backdrop`]) placed once; returns the mesh index.
    pub fn add_backdrop(&mut self, mesh: Mesh, transform: Mat4) -> usize {
        let index = self.mesh(mesh);
        self.instances.push(Instance {
            backdrop: true,
            ..Instance::fixed(index, transform)
        });
        index
    }

    /// The number of triangles placed so far.
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .filter_map(|i| self.meshes.get(i.mesh))
            .map(Mesh::triangle_count)
            .sum()
    }

    /// The scene seen from `camera`, with the default light and ambient and no camera motion.
    pub fn build(self, camera: Camera) -> Scene {
        Scene {
            meshes: self.meshes,
            materials: self.materials,
            instances: self.instances,
            camera,
            camera_motion: None,
            cameras: Vec::new(),
            light: DirectionalLight::default(),
            ambient: DEFAULT_AMBIENT,
        }
    }
}
