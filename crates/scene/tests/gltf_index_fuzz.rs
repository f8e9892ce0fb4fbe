//! Structure-aware fuzzing of the glTF loader: every index field of a few real files is set,
//! one at a time, to one past the end of the array it indexes and to a huge value, and every
//! enum-valued field (animation paths, interpolations, accessor types, modes, component types)
//! to a word or number glTF does not define. Unlike `gltf_fuzz`, which mutates leaves at random,
//! this reaches each field on purpose, so a reader that trusts an index is found.
//! Every outcome is asserted: the loader never panics; it refuses the file with an error that
//! names the file and the place (the JSON path, or the element and its index), or it loads
//! the file, with a warning naming the place whenever the mutated field was one it reads.

mod common;

use aograph_scene::{SceneError, export_glb, import_gltf, procedural_scene, test_scene};
use serde_json::Value;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

/// Object members holding one index, and the top-level array each indexes (`None`: an
/// animation's own `samplers`, found from the field's place).
const INDEX_FIELDS: &[(&str, Option<&str>)] = &[
    ("node", Some("nodes")),
    ("skeleton", Some("nodes")),
    ("mesh", Some("meshes")),
    ("camera", Some("cameras")),
    ("skin", Some("skins")),
    ("material", Some("materials")),
    ("index", Some("textures")),
    ("source", Some("images")),
    ("scene", Some("scenes")),
    ("input", Some("accessors")),
    ("output", Some("accessors")),
    ("indices", Some("accessors")),
    ("inverseBindMatrices", Some("accessors")),
    ("bufferView", Some("bufferViews")),
    ("buffer", Some("buffers")),
    ("sampler", None),
];

/// Object members holding a list of node indices.
const NODE_LISTS: &[&str] = &["children", "joints", "nodes"];

/// Object members holding an enum, and the value glTF does not define that replaces it.
const ENUM_FIELDS: &[(&str, &str)] = &[
    ("path", "\"foo\""),
    ("interpolation", "\"CUBIC\""),
    ("type", "\"VEC5\""),
    ("alphaMode", "\"CUTOUT\""),
    ("mode", "99"),
    ("componentType", "5124"),
    ("target", "99"),
    ("magFilter", "1"),
    ("wrapS", "2"),
];

/// A huge index: past any array, still a valid 32-bit glTF index.
const HUGE: u64 = 4_000_000_000;

/// One mutation: the JSON pointer of the field and the value written there.
struct Mutation {
    pointer: String,
    value: Value,
}

/// The length of the array an index field at `pointer` indexes.
fn indexed_len(json: &Value, pointer: &str, array: Option<&str>) -> usize {
    let array = match array {
        Some(name) => json.get(name),
        // Samplers: a texture's `sampler` indexes the top-level `samplers`, an animation
        // channel's its animation's own.
        None if pointer.starts_with("/animations/") => {
            let animation: Vec<&str> = pointer.split('/').take(3).collect();
            json.pointer(&format!("{}/samplers", animation.join("/")))
        }
        None => json.get("samplers"),
    };
    array.and_then(Value::as_array).map_or(0, Vec::len)
}

/// Every mutation of `json`'s index and enum fields, in document order.
fn mutations(json: &Value) -> Vec<Mutation> {
    let mut out = Vec::new();
    let mut places = Vec::new();
    members(json, String::new(), &mut places);
    for (pointer, key, value) in places {
        let past_end_and_huge = |len: usize, out: &mut Vec<Mutation>, pointer: &str| {
            for bad in [len as u64, HUGE] {
                out.push(Mutation {
                    pointer: pointer.to_owned(),
                    value: Value::from(bad),
                });
            }
        };
        if let Some((_, array)) = INDEX_FIELDS.iter().find(|(k, _)| *k == key) {
            if value.is_u64() {
                past_end_and_huge(indexed_len(json, &pointer, *array), &mut out, &pointer);
            }
        } else if NODE_LISTS.contains(&key.as_str()) {
            let list = value.as_array().filter(|l| l.iter().all(Value::is_u64));
            for i in 0..list.map_or(0, Vec::len) {
                past_end_and_huge(
                    indexed_len(json, "", Some("nodes")),
                    &mut out,
                    &format!("{pointer}/{i}"),
                );
            }
        } else if key == "attributes" {
            for name in value.as_object().into_iter().flat_map(|a| a.keys()) {
                past_end_and_huge(
                    indexed_len(json, "", Some("accessors")),
                    &mut out,
                    &format!("{pointer}/{name}"),
                );
            }
        }
        if let Some((_, unknown)) = ENUM_FIELDS.iter().find(|(k, _)| *k == key) {
            if value.is_string() || value.is_u64() {
                out.push(Mutation {
                    pointer,
                    value: serde_json::from_str(unknown).unwrap(),
                });
            }
        }
    }
    out
}

/// Every (pointer, member name, value) of the objects in `value`.
fn members(value: &Value, pointer: String, out: &mut Vec<(String, String, Value)>) {
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                let at = format!("{pointer}/{k}");
                out.push((at.clone(), k.clone(), v.clone()));
                members(v, at, out);
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                members(v, format!("{pointer}/{i}"), out);
            }
        }
        _ => {}
    }
}

