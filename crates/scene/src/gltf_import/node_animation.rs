//! Reads glTF node animations (translation, rotation, scale channels) into per-node
//! [`TrsKeyframes`].
//!
//! Choices: only the file's first animation clip is used (files with several clips usually hold
//! alternatives such as walk and run, which are not meant to play together); LINEAR and STEP
//! are kept; CUBICSPLINE keeps its key values and drops the tangents, i.e. it is played back
//! linearly (a warning says so); morph-target weight channels are ignored with a warning.
//! Invariant: every returned track passed [`Track::new`]'s checks (matching lengths, sorted
//! finite times); channels that fail them are dropped with a warning, never a panic. The gltf
//! crate's channel readers unwrap their indices and enums, so a channel is read only after
//! [`unreadable_channel`] found its node, path, sampler, interpolation and accessors valid in
//! the JSON; a channel that fails is skipped with a warning naming it.

use super::accessor_reader::{KEY_ROTATIONS, KEY_TIMES, KEY_VECTORS, read_floats};
use crate::animation::{Interpolation, Track, TrsKeyframes};
use glam::{Quat, Vec3};
use gltf::animation::Interpolation as GltfInterpolation;
use gltf::animation::Property;
use std::collections::BTreeMap;

/// The unit quaternion of glTF `[x, y, z, w]` (identity if it has no usable length).
fn unit_quat(xyzw: [f32; 4]) -> Quat {
    glam::Vec4::from_array(xyzw)
        .try_normalize()
        .map_or(Quat::IDENTITY, Quat::from_vec4)
}

/// The rest pose of `node` as keyframes without tracks.
fn rest_keyframes(node: &gltf::Node<'_>) -> TrsKeyframes {
    let (t, r, s) = node.transform().decomposed();
    TrsKeyframes {
        rest_translation: Vec3::from_array(t),
        rest_rotation: unit_quat(r),
        rest_scale: Vec3::from_array(s),
        translation: None,
        rotation: None,
        scale: None,
    }
}

/// CUBICSPLINE outputs are (in-tangent, value, out-tangent) triples: keep the values.
fn key_values<T: Copy>(values: Vec<T>, cubic: bool) -> Vec<T> {
    if cubic {
        values.chunks_exact(3).map(|triple| triple[1]).collect()
    } else {
        values
    }
}

/// Why channel `channel` of the first animation cannot be read safely, if it cannot: an index
/// past its array (node, sampler, accessor) or a target path or interpolation glTF 2.0 does not
/// define (KHR_animation_pointer's `pointer`, say), which the gltf crate's readers unwrap.
fn unreadable_channel(root: &gltf::json::Root, channel: usize) -> Option<String> {
    use gltf::json::validation::Checked;
    let animation = root.animations.first()?;
    let c = animation.channels.get(channel)?;
    let node = c.target.node.value();
    if node >= root.nodes.len() {
        return Some(format!(
            "targets node {node}, but the file has {} nodes",
            root.nodes.len()
        ));
    }
    if !matches!(c.target.path, Checked::Valid(_)) {
        return Some(
            "its target path is none of glTF 2.0's (translation, rotation, scale, weights): \
             an extension's, such as KHR_animation_pointer's `pointer`, or unknown"
                .into(),
        );
    }
    let sampler = c.sampler.value();
    let Some(s) = animation.samplers.get(sampler) else {
        return Some(format!(
            "uses sampler {sampler}, but the animation has {} samplers",
            animation.samplers.len()
        ));
    };
    if !matches!(s.interpolation, Checked::Valid(_)) {
        return Some(format!(
            "sampler {sampler}'s interpolation is none of LINEAR, STEP, CUBICSPLINE"
        ));
    }
    for (what, accessor) in [("input", s.input.value()), ("output", s.output.value())] {
        if accessor >= root.accessors.len() {
            return Some(format!(
                "sampler {sampler}'s {what} is accessor {accessor}, but the file has {} accessors",
                root.accessors.len()
            ));
        }
    }
    None
}

/// Keyframes of every animated node of the first animation, by node index, plus warnings.
pub(super) fn read_node_animations(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
) -> (BTreeMap<usize, TrsKeyframes>, Vec<String>) {
    let mut nodes: BTreeMap<usize, TrsKeyframes> = BTreeMap::new();
    let mut warnings = Vec::new();
    let Some(animation) = document.animations().next() else {
        return (nodes, warnings);
    };
    let extra_clips = document.animations().count() - 1;
    if extra_clips > 0 {
        warnings.push(format!(
            "the file has {} animations; only the first (\"{}\") is played",
            extra_clips + 1,
            animation.name().unwrap_or("unnamed")
        ));
    }
    let mut cubic_warned = false;
    for channel in animation.channels() {
        if let Some(problem) = unreadable_channel(document.as_json(), channel.index()) {
            warnings.push(format!(
                "animation channel {}: {problem}: ignored",
                channel.index()
            ));
            continue;
        }
        let node = channel.target().node();
        let label = format!(
            "animation channel {} (node {})",
            channel.index(),
            node.index()
        );
        let output_shape = match channel.target().property() {
            Property::Translation | Property::Scale => &KEY_VECTORS,
            Property::Rotation => &KEY_ROTATIONS,
            Property::MorphTargetWeights => {
                warnings.push(format!(
                    "{label}: morph target weights are not supported: ignored"
                ));
                continue;
            }
        };
        let keys = read_floats(&channel.sampler().input(), buffers, &KEY_TIMES).and_then(|t| {
            Ok((
                t,
                read_floats(&channel.sampler().output(), buffers, output_shape)?,
            ))
        });
        let (times, outputs) = match keys {
            Ok(keys) => keys,
            Err(problem) => {
                warnings.push(format!("{label}: {problem}: ignored"));
                continue;
            }
        };
        let (interpolation, cubic) = match channel.sampler().interpolation() {
            GltfInterpolation::Linear => (Interpolation::Linear, false),
            GltfInterpolation::Step => (Interpolation::Step, false),
            GltfInterpolation::CubicSpline => (Interpolation::Linear, true),
        };
        if cubic && !cubic_warned {
            warnings
                .push("CUBICSPLINE animation is played back linearly (tangents ignored)".into());
            cubic_warned = true;
        }
        let entry = nodes
            .entry(node.index())
            .or_insert_with(|| rest_keyframes(&node));
        let ok = match channel.target().property() {
            Property::Translation => {
                let values = outputs.chunks_exact(3).map(Vec3::from_slice).collect();
                entry.translation = Track::new(times, key_values(values, cubic), interpolation);
                entry.translation.is_some()
            }
            Property::Scale => {
                let values = outputs.chunks_exact(3).map(Vec3::from_slice).collect();
                entry.scale = Track::new(times, key_values(values, cubic), interpolation);
                entry.scale.is_some()
            }
            Property::Rotation => {
                let values = outputs
                    .chunks_exact(4)
                    .map(|q| unit_quat([q[0], q[1], q[2], q[3]]))
                    .collect();
                entry.rotation = Track::new(times, key_values(values, cubic), interpolation);
                entry.rotation.is_some()
            }
            Property::MorphTargetWeights => true,
        };
        if !ok {
            warnings.push(format!(
                "{label}: key times and values do not match or times are not increasing: ignored"
            ));
        }
    }
    nodes.retain(|_, keys| {
        keys.translation.is_some() || keys.rotation.is_some() || keys.scale.is_some()
    });
    (nodes, warnings)
}
