//! The techniques an application's frame can feed, with every parameter's description, as
//! the JSON the page's script builds its controls from (as the viewer builds its widgets from
//! the same descriptions: one typed description per parameter, no list kept by hand).
//!
//! Invariant: a technique is listed exactly when `aograph_embed::feedable_techniques` offers
//! it, with its parameters in the order `parameters()` gives them.

use aograph_ao_passes::{ParamKind, TechniqueRegistry};
use serde_json::{Value, json};

/// `[{ "name", "description", "parameters": [{ "name", "doc", "kind", ... }] }]`: a
/// parameter's `kind` is `"range"` (with `min`, `max`, `integer`, `odd`, `above_min`),
/// `"choice"` (`choices`), `"bool"` or `"word_or_number"` (`word`, `min`, `max`); `default`
/// is its TOML default as JSON (null for an unset override, whose `unset` says what leaving it
/// out means).
pub fn technique_catalogue(registry: &TechniqueRegistry) -> Value {
    let techniques: Vec<Value> = aograph_embed::feedable_techniques(registry)
        .iter()
        .filter_map(|name| registry.get(name).ok())
        .map(|t| {
            let parameters: Vec<Value> = t
                .parameters()
                .iter()
                .map(|p| {
                    let mut v = match &p.kind {
                        ParamKind::Range {
                            min,
                            max,
                            integer,
                            odd,
                            above_min,
                        } => json!({ "kind": "range", "min": min, "max": max,
                            "integer": integer, "odd": odd, "above_min": above_min }),
                        ParamKind::Choice(choices) => json!({ "kind": "choice", "choices": choices }),
                        ParamKind::Bool => json!({ "kind": "bool" }),
                        ParamKind::WordOrNumber { word, min, max } => {
                            json!({ "kind": "word_or_number", "word": word, "min": min, "max": max })
                        }
                    };
                    v["name"] = json!(p.name);
                    v["doc"] = json!(p.doc);
                    v["allowed"] = json!(p.allowed());
                    v["default"] = p
                        .default
                        .as_ref()
                        .and_then(|d| serde_json::to_value(d).ok())
                        .unwrap_or(Value::Null);
                    v["unset"] = json!(p.unset);
                    v
                })
                .collect();
            json!({ "name": t.name(), "description": t.description(), "parameters": parameters })
        })
        .collect();
    Value::Array(techniques)
}