/// The ways a message may name the place `pointer` points at: its JSON path
/// (`nodes[3].mesh`), or an element and its number (`node 3`, `accessor 7`).
fn names_the_place(message: &str, pointer: &str) -> bool {
    let parts: Vec<&str> = pointer.trim_start_matches('/').split('/').collect();
    // "nodes[3]", "node 3", "animation 0 channel 2", ...
    let mut json_path = String::new();
    let mut ok = false;
    for pair in parts.windows(2) {
        if let Ok(i) = pair[1].parse::<usize>() {
            // "bufferViews" is also "bufferView 3" and "buffer view 3".
            let singular = pair[0].trim_end_matches('s');
            let words: String = singular
                .chars()
                .flat_map(|c| match c.is_uppercase() {
                    true => vec![' ', c.to_ascii_lowercase()],
                    false => vec![c],
                })
                .collect();
            ok |= message.contains(&format!("{}[{i}]", pair[0]))
                || message.contains(&format!("{singular} {i}"))
                || message.contains(&format!("{words} {i}"));
        }
    }
    for part in &parts {
        match part.parse::<usize>() {
            Ok(i) => json_path.push_str(&format!("[{i}]")),
            Err(_) if json_path.is_empty() => json_path.push_str(part),
            Err(_) => json_path.push_str(&format!(".{part}")),
        }
    }
    ok || message.contains(&json_path)
}

/// Applies each mutation of `json` (a .gltf whose buffers sit beside `dir`), loads the result
/// and asserts its outcome; returns (refused, loaded with a warning).
fn fuzz_file(name: &str, json: &Value, dir: &Path, failures: &mut Vec<String>) -> (usize, usize) {
    let target = dir.join(format!("{name}-mutated.gltf"));
    std::fs::write(&target, serde_json::to_vec(json).unwrap()).unwrap();
    let clean = import_gltf(&target).unwrap_or_else(|e| panic!("{name} does not load: {e}"));
    let mut counts = (0, 0);
    let all = mutations(json);
    assert!(all.len() > 10, "{name}: only {} fields found", all.len());
    for Mutation { pointer, value } in all {
        let mut mutated = json.clone();
        *mutated.pointer_mut(&pointer).unwrap() = value.clone();
        std::fs::write(&target, serde_json::to_vec(&mutated).unwrap()).unwrap();
        let what = format!("{name}: {pointer} = {value}");
        let Ok(outcome) = catch_unwind(AssertUnwindSafe(|| import_gltf(&target))) else {
            failures.push(format!("loading panicked after {what}"));
            continue;
        };
        let mut check = |ok: bool, message: String| {
            if !ok {
                failures.push(message);
            }
        };
        match outcome {
            Err(e) => {
                let message = e.to_string();
                check(
                    matches!(
                        e,
                        SceneError::InvalidGltf { .. }
                            | SceneError::MalformedJson { .. }
                            | SceneError::EmptyScene { .. }
                    ),
                    format!("unexpected refusal after {what}: {e:?}"),
                );
                check(
                    message.contains("mutated.gltf"),
                    format!("the refusal after {what} does not name the file: {message}"),
                );
                check(
                    names_the_place(&message, &pointer),
                    format!("the refusal after {what} does not name the place: {message}"),
                );
                counts.0 += 1;
            }
            Ok(import) => {
                if let Err(e) = import.scene.check_invariants() {
                    check(
                        false,
                        format!("the scene loaded after {what} breaks an invariant: {e}"),
                    );
                }
                let new: Vec<&String> = (import.warnings.iter())
                    .filter(|w| !clean.warnings.contains(w))
                    .collect();
                if new.is_empty() {
                    // Every mutated field is one the loader reads or validates: a load that
                    // says nothing has ignored a broken index.
                    failures.push(format!("loaded without a warning after {what}"));
                } else {
                    check(
                        new.iter().any(|w| names_the_place(w, &pointer)),
                        format!("the warnings after {what} do not name the place: {new:?}"),
                    );
                    counts.1 += 1;
                }
            }
        }
    }
    eprintln!(
        "{name}: {} refused, {} loaded with a warning",
        counts.0, counts.1
    );
    counts
}

/// The JSON of a .glb, its binary chunk written as `{name}.bin` in `dir` and named by
/// buffer 0's `uri`.
fn glb_as_gltf(bytes: &[u8], dir: &Path, name: &str) -> Value {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let mut json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = format!("{name}.bin");
    std::fs::write(dir.join(&bin), &bytes[20 + json_len + 8..]).unwrap();
    json["buffers"][0]["uri"] = Value::from(bin);
    json
}

#[test]
fn every_index_and_enum_field_set_out_of_range_is_refused_or_warned_by_place() {
    let dir = common::temp_dir("index-fuzz");
    let mut files = Vec::new();
    if let Some(path) = test_scene("the index fuzz", "CesiumMan.glb") {
        files.push((
            "skinned",
            glb_as_gltf(&std::fs::read(path).unwrap(), &dir, "skinned"),
        ));
    }
    if let Some(path) = test_scene("the index fuzz", "FlightHelmet/FlightHelmet.gltf") {
        let json: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        std::fs::copy(
            path.with_file_name("FlightHelmet.bin"),
            dir.join("FlightHelmet.bin"),
        )
        .unwrap();
        files.push(("textured", json));
    }
    let cameras = dir.join("cameras.glb");
    export_glb(&procedural_scene("stairs").unwrap(), &cameras).unwrap();
    files.push((
        "cameras",
        glb_as_gltf(&std::fs::read(&cameras).unwrap(), &dir, "cameras"),
    ));
    let original = dir.join("columns.glb");
    export_glb(&procedural_scene("columns").unwrap(), &original).unwrap();
    for (kind, args) in [("instanced", &["-mi"][..]), ("meshopt", &["-c"][..])] {
        let packed = dir.join(format!("{kind}.glb"));
        if common::gltfpack(&original, &packed, args).is_some() {
            files.push((
                kind,
                glb_as_gltf(&std::fs::read(&packed).unwrap(), &dir, kind),
            ));
        }
    }
    let mut failures = Vec::new();
    for (name, json) in &files {
        fuzz_file(name, json, &dir, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "{} outcomes failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
