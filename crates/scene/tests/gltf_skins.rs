//! glTF skins: a two-joint bar whose answers are known in closed form (linear blend skinning of
//! a quarter turn), the skinned node's own transform ignored, the errors and warnings of bad
//! skins, and CesiumMan walking.

mod common;

use aograph_scene::{SceneError, import_gltf, load_scene};
use common::{base64, temp_dir};
use glam::{Quat, Vec3};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// A glTF being written: JSON plus one embedded buffer.
struct GltfWriter {
    json: Value,
    bin: Vec<u8>,
}

impl GltfWriter {
    fn new() -> Self {
        GltfWriter {
            json: json!({"asset": {"version": "2.0"}, "bufferViews": [], "accessors": []}),
            bin: Vec::new(),
        }
    }

    /// Appends `bytes` as a buffer view and an accessor described by `accessor` (its
    /// bufferView is filled in); returns the accessor index.
    fn push(&mut self, bytes: &[u8], mut accessor: Value) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let views = self.json["bufferViews"].as_array_mut().unwrap();
        views.push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        accessor["bufferView"] = json!(views.len() - 1);
        self.bin.extend_from_slice(bytes);
        let accessors = self.json["accessors"].as_array_mut().unwrap();
        accessors.push(accessor);
        accessors.len() - 1
    }

    fn floats(&mut self, values: &[f32], kind: &str, components: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|f| f.to_le_bytes()).collect();
        let mut accessor =
            json!({"componentType": 5126, "count": values.len() / components, "type": kind});
        if kind == "VEC3" || kind == "SCALAR" {
            let column = |k: usize| values.iter().skip(k).step_by(components).copied();
            let min: Vec<f32> = (0..components)
                .map(|k| column(k).fold(f32::INFINITY, f32::min))
                .collect();
            let max: Vec<f32> = (0..components)
                .map(|k| column(k).fold(f32::NEG_INFINITY, f32::max))
                .collect();
            accessor["min"] = json!(min);
            accessor["max"] = json!(max);
        }
        self.push(&bytes, accessor)
    }

    fn u16s(&mut self, values: &[u16], kind: &str, components: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.push(
            &bytes,
            json!({"componentType": 5123, "count": values.len() / components, "type": kind}),
        )
    }

    fn write(mut self, dir: &Path, name: &str) -> PathBuf {
        let encoded = base64(&self.bin);
        self.json["buffers"] = json!([{
            "byteLength": self.bin.len(),
            "uri": format!("data:application/octet-stream;base64,{encoded}"),
        }]);
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_vec_pretty(&self.json).unwrap()).unwrap();
        path
    }
}

/// What to break in [`skinned_bar`].
#[derive(Default)]
struct Breakage {
    joint_out_of_range: bool,
    no_weights: bool,
    zero_weight_vertex: bool,
    no_inverse_bind: bool,
    /// No NORMAL: the importer un-indexes the primitive for flat normals.
    no_normals: bool,
}

/// A vertical bar 0.2 wide and 2 high, facing +Z, in three rows of two vertices: y = 0 on
/// joint 0, y = 1 half on each joint, y = 2 on joint 1. Joint 0 ("hip") is at the origin of
/// an "armature" node translated (0, 0, 3); joint 1 ("knee") is its child at (0, 1, 0) and
/// turns a quarter about +X from t = 0 to t = 1. The mesh node is translated (5, 0, 0), which
/// glTF says to ignore for a skinned mesh.
fn skinned_bar(dir: &Path, name: &str, breakage: Breakage) -> PathBuf {
    let mut w = GltfWriter::new();
    let positions: Vec<f32> = [0.0f32, 1.0, 2.0]
        .iter()
        .flat_map(|&y| [-0.1, y, 0.0, 0.1, y, 0.0])
        .collect();
    let position = w.floats(&positions, "VEC3", 3);
    let normal = w.floats(&[0.0, 0.0, 1.0].repeat(6), "VEC3", 3);
    let knee = if breakage.joint_out_of_range { 5 } else { 1 };
    let joints: Vec<u16> = [[0, 0], [0, knee], [knee, 0]]
        .iter()
        .flat_map(|&[a, b]| [a, b, 0, 0, a, b, 0, 0])
        .collect();
    let joints = w.u16s(&joints, "VEC4", 4);
    let bottom = if breakage.zero_weight_vertex {
        0.0
    } else {
        1.0
    };
    let weights = w.floats(
        &[
            [bottom, 0.0],
            [bottom, 0.0],
            [0.5, 0.5],
            [0.5, 0.5],
            [1.0, 0.0],
            [1.0, 0.0],
        ]
        .iter()
        .flat_map(|&[a, b]| [a, b, 0.0, 0.0])
        .collect::<Vec<_>>(),
        "VEC4",
        4,
    );
    let indices = w.u16s(&[0, 1, 3, 0, 3, 2, 2, 3, 5, 2, 5, 4], "SCALAR", 1);
    let inverse_binds: Vec<f32> = [Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0)]
        .iter()
        .flat_map(|t| glam::Mat4::from_translation(*t).to_cols_array())
        .collect();
    let inverse_binds = w.floats(&inverse_binds, "MAT4", 16);
    let times = w.floats(&[0.0, 1.0], "SCALAR", 1);
    let quarter = Quat::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let turns = w.floats(
        &[
            0.0, 0.0, 0.0, 1.0, quarter.x, quarter.y, quarter.z, quarter.w,
        ],
        "VEC4",
        4,
    );
    let mut attributes = json!({"POSITION": position, "JOINTS_0": joints});
    if !breakage.no_normals {
        attributes["NORMAL"] = json!(normal);
    }
    if !breakage.no_weights {
        attributes["WEIGHTS_0"] = json!(weights);
    }
    let mut skin = json!({"name": "bar", "joints": [2, 3]});
    if !breakage.no_inverse_bind {
        skin["inverseBindMatrices"] = json!(inverse_binds);
    }
    w.json["meshes"] =
        json!([{"name": "bar", "primitives": [{"attributes": attributes, "indices": indices}]}]);
    w.json["skins"] = json!([skin]);
    w.json["nodes"] = json!([
        {"name": "bar", "mesh": 0, "skin": 0, "translation": [5.0, 0.0, 0.0]},
        {"name": "armature", "translation": [0.0, 0.0, 3.0], "children": [2]},
        {"name": "hip", "children": [3]},
        {"name": "knee", "translation": [0.0, 1.0, 0.0]},
    ]);
    w.json["scenes"] = json!([{"nodes": [0, 1]}]);
    w.json["scene"] = json!(0);
    w.json["animations"] = json!([{
        "channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}}],
        "samplers": [{"input": times, "output": turns, "interpolation": "LINEAR"}],
    }]);
    w.write(dir, name)
}

