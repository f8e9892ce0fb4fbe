//! glTF 2.0 import: `.gltf` (embedded base64 or external buffers) and `.glb` into a [`Scene`].
//!
//! What is read: the default scene (else the first; else, or when it lists no nodes, every
//! root node), EXT_mesh_gpu_instancing copies, the node hierarchy
//! with parent transforms accumulated, triangle primitives (positions, normals, indices or
//! none), base colour factors, every camera node in depth-first order (named after its node,
//! else its camera, else "camera N"; the first is the default camera; its world transform
//! places it), and translation/rotation/scale node animations of the first clip (as instance
//! and camera animations), and skins (JOINTS_0 / WEIGHTS_0, inverse bind matrices, joints
//! animated by the same clip: see `crate::skin`; the skinned node's own transform is ignored,
//! as glTF specifies).
//! Optimised files read as their originals: KHR_mesh_quantization, EXT_meshopt_compression,
//! sparse accessors and accessors without a buffer view (`accessor_reader`, `meshopt_views`);
//! which extensions are read, ignored or refused is decided once, in `document`.
//! What is not: images and textures (never loaded; missing image files, or images in KTX2 or
//! WebP, only cause a warning, since AO needs no textures), morph targets, lights. Non-triangle primitives (points, lines, line loops,
//! line strips) are skipped with a warning; triangle strips and fans are converted to lists.
//! Warnings go to stderr from [`load_scene`]; [`import_gltf`] returns them instead.
//! Without a camera in the file, the default camera is the automatic one (see
//! [`crate::views::default_camera`]: an interior view of an enclosed scene, else an outside
//! view fitting the bounding sphere). Invariant: a returned scene has at least one triangle, finite
//! positions and in-range indices; anything else is a [`SceneError`] naming the file.

mod accessor_reader;
mod buffers;
mod document;
mod glb_container;
mod lenient_json;
mod mesh_instancing;
mod meshopt_views;
mod node_animation;
mod primitive_reader;
mod skin_reader;
mod validation_report;

use crate::animation::{AnimatedTransform, Animation, TrsKeyframes};
use crate::camera::{Camera, CameraMotion, Projection};
use crate::error::SceneError;
use crate::model::{
    DEFAULT_AMBIENT, DirectionalLight, Instance, Material, Mesh, NamedCamera, Scene,
};
use crate::skin::Skin;
use glam::{Mat4, Vec3};
use primitive_reader::PrimitiveOutcome;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// A scene read from a glTF file and the warnings met on the way.
#[derive(Clone, Debug)]
pub struct GltfImport {
    /// The imported scene: at least one triangle, finite positions, in-range indices.
    pub scene: Scene,
    /// Things skipped or approximated, one sentence each (without the file name).
    pub warnings: Vec<String>,
    /// What the file holds, for `aograph scene info`.
    pub info: GltfInfo,
}

/// What a glTF file holds, as `aograph scene info` reports it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GltfInfo {
    /// Nodes in the file (all of them, placed or not).
    pub nodes: usize,
    /// glTF meshes (each may hold several primitives).
    pub meshes: usize,
    /// Every material in the file, in file order, whether used or not.
    pub materials: Vec<MaterialInfo>,
    /// Skins: name and joint count.
    pub skins: Vec<(String, usize)>,
    /// The file's `extensionsUsed`, each with what aograph does with it.
    pub extensions: Vec<ExtensionUse>,
}

/// One extension a file uses, and what aograph does with it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtensionUse {
    /// The extension's name as in `extensionsUsed`, e.g. `KHR_mesh_quantization`.
    pub name: String,
    /// Listed in `extensionsRequired` too.
    pub required: bool,
    /// Whether aograph reads it, ignores it, or does not know it.
    pub handling: ExtensionHandling,
}

/// What aograph does with an extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExtensionHandling {
    /// Read: the geometry depends on it (KHR_mesh_quantization, EXT_meshopt_compression).
    Read,
    /// Not read, and cannot change AO (texture formats, materials, lights).
    Ignored,
    /// Not known to aograph: drawn without it when optional, refused when required.
    Unknown,
}

