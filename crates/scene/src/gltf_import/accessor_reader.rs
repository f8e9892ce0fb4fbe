//! Reads a glTF accessor's elements by the specification's rules (glTF 2.0 §3.6.2, and
//! KHR_mesh_quantization), instead of the `gltf` crate's readers.
//!
//! What it reads: any component type the caller's [`AccessorShape`] accepts, normalized
//! integers mapped to [-1, 1] or [0, 1] (§3.11: `max(c / 127, -1)`, `c / 255`, ...), plain
//! integers as their value (quantized positions, whose dequantization is the node transform),
//! interleaved views (byte stride), accessors without a buffer view (all zeros, §3.6.2.3), and
//! sparse accessors (§3.6.2.3: the listed elements replace those of the base). Buffer views
//! compressed with EXT_meshopt_compression are already decoded into their buffer (see
//! `meshopt_views`), so they read like any other.
//! Invariant: reading never panics and never reads out of bounds: a count of zero, a stride
//! shorter than the element, a view or sparse part past the end of its buffer, or a sparse index
//! past the accessor's count is an `Err` naming the accessor.

use gltf::accessor::sparse::IndexType;
use gltf::accessor::{DataType, Dimensions};

/// Which component types and shapes a reader accepts.
pub(super) struct AccessorShape {
    pub types: &'static [DataType],
    pub dimensions: Dimensions,
    /// Shown in messages, e.g. "POSITION".
    pub role: &'static str,
}

/// Every integer component type, as KHR_mesh_quantization allows for positions.
pub(super) const QUANTIZED: &[DataType] = &[
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

pub(super) const POSITIONS: AccessorShape = AccessorShape {
    types: QUANTIZED,
    dimensions: Dimensions::Vec3,
    role: "POSITION",
};
pub(super) const NORMALS: AccessorShape = AccessorShape {
    // KHR_mesh_quantization: normalized BYTE or SHORT.
    types: &[DataType::F32, DataType::I8, DataType::I16],
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
    // Quantized translations and scales (gltfpack writes them as integers, KHR_mesh_quantization).
    types: QUANTIZED,
    dimensions: Dimensions::Vec3,
    role: "animation output",
};
pub(super) const KEY_ROTATIONS: AccessorShape = AccessorShape {
    types: QUANTIZED,
    dimensions: Dimensions::Vec4,
    role: "animation output",
};

/// The accessor's components as floats, element after element (`count * components` values).
pub(super) fn read_floats(
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    shape: &AccessorShape,
) -> Result<Vec<f32>, String> {
    let bytes = packed_elements(accessor, buffers, shape)?;
    let data_type = accessor.data_type();
    let normalized = accessor.normalized();
    Ok(bytes
        .chunks_exact(data_type.size())
        .map(|c| to_float(data_type, normalized, c))
        .collect())
}

/// The accessor's components as unsigned integers (indices, joints).
pub(super) fn read_uints(
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    shape: &AccessorShape,
) -> Result<Vec<u32>, String> {
    let bytes = packed_elements(accessor, buffers, shape)?;
    let size = accessor.data_type().size();
    Ok(bytes.chunks_exact(size).map(unsigned).collect())
}

/// A little-endian unsigned integer of 1, 2 or 4 bytes.
fn unsigned(bytes: &[u8]) -> u32 {
    bytes
        .iter()
        .rev()
        .fold(0u32, |value, &b| (value << 8) | u32::from(b))
}

/// One component as a float: glTF 2.0 §3.11's normalization for normalized integers.
fn to_float(data_type: DataType, normalized: bool, c: &[u8]) -> f32 {
    let (value, scale, signed) = match data_type {
        DataType::F32 => return f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
        DataType::I8 => (f32::from(c[0] as i8), 127.0, true),
        DataType::U8 => (f32::from(c[0]), 255.0, false),
        DataType::I16 => (f32::from(i16::from_le_bytes([c[0], c[1]])), 32767.0, true),
        DataType::U16 => (f32::from(u16::from_le_bytes([c[0], c[1]])), 65535.0, false),
        DataType::U32 => (unsigned(c) as f32, u32::MAX as f32, false),
    };
    match (normalized, signed) {
        (false, _) => value,
        (true, true) => (value / scale).max(-1.0),
        (true, false) => value / scale,
    }
}

/// The accessor's elements tightly packed (`count * element size` bytes): read through the
/// buffer view's stride, or zeros without one, then the sparse substitution applied.
fn packed_elements(
    accessor: &gltf::Accessor<'_>,
    buffers: &[gltf::buffer::Data],
    shape: &AccessorShape,
) -> Result<Vec<u8>, String> {
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
    let count = accessor.count();
    if count == 0 {
        return Err(format!("{label} has no elements"));
    }
    let element = accessor.size();
    let total = count
        .checked_mul(element)
        .filter(|&n| n <= MAX_ACCESSOR_BYTES)
        .ok_or_else(|| format!("{label} declares {count} elements, more than a file can hold"))?;
    let mut packed = match accessor.view() {
        None => vec![0; total],
        Some(view) => {
            let data = view_bytes(&view, buffers)?;
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
            if end.is_none_or(|end| end > data.len()) {
                return Err(format!(
                    "{label} reaches past the end of buffer view {}",
                    view.index()
                ));
            }
            let mut packed = Vec::with_capacity(total);
            for i in 0..count {
                let start = accessor.offset() + i * stride;
                packed.extend_from_slice(&data[start..start + element]);
            }
            packed
        }
    };
    if let Some(sparse) = accessor.sparse() {
        substitute_sparse(&label, &sparse, buffers, element, &mut packed)?;
    }
    Ok(packed)
}

/// No accessor of a file that loads is larger than this (1 GiB).
const MAX_ACCESSOR_BYTES: usize = 1 << 30;

/// Writes the sparse part's values over the packed base elements.
fn substitute_sparse(
    label: &str,
    sparse: &gltf::accessor::sparse::Sparse<'_>,
    buffers: &[gltf::buffer::Data],
    element: usize,
    packed: &mut [u8],
) -> Result<(), String> {
    let count = sparse.count();
    let index_size = match sparse.indices().index_type() {
        IndexType::U8 => 1,
        IndexType::U16 => 2,
        IndexType::U32 => 4,
    };
    let indices = view_bytes(&sparse.indices().view(), buffers)?;
    let values = view_bytes(&sparse.values().view(), buffers)?;
    let indices = sparse_part(
        label,
        "indices",
        indices,
        sparse.indices().offset(),
        count,
        index_size,
    )?;
    let values = sparse_part(
        label,
        "values",
        values,
        sparse.values().offset(),
        count,
        element,
    )?;
    let elements = packed.len() / element;
    for (index, value) in indices
        .chunks_exact(index_size)
        .zip(values.chunks_exact(element))
    {
        let index = unsigned(index) as usize;
        if index >= elements {
            return Err(format!(
                "{label}'s sparse index {index} is past its {elements} elements"
            ));
        }
        packed[index * element..(index + 1) * element].copy_from_slice(value);
    }
    Ok(())
}

/// `count` elements of `size` bytes from `offset` in a sparse part's view.
fn sparse_part<'d>(
    label: &str,
    part: &str,
    data: &'d [u8],
    offset: usize,
    count: usize,
    size: usize,
) -> Result<&'d [u8], String> {
    count
        .checked_mul(size)
        .and_then(|n| n.checked_add(offset))
        .filter(|&end| end <= data.len())
        .map(|end| &data[offset..end])
        .ok_or_else(|| format!("{label}'s sparse {part} reach past the end of their buffer view"))
}

