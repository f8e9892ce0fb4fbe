//! EXT_mesh_gpu_instancing: a node whose mesh is drawn once per instance, each placed by the
//! TRANSLATION / ROTATION / SCALE accessors of the node's extension object.
//!
//! Rules (KhronosGroup/glTF, extensions/2.0/Vendor/EXT_mesh_gpu_instancing): every attribute
//! accessor has the same count; TRANSLATION and SCALE are VEC3 (float, or with
//! KHR_mesh_quantization normalized or plain integers), ROTATION is a VEC4 unit quaternion
//! (float or normalized BYTE / SHORT); a missing attribute is the identity; the instance
//! transform T * R * S is applied before the node's own world transform. Other attributes
//! (`_ID`, `_FEATURE_ID_0`) are application data and ignored.
//! Invariant: every returned matrix is finite, and a node's instance list is as long as its
//! accessors' common count; anything else is an `Err` naming the node.

use super::accessor_reader::{AccessorShape, QUANTIZED, read_floats};
use glam::{Mat4, Quat, Vec3};
use gltf::accessor::{DataType, Dimensions};
use serde_json::Value;
use std::collections::BTreeMap;

/// The JSON name of the extension.
pub(super) const EXTENSION: &str = "EXT_mesh_gpu_instancing";

const TRANSLATION: AccessorShape = AccessorShape {
    types: QUANTIZED,
    dimensions: Dimensions::Vec3,
    role: "instance TRANSLATION",
};
const ROTATION: AccessorShape = AccessorShape {
    types: &[DataType::F32, DataType::I8, DataType::I16],
    dimensions: Dimensions::Vec4,
    role: "instance ROTATION",
};
const SCALE: AccessorShape = AccessorShape {
    types: QUANTIZED,
    dimensions: Dimensions::Vec3,
    role: "instance SCALE",
};

/// Each instanced node's instance transforms, by node index.
pub(super) fn read_instances(
    json: &Value,
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> Result<BTreeMap<usize, Vec<Mat4>>, String> {
    let mut out = BTreeMap::new();
    let nodes = json.get("nodes").and_then(Value::as_array);
    for (index, node) in nodes.into_iter().flatten().enumerate() {
        let Some(ext) = node.get("extensions").and_then(|e| e.get(EXTENSION)) else {
            continue;
        };
        let label = format!("node {index}'s {EXTENSION}");
        let attributes = ext.get("attributes").and_then(Value::as_object);
        let read =
            |name: &str, shape: &AccessorShape, width: usize| -> Result<Option<Vec<f32>>, String> {
                let Some(value) = attributes.and_then(|a| a.get(name)) else {
                    return Ok(None);
                };
                let accessor = value
                    .as_u64()
                    .and_then(|i| document.accessors().nth(i as usize))
                    .ok_or_else(|| format!("{label}: {name} names no accessor of the file"))?;
                let values =
                    read_floats(&accessor, buffers, shape).map_err(|e| format!("{label}: {e}"))?;
                debug_assert_eq!(values.len() % width, 0);
                Ok(Some(values))
            };
        let translation = read("TRANSLATION", &TRANSLATION, 3)?;
        let rotation = read("ROTATION", &ROTATION, 4)?;
        let scale = read("SCALE", &SCALE, 3)?;
        let counts: Vec<usize> = [(&translation, 3), (&rotation, 4), (&scale, 3)]
            .iter()
            .filter_map(|(v, w)| v.as_ref().map(|v| v.len() / w))
            .collect();
        let Some(&count) = counts.first() else {
            return Err(format!(
                "{label} has none of TRANSLATION, ROTATION and SCALE"
            ));
        };
        if counts.iter().any(|&c| c != count) {
            return Err(format!(
                "{label}: its attributes have different counts {counts:?}"
            ));
        }
        let mut transforms = Vec::with_capacity(count);
        for i in 0..count {
            let t = translation
                .as_ref()
                .map_or(Vec3::ZERO, |v| Vec3::from_slice(&v[3 * i..]));
            let r = rotation.as_ref().map_or(Quat::IDENTITY, |v| {
                glam::Vec4::from_slice(&v[4 * i..])
                    .try_normalize()
                    .map_or(Quat::IDENTITY, Quat::from_vec4)
            });
            let s = scale
                .as_ref()
                .map_or(Vec3::ONE, |v| Vec3::from_slice(&v[3 * i..]));
            let m = Mat4::from_scale_rotation_translation(s, r, t);
            if !m.is_finite() {
                return Err(format!("{label}: instance {i}'s transform is not finite"));
            }
            transforms.push(m);
        }
        out.insert(index, transforms);
    }
    Ok(out)
}
