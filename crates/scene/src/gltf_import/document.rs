//! Parses a glTF file's bytes (`.gltf` JSON or `.glb`) into a validated [`gltf::Document`],
//! deciding per extension what aograph does with it.
//!
//! The specification (or the validator, which only warns) allows things gltf-json 1.4 refuses,
//! so this module handles them before or instead of the crate: an accessor with neither a
//! buffer view nor a sparse part (all zeros, glTF 2.0 §3.6.2.3), a texture whose image lives
//! in an extension, a malformed accessor nothing uses, the JSON edits of `lenient_json`, and
//! the .glb edge cases of `glb_container`. Required extensions are read (KHR_mesh_quantization,
//! EXT_ / KHR_meshopt_compression, EXT_mesh_gpu_instancing), ignored when they cannot change AO
//! (materials, textures, lights), or refused by name with a conversion.
//! Invariant: a returned document passed gltf-json's validation except for exactly those
//! cases; every required extension is read or ignorable, else the file is refused with
//! [`SceneError::UnsupportedExtension`]; glTF 1.0 is refused as [`SceneError::Gltf1`].

use super::glb_container::{GlbProblem, split_glb};
use super::lenient_json;
use super::{ExtensionHandling, ExtensionUse};
use crate::error::SceneError;
use gltf::json::validation::{Error as ValidationError, Validate};
use serde_json::Value;
use std::collections::BTreeSet;
use std::path::Path;

/// Extensions aograph reads: the geometry depends on them.
pub const READ_EXTENSIONS: &[&str] = &[
    "KHR_mesh_quantization",
    "EXT_meshopt_compression",
    "KHR_meshopt_compression",
    "EXT_mesh_gpu_instancing",
];

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

/// A parsed file: the validated document, its GLB binary chunk, and what was skipped.
pub(super) struct ParsedDocument {
    pub document: gltf::Document,
    pub blob: Option<Vec<u8>>,
    /// The raw JSON, for extension data gltf-json does not keep (EXT_meshopt_compression).
    pub json: Value,
    /// The file is a .glb (a buffer without `uri` may be its binary chunk).
    pub glb: bool,
    /// Buffers something aograph reads points into (see [`read_buffers`]).
    pub read_buffers: BTreeSet<usize>,
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
    let gltf_1 = || SceneError::Gltf1 {
        path: path.to_owned(),
    };
    // RFC 1952's magic number: a .glb.gz or .gltf.gz renamed, or served with its encoding kept.
    if bytes.starts_with(&[0x1f, 0x8b]) {
        return Err(invalid(
            "the file is gzip-compressed, not glTF: decompress it first (gunzip -c file > \
             scene.glb, or 7-Zip), then load the result"
                .into(),
        ));
    }
    let glb = bytes.starts_with(b"glTF");
    let (json_bytes, blob, mut warnings) = if glb {
        match split_glb(bytes) {
            Ok(parts) => (parts.json, parts.bin.map(<[u8]>::to_vec), parts.warnings),
            Err(GlbProblem::Version1) => return Err(gltf_1()),
            Err(GlbProblem::Invalid(message)) => return Err(invalid(message)),
        }
    } else {
        (bytes, None, Vec::new())
    };
    let mut json: Value =
        serde_json::from_slice(json_bytes).map_err(|e| malformed(e.to_string()))?;
    if lenient_json::is_gltf_1(&json) {
        return Err(gltf_1());
    }
    let skipped = lenient_json::drop_channels_without_node(&mut json);
    if skipped > 0 {
        warnings.push(format!(
            "{skipped} animation channel(s) have no target node (their target is named by an \
             extension such as KHR_animation_pointer, which aograph does not read): skipped"
        ));
    }
    let filled = lenient_json::fill_scene_nodes(&mut json);
    if filled > 0 {
        warnings.push(format!(
            "{filled} scene(s) have no `nodes` array: read as empty"
        ));
    }
    let odd_extras = lenient_json::non_object_extras(&json);
    if odd_extras > 0 {
        warnings.push(format!(
            "{odd_extras} `extras` are not JSON objects (glTF says they should be): ignored, as \
             every `extras` is"
        ));
    }
    check_required_extensions(path, &json)?;
    warnings.extend(extension_warnings(&json));
    // Typed parsing from the original bytes keeps serde's line and column in messages; the
    // edited value is parsed only when something was edited, or when strict parsing failed
    // and whole numbers written as decimals are the cause.
    let strict = if skipped + filled > 0 {
        serde_json::from_value(json.clone())
    } else {
        serde_json::from_slice(json_bytes)
    };
    let root: gltf::json::Root = match strict {
        Ok(root) => root,
        Err(strict_error) => {
            let mut lenient = json.clone();
            let rewritten = lenient_json::whole_floats_to_integers(&mut lenient);
            match serde_json::from_value(lenient) {
                Ok(root) if rewritten > 0 => {
                    warnings.push(
                        "the JSON writes whole numbers as decimals (such as 1.0) where glTF \
                         expects integers: read as integers"
                            .into(),
                    );
                    root
                }
                _ => return Err(malformed(strict_error.to_string())),
            }
        }
    };
    check_attribute_indices(&root).map_err(invalid)?;
    let used = used_accessors(&root, &json);
    let mut errors = Vec::new();
    let mut unused_broken = BTreeSet::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path();
        if allowed_by_specification(path.as_str(), &error) {
            return;
        }
        match accessor_of(path.as_str()) {
            Some(i) if !used.contains(&i) => {
                unused_broken.insert(i);
            }
            _ => errors.push((path, error)),
        }
    });
    if !errors.is_empty() {
        return Err(invalid(super::validation_report::refusal(&json, &errors)));
    }
    if !unused_broken.is_empty() {
        warnings.push(format!(
            "accessor(s) {unused_broken:?} break the glTF rules but nothing uses them: ignored"
        ));
    }
    Ok(ParsedDocument {
        read_buffers: read_buffers(&root, &json, &used),
        document: gltf::Document::from_json_without_validation(root),
        blob,
        json,
        glb,
        warnings,
    })
}

