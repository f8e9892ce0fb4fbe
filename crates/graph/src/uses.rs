//! Uses: what one pass declares it does with one resource (a texture, a buffer) or binds to
//! one sampler global; the builder records them, compile checks them against the shader, and
//! custom passes are handed the resources of theirs.
//!
//! Invariant: a use that writes carries the version it produces (`written`), and a use that
//! keeps part of the old contents also carries the version it reads (`read`); see
//! [`TextureUse`]. Uses hold no GPU object and depend on no other part of the graph but the
//! handle and attachment types.

use crate::attachment::AttachmentOps;
use crate::resource::{BufferAccess, BufferHandle, TextureAccess, TextureHandle};
use crate::sampler::SamplerDesc;

/// One use of a texture by a pass. A write that keeps part of the old contents (read-write
/// storage, a single mip of a mipped texture, an attachment that loads) also reads the previous
/// version, so `read` and `written` are both set.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct TextureUse {
    /// The WGSL global this use binds to (`None` for attachments and copies).
    pub binding: Option<String>,
    /// How the pass accesses the texture.
    pub access: TextureAccess,
    /// The version the pass reads, when it reads (or keeps part of) the old contents.
    pub read: Option<TextureHandle>,
    /// The version the pass produces, when it writes.
    pub written: Option<TextureHandle>,
    /// A single mip level, or all levels when `None`.
    pub mip: Option<u32>,
    /// For colour and depth attachments: how the pass starts, blends and tests.
    pub attachment: Option<AttachmentOps>,
}

impl TextureUse {
    /// Index in `GraphDecl::resources` of the texture used.
    pub fn resource(&self) -> usize {
        self.read
            .or(self.written)
            .map(|h| h.id as usize)
            .unwrap_or(0)
    }
}

/// One use of a buffer by a pass.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BufferUse {
    /// The WGSL global this use binds to (`PassBuilder` always names one).
    pub binding: Option<String>,
    /// How the pass accesses the buffer.
    pub access: BufferAccess,
    /// The version the pass reads, when the access reads.
    pub read: Option<BufferHandle>,
    /// The version the pass produces, when the access writes.
    pub written: Option<BufferHandle>,
}

/// The sampler a pass binds to its shader's `sampler` global `binding`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SamplerUse {
    /// Name of the WGSL `sampler` global.
    pub binding: String,
    /// The filter and address mode bound to it.
    pub desc: SamplerDesc,
}