/// One glTF material's properties that matter to AO and shading.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialInfo {
    /// The material's name, or "material N" (its index) when it has none.
    pub name: String,
    /// Rendered from both sides (aograph draws every surface two-sided either way).
    pub double_sided: bool,
    /// "OPAQUE", "MASK" or "BLEND" (aograph treats every surface as opaque).
    pub alpha_mode: &'static str,
}

/// Loads a glTF 2.0 file (`.gltf` or `.glb`), printing warnings to stderr.
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
    let path = path.as_ref();
    let import = import_gltf(path)?;
    for warning in &import.warnings {
        eprintln!("warning: {}: {warning}", path.display());
    }
    Ok(import.scene)
}

/// Upper bound on instances made by walking the node graph (guards against malicious files
/// where nodes are shared by many parents).
const MAX_INSTANCES: usize = 1_000_000;

/// Loads a glTF 2.0 file and returns the scene with its warnings.
pub fn import_gltf(path: impl AsRef<Path>) -> Result<GltfImport, SceneError> {
    let path = path.as_ref();
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(SceneError::MissingFile {
                path: path.to_owned(),
            });
        }
        Err(e) => return Err(SceneError::io("read", path, e)),
    };
    import_gltf_bytes(path, &bytes)
}

/// A glTF 2.0 file already in memory (a `.glb`, or a `.gltf` whose buffers are embedded as
/// data URIs: a web page's fetch, say), named `path` in messages. Buffers it names by a
/// relative URI are read beside `path`, so on a target without files they are refused by name.
pub fn import_gltf_bytes(path: &Path, bytes: &[u8]) -> Result<GltfImport, SceneError> {
    let parsed = document::parse(path, bytes)?;
    let gltf = gltf::Gltf {
        document: parsed.document,
        blob: parsed.blob,
    };
    let fallbacks = meshopt_views::fallback_buffers(&parsed.json);
    let uses = buffers::BufferUse {
        fallbacks: &fallbacks,
        read: &parsed.read_buffers,
        glb: parsed.glb,
    };
    let (mut buffers, buffer_warnings) =
        buffers::load_buffers(path, &gltf.document, gltf.blob.clone(), &uses)?;
    meshopt_views::decode_views(&parsed.json, &mut buffers).map_err(|message| {
        SceneError::InvalidGltf {
            path: path.to_owned(),
            message,
        }
    })?;
    let mut warnings = parsed.warnings;
    warnings.extend(buffer_warnings);
    let missing = buffers::missing_images(path, &gltf.document);
    if !missing.is_empty() {
        warnings.push(format!(
            "{} referenced image file(s) not found ({}); AO needs no textures, continuing",
            missing.len(),
            missing.join(", ")
        ));
    }
    let (animated_nodes, animation_warnings) =
        node_animation::read_node_animations(&gltf.document, &buffers);
    warnings.extend(animation_warnings);
    let skins =
        skin_reader::read_skins(&gltf.document, &buffers, &animated_nodes).map_err(|message| {
            SceneError::InvalidGltf {
                path: path.to_owned(),
                message,
            }
        })?;

    let instancing = mesh_instancing::read_instances(&parsed.json, &gltf.document, &buffers)
        .map_err(|message| SceneError::InvalidGltf {
            path: path.to_owned(),
            message,
        })?;
    let mut walk = NodeWalk {
        path,
        buffers: &buffers,
        animated_nodes: &animated_nodes,
        skins: &skins,
        instancing: &instancing,
        materials: gltf
            .document
            .materials()
            .map(|m| Material {
                base_color: m.pbr_metallic_roughness().base_color_factor(),
            })
            .collect(),
        default_material: None,
        meshes: Vec::new(),
        mesh_map: HashMap::new(),
        instances: Vec::new(),
        cameras: Vec::new(),
        warnings,
        node_count: gltf.document.nodes().count(),
    };
    let roots: Vec<gltf::Node<'_>> = match gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next())
    {
        Some(scene) if scene.nodes().next().is_some() => scene.nodes().collect(),
        Some(scene) => {
            walk.warnings.push(format!(
                "scene {} lists no nodes: every root node is drawn instead",
                scene.index()
            ));
            root_nodes(&gltf.document)
        }
        None => root_nodes(&gltf.document),
    };
    for root in roots {
        walk.visit(&root, &[], 0)?;
    }

    let NodeWalk {
        meshes,
        instances,
        materials,
        cameras,
        warnings,
        ..
    } = walk;
    let info = GltfInfo {
        nodes: gltf.document.nodes().count(),
        meshes: gltf.document.meshes().count(),
        materials: gltf
            .document
            .materials()
            .map(|m| MaterialInfo {
                name: m.name().map_or_else(
                    || format!("material {}", m.index().unwrap_or(0)),
                    str::to_owned,
                ),
                double_sided: m.double_sided(),
                alpha_mode: match m.alpha_mode() {
                    gltf::material::AlphaMode::Opaque => "OPAQUE",
                    gltf::material::AlphaMode::Mask => "MASK",
                    gltf::material::AlphaMode::Blend => "BLEND",
                },
            })
            .collect(),
        skins: skins
            .iter()
            .map(|s| (s.name.clone(), s.joints.len()))
            .collect(),
        extensions: document::extension_uses(&parsed.json),
    };
    let mut scene = Scene {
        meshes,
        materials,
        instances,
        // Replaced below, once the bounds are known.
        camera: crate::views::outside_camera(&crate::bounds::Aabb::EMPTY),
        camera_motion: None,
        cameras,
        light: DirectionalLight::default(),
        ambient: DEFAULT_AMBIENT,
    };
    if scene.triangle_count() == 0 {
        return Err(SceneError::EmptyScene {
            path: path.to_owned(),
        });
    }
    match scene.cameras.first() {
        Some(first) => {
            scene.camera = first.camera;
            scene.camera_motion = first.motion.clone();
        }
        None => scene.camera = crate::views::default_camera(&scene),
    }
    Ok(GltfImport {
        scene,
        warnings,
        info,
    })
}

