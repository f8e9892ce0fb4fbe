//! The texture pool: physical textures kept across frames and across plans, handed out by
//! exact descriptor.
//!
//! Invariant: a texture is either lent (to a frame being recorded, or retained by a plan whose
//! exported outputs stay readable, or held by a history) or free in the pool. A free texture
//! that no frame took for [`TexturePool::IDLE_FRAMES`] frames is dropped, so a resize or a plan
//! that stopped running gives its memory back after a few frames instead of growing the pool,
//! while plans that take turns (A, B, A, B) find their textures still there.

use std::collections::HashMap;

use crate::custom::BoundTexture;
use crate::resource::Extent;

/// What must match for a pooled texture to be reused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PoolKey {
    /// The texture's format.
    pub format: wgpu::TextureFormat,
    /// Size of mip 0 in pixels (the size class resolved at the frame's output size).
    pub extent: Extent,
    /// Number of mip levels.
    pub mip_levels: u32,
    /// The usages the texture is created with.
    pub usage: wgpu::TextureUsages,
}

/// A physical texture with a view per mip level.
pub struct PooledTexture {
    pub key: PoolKey,
    pub bound: BoundTexture,
    last_used: u64,
}

/// The free textures of one descriptor. The list stays (empty) while its descriptor is in use,
/// so steady-state frames do not reallocate it.
#[derive(Default)]
struct FreeList {
    textures: Vec<PooledTexture>,
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
    let bound = BoundTexture::new(texture, serial);
    PooledTexture {
        key,
        bound,
        last_used: 0,
    }
}

/// Free textures by descriptor, plus counters.
#[derive(Default)]
pub struct TexturePool {
    free: HashMap<PoolKey, FreeList>,
    frame: u64,
    lent: usize,
    next_serial: u64,
    created: u64,
}

impl TexturePool {
    /// Frames a free texture waits for a taker before it is dropped.
    pub const IDLE_FRAMES: u64 = 8;

    /// A texture for `key`: the free one with serial `prefer` when there is one (so a plan gets
    /// back the textures its cached bind groups name), else any free one, else a new one.
    pub fn acquire(&mut self, device: &wgpu::Device, key: PoolKey, prefer: u64) -> PooledTexture {
        self.lent += 1;
        if let Some(list) = self.free.get_mut(&key) {
            list.last_used = self.frame;
            let i = list
                .textures
                .iter()
                .position(|t| t.bound.serial == prefer)
                .or(list.textures.len().checked_sub(1));
            if let Some(i) = i {
                let mut t = list.textures.swap_remove(i);
                t.last_used = self.frame;
                return t;
            }
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
        let list = self.free.entry(t.key).or_default();
        list.last_used = self.frame;
        list.textures.push(t);
    }
    /// Ends a frame: drops free textures that no frame took for [`Self::IDLE_FRAMES`] frames.
    pub fn end_frame(&mut self) {
        let frame = self.frame;
        let live = |last_used: u64| last_used + Self::IDLE_FRAMES > frame;
        for list in self.free.values_mut() {
            list.textures.retain(|t| live(t.last_used));
        }
        self.free
            .retain(|_, l| !l.textures.is_empty() || live(l.last_used));
        self.frame += 1;
    }
    /// Textures the pool holds, lent or free.
    pub fn texture_count(&self) -> usize {
        self.lent + self.free_count()
    }
    /// Textures free in the pool.
    pub fn free_count(&self) -> usize {
        self.free.values().map(|l| l.textures.len()).sum::<usize>()
    }
    /// Textures created since the pool was made.
    pub fn created_count(&self) -> u64 {
        self.created
    }
    /// A fresh serial for textures made outside the pool (imports).
    pub fn next_serial(&mut self) -> u64 {
        self.next_serial += 1;
        self.next_serial
    }
}
