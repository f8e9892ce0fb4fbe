//! glb export round trips, the .gltf buffer variants, and the error for each kind of bad file.
//! Bad files are made in a temporary directory from a valid export of a procedural scene.

use aograph_scene::{PROCEDURAL_SCENE_NAMES, SceneError, export_glb, load_scene, procedural_scene};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("aograph-scene-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

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

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
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
    // No node in the scene.
    let mut no_nodes = json.clone();
    no_nodes["scenes"][0]["nodes"] = Value::Array(vec![]);
    let path =
        write_gltf_with_external_bin(&dir, "no-nodes.gltf", no_nodes, "empty.bin", Some(&bin));
    let error = load_scene(&path).unwrap_err();
    assert!(matches!(error, SceneError::EmptyScene { .. }), "{error:?}");
    assert!(error.to_string().contains("no-nodes.gltf"), "{error}");
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
