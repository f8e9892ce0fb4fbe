//! Valid glTF files that gltf-json alone refuses, written here by hand, load with known
//! answers: accessors without a buffer view (zeros) and sparse accessors (on positions and on
//! indices), KHR_mesh_quantization's integer and normalized attributes, textures whose image
//! lives in an extension (KTX2), and animation channels without a target node. Required
//! extensions aograph does not read are refused with a message naming them and a conversion.

mod common;

use aograph_scene::{ExtensionHandling, SceneError, import_gltf};
use glam::Vec3;
use serde_json::json;
#[test]
fn an_accessor_without_a_buffer_view_is_zeros_and_sparse_values_replace_them() {
    // POSITION: zeros (no bufferView) with vertices 1 and 2 set by its sparse part; indices
    // [0, 0, 0] with entries 1 and 2 set by theirs; NORMAL zeros only (unusable: flat normals).
    let (gltf, bytes) = common::sparse_triangle();
    let path = common::write_gltf("sparse", gltf, &bytes);
    let import = import_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &import.scene.meshes[0];
    // Flat shading un-indexes: vertex k is old vertex indices[k] = k.
    assert_eq!(mesh.positions, vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::Y]);
    assert_eq!(mesh.indices, vec![0, 1, 2]);
    assert_eq!(mesh.normals, vec![Vec3::Z; 3]);
}

#[test]
fn a_sparse_index_past_the_accessor_is_an_error_naming_it() {
    let mut bytes = vec![3u8, 0, 0, 0];
    bytes.extend(common::f32_bytes(&[1.0, 0.0, 0.0]));
    let gltf = json!({
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 1},
            {"buffer": 0, "byteOffset": 4, "byteLength": 12},
        ],
        "accessors": [{"componentType": 5126, "count": 3, "type": "VEC3",
            "min": [0, 0, 0], "max": [1, 0, 0],
            "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5121},
                       "values": {"bufferView": 1}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}],
    });
    let e = import_gltf(common::write_gltf("sparse-past", gltf, &bytes))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sparse-past.gltf") && e.contains("POSITION accessor 0's sparse index 3"),
        "{e}"
    );
}