/// The position and normal of the right vertex (x = +0.1) of row `row` at time `t`.
fn right_vertex(scene: &aograph_scene::Scene, row: usize, t: f32) -> (Vec3, Vec3) {
    // Triangle 2k + 1 of each row's quad is (row, row + 1 right, row + 1 left); the first
    // triangle's second corner is the right vertex of the quad's lower row.
    let (tris, normals) = (scene.world_triangles(t), scene.world_vertex_normals(t));
    let (tri, corner) = match row {
        0 => (0, 1),
        1 => (2, 1),
        _ => (2, 2),
    };
    (tris[tri][corner], normals[tri][corner])
}

fn assert_close(got: Vec3, want: Vec3, what: &str) {
    assert!(
        (got - want).length() < 1e-5,
        "{what}: got {got}, want {want}"
    );
}

#[test]
fn skinned_bar_bends_as_linear_blend_skinning_says() {
    let dir = temp_dir("bar");
    let scene = load_scene(skinned_bar(&dir, "bar.gltf", Breakage::default())).unwrap();
    assert!(
        scene.is_animated(),
        "a skin's animated joint moves the scene"
    );
    assert_eq!(scene.duration(), 1.0);
    scene.check_invariants().unwrap();
    // Bind pose, moved only by the armature: the mesh node's (5, 0, 0) is ignored.
    for row in 0..3 {
        let (p, n) = right_vertex(&scene, row, 0.0);
        assert_close(p, Vec3::new(0.1, row as f32, 3.0), "bind pose");
        assert_close(n, Vec3::Z, "bind-pose normal");
    }
    // A quarter turn of the knee about +X: the top row, all on the knee, swings to
    // (0.1, 1, 1) about the knee at (0, 1, 3) and faces -Y; the hip row stays; the middle
    // row, half on each, averages two coincident points and its normal turns half way (the
    // cofactor of 0.5 (I + Rx(90)) maps +Z to (0, -1, 1) / sqrt 2).
    let (p, n) = right_vertex(&scene, 2, 1.0);
    assert_close(p, Vec3::new(0.1, 1.0, 4.0), "top row");
    assert_close(n, Vec3::NEG_Y, "top normal");
    let (p, n) = right_vertex(&scene, 1, 1.0);
    assert_close(p, Vec3::new(0.1, 1.0, 3.0), "middle row");
    assert_close(n, Vec3::new(0.0, -1.0, 1.0).normalize(), "middle normal");
    let (p, _) = right_vertex(&scene, 0, 1.0);
    assert_close(p, Vec3::new(0.1, 0.0, 3.0), "hip row");
    // Bounds follow the posed vertices.
    let b = scene.bounds_at(1.0);
    assert!(
        (b.max.z - 4.0).abs() < 1e-5 && (b.max.y - 1.0).abs() < 1e-5,
        "{b:?}"
    );
}

