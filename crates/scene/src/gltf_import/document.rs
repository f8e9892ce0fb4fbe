//! Parses a glTF file's bytes (`.gltf` JSON or `.glb`) into a validated [`gltf::Document`],
//! deciding per extension what aograph does with it.
//!
//! The specification allows three things gltf-json 1.4 refuses, so this module handles them
//! before or instead of the crate: an accessor with neither a buffer view nor a sparse part (all
//! zeros, glTF 2.0 §3.6.2.3), an animation channel without a target node (allowed when an
//! extension such as KHR_animation_pointer names the target: skipped with a warning), and
//! required extensions aograph reads itself (KHR_mesh_quantization, EXT_meshopt_compression) or
//! that cannot change AO (texture formats, materials, lights).
//! Invariant: a returned document passed gltf-json's validation except for exactly those
//! cases; every required extension is in [`READ_EXTENSIONS`] or [`IGNORED_EXTENSIONS`], else the
//! file is refused with [`SceneError::UnsupportedExtension`] naming it and how to convert.

use super::{ExtensionHandling, ExtensionUse};
use crate::error::SceneError;
use gltf::json::validation::{Error as ValidationError, Validate};
use serde_json::Value;
use std::path::Path;

/// Extensions aograph reads: the geometry depends on them.
pub const READ_EXTENSIONS: &[&str] = &["KHR_mesh_quantization", "EXT_meshopt_compression"];

/// Extensions that cannot change AO, so a file that requires them still loads: texture
/// formats and transforms (AO reads no texture; albedo is the base colour factor), material
/// models, punctual lights (aograph lights every scene itself), and metadata.
pub const IGNORED_EXTENSIONS: &[&str] = &[
    "KHR_texture_basisu",
    "EXT_texture_webp",
    "EXT_texture_avif",
    "MSFT_texture_dds",
    "KHR_texture_transform",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_unlit",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
    "KHR_materials_dispersion",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_variants",
    "KHR_lights_punctual",
    "KHR_xmp_json_ld",
];

/// Texture extensions whose image aograph cannot read (one warning names them).
const TEXTURE_SOURCE_EXTENSIONS: &[&str] = &[
    "KHR_texture_basisu",
    "EXT_texture_webp",
    "EXT_texture_avif",
    "MSFT_texture_dds",
];

/// A parsed file: the validated document, its GLB binary chunk, and what was skipped.
pub(super) struct ParsedDocument {
    pub document: gltf::Document,
    pub blob: Option<Vec<u8>>,
    /// The raw JSON, for extension data gltf-json does not keep (EXT_meshopt_compression).
    pub json: Value,
    pub warnings: Vec<String>,
}

/// Parses and validates `bytes`, read from `path`.
pub(super) fn parse(path: &Path, bytes: &[u8]) -> Result<ParsedDocument, SceneError> {
    let malformed = |message: String| SceneError::MalformedJson {
        path: path.to_owned(),
        message,
    };
    let invalid = |message: String| SceneError::InvalidGltf {
        path: path.to_owned(),
        message,
    };
    let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
        let glb = gltf::binary::Glb::from_slice(bytes).map_err(|e| super::parse_error(path, e))?;
        (glb.json.into_owned(), glb.bin.map(|b| b.into_owned()))
    } else {
        (bytes.to_vec(), None)
    };
    let mut json: Value =
        serde_json::from_slice(&json_bytes).map_err(|e| malformed(e.to_string()))?;
    let mut warnings = Vec::new();
    let skipped = drop_channels_without_node(&mut json);
    if skipped > 0 {
        warnings.push(format!(
            "{skipped} animation channel(s) have no target node (their target is named by an \
             extension such as KHR_animation_pointer, which aograph does not read): skipped"
        ));
    }
    check_required_extensions(path, &json)?;
    warnings.extend(extension_warnings(&json));
    // Typed parsing from the original bytes keeps serde's line and column in messages; the
    // edited value is parsed only when something was dropped.
    let root: gltf::json::Root = if skipped > 0 {
        serde_json::from_value(json.clone()).map_err(|e| malformed(e.to_string()))?
    } else {
        serde_json::from_slice(&json_bytes).map_err(|e| malformed(e.to_string()))?
    };
    check_attribute_indices(&root).map_err(invalid)?;
    let mut errors = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        if !allowed_by_specification(path.as_str(), &error) {
            errors.push((path, error));
        }
    });
    if !errors.is_empty() {
        return Err(super::parse_error(path, gltf::Error::Validation(errors)));
    }
    Ok(ParsedDocument {
        document: gltf::Document::from_json_without_validation(root),
        blob,
        json,
        warnings,
    })
}

/// The extension names a file lists in `extensionsUsed`.
fn extensions_used(json: &Value) -> Vec<String> {
    string_list(json, "extensionsUsed")
}

