//! Checks an accessor before the `gltf` crate's readers touch it.
//!
//! gltf 1.4's readers trust the file: a zero count underflows, a stride shorter than the element
//! or a component type the reader does not expect trips a debug assertion or `unreachable!`, and
//! the end offset is computed without overflow checks. glTF validation covers none of these.
//! Invariant: an accessor that passes [`check_accessor`] has one of the expected types, no
//! sparse part, a buffer view, at least one element, a stride at least the element size, and
//! its last element inside both its buffer view and the loaded buffer, so reading it cannot
//! panic.

use gltf::accessor::{DataType, Dimensions};

/// Which component types and shapes a reader accepts.
pub(super) struct AccessorShape {
    pub types: &'static [DataType],
    pub dimensions: Dimensions,
    /// Shown in messages, e.g. "POSITION".
    pub role: &'static str,
}

pub(super) const POSITIONS: AccessorShape = AccessorShape {
    types: &[DataType::F32],
    dimensions: Dimensions::Vec3,
    role: "POSITION",
};
pub(super) const NORMALS: AccessorShape = AccessorShape {
    types: &[DataType::F32],
    dimensions: Dimensions::Vec3,
    role: "NORMAL",
};
pub(super) const INDICES: AccessorShape = AccessorShape {
    types: &[DataType::U8, DataType::U16, DataType::U32],
    dimensions: Dimensions::Scalar,
    role: "indices",
};
pub(super) const JOINTS: AccessorShape = AccessorShape {
    types: &[DataType::U8, DataType::U16],
    dimensions: Dimensions::Vec4,
    role: "JOINTS_0",
};
pub(super) const WEIGHTS: AccessorShape = AccessorShape {
    types: &[DataType::F32, DataType::U8, DataType::U16],
    dimensions: Dimensions::Vec4,
    role: "WEIGHTS_0",
};
pub(super) const INVERSE_BIND_MATRICES: AccessorShape = AccessorShape {
    types: &[DataType::F32],
    dimensions: Dimensions::Mat4,
    role: "inverseBindMatrices",
};
pub(super) const KEY_TIMES: AccessorShape = AccessorShape {
    types: &[DataType::F32],
    dimensions: Dimensions::Scalar,
    role: "animation input",
};
pub(super) const KEY_VECTORS: AccessorShape = AccessorShape {
    types: &[DataType::F32],
    dimensions: Dimensions::Vec3,
    role: "animation output",
};
pub(super) const KEY_ROTATIONS: AccessorShape = AccessorShape {
    types: &[
        DataType::F32,
        DataType::I8,
        DataType::U8,
        DataType::I16,
        DataType::U16,
    ],
    dimensions: Dimensions::Vec4,
    role: "animation output",
};

/// `Ok` when `accessor` can be read safely as `shape`, else why not.
pub(super) fn check_accessor(
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    shape: &AccessorShape,
) -> Result<(), String> {
    let label = format!("{} accessor {}", shape.role, accessor.index());
    if !shape.types.contains(&accessor.data_type()) || accessor.dimensions() != shape.dimensions {
        return Err(format!(
            "{label} is {:?} {:?}, expected {:?} of {:?}",
            accessor.dimensions(),
            accessor.data_type(),
            shape.dimensions,
            shape.types
        ));
    }
    if accessor.sparse().is_some() {
        return Err(format!("{label} is sparse, which is not supported"));
    }
    let Some(view) = accessor.view() else {
        return Err(format!("{label} has no buffer view"));
    };
    let count = accessor.count();
    if count == 0 {
        return Err(format!("{label} has no elements"));
    }
    let element = accessor.size();
    let stride = view.stride().unwrap_or(element);
    if stride < element {
        return Err(format!(
            "{label} has a byte stride of {stride}, less than its element size {element}"
        ));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|n| n.checked_add(element))
        .and_then(|n| n.checked_add(accessor.offset()));
    if end.is_none_or(|end| end > view.length()) {
        return Err(format!(
            "{label} reaches past the end of buffer view {}",
            view.index()
        ));
    }
    let buffer_len = buffers.get(view.buffer().index()).map_or(0, |b| b.0.len());
    let view_end = view.offset().checked_add(view.length());
    if view_end.is_none_or(|end| end > buffer_len) {
        return Err(format!(
            "buffer view {} reaches past the end of buffer {}",
            view.index(),
            view.buffer().index()
        ));
    }
    Ok(())
}
