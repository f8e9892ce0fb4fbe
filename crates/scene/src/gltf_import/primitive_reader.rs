//! Turns one glTF mesh primitive into a [`Mesh`]: positions, normals, a triangle list, and
//! skinning influences (JOINTS_0 / WEIGHTS_0) when it has both.
//!
//! Choices: triangle strips and fans are converted to triangle lists (glTF 2.0 §3.7.2.1 vertex
//! order); points, lines, line loops and line strips are skipped with a warning. A primitive
//! without normals (or with unusable ones: wrong count, NaN, zero length) gets flat face normals,
//! made by un-indexing so each triangle has its own three vertices. Invariant of the result:
//! finite positions (a NaN or infinite one is a [`SceneError::NonFiniteVertex`]), indices in
//! range (else [`SceneError::InvalidGltf`]), one unit normal per position, a whole number of
//! triangles. Accessors are read by `accessor_reader` (quantized and normalized integers,
//! sparse parts, accessors without a buffer view), never by the `gltf` crate's readers, so a
//! broken accessor is an error, not a panic. Weights are normalised to sum
//! to 1 (a vertex with no positive weight follows its first joint alone, with a warning);
//! influence sets beyond the first (JOINTS_1, more than four joints) are ignored with a warning.

use super::accessor_reader::{
    INDICES, JOINTS, NORMALS, POSITIONS, WEIGHTS, read_floats, read_uints,
};
use crate::error::SceneError;
use crate::model::Mesh;
use crate::skin::JointWeights;
use glam::Vec3;
use gltf::mesh::Mode;
use std::path::Path;

/// What became of a primitive.
pub(super) enum PrimitiveOutcome {
    /// The mesh, and warnings about it.
    Mesh(Mesh, Vec<String>),
    /// Skipped for the reason given (a warning for the user).
    Skipped(String),
}

/// Converts a strip or fan index sequence into a triangle list.
fn to_triangle_list(mode: Mode, indices: Vec<u32>) -> Vec<u32> {
    let n = indices.len();
    match mode {
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [indices[i], indices[i + 1], indices[i + 2]]
                } else {
                    [indices[i], indices[i + 2], indices[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .flat_map(|i| [indices[i], indices[i + 1], indices[0]])
            .collect(),
        _ => indices,
    }
}

/// Un-indexes `positions`/`indices` so every triangle gets its own vertices and face normal.
fn flat_shaded(positions: &[Vec3], indices: &[u32]) -> (Vec<Vec3>, Vec<Vec3>, Vec<u32>) {
    let mut out_positions = Vec::with_capacity(indices.len());
    let mut out_normals = Vec::with_capacity(indices.len());
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        let normal = (b - a).cross(c - a).try_normalize().unwrap_or(Vec3::Y);
        out_positions.extend([a, b, c]);
        out_normals.extend([normal; 3]);
    }
    let count = out_positions.len() as u32;
    (out_positions, out_normals, (0..count).collect())
}

/// Reads primitive `primitive` of mesh `mesh_name`; `material` is its index in the scene.
pub(super) fn read_primitive(
    path: &Path,
    buffers: &[gltf::buffer::Data],
    mesh_name: &str,
    primitive: &gltf::Primitive<'_>,
    material: usize,
) -> Result<PrimitiveOutcome, SceneError> {
    let label = format!("mesh \"{mesh_name}\" primitive {}", primitive.index());
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(PrimitiveOutcome::Skipped(format!(
            "{label} is drawn as {mode:?}, not triangles: skipped"
        )));
    }
    let invalid = |message: String| SceneError::InvalidGltf {
        path: path.to_owned(),
        message: format!("{label}: {message}"),
    };
    let Some(position_accessor) = primitive.get(&gltf::Semantic::Positions) else {
        return Ok(PrimitiveOutcome::Skipped(format!(
            "{label} has no POSITION attribute: skipped"
        )));
    };
    let positions: Vec<Vec3> = read_floats(&position_accessor, buffers, &POSITIONS)
        .map_err(invalid)?
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect();
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(SceneError::NonFiniteVertex {
            path: path.to_owned(),
            mesh: mesh_name.to_owned(),
            vertex,
        });
    }
    let indices: Vec<u32> = match primitive.indices() {
        // §3.6.2.3: without a buffer view (or a sparse part) every index is zero, so every
        // triangle is the first vertex three times.
        Some(accessor) if accessor.view().is_none() && accessor.sparse().is_none() => {
            return Ok(PrimitiveOutcome::Skipped(format!(
                "{label}: index accessor {} has no bufferView (all zeros): no triangles in this \
                 primitive, skipped",
                accessor.index()
            )));
        }
        Some(accessor) => read_uints(&accessor, buffers, &INDICES).map_err(invalid)?,
        None => (0..positions.len() as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(invalid(format!(
            "index {bad} refers past the last of its {} vertices",
            positions.len()
        )));
    }
    let mut indices = to_triangle_list(mode, indices);
    indices.truncate(indices.len() / 3 * 3);
    if indices.is_empty() {
        return Ok(PrimitiveOutcome::Skipped(format!(
            "{label} has no triangles: skipped"
        )));
    }
    // Unusable normals (wrong type or count, zero length) mean flat shading, not an error.
    let normals: Option<Vec<Vec3>> = primitive
        .get(&gltf::Semantic::Normals)
        .and_then(|accessor| read_floats(&accessor, buffers, &NORMALS).ok())
        .and_then(|normals| {
            normals
                .chunks_exact(3)
                .map(|n| Vec3::from_slice(n).try_normalize())
                .collect::<Option<Vec<Vec3>>>()
        })
        .filter(|normals| normals.len() == positions.len());
    let mut warnings = Vec::new();
    let skin_weights =
        read_skin_weights(buffers, primitive, positions.len(), &mut warnings).map_err(invalid)?;
    if let Some(w) = warnings.last_mut() {
        *w = format!("{label}: {w}");
    }
    let (positions, normals, indices, skin_weights) = match normals {
        Some(normals) => (positions, normals, indices, skin_weights),
        None => {
            // Un-indexing: flat vertex k is old vertex indices[k], and so are its weights.
            let unindexed = if skin_weights.is_empty() {
                Vec::new()
            } else {
                indices.iter().map(|&i| skin_weights[i as usize]).collect()
            };
            let (p, n, i) = flat_shaded(&positions, &indices);
            (p, n, i, unindexed)
        }
    };
    Ok(PrimitiveOutcome::Mesh(
        Mesh {
            name: if primitive.index() == 0 {
                mesh_name.to_owned()
            } else {
                format!("{mesh_name}#{}", primitive.index())
            },
            positions,
            normals,
            indices,
            material,
            skin_weights,
        },
        warnings,
    ))
}