/// Nodes that are nobody's child (used when the file has no scene).
fn root_nodes(document: &gltf::Document) -> Vec<gltf::Node<'_>> {
    let mut is_child = vec![false; document.nodes().count()];
    for node in document.nodes() {
        for child in node.children() {
            if let Some(flag) = is_child.get_mut(child.index()) {
                *flag = true;
            }
        }
    }
    document
        .nodes()
        .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
        .collect()
}

/// One entry of the path from a root to a node: its local transform, animated or not.
#[derive(Clone)]
enum ChainLink {
    Static(Mat4),
    Animated(TrsKeyframes),
}

/// Node `node`'s own link: its keyframes if the first clip animates it, else its local matrix
/// (`Err` when that is not finite).
fn node_link(
    node: &gltf::Node<'_>,
    animated_nodes: &BTreeMap<usize, TrsKeyframes>,
) -> Result<ChainLink, String> {
    if let Some(keys) = animated_nodes.get(&node.index()) {
        return Ok(ChainLink::Animated(keys.clone()));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    if !local.is_finite() {
        return Err(format!(
            "node {} has a transform that is not finite (a value overflows a 32-bit float)",
            node.index()
        ));
    }
    Ok(ChainLink::Static(local))
}

/// Parent-first chain of local transforms as an [`Animation`] if any link moves (adjacent
/// static links are multiplied together), else the fixed world matrix.
fn chain_transform(chain: &[ChainLink]) -> Result<Animation, Mat4> {
    let mut layers = Vec::new();
    let mut fixed = Mat4::IDENTITY;
    for link in chain {
        match link {
            ChainLink::Static(m) => fixed *= *m,
            ChainLink::Animated(keys) => {
                if fixed != Mat4::IDENTITY {
                    layers.push(AnimatedTransform::Static(fixed));
                }
                fixed = Mat4::IDENTITY;
                layers.push(AnimatedTransform::Keyframes(keys.clone()));
            }
        }
    }
    if layers.is_empty() {
        return Err(fixed);
    }
    if fixed != Mat4::IDENTITY {
        layers.push(AnimatedTransform::Static(fixed));
    }
    Ok(Animation::new(layers))
}

/// State of the depth-first walk over the node hierarchy.
struct NodeWalk<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    animated_nodes: &'a BTreeMap<usize, TrsKeyframes>,
    /// Every skin of the file, by glTF skin index.
    skins: &'a [Skin],
    /// EXT_mesh_gpu_instancing transforms, by node index.
    instancing: &'a BTreeMap<usize, Vec<Mat4>>,
    materials: Vec<Material>,
    default_material: Option<usize>,
    meshes: Vec<Mesh>,
    /// glTF mesh index -> indices of the meshes made from its primitives.
    mesh_map: HashMap<usize, Vec<usize>>,
    instances: Vec<Instance>,
    cameras: Vec<NamedCamera>,
    warnings: Vec<String>,
    node_count: usize,
}