#[test]
fn skin_without_inverse_bind_matrices_uses_identity() {
    // glTF: missing inverseBindMatrices are identity, so the knee's (0, 1, 0) is added to
    // every vertex on it at the bind pose.
    let dir = temp_dir("no-ibm");
    let path = skinned_bar(
        &dir,
        "bar.gltf",
        Breakage {
            no_inverse_bind: true,
            ..Default::default()
        },
    );
    let scene = load_scene(path).unwrap();
    let (p, _) = right_vertex(&scene, 2, 0.0);
    assert_close(
        p,
        Vec3::new(0.1, 3.0, 3.0),
        "top row on an identity inverse bind",
    );
}

#[test]
fn flat_shaded_skinned_primitive_keeps_each_vertex_on_its_joints() {
    // Without normals the importer gives every triangle its own three vertices; their
    // weights must come along, so the posed triangles equal the indexed file's exactly.
    let dir = temp_dir("flat");
    let indexed = load_scene(skinned_bar(&dir, "bar.gltf", Breakage::default())).unwrap();
    let flat = load_scene(skinned_bar(
        &dir,
        "flat.gltf",
        Breakage {
            no_normals: true,
            ..Default::default()
        },
    ))
    .unwrap();
    assert_eq!(flat.meshes[0].positions.len(), 12, "un-indexed");
    assert_eq!(flat.meshes[0].skin_weights.len(), 12);
    for t in [0.0, 0.5, 1.0] {
        assert_eq!(
            flat.world_triangles(t),
            indexed.world_triangles(t),
            "t = {t}"
        );
    }
}

#[test]
fn joint_index_past_the_skin_is_an_error_naming_the_vertex_and_skin() {
    let dir = temp_dir("bad-joint");
    let path = skinned_bar(
        &dir,
        "bar.gltf",
        Breakage {
            joint_out_of_range: true,
            ..Default::default()
        },
    );
    match load_scene(&path) {
        Err(SceneError::InvalidGltf { message, .. }) => {
            assert!(
                message.contains("vertex 2")
                    && message.contains("skin \"bar\"")
                    && message.contains("2 joints"),
                "{message}"
            );
        }
        other => panic!("expected InvalidGltf, got {other:?}"),
    }
}

#[test]
fn joints_without_weights_is_an_error() {
    let dir = temp_dir("no-weights");
    let path = skinned_bar(
        &dir,
        "bar.gltf",
        Breakage {
            no_weights: true,
            ..Default::default()
        },
    );
    match load_scene(&path) {
        Err(SceneError::InvalidGltf { message, .. }) => {
            assert!(message.contains("JOINTS_0 but no WEIGHTS_0"), "{message}")
        }
        other => panic!("expected InvalidGltf, got {other:?}"),
    }
}

#[test]
fn vertex_without_weight_follows_its_first_joint_with_a_warning() {
    let dir = temp_dir("zero-weight");
    let path = skinned_bar(
        &dir,
        "bar.gltf",
        Breakage {
            zero_weight_vertex: true,
            ..Default::default()
        },
    );
    let import = import_gltf(&path).unwrap();
    assert!(
        import
            .warnings
            .iter()
            .any(|w| w.contains("2 vertices have no positive weight")),
        "{:?}",
        import.warnings
    );
    let (p, _) = right_vertex(&import.scene, 0, 1.0);
    assert_close(
        p,
        Vec3::new(0.1, 0.0, 3.0),
        "the bottom row stays on the hip",
    );
}

#[test]
fn cesium_man_walks() {
    let Some(path) = aograph_scene::test_scene("cesium_man_walks", "CesiumMan.glb") else {
        return;
    };
    let import = import_gltf(path).unwrap();
    let scene = &import.scene;
    assert_eq!(
        import.info.skins,
        vec![("skin \"Armature\"".to_string(), 19)]
    );
    let skinned: Vec<_> = scene
        .instances
        .iter()
        .filter(|i| i.skin_for(&scene.meshes[i.mesh]).is_some())
        .collect();
    assert_eq!(skinned.len(), 1, "the man is one skinned instance");
    assert!(scene.is_animated() && scene.duration() > 1.0);
    scene.check_invariants().unwrap();
    let mesh = &scene.meshes[skinned[0].mesh];
    for w in &mesh.skin_weights {
        assert!((w.weights.iter().sum::<f32>() - 1.0).abs() < 1e-5, "{w:?}");
    }
    // He stands on y = 0 (Y up after the armature's turn), about 1.5 m tall, and his
    // vertices move between two instants of the walk while his height stays.
    let (a, b) = (scene.world_triangles(0.0), scene.world_triangles(0.5));
    let (ba, bb) = (scene.bounds_at(0.0), scene.bounds_at(0.5));
    for bounds in [ba, bb] {
        assert!(
            bounds.min.y.abs() < 0.05 && (bounds.max.y - 1.45).abs() < 0.1,
            "{bounds:?}"
        );
    }
    let moved = a
        .iter()
        .zip(&b)
        .filter(|(p, q)| p[0].distance(q[0]) > 0.05)
        .count();
    assert!(
        moved > a.len() / 10,
        "{moved} of {} triangles moved over 5 cm",
        a.len()
    );
}
