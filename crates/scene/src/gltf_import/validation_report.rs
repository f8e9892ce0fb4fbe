//! Turns gltf-json's validation errors into sentences a user can act on: the JSON path, the
//! value the file writes there, and what glTF allows (for an index, how many entries its array
//! has). Invariant: every message names the JSON path as gltf-json reports it
//! (`meshes[0].primitives[1].indices`), so a message can be found in the file.

use gltf::json::validation::Error as ValidationError;
use serde_json::Value;

/// The top-level array an index field indexes, by the field's name; `None` for a field whose
/// array depends on its place (`sampler`) or that is not an index.
fn indexed_array(path: &str, field: &str) -> Option<String> {
    let array = match field {
        "node" | "skeleton" | "children" | "joints" | "nodes" => "nodes",
        "mesh" => "meshes",
        "camera" => "cameras",
        "skin" => "skins",
        "material" => "materials",
        "index" => "textures",
        "source" => "images",
        "scene" => "scenes",
        "input" | "output" | "indices" | "inverseBindMatrices" | "attributes" => "accessors",
        "bufferView" => "bufferViews",
        "buffer" => "buffers",
        "sampler" if path.starts_with("animations[") => {
            let animation = &path[..path.find(']')? + 1];
            return Some(format!("{animation}.samplers"));
        }
        "sampler" => "samplers",
        _ => return None,
    };
    Some(array.to_owned())
}

/// The JSON value at a gltf-json path such as `nodes[3].children[0]` or
/// `meshes[0].primitives[0].attributes["POSITION"]`.
fn value_at<'v>(json: &'v Value, path: &str) -> Option<&'v Value> {
    let mut value = json;
    for segment in path.split('.') {
        let (name, rest) = segment.split_at(segment.find('[').unwrap_or(segment.len()));
        value = value.get(name)?;
        for subscript in rest.split('[').skip(1) {
            let subscript = subscript.strip_suffix(']')?;
            value = match subscript.parse::<usize>() {
                Ok(i) => value.get(i)?,
                Err(_) => value.get(subscript.trim_matches('"'))?,
            };
        }
    }
    Some(value)
}

/// The name of the last field of `path` (`children` for `nodes[3].children[0]`).
fn last_field(path: &str) -> &str {
    let last = path.rsplit('.').next().unwrap_or(path);
    &last[..last.find('[').unwrap_or(last.len())]
}

/// One validation error as a sentence, e.g. "nodes[3].mesh is 7, but the file has 2 meshes".
pub(super) fn describe(json: &Value, path: &str, error: &ValidationError) -> String {
    let written = value_at(json, path).map(Value::to_string);
    match (error, written) {
        (ValidationError::IndexOutOfBounds, Some(written)) => {
            let field = last_field(path);
            match indexed_array(path, field) {
                Some(array) => {
                    let len = value_at(json, &array)
                        .and_then(Value::as_array)
                        .map_or(0, Vec::len);
                    format!(
                        "{path} is {written}, but the file has {len} {array} (indices 0 to {len} exclusive)"
                    )
                }
                None => format!("{path} is {written}, past the end of the array it indexes"),
            }
        }
        (ValidationError::Invalid, Some(written)) => {
            format!("{path} is {written}, which is not a value glTF 2.0 defines there")
        }
        (error, _) => format!("{path}: {error}"),
    }
}

/// The message refusing a file for `errors`: the first five described, and how many more.
pub(super) fn refusal(json: &Value, errors: &[(gltf::json::Path, ValidationError)]) -> String {
    let shown: Vec<String> = (errors.iter().take(5))
        .map(|(path, error)| describe(json, path.as_str(), error))
        .collect();
    let more = errors.len().saturating_sub(shown.len());
    let suffix = if more > 0 {
        format!(" (and {more} more)")
    } else {
        String::new()
    };
    format!("{}{suffix}", shown.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn an_index_past_its_array_is_described_with_the_array_length() {
        let file = json!({
            "nodes": [{"children": [0, 9]}],
            "animations": [{"channels": [{"sampler": 4}], "samplers": [{}, {}]}],
        });
        assert_eq!(
            describe(
                &file,
                "nodes[0].children[1]",
                &ValidationError::IndexOutOfBounds
            ),
            "nodes[0].children[1] is 9, but the file has 1 nodes (indices 0 to 1 exclusive)"
        );
        assert_eq!(
            describe(
                &file,
                "animations[0].channels[0].sampler",
                &ValidationError::IndexOutOfBounds
            ),
            "animations[0].channels[0].sampler is 4, but the file has 2 animations[0].samplers \
             (indices 0 to 2 exclusive)"
        );
    }

    #[test]
    fn an_unknown_enum_value_is_quoted_as_written() {
        let file = json!({"meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 9}]}],
            "accessors": [{"type": "VEC5"}]});
        assert_eq!(
            describe(&file, "accessors[0].type", &ValidationError::Invalid),
            "accessors[0].type is \"VEC5\", which is not a value glTF 2.0 defines there"
        );
        assert_eq!(
            value_at(&file, "meshes[0].primitives[0].attributes[\"POSITION\"]"),
            Some(&json!(0))
        );
    }
}