impl NodeWalk<'_> {
    fn invalid(&self, message: String) -> SceneError {
        SceneError::InvalidGltf {
            path: self.path.to_owned(),
            message,
        }
    }

    fn visit(
        &mut self,
        node: &gltf::Node<'_>,
        parents: &[ChainLink],
        depth: usize,
    ) -> Result<(), SceneError> {
        if depth > self.node_count {
            return Err(self.invalid(format!(
                "the node hierarchy has a cycle through node {}",
                node.index()
            )));
        }
        let mut chain = parents.to_vec();
        chain.push(node_link(node, self.animated_nodes).map_err(|m| self.invalid(m))?);
        if let Some(mesh) = node.mesh() {
            let meshes = self.meshes_of(&mesh)?;
            // EXT_mesh_gpu_instancing: one copy per instance transform, applied before the
            // node's own (see `mesh_instancing`); a node without it is one copy.
            let copies: Vec<Option<Mat4>> = match self.instancing.get(&node.index()) {
                Some(transforms) => transforms.iter().copied().map(Some).collect(),
                None => vec![None],
            };
            if self.instances.len() + meshes.len() * copies.len() > MAX_INSTANCES {
                return Err(self.invalid(format!(
                    "the node hierarchy makes more than {MAX_INSTANCES} mesh instances"
                )));
            }
            let skin = node.skin().and_then(|s| self.skins.get(s.index()));
            for index in meshes {
                if let Some(instance) = self.skinned_instance(node, index, skin)? {
                    self.instances.push(instance);
                    continue;
                }
                for copy in &copies {
                    let mut placed = chain.clone();
                    placed.extend(copy.map(ChainLink::Static));
                    let instance = match chain_transform(&placed) {
                        Ok(animation) => Instance::animated(index, animation),
                        Err(matrix) => Instance::fixed(index, matrix),
                    };
                    if !instance.transform.is_finite() {
                        return Err(self.invalid(format!(
                            "node {}'s world transform is not finite (its parents' scales overflow a 32-bit float)",
                            node.index()
                        )));
                    }
                    self.instances.push(instance);
                }
            }
        }
        if let Some(camera) = node.camera() {
            let (at_zero, motion) = camera_from_node(&camera, &chain);
            let name = node
                .name()
                .or_else(|| camera.name())
                .map_or_else(|| format!("camera {}", self.cameras.len()), str::to_owned);
            self.cameras.push(NamedCamera {
                name,
                camera: at_zero,
                motion,
            });
        }
        for child in node.children() {
            self.visit(&child, &chain, depth + 1)?;
        }
        Ok(())
    }

    /// The instance of scene mesh `mesh` deformed by `skin`, when the node has a skin and the
    /// mesh has weights (a skin without weights to follow is a warning, the mesh drawn rigid);
    /// `Err` when a weight names a joint the skin does not have.
    fn skinned_instance(
        &mut self,
        node: &gltf::Node<'_>,
        mesh: usize,
        skin: Option<&Skin>,
    ) -> Result<Option<Instance>, SceneError> {
        let Some(skin) = skin else {
            return Ok(None);
        };
        let weights = &self.meshes[mesh].skin_weights;
        if weights.is_empty() {
            self.warnings.push(format!(
                "node {} has {} but mesh \"{}\" has no JOINTS_0 / WEIGHTS_0: drawn unskinned",
                node.index(),
                skin.name,
                self.meshes[mesh].name
            ));
            return Ok(None);
        }
        let joints = skin.joints.len();
        if let Some((vertex, w)) = weights
            .iter()
            .enumerate()
            .find(|(_, w)| w.joints.iter().any(|&j| j as usize >= joints))
        {
            return Err(self.invalid(format!(
                "mesh \"{}\" vertex {vertex} names joints {:?}, but {} (node {}) has {joints} joints",
                self.meshes[mesh].name,
                w.joints,
                skin.name,
                node.index()
            )));
        }
        if skin.palette(0.0).iter().any(|m| !m.is_finite()) {
            return Err(self.invalid(format!(
                "{} (node {}): a joint's world transform is not finite (its parents' scales overflow a 32-bit float)",
                skin.name,
                node.index()
            )));
        }
        Ok(Some(Instance::skinned(mesh, skin.clone())))
    }

    /// Indices of the scene meshes made from glTF mesh `mesh`, reading it on first use.
    fn meshes_of(&mut self, mesh: &gltf::Mesh<'_>) -> Result<Vec<usize>, SceneError> {
        if let Some(known) = self.mesh_map.get(&mesh.index()) {
            return Ok(known.clone());
        }
        let name = mesh
            .name()
            .map_or_else(|| format!("mesh {}", mesh.index()), str::to_owned);
        let mut made = Vec::new();
        for primitive in mesh.primitives() {
            let material = match primitive.material().index() {
                Some(i) if i < self.materials.len() => i,
                _ => *self.default_material.get_or_insert_with(|| {
                    self.materials.push(Material::default());
                    self.materials.len() - 1
                }),
            };
            match primitive_reader::read_primitive(
                self.path,
                self.buffers,
                &name,
                &primitive,
                material,
            )? {
                PrimitiveOutcome::Mesh(m, warnings) => {
                    self.warnings.extend(warnings);
                    self.meshes.push(m);
                    made.push(self.meshes.len() - 1);
                }
                PrimitiveOutcome::Skipped(reason) => self.warnings.push(reason),
            }
        }
        self.mesh_map.insert(mesh.index(), made.clone());
        Ok(made)
    }
}

/// The scene camera for a glTF camera at the end of `chain`.
fn camera_from_node(
    camera: &gltf::Camera<'_>,
    chain: &[ChainLink],
) -> (Camera, Option<CameraMotion>) {
    let projection = match camera.projection() {
        gltf::camera::Projection::Perspective(p) => Projection::Perspective {
            fov_y: p.yfov(),
            near: p.znear(),
            far: p.zfar().unwrap_or(f32::INFINITY),
            reversed_z_infinite: p.zfar().is_none(),
        },
        gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
            height: 2.0 * o.ymag().abs(),
            near: o.znear(),
            far: o.zfar(),
        },
    };
    let base = Camera {
        position: Vec3::ZERO,
        target: Vec3::NEG_Z,
        up: Vec3::Y,
        projection,
    };
    let (animation, motion) = match chain_transform(chain) {
        Ok(animation) => (animation.clone(), Some(CameraMotion::Node(animation))),
        Err(matrix) => (
            Animation::new(vec![AnimatedTransform::Static(matrix)]),
            None,
        ),
    };
    let camera = CameraMotion::Node(animation).camera_at(&base, 0.0);
    (camera, motion)
}
