//! Whether a BVH fits the device: each of its three storage buffers must be within both the
//! largest storage-buffer binding and the largest buffer the device allows. Pure, so it is
//! tested with made-up limits; the error names the buffer, its size, the whole BVH's size and
//! the limit it exceeds (never a panic inside wgpu, never a silent truncation).

use crate::error::TracingError;

/// Bytes of the BVH's three buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BvhSizes {
    /// Bytes of the node buffer (32 per [`FlatNode`](super::FlatNode)).
    pub nodes: u64,
    /// Bytes of the instance buffer (64 per [`GpuInstance`](super::GpuInstance)).
    pub instances: u64,
    /// Bytes of the triangle buffer (48 per [`GpuTriangle`](super::GpuTriangle)).
    pub triangles: u64,
}

impl BvhSizes {
    /// Bytes of all three buffers together.
    pub fn total(&self) -> u64 {
        self.nodes + self.instances + self.triangles
    }
}

/// Checks `sizes` against `limits`.
pub fn check_bvh_fits(sizes: &BvhSizes, limits: &wgpu::Limits) -> Result<(), TracingError> {
    let (limit, limit_name) = if limits.max_storage_buffer_binding_size <= limits.max_buffer_size {
        (
            limits.max_storage_buffer_binding_size,
            "max_storage_buffer_binding_size",
        )
    } else {
        (limits.max_buffer_size, "max_buffer_size")
    };
    for (buffer, size) in [
        ("node", sizes.nodes),
        ("instance", sizes.instances),
        ("triangle", sizes.triangles),
    ] {
        if size > limit {
            return Err(TracingError::BvhTooLarge {
                buffer,
                size,
                total: sizes.total(),
                limit,
                limit_name,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_buffer_over_the_binding_limit_is_an_error_naming_both_sizes_and_the_limit() {
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 1000,
            ..wgpu::Limits::default()
        };
        let fits = BvhSizes {
            nodes: 1000,
            instances: 64,
            triangles: 960,
        };
        assert!(check_bvh_fits(&fits, &limits).is_ok());
        let over = BvhSizes {
            triangles: 1008,
            ..fits
        };
        let e = check_bvh_fits(&over, &limits).unwrap_err().to_string();
        assert!(
            e.contains("triangle buffer is 1008 bytes")
                && e.contains("whole BVH 2072 bytes")
                && e.contains("limit of 1000 bytes (max_storage_buffer_binding_size)"),
            "{e}"
        );
    }

    #[test]
    fn the_smaller_of_binding_and_buffer_limits_applies() {
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 4096,
            max_buffer_size: 2048,
            ..wgpu::Limits::default()
        };
        let sizes = BvhSizes {
            nodes: 3000,
            instances: 64,
            triangles: 48,
        };
        let e = check_bvh_fits(&sizes, &limits).unwrap_err().to_string();
        assert!(
            e.contains("node buffer is 3000 bytes") && e.contains("2048 bytes (max_buffer_size)"),
            "{e}"
        );
    }
}
