//! aograph scenes and their geometry on the CPU: the scene model, glTF 2.0 import (every index
//! checked, malformed files refused by name, never a panic) and export, procedural test scenes,
//! cameras and the view heuristics (`views`), and the CPU ray queries the heuristics and the
//! reference share: the two-level [`SceneRays`] and flat [`TriangleBvh`], primary hits, and
//! the ray-traced ambient-occlusion integrator every screen-space technique is measured
//! against ([`trace_reference`]). The reference's cache, ceilings and radiance, and the GPU ray
//! tracers, are `aograph-tracing`'s; the g-buffer node is `aograph-renderer`'s.
//!
//! Conventions shared with the rest of aograph (docs/guide/render-graph.md): world units
//! are scene units, right-handed with +Y up, counter-clockwise front faces; accessibility is in
//! [0, 1] with 1 = unoccluded; sky pixels get exactly 1; nothing returns NaN or infinity.
//!
//! # Example
//!
//! Build a procedural scene, resolve the automatic AO radius, and trace a small CPU reference
//! from the scene's own camera (no GPU needed; [`load_scene`] reads a glTF file instead):
//!
//! ```
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use aograph_scene::reference::ProgressMode;
//! use aograph_scene::{ReferenceParams, TriangleBvh, primary_hits, trace_reference};
//!
//! let scene = aograph_scene::procedural_scene("columns")?;
//! let radius = aograph_scene::suggested_radius(&scene);
//! println!(
//!     "{} triangles, camera at {} looking at {}, R = {} ({})",
//!     scene.triangle_count(),
//!     scene.camera.position,
//!     scene.camera.target,
//!     radius.radius,
//!     radius.derivation,
//! );
//!
//! // The world-space surface under each pixel of a 32x18 view at t = 0 (CPU primary rays),
//! // then 16 cosine-weighted rays per pixel against the scene's triangles.
//! let surfaces = primary_hits(&scene, &scene.camera, 32, 18, 0.0);
//! let bvh = TriangleBvh::new(&scene.world_triangles(0.0));
//! let params = ReferenceParams {
//!     radius: radius.radius,
//!     rays_per_pixel: 16,
//!     progress: ProgressMode::Never,
//!     ..Default::default()
//! };
//! let reference = trace_reference(&bvh, &surfaces, &params)?;
//! let centre = reference.at(16, 9).expect("inside the image");
//! assert!((0.0..=1.0).contains(&centre));
//! println!("accessibility at the centre: {centre:.3}");
//! # Ok(())
//! # }
//! ```

#![warn(missing_docs)]

pub mod animation;
mod atomic_file;
pub mod bounds;
pub mod camera;
pub mod environment;
pub mod error;
pub mod gltf_export;
pub mod gltf_import;
pub mod model;
pub mod normal_transform;
pub mod pose;
pub mod primitives;
pub mod procedural;
pub mod projected_radius;
pub mod radius;
pub mod reference;
pub mod scene_builder;
pub mod skin;
pub mod test_scenes;
pub mod view_block;
pub mod view_radius;
pub mod views;

pub use animation::{AnimatedTransform, Animation, Interpolation, Track, TrsKeyframes};
pub use bounds::Aabb;
pub use camera::{Camera, CameraMotion, CameraRay, Projection};
pub use environment::{SkyEnvironment, SkyIrradiance};
pub use error::SceneError;
pub use gltf_export::export_glb;
pub use gltf_import::{
    ExtensionHandling, ExtensionUse, GltfImport, GltfInfo, MaterialInfo, import_gltf,
    import_gltf_bytes, load_scene,
};
pub use model::{DEFAULT_AMBIENT, DirectionalLight, Instance, Material, Mesh, NamedCamera, Scene};
pub use normal_transform::{normal_matrix, transform_normal};
pub use procedural::{PROCEDURAL_SCENE_NAMES, procedural_scene};
pub use projected_radius::{ProjectedRadius, projected_radius};
pub use radius::{SuggestedRadius, suggested_radius};
pub use reference::{
    BruteForceTracer, CpuGBuffer, RayQueries, ReferenceImage, ReferenceMode, ReferenceNormals,
    ReferenceParams, ReferenceTracer, SceneRays, SurfaceBuffer, TriangleBvh, primary_hits,
    trace_reference, trace_reference_rows,
};
pub use scene_builder::SceneBuilder;
pub use skin::{Joint, JointWeights, Skin};
pub use test_scenes::{TEST_SCENES, test_scene};
pub use view_radius::{ViewRadius, is_interior_view, view_radius};
