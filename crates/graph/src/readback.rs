//! Reading textures back to the CPU: a copy into a mappable buffer with rows padded to wgpu's
//! 256-byte alignment, a blocking map, and unpadding. Used by tests, the reference and the CLI.

use crate::error::{GraphError, GraphResult};
use crate::resource::{Extent, texel_bytes};

/// Tightly packed texels of one mip level.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureReadback {
    /// Size of the mip level read, in pixels.
    pub extent: Extent,
    /// The texture's format, which says how to decode `bytes`.
    pub format: wgpu::TextureFormat,
    /// The texels, row by row from the top, without row padding, in the format's own byte
    /// layout (depth formats: the depth aspect only).
    pub bytes: Vec<u8>,
}

fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let man = (h & 0x3ff) as f32;
    match exp {
        0 => sign * man * 2f32.powi(-24),
        31 if man == 0.0 => sign * f32::INFINITY,
        31 => f32::NAN,
        _ => sign * (1.0 + man / 1024.0) * 2f32.powi(exp - 15),
    }
}

impl TextureReadback {
    /// Channels per texel of the format.
    pub fn channels(&self) -> usize {
        self.format.components() as usize
    }
    /// Every channel as f32 (floats as stored, unorm formats scaled to [0, 1]).
    pub fn to_f32(&self) -> GraphResult<Vec<f32>> {
        use wgpu::TextureFormat as F;
        let b = &self.bytes;
        Ok(match self.format {
            F::R32Float | F::Rg32Float | F::Rgba32Float | F::Depth32Float => b
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
            F::R16Float | F::Rg16Float | F::Rgba16Float => b
                .chunks_exact(2)
                .map(|c| f16_to_f32(u16::from_le_bytes([c[0], c[1]])))
                .collect(),
            F::R8Unorm | F::Rg8Unorm | F::Rgba8Unorm | F::Rgba8UnormSrgb | F::Bgra8Unorm => {
                b.iter().map(|&v| v as f32 / 255.0).collect()
            }
            F::R16Unorm | F::Rgba16Unorm => b
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]) as f32 / 65535.0)
                .collect(),
            F::R32Uint => b
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f32)
                .collect(),
            f => {
                return Err(GraphError::ReadbackFormat {
                    format: f,
                    wanted: "floats",
                    allowed: "to_f32 reads float, unorm, Depth32Float and R32Uint textures; \
                              read 32-bit integer ones with to_u32",
                });
            }
        })
    }
    /// Every channel of a 32-bit integer format as stored (bit patterns kept: `to_f32` would
    /// round values above 2^24, such as packed normals).
    pub fn to_u32(&self) -> GraphResult<Vec<u32>> {
        use wgpu::TextureFormat as F;
        match self.format {
            F::R32Uint | F::Rg32Uint | F::Rgba32Uint => Ok(self
                .bytes
                .chunks_exact(4)
                .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect()),
            f => Err(GraphError::ReadbackFormat {
                format: f,
                wanted: "32-bit unsigned integers",
                allowed: "R32Uint, Rg32Uint and Rgba32Uint can; read other formats with to_f32",
            }),
        }
    }
    /// Channel `c` of every texel as f32.
    pub fn channel(&self, c: usize) -> GraphResult<Vec<f32>> {
        let n = self.channels().max(1);
        Ok(self.to_f32()?.into_iter().skip(c).step_by(n).collect())
    }
}

/// Copies mip `mip` of `texture` to the CPU (blocking).
pub fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    mip: u32,
) -> GraphResult<TextureReadback> {
    let format = texture.format();
    let extent = Extent::new(texture.width(), texture.height()).mip(mip);
    let aspect = if format.is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    let texel = texel_bytes(format) as u32;
    let row = extent.width * texel;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded as u64 * extent.height as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip,
            origin: wgpu::Origin3d::ZERO,
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(extent.height),
            },
        },
        wgpu::Extent3d {
            width: extent.width,
            height: extent.height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([enc.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GraphError::ReadbackFailed {
            during: "reading a texture back",
            message: e.to_string(),
        })?;
    rx.recv()
        .map_err(|e| GraphError::ReadbackFailed {
            during: "reading a texture back",
            message: e.to_string(),
        })?
        .map_err(|e| GraphError::ReadbackFailed {
            during: "reading a texture back",
            message: e.to_string(),
        })?;
    let mut bytes = Vec::with_capacity((row * extent.height) as usize);
    {
        let view = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| GraphError::ReadbackFailed {
                during: "reading a texture back",
                message: e.to_string(),
            })?;
        for y in 0..extent.height as usize {
            let start = y * padded as usize;
            bytes.extend_from_slice(&view[start..start + row as usize]);
        }
    }
    buffer.unmap();
    Ok(TextureReadback {
        extent,
        format,
        bytes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texel(format: wgpu::TextureFormat, bytes: Vec<u8>) -> TextureReadback {
        TextureReadback {
            extent: Extent::new(1, 1),
            format,
            bytes,
        }
    }

    #[test]
    fn a_format_read_back_in_the_wrong_form_is_an_error_naming_the_other_reader() {
        let e = texel(wgpu::TextureFormat::Rgba32Uint, vec![0; 16])
            .to_f32()
            .unwrap_err();
        assert!(
            matches!(
                e,
                GraphError::ReadbackFormat {
                    format: wgpu::TextureFormat::Rgba32Uint,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().contains("to_u32"), "{e}");
        let e = texel(wgpu::TextureFormat::R32Float, vec![0; 4])
            .to_u32()
            .unwrap_err()
            .to_string();
        assert!(e.contains("R32Float") && e.contains("to_f32"), "{e}");
        // And the forms that are supported read the value.
        let one = 1.0f32.to_le_bytes().to_vec();
        assert_eq!(
            texel(wgpu::TextureFormat::R32Float, one).to_f32().unwrap(),
            [1.0]
        );
        let seven = 7u32.to_le_bytes().to_vec();
        assert_eq!(
            texel(wgpu::TextureFormat::R32Uint, seven).to_u32().unwrap(),
            [7]
        );
    }
}
