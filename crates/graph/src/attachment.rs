//! Attachment operations of render passes: how a colour or depth attachment starts (loaded or
//! cleared, and to what), how colour blends, and how depth is tested and whether it is written.
//!
//! Invariant (resolved by the builder, so the executor only follows it): without an explicit
//! choice, the first write of a graph-owned texture clears (colour to 0, depth to the far
//! value of its depth test), an imported texture loads (a user's target survives where nothing
//! is drawn), and every later version loads. A read-only depth attachment is never written.

use std::hash::{Hash, Hasher};

/// How an attachment starts: keep what is there, or clear it to a value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LoadOp<T> {
    /// Keep the attachment's current contents (wgpu's `LoadOp::Load`).
    Load,
    /// Overwrite the whole attachment with this value before the pass draws: an RGBA colour
    /// for colour attachments, a depth in [0, 1] for depth attachments.
    Clear(T),
}

/// A colour attachment's start and blend. `load: None` follows the module's rule.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ColorTarget {
    /// How the attachment starts; `None` follows the module's rule (clear to 0 on a
    /// graph-owned texture's first write, load otherwise).
    pub load: Option<LoadOp<[f32; 4]>>,
    /// Blend state of the attachment; `None` replaces the attachment's texels.
    pub blend: Option<wgpu::BlendState>,
}

impl ColorTarget {
    /// Clears to `rgba` before the pass draws.
    pub fn clear(rgba: [f32; 4]) -> Self {
        Self {
            load: Some(LoadOp::Clear(rgba)),
            blend: None,
        }
    }
    /// Keeps the attachment's contents (an imported target, or an earlier version).
    pub fn load() -> Self {
        Self {
            load: Some(LoadOp::Load),
            blend: None,
        }
    }
    /// Blends the pass's output over what the attachment holds.
    pub fn blend(mut self, blend: wgpu::BlendState) -> Self {
        self.blend = Some(blend);
        self
    }
}

/// A depth attachment's start and test. `load: None` follows the module's rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthTarget {
    /// How the attachment starts; `None` follows the module's rule (clear to
    /// [`DepthTarget::far_value`] on a graph-owned texture's first write, load otherwise).
    pub load: Option<LoadOp<f32>>,
    /// The depth test: a fragment passes when `compare(fragment depth, stored depth)` holds.
    pub compare: wgpu::CompareFunction,
}

impl Default for DepthTarget {
    fn default() -> Self {
        Self::standard()
    }
}

impl DepthTarget {
    /// Near 0, far 1: clears to 1.0 and passes `LessEqual`.
    pub fn standard() -> Self {
        Self {
            load: None,
            compare: wgpu::CompareFunction::LessEqual,
        }
    }
    /// Reversed Z (near 1, far 0): clears to 0.0 and passes `GreaterEqual`.
    pub fn reversed_z() -> Self {
        Self {
            load: None,
            compare: wgpu::CompareFunction::GreaterEqual,
        }
    }
    /// Keeps the attachment's depth (e.g. a depth buffer rendered by an earlier pass or
    /// imported) instead of the automatic choice.
    pub fn load(mut self) -> Self {
        self.load = Some(LoadOp::Load);
        self
    }
    /// Clears the attachment to `depth` (in [0, 1]) before the pass draws, whatever version
    /// it writes.
    pub fn clear(mut self, depth: f32) -> Self {
        self.load = Some(LoadOp::Clear(depth));
        self
    }
    /// The value the test treats as farthest: what an automatic clear writes.
    pub fn far_value(&self) -> f32 {
        use wgpu::CompareFunction as C;
        match self.compare {
            C::Greater | C::GreaterEqual => 0.0,
            _ => 1.0,
        }
    }
}

/// What a render pass does with one attachment, with the load resolved (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttachmentOps {
    /// A colour attachment.
    Color {
        /// Load or clear value (RGBA) the pass starts with.
        load: LoadOp<[f32; 4]>,
        /// Blend state; `None` replaces the attachment's texels.
        blend: Option<wgpu::BlendState>,
    },
    /// The depth attachment.
    Depth {
        /// Ignored when `read_only`: a read-only attachment always loads.
        load: LoadOp<f32>,
        /// The depth test the pipeline uses.
        compare: wgpu::CompareFunction,
        /// Tested but not written ([`TextureAccess::DepthRead`](crate::TextureAccess::DepthRead)):
        /// the pipeline has depth writes off and the pass may also sample the texture.
        read_only: bool,
    },
}

impl AttachmentOps {
    /// True when the pass keeps the attachment's previous contents.
    pub fn loads(&self) -> bool {
        match self {
            Self::Color { load, .. } => *load == LoadOp::Load,
            Self::Depth {
                load, read_only, ..
            } => *read_only || *load == LoadOp::Load,
        }
    }
}

impl Eq for AttachmentOps {}

impl Hash for AttachmentOps {
    fn hash<H: Hasher>(&self, h: &mut H) {
        match self {
            Self::Color { load, blend } => {
                0u8.hash(h);
                match load {
                    LoadOp::Load => 0u8.hash(h),
                    LoadOp::Clear(c) => (1u8, c.map(f32::to_bits)).hash(h),
                }
                blend.hash(h);
            }
            Self::Depth {
                load,
                compare,
                read_only,
            } => {
                1u8.hash(h);
                match load {
                    LoadOp::Load => 0u8.hash(h),
                    LoadOp::Clear(d) => (1u8, d.to_bits()).hash(h),
                }
                (compare, read_only).hash(h);
            }
        }
    }
}