#[test]
fn quantized_positions_and_normals_are_dequantized_by_the_accessor_rules() {
    // KHR_mesh_quantization: SHORT positions (not normalized; the node scales them by 1/100)
    // and normalized BYTE normals, each element padded to 4-byte alignment (stride 8 and 4).
    let positions: [[i16; 4]; 3] = [[0, 0, 0, 0], [100, 0, 0, 0], [0, -250, 0, 0]];
    let normals: [[i8; 4]; 3] = [[0, 0, 127, 0], [0, 0, -128, 0], [0, 127, 0, 0]];
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend(normals.iter().flatten().map(|&v| v as u8));
    let gltf = json!({
        "extensionsUsed": ["KHR_mesh_quantization"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 24, "byteStride": 8},
            {"buffer": 0, "byteOffset": 24, "byteLength": 12, "byteStride": 4},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5122, "count": 3, "type": "VEC3",
             "min": [0, -250, 0], "max": [100, 0, 0]},
            {"bufferView": 1, "componentType": 5120, "normalized": true, "count": 3, "type": "VEC3"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
        "nodes": [{"mesh": 0, "scale": [0.01, 0.01, 0.01]}],
    });
    let path = common::write_gltf("quantized", gltf, &bytes);
    let import = import_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &import.scene.meshes[0];
    assert_eq!(
        mesh.positions,
        vec![
            Vec3::ZERO,
            Vec3::new(100.0, 0.0, 0.0),
            Vec3::new(0.0, -250.0, 0.0)
        ]
    );
    // -128 normalizes to max(-128 / 127, -1) = -1 (glTF 2.0 §3.11).
    assert_eq!(mesh.normals, vec![Vec3::Z, Vec3::NEG_Z, Vec3::Y]);
    let world = import.scene.world_triangles(0.0);
    assert_eq!(world[0][1], Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(world[0][2], Vec3::new(0.0, -2.5, 0.0));
    assert_eq!(
        import.info.extensions[0].handling,
        ExtensionHandling::Read,
        "{:?}",
        import.info.extensions
    );
}

#[test]
fn a_ktx2_texture_is_ignored_with_one_warning_and_albedo_is_the_base_colour_factor() {
    let (mut gltf, bytes) = common::material_triangle();
    gltf["extensionsUsed"] = json!(["KHR_texture_basisu"]);
    gltf["extensionsRequired"] = json!(["KHR_texture_basisu"]);
    gltf["images"] = json!([{"uri": "albedo.ktx2", "mimeType": "image/ktx2"}]);
    gltf["textures"] = json!([{"extensions": {"KHR_texture_basisu": {"source": 0}}}]);
    gltf["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    let import =
        import_gltf(common::write_gltf("ktx2", gltf, &bytes)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(import.scene.materials[0].base_color, [0.25, 0.5, 0.75, 1.0]);
    let texture_warnings: Vec<&String> = (import.warnings.iter())
        .filter(|w| w.contains("KHR_texture_basisu"))
        .collect();
    assert_eq!(texture_warnings.len(), 1, "{:?}", import.warnings);
    assert!(
        texture_warnings[0].contains("base colour factor"),
        "{texture_warnings:?}"
    );
}

#[test]
fn an_animation_channel_without_a_target_node_is_skipped_with_a_warning() {
    let (mut gltf, mut bytes) = common::material_triangle();
    bytes.extend(common::f32_bytes(&[0.0, 1.0]));
    gltf["bufferViews"]
        .as_array_mut()
        .unwrap()
        .push(json!({"buffer": 0, "byteOffset": 36, "byteLength": 8}));
    gltf["accessors"].as_array_mut().unwrap().push(
        json!({"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR",
               "min": [0], "max": [1]}),
    );
    gltf["extensionsUsed"] = json!(["KHR_animation_pointer"]);
    gltf["animations"] = json!([{
        "samplers": [{"input": 1, "output": 1}],
        "channels": [{"sampler": 0, "target": {"path": "pointer",
            "extensions": {"KHR_animation_pointer": {"pointer": "/materials/0/alphaCutoff"}}}}],
    }]);
    let import =
        import_gltf(common::write_gltf("pointer", gltf, &bytes)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(import.scene.triangle_count(), 1);
    assert!(
        import
            .warnings
            .iter()
            .any(|w| w.starts_with("1 animation channel(s) have no target node")),
        "{:?}",
        import.warnings
    );
    // The unknown optional extension is named once.
    let unknown: Vec<&String> = (import.warnings.iter())
        .filter(|w| w.contains("KHR_animation_pointer") && w.contains("optional"))
        .collect();
    assert_eq!(unknown.len(), 1, "{:?}", import.warnings);
}

#[test]
fn a_required_extension_aograph_does_not_read_is_refused_with_a_conversion() {
    for (extension, advice) in [
        ("KHR_draco_mesh_compression", "gltf-transform meshopt"),
        (
            "VENDOR_mesh_subdivision",
            "convert it without that extension",
        ),
        ("VENDOR_made_up", "convert it without that extension"),
    ] {
        let (mut gltf, bytes) = common::material_triangle();
        gltf["extensionsUsed"] = json!([extension]);
        gltf["extensionsRequired"] = json!([extension]);
        let error = import_gltf(common::write_gltf("required", gltf, &bytes)).unwrap_err();
        assert!(
            matches!(&error, SceneError::UnsupportedExtension { extension: e, .. } if e == extension),
            "{error:?}"
        );
        let message = error.to_string();
        assert!(
            message.contains("required.gltf")
                && message.contains(extension)
                && message.contains(advice)
                && message.contains("KHR_mesh_quantization"),
            "{message}"
        );
    }
}

#[test]
fn a_khr_meshopt_compressed_triangle_decodes_to_its_vertices_and_indices() {
    // KHR_meshopt_compression (the Khronos successor of EXT_meshopt_compression, same JSON):
    // positions (ATTRIBUTES, stride 12) and indices (TRIANGLES, u16) compressed by meshoptimizer
    // into buffer 0; buffer 1 is the fallback without data that they decode into.
    let positions: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]];
    let vertices = meshopt::encoding::encode_vertex_buffer(&positions).unwrap();
    let indices = meshopt::encoding::encode_index_buffer(&[0, 2, 1], 3).unwrap();
    let mut bytes = vertices.clone();
    while !bytes.len().is_multiple_of(4) {
        bytes.push(0);
    }
    let index_offset = bytes.len();
    bytes.extend(&indices);
    let ext = "KHR_meshopt_compression";
    let gltf = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": [ext],
        "extensionsRequired": [ext],
        "buffers": [
            {"byteLength": bytes.len(),
             "uri": format!("data:application/octet-stream;base64,{}", common::base64(&bytes))},
            {"byteLength": 44, "extensions": {ext: {"fallback": true}}},
        ],
        "bufferViews": [
            {"buffer": 1, "byteOffset": 0, "byteLength": 36, "byteStride": 12,
             "extensions": {ext: {"buffer": 0, "byteOffset": 0, "byteLength": vertices.len(),
                                  "byteStride": 12, "count": 3, "mode": "ATTRIBUTES"}}},
            {"buffer": 1, "byteOffset": 36, "byteLength": 6,
             "extensions": {ext: {"buffer": 0, "byteOffset": index_offset,
                                  "byteLength": indices.len(), "byteStride": 2, "count": 3,
                                  "mode": "TRIANGLES"}}},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [0, 0, 0], "max": [2, 3, 0]},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
    });
    let path = common::temp_dir("khr-meshopt").join("khr-meshopt.gltf");
    std::fs::write(&path, serde_json::to_vec(&gltf).unwrap()).unwrap();
    let import = import_gltf(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &import.scene.meshes[0];
    // No normals: flat shading un-indexes in index order 0, 2, 1.
    assert_eq!(
        mesh.positions,
        vec![
            Vec3::ZERO,
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0)
        ]
    );
    assert_eq!(mesh.normals, vec![Vec3::NEG_Z; 3]);
    assert_eq!(import.info.extensions[0].handling, ExtensionHandling::Read);
}
