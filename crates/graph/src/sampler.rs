//! Samplers: what a pass binds to each WGSL `sampler` global, declared on the pass with
//! `PassBuilder::sampler` as a [`SamplerDesc`] (filter and address mode), and the executor's
//! cache that makes the wgpu sampler of each description.
//!
//! Invariants: compile gives every sampler binding of a kept pass exactly one description (a
//! binding without one, or a description naming no sampler binding, is an error naming the
//! pass and the binding); the executor creates one wgpu sampler per distinct description, the
//! first time a plan needs it, and never one per frame.

use std::collections::HashMap;

/// How a pass's `sampler` global filters and addresses: one wgpu sampler per distinct value.
/// The default is nearest, clamped to the edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SamplerDesc {
    /// Magnification and minification filter; between mip levels the nearest is taken.
    pub filter: wgpu::FilterMode,
    /// Address mode along u and v.
    pub address: wgpu::AddressMode,
}

impl SamplerDesc {
    /// Bilinear, clamped to the edge.
    pub const LINEAR_CLAMP: Self = Self {
        filter: wgpu::FilterMode::Linear,
        address: wgpu::AddressMode::ClampToEdge,
    };
    /// Nearest texel, clamped to the edge.
    pub const NEAREST_CLAMP: Self = Self {
        filter: wgpu::FilterMode::Nearest,
        address: wgpu::AddressMode::ClampToEdge,
    };

    /// The layout entry a binding of this sampler needs: filtering when it filters linearly.
    pub fn binding_type(&self) -> wgpu::SamplerBindingType {
        match self.filter {
            wgpu::FilterMode::Linear => wgpu::SamplerBindingType::Filtering,
            wgpu::FilterMode::Nearest => wgpu::SamplerBindingType::NonFiltering,
        }
    }
}

/// The executor's samplers, one per distinct [`SamplerDesc`] (see the module invariants).
#[derive(Default)]
pub(crate) struct SamplerCache {
    samplers: HashMap<SamplerDesc, wgpu::Sampler>,
}

impl SamplerCache {
    /// The sampler of `desc`, created on its first request.
    pub fn get(&mut self, device: &wgpu::Device, desc: SamplerDesc) -> wgpu::Sampler {
        self.samplers
            .entry(desc)
            .or_insert_with(|| {
                device.create_sampler(&wgpu::SamplerDescriptor {
                    label: Some("aograph sampler"),
                    mag_filter: desc.filter,
                    min_filter: desc.filter,
                    address_mode_u: desc.address,
                    address_mode_v: desc.address,
                    ..Default::default()
                })
            })
            .clone()
    }
    /// Samplers created so far.
    pub fn len(&self) -> usize {
        self.samplers.len()
    }
}
