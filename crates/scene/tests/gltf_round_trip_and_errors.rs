//! glb export round trips, the .gltf buffer variants, and the error for each kind of bad file.
//! Bad files are made in a temporary directory from a valid export of a procedural scene.

mod common;

use aograph_scene::{PROCEDURAL_SCENE_NAMES, SceneError, export_glb, load_scene, procedural_scene};
use common::{base64, temp_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Splits a .glb into its JSON and BIN chunks, checking the container layout on the way.
fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(word(4), 2, "glTF version");
    assert_eq!(word(8), bytes.len(), "total length in the header");
    let json_len = word(12);
    assert_eq!(&bytes[16..20], b"JSON");
    assert_eq!(json_len % 4, 0, "JSON chunk must be 4-byte aligned");
    let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_start = 20 + json_len;
    let bin_len = word(bin_start);
    assert_eq!(&bytes[bin_start + 4..bin_start + 8], b"BIN\0");
    assert_eq!(bin_len % 4, 0, "BIN chunk must be 4-byte aligned");
    (json, bytes[bin_start + 8..bin_start + 8 + bin_len].to_vec())
}

/// Exports `name` and returns its JSON and BIN chunks.
fn exported(name: &str, dir: &Path) -> (Value, Vec<u8>) {
    let path = dir.join(format!("{name}.glb"));
    export_glb(&procedural_scene(name).unwrap(), &path).unwrap();
    split_glb(&std::fs::read(&path).unwrap())
}

/// Writes `json` as a .gltf whose buffer is the external file `bin_name` (written only when
/// `bin` is given).
fn write_gltf_with_external_bin(
    dir: &Path,
    name: &str,
    mut json: Value,
    bin_name: &str,
    bin: Option<&[u8]>,
) -> PathBuf {
    json["buffers"][0]["uri"] = Value::from(bin_name);
    if let Some(bin) = bin {
        std::fs::write(dir.join(bin_name), bin).unwrap();
    }
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
    path
}

#[test]
fn every_procedural_scene_round_trips_through_glb() {
    let dir = temp_dir("round-trip");
    for name in PROCEDURAL_SCENE_NAMES {
        let scene = procedural_scene(name).unwrap();
        let path = dir.join(format!("{name}.glb"));
        export_glb(&scene, &path).unwrap();
        let back = load_scene(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.triangle_count(), scene.triangle_count(), "{name}");
        let (a, b) = (scene.bounds(), back.bounds());
        assert!(
            (a.min - b.min).abs().max_element() < 1e-4
                && (a.max - b.max).abs().max_element() < 1e-4,
            "{name}: bounds {a:?} became {b:?}"
        );
        let camera = scene.camera_at(0.0);
        assert!(
            back.camera.position.distance(camera.position) < 1e-4,
            "{name}: camera position"
        );
        assert!(
            back.camera.forward().dot(camera.forward()) > 0.9999,
            "{name}: camera direction"
        );
        assert_eq!(
            back.materials.len(),
            scene.materials.len(),
            "{name}: materials"
        );
    }
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporary files left behind: {leftovers:?}"
    );
}

#[test]
fn exported_glb_positions_have_min_and_max() {
    let (json, _) = exported("cornell-box", &temp_dir("min-max"));
    let accessors = json["accessors"].as_array().unwrap();
    for mesh in json["meshes"].as_array().unwrap() {
        let position = mesh["primitives"][0]["attributes"]["POSITION"]
            .as_u64()
            .unwrap() as usize;
        assert!(accessors[position]["min"].is_array() && accessors[position]["max"].is_array());
    }
    assert!(
        json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n.get("camera").is_some())
    );
}

