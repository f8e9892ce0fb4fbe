//! The texture pool: physical textures kept across frames, handed out by exact descriptor.
//!
//! Invariant: a texture is either lent to the current frame or free in the pool. Textures not
//! lent during the last frame are dropped when the frame ends, so a resize replaces the pool's
//! contents instead of growing it.

use std::collections::HashMap;

use crate::custom::BoundTexture;
use crate::resource::Extent;

/// What must match for a pooled texture to be reused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PoolKey {
    pub format: wgpu::TextureFormat,
    pub extent: Extent,
    pub mip_levels: u32,
    pub usage: wgpu::TextureUsages,
}

/// A physical texture with a view per mip level.
pub struct PooledTexture {
    pub key: PoolKey,
    pub bound: BoundTexture,
    last_used: u64,
}

/// Creates a texture with a full view and one view per mip.
pub fn create_texture(
    device: &wgpu::Device,
    label: &str,
    key: PoolKey,
    serial: u64,
) -> PooledTexture {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: key.extent.width,
            height: key.extent.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: key.mip_levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: key.format,
        usage: key.usage,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    let mip_views = (0..key.mip_levels)
        .map(|m| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                base_mip_level: m,
                mip_level_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    PooledTexture {
        key,
        bound: BoundTexture {
            texture,
            view,
            mip_views,
            extent: key.extent,
            serial,
        },
        last_used: 0,
    }
}

/// Free textures by descriptor, plus counters.
#[derive(Default)]
pub struct TexturePool {
    free: HashMap<PoolKey, Vec<PooledTexture>>,
    frame: u64,
    lent: usize,
    next_serial: u64,
    created: u64,
}

impl TexturePool {
    /// A texture for `key`: a free one when there is one, else a new one.
    pub fn acquire(&mut self, device: &wgpu::Device, key: PoolKey) -> PooledTexture {
        self.lent += 1;
        if let Some(mut t) = self.free.get_mut(&key).and_then(Vec::pop) {
            t.last_used = self.frame;
            return t;
        }
        self.next_serial += 1;
        self.created += 1;
        let mut t = create_texture(device, "aograph pooled texture", key, self.next_serial);
        t.last_used = self.frame;
        t
    }
    /// Returns a lent texture.
    pub fn release(&mut self, t: PooledTexture) {
        self.lent = self.lent.saturating_sub(1);
        self.free.entry(t.key).or_default().push(t);
    }
    /// Ends a frame: drops free textures that no frame used since the previous one.
    pub fn end_frame(&mut self) {
        let cutoff = self.frame;
        for list in self.free.values_mut() {
            list.retain(|t| t.last_used >= cutoff);
        }
        self.free.retain(|_, l| !l.is_empty());
        self.frame += 1;
    }
    /// Textures the pool holds, lent or free.
    pub fn texture_count(&self) -> usize {
        self.lent + self.free.values().map(Vec::len).sum::<usize>()
    }
    /// Textures created since the pool was made.
    pub fn created_count(&self) -> u64 {
        self.created
    }
    /// A fresh serial for textures made outside the pool (history, imports).
    pub fn next_serial(&mut self) -> u64 {
        self.next_serial += 1;
        self.next_serial
    }
}
