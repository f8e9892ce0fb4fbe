//! Edits of a glTF's JSON value for what the validator accepts (or only warns about) but
//! gltf-json 1.4's typed parsing refuses. Each edit returns how many places it changed, so
//! the caller can warn once per kind, and each leaves a valid file unchanged.
//!
//! - an animation channel without `target.node` (its target named by an extension such as
//!   KHR_animation_pointer) is removed;
//! - a scene without a `nodes` array gets an empty one;
//! - a whole number written as a decimal (`1.0`) becomes an integer: used only when strict
//!   parsing failed, since every float field of the schema accepts integers too.
//!
//! - `extras` that are not objects are only counted (gltf-json's `extras` feature reads any
//!   JSON there).
//!
//! Invariant: no edit adds geometry or changes a value's meaning.

use serde_json::{Number, Value};

/// Removes animation channels whose target has no `node`; returns how many.
pub(super) fn drop_channels_without_node(json: &mut Value) -> usize {
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

/// Gives every scene without a `nodes` array an empty one; returns how many.
pub(super) fn fill_scene_nodes(json: &mut Value) -> usize {
    let Some(scenes) = json.get_mut("scenes").and_then(Value::as_array_mut) else {
        return 0;
    };
    let mut filled = 0;
    for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
        if !scene.contains_key("nodes") {
            scene.insert("nodes".into(), Value::Array(Vec::new()));
            filled += 1;
        }
    }
    filled
}

/// Rewrites every whole-number float (`3.0`) as an integer; returns how many.
pub(super) fn whole_floats_to_integers(value: &mut Value) -> usize {
    match value {
        Value::Number(n) if !n.is_i64() && !n.is_u64() => {
            let Some(f) = n.as_f64() else { return 0 };
            if f.fract() != 0.0 || f.abs() > 9.0e15 {
                return 0;
            }
            *n = if f < 0.0 {
                Number::from(f as i64)
            } else {
                Number::from(f as u64)
            };
            1
        }
        Value::Array(items) => items.iter_mut().map(whole_floats_to_integers).sum(),
        Value::Object(map) => map.values_mut().map(whole_floats_to_integers).sum(),
        _ => 0,
    }
}

/// How many `extras` are not JSON objects (the specification says they SHOULD be; they are
/// kept as they are, since aograph reads none).
pub(super) fn non_object_extras(value: &Value) -> usize {
    match value {
        Value::Object(map) => map
            .iter()
            .map(|(k, v)| usize::from(k == "extras" && !v.is_object()) + non_object_extras(v))
            .sum(),
        Value::Array(items) => items.iter().map(non_object_extras).sum(),
        _ => 0,
    }
}

/// True when the JSON is a glTF 1.0 file: `asset.version` "1.x", or, without a version, the
/// 1.0 shape (top-level objects keyed by id where 2.0 has arrays).
pub(super) fn is_gltf_1(json: &Value) -> bool {
    let version = json
        .get("asset")
        .and_then(|a| a.get("version"))
        .and_then(Value::as_str);
    match version {
        Some(v) => v.starts_with("1."),
        None => ["meshes", "nodes", "accessors", "buffers"]
            .iter()
            .any(|k| json.get(*k).is_some_and(Value::is_object)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn whole_floats_become_integers_and_fractions_stay() {
        let mut v = json!({"count": 3.0, "min": [-1.0, 0.5], "n": 7});
        assert_eq!(whole_floats_to_integers(&mut v), 2);
        assert_eq!(v, json!({"count": 3, "min": [-1, 0.5], "n": 7}));
    }

    #[test]
    fn gltf_1_is_told_by_its_version_or_its_shape() {
        assert!(is_gltf_1(&json!({"asset": {"version": "1.0"}})));
        assert!(is_gltf_1(&json!({"meshes": {"mesh_0": {}}})));
        assert!(!is_gltf_1(
            &json!({"asset": {"version": "2.0"}, "meshes": []})
        ));
    }

    #[test]
    fn a_scene_without_nodes_gets_an_empty_list() {
        let mut v = json!({"scenes": [{"name": "a"}, {"nodes": [0]}]});
        assert_eq!(fill_scene_nodes(&mut v), 1);
        assert_eq!(
            v,
            json!({"scenes": [{"name": "a", "nodes": []}, {"nodes": [0]}]})
        );
    }
}
