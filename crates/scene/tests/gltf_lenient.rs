//! Files the glTF validator accepts, or only warns about, load, each off-spec one with a
//! warning: application attributes (`_FEATURE_ID_0`), required extensions that only change
//! materials or textures, whole numbers written as decimals, `extras` that are not objects,
//! a malformed accessor nothing uses, a scene without `nodes`, and .glb files with bytes after
//! the last chunk, an unknown chunk, or a data-URI buffer. glTF 1.0 is named as such; points and
//! lines beside triangles leave the triangles, and no triangle at all is refused.

mod common;

use aograph_scene::{SceneError, import_gltf};
use serde_json::{Value, json};
use std::path::Path;

/// Imports `gltf` written as `{test}.gltf`: the triangle count and the warnings.
fn load(test: &str, gltf: Value, bytes: &[u8]) -> (usize, Vec<String>) {
    let import = import_gltf(common::write_gltf(test, gltf, bytes))
        .unwrap_or_else(|e| panic!("{test}: {e}"));
    (import.scene.triangle_count(), import.warnings)
}

fn one_warning_with(warnings: &[String], words: &[&str]) {
    let matching = warnings
        .iter()
        .filter(|w| words.iter().all(|x| w.contains(x)))
        .count();
    assert_eq!(
        matching, 1,
        "one warning with {words:?} expected: {warnings:?}"
    );
}

#[test]
fn application_attributes_are_accepted_and_ignored() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["meshes"][0]["primitives"][0]["attributes"]["_FEATURE_ID_0"] = json!(0);
    gltf["meshes"][0]["primitives"][0]["attributes"]["_BATCHID"] = json!(0);
    let (triangles, warnings) = load("app-attributes", gltf, &bytes);
    assert_eq!(triangles, 1);
    assert!(warnings.is_empty(), "{warnings:?}");
}

#[test]
fn required_material_and_texture_extensions_load_with_one_warning() {
    let (mut gltf, bytes) = common::material_triangle();
    let extensions = [
        "KHR_materials_unlit",
        "KHR_texture_transform",
        "VENDOR_materials_sparkle",
    ];
    gltf["extensionsUsed"] = json!(extensions);
    gltf["extensionsRequired"] = json!(extensions);
    gltf["materials"][0]["extensions"] = json!({"KHR_materials_unlit": {}});
    let import = import_gltf(common::write_gltf("material-extensions", gltf, &bytes)).unwrap();
    assert_eq!(import.scene.materials[0].base_color, [0.25, 0.5, 0.75, 1.0]);
    one_warning_with(&import.warnings, &extensions);
    one_warning_with(&import.warnings, &["base colour factor"]);
}

#[test]
fn whole_numbers_written_as_decimals_are_read_as_integers_with_a_warning() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["accessors"][0]["count"] = json!(3.0);
    gltf["accessors"][0]["componentType"] = json!(5126.0);
    gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(0.0);
    let (triangles, warnings) = load("decimals", gltf, &bytes);
    assert_eq!(triangles, 1);
    one_warning_with(&warnings, &["whole numbers as decimals"]);
}

#[test]
fn extras_that_are_not_objects_load_with_a_warning() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["nodes"][0]["extras"] = json!(5);
    gltf["materials"][0]["extras"] = json!("note");
    let (triangles, warnings) = load("extras", gltf, &bytes);
    assert_eq!(triangles, 1);
    one_warning_with(&warnings, &["2 `extras` are not JSON objects"]);
}

#[test]
fn a_malformed_accessor_nothing_uses_is_ignored_with_a_warning() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["accessors"]
        .as_array_mut()
        .unwrap()
        .push(json!({"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC5"}));
    let (triangles, warnings) = load("unused-accessor", gltf.clone(), &bytes);
    assert_eq!(triangles, 1);
    one_warning_with(&warnings, &["accessor(s) {1}", "nothing uses them"]);
    // The same accessor, used, stays an error.
    gltf["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(1);
    let e = import_gltf(common::write_gltf("used-accessor", gltf, &bytes)).unwrap_err();
    assert!(e.to_string().contains("accessors[1].type"), "{e}");
}

#[test]
fn a_scene_without_nodes_draws_the_root_nodes_with_a_warning() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["scenes"] = json!([{"name": "empty"}]);
    let (triangles, warnings) = load("scene-without-nodes", gltf, &bytes);
    assert_eq!(triangles, 1);
    one_warning_with(&warnings, &["no `nodes` array"]);
    one_warning_with(
        &warnings,
        &["scene 0 lists no nodes: every root node is drawn"],
    );
}

