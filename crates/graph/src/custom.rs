//! Custom passes: user code that records its own commands (e.g. drawing meshes).
//!
//! A custom pass still declares every read and write through the builder, so ordering, culling
//! and reuse treat it like any other pass; at execution it is handed the physical textures of
//! exactly the resources it declared.
//!
//! Invariant: a [`PassContext`] hands out only the textures and buffers of the pass's own
//! uses; it sees the uses (`uses.rs`), not the declaration, so this module depends on no part
//! of the graph that depends on it.

use crate::error::{GraphError, GraphResult};
use crate::resource::{BufferHandle, Extent, TextureHandle};
use crate::shader::ShaderLibrary;
use crate::uses::{BufferUse, TextureUse};

/// A physical texture bound to a resource for this frame. Cloning is cheap (reference counts).
#[derive(Clone, Debug)]
pub struct BoundTexture {
    /// The physical texture (pooled, imported or a history half).
    pub texture: wgpu::Texture,
    /// A view of all mip levels.
    pub view: wgpu::TextureView,
    /// One view per mip level.
    pub mip_views: std::sync::Arc<[wgpu::TextureView]>,
    /// Size of mip 0 in pixels.
    pub extent: Extent,
    /// Identifies the physical texture in bind-group caches.
    pub serial: u64,
}

impl BoundTexture {
    /// `texture` with a view of all mips and one per mip, identified by `serial`.
    pub fn new(texture: wgpu::Texture, serial: u64) -> Self {
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let mip_views = (0..texture.mip_level_count())
            .map(|m| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: m,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let extent = Extent::new(texture.width(), texture.height());
        Self {
            texture,
            view,
            mip_views,
            extent,
            serial,
        }
    }
    /// The view of one mip level, or of all levels.
    pub fn view_of(&self, mip: Option<u32>) -> &wgpu::TextureView {
        mip.and_then(|m| self.mip_views.get(m as usize))
            .unwrap_or(&self.view)
    }
}

/// Commands recorded by user code.
pub trait CustomPass: Send + Sync {
    /// A short name of what the pass does (enters the plan's hash with `cache_key`).
    fn kind_name(&self) -> &str;
    /// Changes when the pass's behaviour changes in a way the plan should notice.
    fn cache_key(&self) -> u64 {
        0
    }
    /// Records the pass's commands.
    fn record(&self, ctx: &mut PassContext<'_>) -> GraphResult<()>;
}

/// What a custom pass sees while recording.
pub struct PassContext<'a> {
    /// The executor's device, for creating pipelines and buffers (cache them in the pass;
    /// `record` runs every frame).
    pub device: &'a wgpu::Device,
    /// The executor's queue, for uploads (`write_buffer`, `write_texture`): they take effect at
    /// the next submit, before any command recorded into `encoder` runs.
    pub queue: &'a wgpu::Queue,
    /// The frame's command encoder: record the pass's commands here, in execution order with
    /// the other passes.
    pub encoder: &'a mut wgpu::CommandEncoder,
    /// The graph's output size this frame.
    pub output: Extent,
    /// The pass's name and uses (what it may ask for).
    pub(crate) pass_name: &'a str,
    pub(crate) texture_uses: &'a [TextureUse],
    pub(crate) buffer_uses: &'a [BufferUse],
    /// Per resource: what is bound this frame.
    pub(crate) textures: &'a [Option<BoundTexture>],
    pub(crate) buffers: &'a [Option<wgpu::Buffer>],
    pub(crate) shaders: &'a ShaderLibrary,
    pub(crate) features: wgpu::Features,
}

impl PassContext<'_> {
    fn bound(&self, handle: TextureHandle) -> GraphResult<&BoundTexture> {
        let declared = self
            .texture_uses
            .iter()
            .any(|u| u.resource() == handle.resource_index());
        let missing = |message: &str| GraphError::MissingResource {
            resource: format!("{handle:?}"),
            message: format!("{message} (pass `{}`)", self.pass_name),
        };
        if !declared {
            return Err(missing("the pass did not declare this texture"));
        }
        self.textures
            .get(handle.resource_index())
            .and_then(Option::as_ref)
            .ok_or_else(|| missing("not allocated this frame"))
    }
    /// The view of a texture this pass declared.
    pub fn view(&self, handle: TextureHandle) -> GraphResult<&wgpu::TextureView> {
        Ok(&self.bound(handle)?.view)
    }
    /// The texture this pass declared.
    pub fn texture(&self, handle: TextureHandle) -> GraphResult<&wgpu::Texture> {
        Ok(&self.bound(handle)?.texture)
    }
    /// A buffer this pass declared (e.g. the imported view block).
    pub fn buffer(&self, handle: BufferHandle) -> GraphResult<&wgpu::Buffer> {
        let declared = self
            .buffer_uses
            .iter()
            .any(|u| u.read.or(u.written).is_some_and(|h| h.id == handle.id));
        let missing = |message: &str| GraphError::MissingResource {
            resource: format!("{handle:?}"),
            message: format!("{message} (pass `{}`)", self.pass_name),
        };
        if !declared {
            return Err(missing("the pass did not declare this buffer"));
        }
        self.buffers
            .get(handle.resource_index())
            .and_then(Option::as_ref)
            .ok_or_else(|| missing("not bound this frame"))
    }
    /// The shader library of the executor (custom passes load their WGSL through it, so it is
    /// validated and its includes expanded like every other shader).
    pub fn shaders(&self) -> &ShaderLibrary {
        self.shaders
    }
    /// Features of the device (e.g. whether 32-bit floats are filterable).
    pub fn features(&self) -> wgpu::Features {
        self.features
    }
    /// The concrete size of a texture this pass declared.
    pub fn extent(&self, handle: TextureHandle) -> GraphResult<Extent> {
        Ok(self.bound(handle)?.extent)
    }
}

/// A pass that records nothing: for GPU-free tests and for sketching a graph's shape.
pub struct NoopPass;

impl CustomPass for NoopPass {
    fn kind_name(&self) -> &str {
        "noop"
    }
    fn record(&self, _ctx: &mut PassContext<'_>) -> GraphResult<()> {
        Ok(())
    }
}
