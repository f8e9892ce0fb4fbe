//! Turns one glTF mesh primitive into a [`Mesh`]: positions, normals, a triangle list.
//!
//! Choices: triangle strips and fans are converted to triangle lists (glTF 2.0 §3.7.2.1 vertex
//! order); points, lines, line loops and line strips are skipped with a warning. A primitive
//! without normals (or with unusable ones: wrong count, NaN, zero length) gets flat face normals,
//! made by un-indexing so each triangle has its own three vertices. Invariant of the result:
//! finite positions (a NaN or infinite one is a [`SceneError::NonFiniteVertex`]), indices in
//! range (else [`SceneError::InvalidGltf`]), one unit normal per position, a whole number of
//! triangles. Quantized (non-float) positions are skipped with a warning; every accessor is
//! checked (see `accessor_check`) before the `gltf` reader sees it.

use super::accessor_check::{INDICES, NORMALS, POSITIONS, check_accessor};
use crate::error::SceneError;
use crate::model::Mesh;
use glam::Vec3;
use gltf::mesh::Mode;
use std::path::Path;

/// What became of a primitive.
pub(super) enum PrimitiveOutcome {
    Mesh(Mesh),
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
    if position_accessor.data_type() != gltf::accessor::DataType::F32 {
        return Ok(PrimitiveOutcome::Skipped(format!(
            "{label} has quantized ({:?}) positions, which are not supported: skipped",
            position_accessor.data_type()
        )));
    }
    check_accessor(&position_accessor, buffers, &POSITIONS).map_err(invalid)?;
    if let Some(indices) = primitive.indices() {
        check_accessor(&indices, buffers, &INDICES).map_err(invalid)?;
    }
    let normals_usable = primitive
        .get(&gltf::Semantic::Normals)
        .is_some_and(|normals| check_accessor(&normals, buffers, &NORMALS).is_ok());
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(|data| &data.0[..]));
    let Some(positions) = reader.read_positions() else {
        return Ok(PrimitiveOutcome::Skipped(format!(
            "{label} has no readable POSITION attribute (sparse-only accessors are not \
             supported): skipped"
        )));
    };
    let positions: Vec<Vec3> = positions.map(Vec3::from_array).collect();
    if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
        return Err(SceneError::NonFiniteVertex {
            path: path.to_owned(),
            mesh: mesh_name.to_owned(),
            vertex,
        });
    }
    let indices: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
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
    let normals = if normals_usable {
        reader.read_normals()
    } else {
        None
    };
    let normals: Option<Vec<Vec3>> = normals.and_then(|normals| {
        let normals: Vec<Vec3> = normals
            .map(|n| Vec3::from_array(n).try_normalize())
            .collect::<Option<_>>()?;
        (normals.len() == positions.len()).then_some(normals)
    });
    let (positions, normals, indices) = match normals {
        Some(normals) => (positions, normals, indices),
        None => flat_shaded(&positions, &indices),
    };
    Ok(PrimitiveOutcome::Mesh(Mesh {
        name: if primitive.index() == 0 {
            mesh_name.to_owned()
        } else {
            format!("{mesh_name}#{}", primitive.index())
        },
        positions,
        normals,
        indices,
        material,
    }))
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