#[test]
fn gltf_with_external_and_embedded_buffers_loads_like_the_glb() {
    let dir = temp_dir("buffers");
    let (json, bin) = exported("stairs", &dir);
    let expected = procedural_scene("stairs").unwrap().triangle_count();
    let external = write_gltf_with_external_bin(
        &dir,
        "external.gltf",
        json.clone(),
        "external data.bin",
        Some(&bin),
    );
    assert_eq!(load_scene(&external).unwrap().triangle_count(), expected);
    let mut embedded = json;
    embedded["buffers"][0]["uri"] = Value::from(format!(
        "data:application/octet-stream;base64,{}",
        base64(&bin)
    ));
    let path = dir.join("embedded.gltf");
    std::fs::write(&path, serde_json::to_vec(&embedded).unwrap()).unwrap();
    assert_eq!(load_scene(&path).unwrap().triangle_count(), expected);
}

#[test]
fn missing_file_error_names_the_file() {
    let path = temp_dir("missing").join("no-such-scene.gltf");
    let error = load_scene(&path).unwrap_err();
    assert!(matches!(error, SceneError::MissingFile { .. }), "{error:?}");
    let message = error.to_string();
    eprintln!("{message}");
    assert!(
        message.contains("no-such-scene.gltf") && message.contains("does not exist"),
        "{message}"
    );
}

