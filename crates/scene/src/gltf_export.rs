//! glTF 2.0 binary (.glb) export of a scene, e.g. to view a procedural scene in another tool or
//! to test the importer on files with known content.
//!
//! What is written: one node per instance (its t = 0 object-to-world matrix), one mesh per
//! scene mesh that has triangles (POSITION with min/max, NORMAL when the mesh has one per
//! vertex, u32 indices), materials with baseColorFactor (metallic 0, roughness 1), and the t = 0
//! camera as a camera node (a reversed-Z infinite perspective is written without zfar).
//! A skinned instance is written as a mesh of its own, posed at t = 0 in world space (the
//! skeleton is not exported).
//! Not written: animations, skins, camera motion, the light and ambient (glTF has no ambient).
//! Invariants: the file is a valid glb (12-byte header, JSON chunk padded with spaces and BIN
//! chunk padded with zeros to 4 bytes, every buffer view 4-byte aligned); it is written to a
//! temporary file in the same directory and renamed, so a failed export leaves no partial file;
//! non-finite positions are refused with an error naming the mesh.

use crate::atomic_file::write_atomically;
use crate::camera::{Camera, Projection};
use crate::error::SceneError;
use crate::model::{Mesh, Scene};
use glam::{Mat4, Vec3};
use serde_json::{Value, json};
use std::path::Path;

const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;

/// Buffer views and accessors being laid out in one BIN buffer.
#[derive(Default)]
struct BinLayout {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl BinLayout {
    /// Appends `bytes` as a buffer view and an accessor over it; returns the accessor index.
    fn push(&mut self, bytes: &[u8], target: u32, accessor: Value) -> usize {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": bytes.len(),
            "target": target,
        }));
        let mut accessor = accessor;
        accessor["bufferView"] = json!(self.views.len() - 1);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn push_vec3s(&mut self, values: &[Vec3], with_bounds: bool) -> usize {
        let floats: Vec<f32> = values.iter().flat_map(|v| v.to_array()).collect();
        let mut accessor = json!({"componentType": FLOAT, "count": values.len(), "type": "VEC3"});
        if with_bounds {
            let min = values.iter().copied().fold(Vec3::INFINITY, Vec3::min);
            let max = values.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
            accessor["min"] = json!(min.to_array());
            accessor["max"] = json!(max.to_array());
        }
        self.push(bytemuck::cast_slice(&floats), ARRAY_BUFFER, accessor)
    }
}

/// The camera-to-world matrix of `camera` (glTF cameras look down their local -Z).
fn camera_matrix(camera: &Camera) -> Mat4 {
    let (right, up, forward) = camera.basis();
    Mat4::from_cols(
        right.extend(0.0),
        up.extend(0.0),
        (-forward).extend(0.0),
        camera.position.extend(1.0),
    )
}

/// The glTF camera object for `camera`.
fn camera_json(camera: &Camera) -> Value {
    let (near, far) = (camera.near(), camera.far());
    match camera.projection {
        Projection::Perspective { fov_y, .. } => {
            let yfov = if fov_y.is_finite() && fov_y > 0.0 {
                fov_y
            } else {
                std::f32::consts::FRAC_PI_4
            };
            let mut perspective = json!({"yfov": yfov, "znear": near});
            if far.is_finite() {
                perspective["zfar"] = json!(far);
            }
            json!({"type": "perspective", "perspective": perspective})
        }
        Projection::Orthographic { height, .. } => {
            let half = if height.is_finite() && height > 0.0 {
                0.5 * height
            } else {
                0.5
            };
            let far = if far.is_finite() { far } else { near + 1e6 };
            json!({"type": "orthographic",
                   "orthographic": {"xmag": half, "ymag": half, "znear": near, "zfar": far}})
        }
    }
}

/// The glTF primitive of `mesh`, laid out in `layout`, or `None` if it has no triangle.
fn mesh_json(layout: &mut BinLayout, mesh: &Mesh, material_count: usize) -> Option<Value> {
    if mesh.indices.len() < 3 || mesh.positions.is_empty() {
        return None;
    }
    let indices = &mesh.indices[..mesh.indices.len() / 3 * 3];
    let position = layout.push_vec3s(&mesh.positions, true);
    let mut attributes = json!({"POSITION": position});
    if mesh.normals.len() == mesh.positions.len() {
        attributes["NORMAL"] = json!(layout.push_vec3s(&mesh.normals, false));
    }
    let index_accessor = layout.push(
        bytemuck::cast_slice(indices),
        ELEMENT_ARRAY_BUFFER,
        json!({"componentType": UNSIGNED_INT, "count": indices.len(), "type": "SCALAR"}),
    );
    let mut primitive =
        json!({"attributes": attributes, "indices": index_accessor, "mode": TRIANGLES});
    if mesh.material < material_count {
        primitive["material"] = json!(mesh.material);
    }
    Some(json!({"name": mesh.name, "primitives": [primitive]}))
}