/// The accessor index a validation path such as `accessors[3].type` is about.
fn accessor_of(path: &str) -> Option<usize> {
    let rest = path.strip_prefix("accessors[")?;
    rest[..rest.find(']')?].parse().ok()
}

/// Every accessor something reads: attributes, indices and morph targets of every primitive,
/// inverse bind matrices, animation samplers, and EXT_mesh_gpu_instancing attributes.
fn used_accessors(root: &gltf::json::Root, json: &Value) -> BTreeSet<usize> {
    let mut used = BTreeSet::new();
    for primitive in root.meshes.iter().flat_map(|m| &m.primitives) {
        used.extend(primitive.attributes.values().map(|i| i.value()));
        used.extend(primitive.indices.map(|i| i.value()));
        for target in primitive.targets.iter().flatten() {
            used.extend(
                [target.positions, target.normals, target.tangents]
                    .into_iter()
                    .flatten()
                    .map(|i| i.value()),
            );
        }
    }
    used.extend(
        root.skins
            .iter()
            .filter_map(|s| s.inverse_bind_matrices.map(|i| i.value())),
    );
    for sampler in root.animations.iter().flat_map(|a| &a.samplers) {
        used.extend([sampler.input.value(), sampler.output.value()]);
    }
    let nodes = json.get("nodes").and_then(Value::as_array);
    for node in nodes.into_iter().flatten() {
        let attributes = node
            .pointer("/extensions/EXT_mesh_gpu_instancing/attributes")
            .and_then(Value::as_object);
        for index in attributes.into_iter().flat_map(|a| a.values()) {
            used.extend(index.as_u64().map(|i| i as usize));
        }
    }
    used
}

/// Buffers something aograph reads points into: those of the buffer views (sparse parts
/// included) of the `used` accessors, and the compressed streams of EXT / KHR_meshopt_compression.
fn read_buffers(root: &gltf::json::Root, json: &Value, used: &BTreeSet<usize>) -> BTreeSet<usize> {
    let buffer_of = |view: gltf::json::Index<gltf::json::buffer::View>| {
        root.buffer_views
            .get(view.value())
            .map(|v| v.buffer.value())
    };
    let mut read = BTreeSet::new();
    for accessor in used.iter().filter_map(|&i| root.accessors.get(i)) {
        read.extend(accessor.buffer_view.and_then(buffer_of));
        if let Some(sparse) = &accessor.sparse {
            read.extend(buffer_of(sparse.indices.buffer_view));
            read.extend(buffer_of(sparse.values.buffer_view));
        }
    }
    let views = json.get("bufferViews").and_then(Value::as_array);
    for view in views.into_iter().flatten() {
        for name in super::meshopt_views::EXTENSIONS {
            let source = view.pointer(&format!("/extensions/{name}/buffer"));
            read.extend(source.and_then(Value::as_u64).map(|b| b as usize));
        }
    }
    read
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

/// What aograph does with extension `name`: one not in the lists whose name says it concerns
/// only materials or textures (`VENDOR_materials_*`, `VENDOR_texture_*`, the naming rule of the
/// Khronos extension registry) is ignored like the listed ones.
fn handling(name: &str) -> ExtensionHandling {
    let material_or_texture = name.contains("_materials_") || name.contains("_texture_");
    if READ_EXTENSIONS.contains(&name) {
        ExtensionHandling::Read
    } else if IGNORED_EXTENSIONS.contains(&name) || material_or_texture {
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
    // §3.7.2.1: "When positions are not specified, client implementations SHOULD skip
    // primitive's rendering" (`primitive_reader` skips it with a warning).
    let no_position = matches!(error, ValidationError::Missing)
        && path.starts_with("meshes[")
        && path.ends_with(".attributes[\"POSITION\"]");
    zeros_accessor || required_extension || texture_source || no_position
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

/// One warning for the material, texture and light extensions aograph does not apply, one for
/// optional extensions it does not know.
fn extension_warnings(json: &Value) -> Vec<String> {
    let used = extension_uses(json);
    let named = |handling: ExtensionHandling| -> Vec<&str> {
        (used.iter())
            .filter(|e| e.handling == handling)
            .map(|e| e.name.as_str())
            .collect()
    };
    let mut warnings = Vec::new();
    let ignored = named(ExtensionHandling::Ignored);
    if !ignored.is_empty() {
        warnings.push(format!(
            "{} change only materials, textures or lights, which AO does not use: not applied \
             (albedo is each material's base colour factor)",
            ignored.join(", ")
        ));
    }
    let unknown = named(ExtensionHandling::Unknown);
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
