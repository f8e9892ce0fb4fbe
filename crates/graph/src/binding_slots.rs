//! Binding slots: where each shader binding of a kept pass takes its resource from, resolved
//! once at compile (`shader_check.rs`, which matches the WGSL names to the pass's uses), so
//! that binding a frame (`bind.rs`) walks indices and compares no names.
//!
//! Invariant: for a kept compute or full-screen pass `p`, `CompiledGraph::binding_slots[p][i]`
//! is the slot of `CompiledGraph::shaders[p].bindings[i]` (same group and binding), and its
//! source is a use of that pass of the kind the binding needs, as compile checked; every other
//! pass has no slots. Slots depend only on the declaration's structure, so a compile-cache hit
//! keeps them.

use crate::declaration::UniformHandle;

/// One `@group(group) @binding(binding)` global of a pass's shader and what is bound to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BindingSlot {
    /// The global's `@group` index: which bind group of the pass it goes into.
    pub group: u32,
    /// The global's `@binding` index within its group.
    pub binding: u32,
    /// Where the bound resource comes from.
    pub source: BindingSource,
}

/// What a [`BindingSlot`] binds, as indices into the plan and its declaration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingSource {
    /// `PassDecl::textures[texture_use]`, of resource `resource`, sampled: a view of mip `mip`,
    /// or of all mips when `None`.
    SampledTexture {
        /// Index of the use in the pass's `PassDecl::textures`.
        texture_use: usize,
        /// Index of the texture in `GraphDecl::resources`.
        resource: usize,
        /// The single mip level viewed, or `None` for a view of all levels.
        mip: Option<u32>,
    },
    /// `PassDecl::textures[texture_use]`, of resource `resource`, as a storage texture: a view
    /// of mip `mip` (0 when the use names none).
    StorageTexture {
        /// Index of the use in the pass's `PassDecl::textures`.
        texture_use: usize,
        /// Index of the texture in `GraphDecl::resources`.
        resource: usize,
        /// The mip level viewed (storage views always name one level).
        mip: u32,
    },
    /// A uniform block of the declaration (`GraphDecl::uniforms`).
    Uniform(UniformHandle),
    /// `PassDecl::buffers[buffer_use]`, of resource `resource`.
    Buffer {
        /// Index of the use in the pass's `PassDecl::buffers`.
        buffer_use: usize,
        /// Index of the buffer in `GraphDecl::resources`.
        resource: usize,
    },
    /// `PassDecl::buffers[buffer_use]`, an imported top-level acceleration structure, resource
    /// `resource`.
    AccelerationStructure {
        /// Index of the use in the pass's `PassDecl::buffers`.
        buffer_use: usize,
        /// Index of the structure in `GraphDecl::resources`.
        resource: usize,
    },
    /// `CompiledGraph::samplers[sampler]`.
    Sampler {
        /// Index into `CompiledGraph::samplers`.
        sampler: usize,
    },
}

impl BindingSource {
    /// The texture resource this binds, if it binds one.
    pub fn texture_resource(&self) -> Option<usize> {
        match *self {
            Self::SampledTexture { resource, .. } | Self::StorageTexture { resource, .. } => {
                Some(resource)
            }
            _ => None,
        }
    }
}
