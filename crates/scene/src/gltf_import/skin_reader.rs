//! Reads glTF skins (§3.7.3) into [`Skin`]s: every joint's world transform over time (the whole
//! chain of its ancestors, animated links played from the first clip, as instances' are) and
//! its inverse bind matrix (identity when the file gives none, as glTF specifies).
//! Invariant of the result: every skin has at least one joint, every inverse bind matrix is
//! finite and there is one per joint; anything else is an error naming the skin, never a panic.

use super::accessor_reader::{INVERSE_BIND_MATRICES, read_floats};
use super::{ChainLink, chain_transform, node_link};
use crate::animation::{AnimatedTransform, Animation, TrsKeyframes};
use crate::skin::{Joint, Skin};
use glam::Mat4;
use std::collections::BTreeMap;

/// Every skin of the file, by glTF skin index; `Err` says what is wrong with which skin.
pub(super) fn read_skins(
    document: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    animated_nodes: &BTreeMap<usize, TrsKeyframes>,
) -> Result<Vec<Skin>, String> {
    let parents = parent_map(document);
    let nodes: Vec<gltf::Node<'_>> = document.nodes().collect();
    document
        .skins()
        .map(|skin| {
            let label = skin.name().map_or_else(
                || format!("skin {}", skin.index()),
                |n| format!("skin \"{n}\""),
            );
            let joints: Vec<gltf::Node<'_>> = skin.joints().collect();
            if joints.is_empty() {
                return Err(format!("{label} has no joints"));
            }
            let inverse_binds = inverse_bind_matrices(&skin, buffers, joints.len())
                .map_err(|problem| format!("{label}: {problem}"))?;
            let joints = joints
                .iter()
                .zip(inverse_binds)
                .map(|(node, inverse_bind)| {
                    let chain = ancestor_chain(&nodes, &parents, node.index(), animated_nodes)
                        .map_err(|problem| format!("{label}: {problem}"))?;
                    let world = chain_transform(&chain).unwrap_or_else(|fixed| {
                        Animation::new(vec![AnimatedTransform::Static(fixed)])
                    });
                    Ok(Joint {
                        name: node
                            .name()
                            .map_or_else(|| format!("node {}", node.index()), str::to_owned),
                        world,
                        inverse_bind,
                    })
                })
                .collect::<Result<Vec<_>, String>>()?;
            Ok(Skin {
                name: label,
                joints,
            })
        })
        .collect()
}

/// One inverse bind matrix per joint: the file's, or identity when it has none.
fn inverse_bind_matrices(
    skin: &gltf::Skin<'_>,
    buffers: &[gltf::buffer::Data],
    joints: usize,
) -> Result<Vec<Mat4>, String> {
    let Some(accessor) = skin.inverse_bind_matrices() else {
        return Ok(vec![Mat4::IDENTITY; joints]);
    };
    if accessor.count() < joints {
        return Err(format!(
            "{} inverse bind matrices for {joints} joints",
            accessor.count()
        ));
    }
    let matrices: Vec<Mat4> = read_floats(&accessor, buffers, &INVERSE_BIND_MATRICES)?
        .chunks_exact(16)
        .take(joints)
        .map(Mat4::from_cols_slice)
        .collect();
    if let Some(bad) = matrices.iter().position(|m| !m.is_finite()) {
        return Err(format!("inverse bind matrix {bad} is not finite"));
    }
    Ok(matrices)
}

/// Each node's parent (a node nobody lists as a child has none).
fn parent_map(document: &gltf::Document) -> Vec<Option<usize>> {
    let mut parents = vec![None; document.nodes().count()];
    for node in document.nodes() {
        for child in node.children() {
            if let Some(slot) = parents.get_mut(child.index()) {
                *slot = Some(node.index());
            }
        }
    }
    parents
}

/// The links from node `index`'s root down to it, parent first.
fn ancestor_chain(
    nodes: &[gltf::Node<'_>],
    parents: &[Option<usize>],
    index: usize,
    animated_nodes: &BTreeMap<usize, TrsKeyframes>,
) -> Result<Vec<ChainLink>, String> {
    let mut path = vec![index];
    while let Some(parent) = parents
        .get(*path.last().unwrap_or(&index))
        .copied()
        .flatten()
    {
        if path.len() > nodes.len() {
            return Err(format!(
                "the node hierarchy has a cycle through node {index}"
            ));
        }
        path.push(parent);
    }
    path.iter()
        .rev()
        .map(|&i| {
            let node = nodes.get(i).ok_or(format!("node {i} does not exist"))?;
            node_link(node, animated_nodes)
        })
        .collect()
}
