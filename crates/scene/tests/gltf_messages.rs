//! What the loader says about files that are valid but unusual, or whose data is elsewhere:
//! each message says what is true of the file and what aograph did.

mod common;

use aograph_scene::{SceneError, import_gltf};
use common::{f32_bytes, material_triangle, temp_dir, write_gltf};
use serde_json::{Value, json};

#[test]
fn a_gltf_buffer_without_uri_is_data_not_in_the_file() {
    let (mut gltf, bytes) = material_triangle();
    let path = write_gltf("no-uri", gltf.clone(), &bytes);
    let mut written: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    written["buffers"][0].as_object_mut().unwrap().remove("uri");
    std::fs::write(&path, serde_json::to_vec(&written).unwrap()).unwrap();
    let e = import_gltf(&path).unwrap_err().to_string();
    assert!(
        e.contains("no-uri.gltf")
            && e.contains(
                "buffer 0 has no uri and this .gltf file has no binary chunk, so its data is not \
                 in the file"
            ),
        "{e}"
    );
    // A uri-less buffer that nothing aograph reads uses (here: an image's) is no obstacle.
    gltf["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 1, "byteLength": 4}));
    gltf["images"] = json!([{"bufferView": 1, "mimeType": "image/png"}]);
    let path = write_gltf("unused-no-uri", gltf, &bytes);
    let mut written: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    written["buffers"]
        .as_array_mut()
        .unwrap()
        .push(json!({"byteLength": 4}));
    std::fs::write(&path, serde_json::to_vec(&written).unwrap()).unwrap();
    let import = import_gltf(&path).unwrap();
    assert_eq!(import.scene.triangle_count(), 1);
    assert!(
        import
            .warnings
            .iter()
            .any(|w| w.contains("buffer 1 has no uri") && w.contains("nothing aograph reads")),
        "{:?}",
        import.warnings
    );
}

#[test]
fn a_meshopt_fallback_buffer_without_the_fallback_flag_is_never_read() {
    // gltfpack -c writes the fallback buffer as `{"byteLength": n, "extensions":
    // {"EXT_meshopt_compression": {"fallback": true}}}`; a writer that omits the flag leaves a
    // buffer without uri that only compressed views use: it is still a fallback.
    let dir = temp_dir("unflagged-fallback");
    let packed = dir.join("teapot.gltf");
    let Some(teapot) = aograph_scene::test_scene("the fallback test", "teapot.gltf") else {
        return;
    };
    if common::gltfpack(&teapot, &packed, &["-c"]).is_none() {
        return;
    }
    let flagged = import_gltf(&packed).unwrap();
    let mut json: Value = serde_json::from_slice(&std::fs::read(&packed).unwrap()).unwrap();
    let fallback = json["buffers"]
        .as_array()
        .unwrap()
        .iter()
        .position(|b| b.get("uri").is_none())
        .expect("gltfpack -c writes a fallback buffer");
    json["buffers"][fallback]
        .as_object_mut()
        .unwrap()
        .remove("extensions");
    std::fs::write(&packed, serde_json::to_vec(&json).unwrap()).unwrap();
    let unflagged = import_gltf(&packed).unwrap();
    assert_eq!(unflagged.scene.meshes, flagged.scene.meshes);
}

#[test]
fn a_percent_encoded_data_uri_is_decoded() {
    let (gltf, bytes) = material_triangle();
    let path = write_gltf("percent-uri", gltf, &bytes);
    let mut written: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    let encoded: String = bytes.iter().map(|b| format!("%{b:02X}")).collect();
    written["buffers"][0]["uri"] = Value::from(format!("data:application/octet-stream,{encoded}"));
    std::fs::write(&path, serde_json::to_vec(&written).unwrap()).unwrap();
    let import = import_gltf(&path).unwrap();
    let base64 = import_gltf(write_gltf("base64-uri", material_triangle().0, &bytes)).unwrap();
    assert_eq!(import.scene.meshes, base64.scene.meshes);
    // Unreserved characters stand for themselves: "AB" is bytes 0x41 0x42.
    written["buffers"][0]["uri"] = Value::from(
        format!(
            "data:application/octet-stream,{}",
            &encoded[..encoded.len() - 6]
        ) + "AB",
    );
    std::fs::write(&path, serde_json::to_vec(&written).unwrap()).unwrap();
    let import = import_gltf(&path).unwrap();
    // The last float is the third vertex's z: its two high bytes are now 'A' and 'B'.
    let last = import.scene.meshes[0].positions[2];
    let mut expected = bytes[32..34].to_vec();
    expected.extend(b"AB");
    assert_eq!(last.z.to_le_bytes().to_vec(), expected);
}

#[test]
fn a_primitive_without_position_is_skipped_with_a_warning() {
    let (mut gltf, bytes) = material_triangle();
    let extra = json!({"attributes": {"NORMAL": 0}});
    gltf["meshes"][0]["primitives"]
        .as_array_mut()
        .unwrap()
        .push(extra);
    let import = import_gltf(write_gltf("no-position", gltf, &bytes)).unwrap();
    assert_eq!(import.scene.triangle_count(), 1);
    assert!(
        import
            .warnings
            .iter()
            .any(|w| w == "mesh \"mesh 0\" primitive 1 has no POSITION attribute: skipped"),
        "{:?}",
        import.warnings
    );
}

#[test]
fn a_gzipped_file_is_named_as_gzipped() {
    let dir = temp_dir("gzipped");
    for name in ["scene.glb", "scene.gltf"] {
        let path = dir.join(name);
        // The gzip magic number and deflate method, then a few bytes.
        std::fs::write(&path, [0x1f, 0x8b, 0x08, 0x00, 0, 0, 0, 0, 0, 3, 1, 2, 3]).unwrap();
        let e = import_gltf(&path).unwrap_err();
        let message = e.to_string();
        assert!(
            matches!(e, SceneError::InvalidGltf { .. })
                && message.contains(name)
                && message.contains("gzip-compressed")
                && message.contains("gunzip"),
            "{message}"
        );
    }
}

#[test]
fn an_index_accessor_without_a_buffer_view_means_no_triangles() {
    let (mut gltf, mut bytes) = material_triangle();
    // A second primitive whose indices are all zeros (no bufferView, no sparse part).
    bytes.extend(f32_bytes(&[0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 1.0, 1.0]));
    gltf["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": 36, "byteLength": 36}));
    let accessors = gltf["accessors"].as_array_mut().unwrap();
    accessors.push(
        json!({"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 1], "max": [1, 1, 1]}),
    );
    accessors.push(json!({"componentType": 5123, "count": 3, "type": "SCALAR"}));
    gltf["meshes"][0]["primitives"]
        .as_array_mut()
        .unwrap()
        .push(json!({"attributes": {"POSITION": 1}, "indices": 2}));
    let import = import_gltf(write_gltf("zero-indices", gltf, &bytes)).unwrap();
    assert_eq!(import.scene.triangle_count(), 1);
    assert_eq!(import.scene.meshes.len(), 1);
    assert!(
        import.warnings.iter().any(|w| w
            == "mesh \"mesh 0\" primitive 1: index accessor 2 has no bufferView (all zeros): no \
                triangles in this primitive, skipped"),
        "{:?}",
        import.warnings
    );
}