/// The bytes of buffer view `view`, checked to lie inside its loaded buffer.
fn view_bytes<'b>(
    view: &gltf::buffer::View<'_>,
    buffers: &'b [gltf::buffer::Data],
) -> Result<&'b [u8], String> {
    let buffer = buffers
        .get(view.buffer().index())
        .map_or(&[][..], |b| &b.0[..]);
    view.offset()
        .checked_add(view.length())
        .filter(|&end| end <= buffer.len())
        .map(|end| &buffer[view.offset()..end])
        .ok_or_else(|| {
            format!(
                "buffer view {} reaches past the end of buffer {}",
                view.index(),
                view.buffer().index()
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_follow_the_specification() {
        // glTF 2.0 §3.11: signed values use max(c / (2^(b-1) - 1), -1), unsigned c / (2^b - 1).
        assert_eq!(to_float(DataType::I8, true, &[0x81]), -1.0); // -127
        assert_eq!(to_float(DataType::I8, true, &[0x80]), -1.0); // -128 clamps
        assert_eq!(to_float(DataType::I8, true, &[127]), 1.0);
        assert_eq!(to_float(DataType::U8, true, &[51]), 0.2);
        assert_eq!(
            to_float(DataType::I16, true, &(-16384i16).to_le_bytes()),
            -16384.0 / 32767.0
        );
        assert_eq!(to_float(DataType::U16, true, &u16::MAX.to_le_bytes()), 1.0);
        // Plain integers (KHR_mesh_quantization positions) keep their value.
        assert_eq!(
            to_float(DataType::I16, false, &(-300i16).to_le_bytes()),
            -300.0
        );
        assert_eq!(to_float(DataType::U8, false, &[200]), 200.0);
    }

    #[test]
    fn unsigned_reads_little_endian() {
        assert_eq!(unsigned(&[0x34, 0x12]), 0x1234);
        assert_eq!(unsigned(&[1, 0, 0, 0x80]), 0x8000_0001);
    }
}
