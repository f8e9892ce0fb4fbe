//! The one shape of texture applications and tools around the graph make most: 2D, one mip,
//! one sample, no extra view formats. One function, so each caller states only what differs
//! (label, size, format, usage).

/// A `width` x `height` 2D texture with one mip and one sample.
pub fn plain_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}