/// Every extension the file uses or requires, with what aograph does with it.
pub(super) fn extension_uses(json: &Value) -> Vec<ExtensionUse> {
    let required = string_list(json, "extensionsRequired");
    let mut names = extensions_used(json);
    names.extend(
        required
            .iter()
            .filter(|r| !names.contains(r))
            .cloned()
            .collect::<Vec<_>>(),
    );
    names
        .into_iter()
        .map(|name| ExtensionUse {
            required: required.contains(&name),
            handling: handling(&name),
            name,
        })
        .collect()
}

/// What aograph does with extension `name`.
fn handling(name: &str) -> ExtensionHandling {
    if READ_EXTENSIONS.contains(&name) {
        ExtensionHandling::Read
    } else if IGNORED_EXTENSIONS.contains(&name) {
        ExtensionHandling::Ignored
    } else {
        ExtensionHandling::Unknown
    }
}

fn string_list(json: &Value, key: &str) -> Vec<String> {
    json.get(key)
        .and_then(Value::as_array)
        .map(|list| {
            list.iter()
                .filter_map(Value::as_str)
                .map(str::to_owned)
                .collect()
        })
        .unwrap_or_default()
}

/// Validation errors that are gltf-json's, not the specification's.
fn allowed_by_specification(path: &str, error: &ValidationError) -> bool {
    // §3.6.2.3: "When bufferView is undefined, the accessor MUST be initialized with zeros".
    let zeros_accessor = matches!(error, ValidationError::Missing)
        && path.starts_with("accessors[")
        && path.ends_with("].bufferView");
    // Checked by `check_required_extensions` against aograph's own lists.
    let required_extension = path.starts_with("extensionsRequired[");
    // A texture whose image lives in an extension (KTX2, WebP) has no `source`; AO reads none.
    let texture_source = matches!(error, ValidationError::Missing)
        && path.starts_with("textures[")
        && path.ends_with("].source");
    zeros_accessor || required_extension || texture_source
}

/// Removes animation channels whose target has no `node`; returns how many.
fn drop_channels_without_node(json: &mut Value) -> usize {
    let mut dropped = 0;
    let Some(animations) = json.get_mut("animations").and_then(Value::as_array_mut) else {
        return 0;
    };
    for animation in animations {
        if let Some(channels) = animation.get_mut("channels").and_then(Value::as_array_mut) {
            let before = channels.len();
            channels.retain(|c| c.get("target").is_none_or(|t| t.get("node").is_some()));
            dropped += before - channels.len();
        }
    }
    dropped
}

/// `Err` naming the first required extension aograph neither reads nor may ignore.
fn check_required_extensions(path: &Path, json: &Value) -> Result<(), SceneError> {
    let unsupported = string_list(json, "extensionsRequired")
        .into_iter()
        .find(|e| handling(e) == ExtensionHandling::Unknown);
    let Some(extension) = unsupported else {
        return Ok(());
    };
    let conversion = match extension.as_str() {
        "KHR_draco_mesh_compression" => {
            "decode it first, e.g. `gltf-transform meshopt in.glb out.glb` (meshopt compression, \
             which aograph reads) or re-export without Draco compression"
        }
        "EXT_mesh_gpu_instancing" => {
            "write it without instancing, e.g. `gltfpack -i in.glb -o out.glb` (without -mi)"
        }
        _ => "convert it without that extension, e.g. with gltf-transform, or re-export it",
    };
    Err(SceneError::UnsupportedExtension {
        path: path.to_owned(),
        extension,
        supported: READ_EXTENSIONS
            .iter()
            .chain(IGNORED_EXTENSIONS)
            .map(|e| (*e).to_owned())
            .collect(),
        conversion: conversion.to_owned(),
    })
}

/// One warning for textures aograph cannot read, one for optional extensions it does not know.
fn extension_warnings(json: &Value) -> Vec<String> {
    let used = extensions_used(json);
    let mut warnings = Vec::new();
    let textures: Vec<&str> = TEXTURE_SOURCE_EXTENSIONS
        .iter()
        .copied()
        .filter(|e| used.iter().any(|u| u == e))
        .collect();
    if !textures.is_empty() {
        warnings.push(format!(
            "textures in {} are not read (AO reads no texture; albedo is each material's base \
             colour factor)",
            textures.join(", ")
        ));
    }
    let unknown: Vec<&str> = used
        .iter()
        .map(String::as_str)
        .filter(|e| handling(e) == ExtensionHandling::Unknown)
        .collect();
    if !unknown.is_empty() {
        warnings.push(format!(
            "optional extension(s) {} are not read: the file is drawn without them",
            unknown.join(", ")
        ));
    }
    warnings
}

/// Every mesh attribute must name an existing accessor (gltf-json 1.4's validator indexes
/// POSITION without a bounds check).
fn check_attribute_indices(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for index in primitive.attributes.values() {
                if index.value() >= root.accessors.len() {
                    return Err(format!(
                        "mesh {m} primitive {p} refers to accessor {}, but the file has {}",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    Ok(())
}