/// The primitive's JOINTS_0 / WEIGHTS_0 per vertex, normalised, or empty when it has
/// neither; `Err` names a broken accessor. Pushes a warning for ignored influences.
fn read_skin_weights(
    buffers: &[gltf::buffer::Data],
    primitive: &gltf::Primitive<'_>,
    vertices: usize,
    warnings: &mut Vec<String>,
) -> Result<Vec<JointWeights>, String> {
    let joints = primitive.get(&gltf::Semantic::Joints(0));
    let weights = primitive.get(&gltf::Semantic::Weights(0));
    let (joints, weights) = match (joints, weights) {
        (Some(j), Some(w)) => (j, w),
        (None, None) => return Ok(Vec::new()),
        (Some(_), None) => return Err("has JOINTS_0 but no WEIGHTS_0".into()),
        (None, Some(_)) => return Err("has WEIGHTS_0 but no JOINTS_0".into()),
    };
    if joints.count() != vertices || weights.count() != vertices {
        return Err(format!(
            "JOINTS_0 has {} and WEIGHTS_0 {} entries for {vertices} vertices",
            joints.count(),
            weights.count()
        ));
    }
    let j = read_uints(&joints, buffers, &JOINTS)?;
    let w = read_floats(&weights, buffers, &WEIGHTS)?;
    let mut unweighted = 0;
    let out = j
        .chunks_exact(4)
        .zip(w.chunks_exact(4))
        .map(|(j, w)| {
            // JOINTS_0 is UNSIGNED_BYTE or UNSIGNED_SHORT: every value fits a u16.
            let joints = [j[0], j[1], j[2], j[3]].map(|j| j as u16);
            let weights = [w[0], w[1], w[2], w[3]];
            let raw = JointWeights { joints, weights };
            raw.normalised().unwrap_or_else(|| {
                unweighted += 1;
                JointWeights {
                    joints: [joints[0], 0, 0, 0],
                    weights: [1.0, 0.0, 0.0, 0.0],
                }
            })
        })
        .collect();
    let mut ignored = Vec::new();
    if unweighted > 0 {
        ignored.push(format!(
            "{unweighted} vertices have no positive weight in WEIGHTS_0: they follow their first joint alone"
        ));
    }
    if primitive.get(&gltf::Semantic::Joints(1)).is_some() {
        ignored.push(
            "JOINTS_1 / WEIGHTS_1 (over four joints a vertex) are ignored: the first four are renormalised"
                .into(),
        );
    }
    if !ignored.is_empty() {
        warnings.push(ignored.join("; "));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists_with_consistent_winding() {
        assert_eq!(
            to_triangle_list(Mode::TriangleStrip, vec![0, 1, 2, 3]),
            vec![0, 1, 2, 1, 3, 2]
        );
        assert_eq!(
            to_triangle_list(Mode::TriangleFan, vec![0, 1, 2, 3]),
            vec![1, 2, 0, 2, 3, 0]
        );
        assert!(to_triangle_list(Mode::TriangleStrip, vec![0, 1]).is_empty());
    }

    #[test]
    fn flat_shading_unindexes_with_face_normals() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let (p, n, i) = flat_shaded(&positions, &[0, 1, 2, 0, 3, 1]);
        assert_eq!(p.len(), 6);
        assert_eq!(i, vec![0, 1, 2, 3, 4, 5]);
        assert_eq!(n[0], Vec3::Z);
        assert_eq!(n[3], Vec3::Y);
    }
}