/// Checks that `scene` can be written: finite positions and indices in range.
fn check_exportable(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    let refuse = |message: String| SceneError::Export {
        path: path.to_owned(),
        message,
    };
    for mesh in &scene.meshes {
        if let Some(vertex) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(refuse(format!(
                "mesh \"{}\" has a non-finite position at vertex {vertex}",
                mesh.name
            )));
        }
        if let Some(bad) = mesh
            .indices
            .iter()
            .find(|&&i| i as usize >= mesh.positions.len())
        {
            return Err(refuse(format!(
                "mesh \"{}\" has index {bad}, past its {} vertices",
                mesh.name,
                mesh.positions.len()
            )));
        }
    }
    Ok(())
}

/// The complete .glb file bytes for `scene`.
pub fn glb_bytes(scene: &Scene, path_for_errors: &Path) -> Result<Vec<u8>, SceneError> {
    check_exportable(scene, path_for_errors)?;
    let mut layout = BinLayout::default();
    let mut meshes = Vec::new();
    let mut mesh_index = Vec::with_capacity(scene.meshes.len());
    for mesh in &scene.meshes {
        let made = mesh_json(&mut layout, mesh, scene.materials.len());
        mesh_index.push(made.as_ref().map(|_| meshes.len()));
        meshes.extend(made);
    }
    let mut nodes: Vec<Value> = Vec::with_capacity(scene.instances.len() + 1);
    for (i, instance) in scene.instances.iter().enumerate() {
        let skinned = scene
            .meshes
            .get(instance.mesh)
            .is_some_and(|m| instance.skin_for(m).is_some());
        if skinned {
            let Some(posed) = scene.posed_mesh(i, 0.0) else {
                continue;
            };
            let Some(made) = mesh_json(&mut layout, &posed, scene.materials.len()) else {
                continue;
            };
            meshes.push(made);
            nodes.push(json!({"mesh": meshes.len() - 1}));
            continue;
        }
        let Some(mesh) = mesh_index.get(instance.mesh).copied().flatten() else {
            continue;
        };
        let matrix = instance.transform_at(0.0);
        if matrix.is_finite() {
            nodes.push(json!({"mesh": mesh, "matrix": matrix.to_cols_array()}));
        }
    }
    let camera = scene.camera_at(0.0);
    nodes.push(
        json!({"name": "camera", "camera": 0, "matrix": camera_matrix(&camera).to_cols_array()}),
    );
    let materials: Vec<Value> = scene
        .materials
        .iter()
        .map(|m| {
            json!({"pbrMetallicRoughness": {
                "baseColorFactor": m.base_color.map(|c| if c.is_finite() { c.clamp(0.0, 1.0) } else { 1.0 }),
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
            }})
        })
        .collect();
    let mut root = json!({
        "asset": {"version": "2.0", "generator": "aograph-scene"},
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "cameras": [camera_json(&camera)],
    });
    if !meshes.is_empty() {
        root["meshes"] = json!(meshes);
        root["accessors"] = json!(layout.accessors);
        root["bufferViews"] = json!(layout.views);
        root["buffers"] = json!([{"byteLength": layout.bin.len()}]);
    }
    if !materials.is_empty() {
        root["materials"] = json!(materials);
    }
    let mut json_chunk = serde_json::to_vec(&root).map_err(|e| SceneError::Export {
        path: path_for_errors.to_owned(),
        message: format!("could not serialise the glTF JSON: {e}"),
    })?;
    while !json_chunk.len().is_multiple_of(4) {
        json_chunk.push(b' ');
    }
    let bin_chunk = layout.bin;
    let chunk_header = 8;
    let total = 12
        + chunk_header
        + json_chunk.len()
        + if bin_chunk.is_empty() {
            0
        } else {
            chunk_header + bin_chunk.len()
        };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json_chunk);
    if !bin_chunk.is_empty() {
        out.extend_from_slice(&(bin_chunk.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin_chunk);
    }
    Ok(out)
}

/// Writes `scene` as a .glb file at `path` (atomically: temporary file, then rename).
pub fn export_glb(scene: &Scene, path: impl AsRef<Path>) -> Result<(), SceneError> {
    let path = path.as_ref();
    let bytes = glb_bytes(scene, path)?;
    write_atomically(path, &bytes)
}
