//! Where the AO goes: the application's format ([`AoOutputFormat`]) and the texture a frame
//! wrote ([`AoOutputView`]). Accessibility is 1 where nothing occludes, clamped to [0, 1].

/// Formats the AO can be written in: all renderable, so one full-screen pass writes any of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AoOutputFormat {
    /// 8-bit, enough to multiply into shading.
    #[default]
    R8Unorm,
    /// Half float.
    R16Float,
    /// Full precision, what aograph's own tests compare.
    R32Float,
}

impl AoOutputFormat {
    /// The wgpu format.
    pub fn wgpu(self) -> wgpu::TextureFormat {
        match self {
            Self::R8Unorm => wgpu::TextureFormat::R8Unorm,
            Self::R16Float => wgpu::TextureFormat::R16Float,
            Self::R32Float => wgpu::TextureFormat::R32Float,
        }
    }
    /// The output format of an application's texture, or `None` when it is none of them.
    pub fn of(format: wgpu::TextureFormat) -> Option<Self> {
        [Self::R8Unorm, Self::R16Float, Self::R32Float]
            .into_iter()
            .find(|f| f.wgpu() == format)
    }
}

/// Usages a texture the application passes for the output must have.
pub const OUTPUT_USAGE: wgpu::TextureUsages = wgpu::TextureUsages::RENDER_ATTACHMENT;

/// The texture a frame's AO was written to (aograph's own, or the application's), and a view
/// of it. Both are cheap handles: keep them as long as needed; the next `encode` writes the
/// same texture again unless the size or format changed.
#[derive(Clone, Debug)]
pub struct AoOutputView {
    /// The texture.
    pub texture: wgpu::Texture,
    /// A view of all of it.
    pub view: wgpu::TextureView,
}