#[test]
fn malformed_json_error_names_the_file_and_the_parser_message() {
    let path = temp_dir("malformed").join("broken.gltf");
    std::fs::write(&path, br#"{ "asset": { "version": "2.0" }, "nodes": [ "#).unwrap();
    let error = load_scene(&path).unwrap_err();
    assert!(
        matches!(error, SceneError::MalformedJson { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    eprintln!("{message}");
    assert!(
        message.contains("broken.gltf") && message.contains("not valid glTF JSON"),
        "{message}"
    );
    assert!(
        message.contains("EOF") || message.contains("line"),
        "parser detail missing: {message}"
    );
}

#[test]
fn missing_buffer_error_names_the_bin_file() {
    let dir = temp_dir("missing-buffer");
    let (json, _) = exported("corner", &dir);
    let path = write_gltf_with_external_bin(&dir, "needs-bin.gltf", json, "absent.bin", None);
    let error = load_scene(&path).unwrap_err();
    assert!(
        matches!(error, SceneError::MissingBuffer { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    eprintln!("{message}");
    assert!(
        message.contains("needs-bin.gltf") && message.contains("absent.bin"),
        "{message}"
    );
}

#[test]
fn nan_vertex_error_names_the_mesh_and_vertex() {
    let dir = temp_dir("nan");
    let (json, mut bin) = exported("corner", &dir);
    // Overwrite the y of vertex 1 of the first mesh's POSITION accessor with NaN.
    let accessor = json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    let view = json["accessors"][accessor]["bufferView"].as_u64().unwrap() as usize;
    let offset = json["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize + 12 + 4;
    bin[offset..offset + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let path = write_gltf_with_external_bin(&dir, "nan.gltf", json, "nan.bin", Some(&bin));
    let error = load_scene(&path).unwrap_err();
    assert!(
        matches!(error, SceneError::NonFiniteVertex { vertex: 1, .. }),
        "{error:?}"
    );
    let message = error.to_string();
    eprintln!("{message}");
    assert!(
        message.contains("nan.gltf") && message.contains("vertex 1") && message.contains("quad"),
        "{message}"
    );
}

#[test]
fn scene_without_triangles_is_an_empty_scene_error() {
    let dir = temp_dir("empty");
    let (json, bin) = exported("corner", &dir);
    // No node in the scene: the file's root nodes are drawn instead, with a warning (see
    // gltf_lenient.rs), so the triangles are still there.
    let mut no_nodes = json.clone();
    no_nodes["scenes"][0]["nodes"] = Value::Array(vec![]);
    let path =
        write_gltf_with_external_bin(&dir, "no-nodes.gltf", no_nodes, "empty.bin", Some(&bin));
    let import = aograph_scene::import_gltf(&path).unwrap();
    assert!(import.scene.triangle_count() > 0);
    assert!(
        import.warnings.iter().any(|w| w.contains("lists no nodes")),
        "{:?}",
        import.warnings
    );
    // Only line primitives: skipped with warnings, leaving nothing.
    let mut lines = json;
    for mesh in lines["meshes"].as_array_mut().unwrap() {
        mesh["primitives"][0]["mode"] = Value::from(1);
    }
    let path = write_gltf_with_external_bin(&dir, "lines.gltf", lines, "empty.bin", Some(&bin));
    let message = load_scene(&path).unwrap_err().to_string();
    eprintln!("{message}");
    assert!(
        message.contains("lines.gltf") && message.contains("no triangles"),
        "{message}"
    );
}

/// Appends `floats` to `bin` as a new buffer view and accessor of `kind` ("SCALAR", "VEC3",
/// "VEC4"); returns the accessor index.
fn push_float_accessor(
    json: &mut Value,
    bin: &mut Vec<u8>,
    floats: &[f32],
    kind: &str,
    components: usize,
) -> usize {
    let offset = bin.len();
    for f in floats {
        bin.extend_from_slice(&f.to_le_bytes());
    }
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(
        serde_json::json!({"buffer": 0, "byteOffset": offset, "byteLength": floats.len() * 4}),
    );
    let view = views.len() - 1;
    let accessors = json["accessors"].as_array_mut().unwrap();
    let mut accessor = serde_json::json!({
        "bufferView": view, "componentType": 5126, "count": floats.len() / components, "type": kind
    });
    if kind == "SCALAR" {
        let (min, max) = (floats[0], floats[floats.len() - 1]);
        accessor["min"] = serde_json::json!([min]);
        accessor["max"] = serde_json::json!([max]);
    }
    accessors.push(accessor);
    accessors.len() - 1
}

#[test]
fn node_translation_and_rotation_animation_becomes_instance_motion() {
    let dir = temp_dir("animation");
    let (mut json, mut bin) = exported("cornell-box", &dir);
    // Move node 5 (the tall box) by +2 in x over 2 s and turn it a quarter around Y.
    let times = push_float_accessor(&mut json, &mut bin, &[0.0, 2.0], "SCALAR", 1);
    let node_matrix: Vec<f32> = json["nodes"][5]["matrix"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap() as f32)
        .collect();
    let start = glam::Mat4::from_cols_slice(&node_matrix);
    let (_, rotation, translation) = start.to_scale_rotation_translation();
    let end = translation + glam::Vec3::X * 2.0;
    let moves = push_float_accessor(
        &mut json,
        &mut bin,
        &[
            translation.x,
            translation.y,
            translation.z,
            end.x,
            end.y,
            end.z,
        ],
        "VEC3",
        3,
    );
    let turned = glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2) * rotation;
    let turns = push_float_accessor(
        &mut json,
        &mut bin,
        &[
            rotation.x, rotation.y, rotation.z, rotation.w, turned.x, turned.y, turned.z, turned.w,
        ],
        "VEC4",
        4,
    );
    json["buffers"][0]["byteLength"] = Value::from(bin.len());
    json["animations"] = serde_json::json!([{
        "channels": [
            {"sampler": 0, "target": {"node": 5, "path": "translation"}},
            {"sampler": 1, "target": {"node": 5, "path": "rotation"}}
        ],
        "samplers": [
            {"input": times, "output": moves, "interpolation": "LINEAR"},
            {"input": times, "output": turns, "interpolation": "LINEAR"}
        ]
    }]);
    let path =
        write_gltf_with_external_bin(&dir, "animated.gltf", json, "animated.bin", Some(&bin));
    let scene = load_scene(&path).unwrap();
    assert!(!scene.is_static());
    let moving: Vec<_> = scene.instances.iter().filter(|i| i.is_moving()).collect();
    assert_eq!(moving.len(), 1);
    let halfway = moving[0].transform_at(1.0).w_axis.truncate();
    assert!(
        (halfway - (translation + glam::Vec3::X)).length() < 1e-4,
        "{halfway}"
    );
    let (_, rotation_at_end, _) = moving[0].transform_at(5.0).to_scale_rotation_translation();
    assert!(
        rotation_at_end.angle_between(turned) < 1e-3,
        "clamped to the last key"
    );
}

#[test]
fn orthographic_camera_round_trips() {
    let dir = temp_dir("ortho");
    let mut scene = procedural_scene("corner").unwrap();
    scene.camera.projection = aograph_scene::Projection::Orthographic {
        height: 12.0,
        near: 0.5,
        far: 80.0,
    };
    let path = dir.join("ortho.glb");
    export_glb(&scene, &path).unwrap();
    let back = load_scene(&path).unwrap();
    assert_eq!(back.camera.projection, scene.camera.projection);
}

#[test]
fn refused_export_names_the_mesh_and_leaves_no_file() {
    let dir = temp_dir("refused-export");
    let mut scene = procedural_scene("corner").unwrap();
    scene.meshes[1].positions[2].y = f32::INFINITY;
    let path = dir.join("never.glb");
    let error = export_glb(&scene, &path).unwrap_err();
    let message = error.to_string();
    assert!(matches!(error, SceneError::Export { .. }), "{error:?}");
    assert!(
        message.contains("never.glb") && message.contains("vertex 2"),
        "{message}"
    );
    assert!(!path.exists());
    let leftovers = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(leftovers, 0, "temporary files left behind");
}

#[test]
fn malformed_animation_channels_are_skipped_with_a_warning_naming_each() {
    // Channels the gltf crate's readers would unwrap into a panic, which its validation lets
    // through: a node past the array, an extension's path (KHR_animation_pointer's `pointer`),
    // an unknown path. Each is skipped, named; the one valid channel still moves its node. (A
    // sampler past the animation's is refused by the validation, naming the field.)
    let dir = temp_dir("bad-channels");
    let (mut json, mut bin) = exported("cornell-box", &dir);
    let nodes = json["nodes"].as_array().unwrap().len();
    let times = push_float_accessor(&mut json, &mut bin, &[0.0, 2.0], "SCALAR", 1);
    let moves = push_float_accessor(
        &mut json,
        &mut bin,
        &[0.0, 0.0, 0.0, 2.0, 0.0, 0.0],
        "VEC3",
        3,
    );
    json["buffers"][0]["byteLength"] = Value::from(bin.len());
    json["animations"] = serde_json::json!([{
        "channels": [
            {"sampler": 0, "target": {"node": nodes, "path": "translation"}},
            {"sampler": 0, "target": {"node": 5, "path": "pointer"}},
            {"sampler": 0, "target": {"node": 5, "path": "foo"}},
            {"sampler": 0, "target": {"node": 5, "path": "translation"}}
        ],
        "samplers": [{"input": times, "output": moves, "interpolation": "LINEAR"}]
    }]);
    let path = write_gltf_with_external_bin(&dir, "bad-channels.gltf", json, "bad.bin", Some(&bin));
    let import = aograph_scene::import_gltf(&path).expect("the file loads");
    let expected = [
        format!(
            "animation channel 0: targets node {nodes}, but the file has {nodes} nodes: ignored"
        ),
        "animation channel 1: its target path is none of glTF 2.0's".to_string(),
        "animation channel 2: its target path is none of glTF 2.0's".to_string(),
    ];
    for e in &expected {
        assert!(
            import.warnings.iter().any(|w| w.starts_with(e.as_str())),
            "no warning `{e}` in {:?}",
            import.warnings
        );
    }
    let moving: Vec<_> = import
        .scene
        .instances
        .iter()
        .filter(|i| i.is_moving())
        .collect();
    assert_eq!(moving.len(), 1, "channel 3 still animates node 5");
}