/// A .glb of `json` with `chunks` after the JSON chunk and `trailing` bytes past its length.
fn glb(json: &Value, chunks: &[(u32, &[u8])], trailing: &[u8]) -> Vec<u8> {
    let mut json_bytes = serde_json::to_vec(json).unwrap();
    while !json_bytes.len().is_multiple_of(4) {
        json_bytes.push(b' ');
    }
    let mut body = Vec::new();
    for (kind, data) in std::iter::once(&(0x4E4F_534A, &json_bytes[..])).chain(chunks) {
        body.extend((data.len() as u32).to_le_bytes());
        body.extend(kind.to_le_bytes());
        body.extend(*data);
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend((12 + body.len() as u32).to_le_bytes());
    out.extend(body);
    out.extend(trailing);
    out
}

fn write_glb(test: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = common::temp_dir(test).join(format!("{test}.glb"));
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn glb_edge_cases_the_validator_warns_about_load() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["asset"] = json!({"version": "2.0"});
    gltf["buffers"] = json!([{"byteLength": bytes.len()}]);
    // Bytes after the last chunk, past the length the header declares.
    let file = glb(&gltf, &[(0x004E_4942, &bytes)], &[0, 0, 0, 0, 7, 7]);
    let import = import_gltf(write_glb("glb-trailing", &file)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(import.scene.triangle_count(), 1);
    one_warning_with(
        &import.warnings,
        &["6 bytes after the length its header declares"],
    );
    // A chunk of an unknown type between JSON and BIN is skipped (glTF 2.0 §4.4.1).
    let file = glb(&gltf, &[(0x1234_5678, b"note"), (0x004E_4942, &bytes)], &[]);
    let import =
        import_gltf(write_glb("glb-unknown-chunk", &file)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(import.scene.triangle_count(), 1);
    // A data-URI buffer inside a .glb without a BIN chunk.
    gltf["buffers"] = json!([{"byteLength": bytes.len(),
        "uri": format!("data:application/octet-stream;base64,{}", common::base64(&bytes))}]);
    let file = glb(&gltf, &[], &[]);
    let import = import_gltf(write_glb("glb-data-uri", &file)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(import.scene.triangle_count(), 1);
}

#[test]
fn gltf_1_files_are_named_as_such_with_a_conversion() {
    let check = |path: &Path| {
        let e = import_gltf(path).unwrap_err();
        assert!(matches!(e, SceneError::Gltf1 { .. }), "{e:?}");
        let message = e.to_string();
        assert!(
            message.contains("glTF 1.0") && message.contains("gltf-pipeline"),
            "{message}"
        );
    };
    let dir = common::temp_dir("gltf-1");
    let json_1 = dir.join("old.gltf");
    std::fs::write(
        &json_1,
        br#"{"asset": {"version": "1.0"}, "meshes": {"m": {}}}"#,
    )
    .unwrap();
    check(&json_1);
    let mut glb_1 = glb(&json!({"asset": {"version": "1.0"}}), &[], &[]);
    glb_1[4] = 1; // the header's version
    check(&write_glb("glb-1", &glb_1));
}

#[test]
fn points_and_lines_beside_triangles_leave_the_triangles_and_none_at_all_is_refused() {
    let (mut gltf, bytes) = common::material_triangle();
    let lines = json!({"attributes": {"POSITION": 0}, "mode": 1});
    let points = json!({"attributes": {"POSITION": 0}, "mode": 0});
    gltf["meshes"][0]["primitives"]
        .as_array_mut()
        .unwrap()
        .extend([lines.clone(), points]);
    let (triangles, warnings) = load("mixed-modes", gltf.clone(), &bytes);
    assert_eq!(triangles, 1);
    assert_eq!(
        warnings
            .iter()
            .filter(|w| w.contains("not triangles: skipped"))
            .count(),
        2
    );
    gltf["meshes"][0]["primitives"] = json!([lines]);
    let e = import_gltf(common::write_gltf("lines-only", gltf, &bytes)).unwrap_err();
    assert!(matches!(e, SceneError::EmptyScene { .. }), "{e:?}");
    assert!(e.to_string().contains("contains no triangles"), "{e}");
}
