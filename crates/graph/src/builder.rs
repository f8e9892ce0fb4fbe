//! Declare phase: [`GraphBuilder`] creates virtual resources and passes; each pass's uses
//! are added through its [`PassBuilder`] (`pass_builder.rs`).
//!
//! Methods are infallible so declaring reads like the pipeline it describes; misuse that can
//! only be seen here (a write to a stale version, a handle of another graph) is recorded and
//! reported by compile, which also checks everything that needs the whole graph. Invariant:
//! the declaration only grows; a handle or `PassId` it gave out stays valid.

use std::sync::Arc;

use crate::custom::CustomPass;
use crate::declaration::*;
use crate::error::GraphError;
use crate::pass_builder::PassBuilder;
use crate::resource::*;

/// Builds a [`GraphDecl`].
#[derive(Default)]
pub struct GraphBuilder {
    decl: GraphDecl,
    /// Sizes of created textures and dispatches are divided by this (0 reads as 1): see
    /// [`GraphBuilder::set_size_divisor`].
    size_divisor: u32,
}

/// Both halves of a history (ping-pong) texture: read `previous`, write `current`.
#[derive(Clone, Copy, Debug)]
pub struct HistoryTexture {
    /// Last frame's contents (resource `{name}.previous`), readable without a write; zeros
    /// when the history is not valid (see `Executor::history_valid`).
    pub previous: TextureHandle,
    /// This frame's contents (resource `{name}`): must be written every frame, and becomes
    /// next frame's `previous`.
    pub current: TextureHandle,
}

impl GraphBuilder {
    /// An empty graph, declared at full size (size divisor 1).
    pub fn new() -> Self {
        Self::default()
    }
    /// Continues declaring on top of an existing declaration (e.g. to add user passes after a
    /// frame graph built elsewhere); its handles stay valid.
    pub fn from_decl(decl: GraphDecl) -> Self {
        Self {
            decl,
            size_divisor: 1,
        }
    }

    /// Declares what follows at 1/`divisor` of the sizes it names: every texture created
    /// (transient or history) and every `dispatch_size` afterwards has its size class
    /// [`SizeClass::divided`] by `divisor`, until the divisor is set back. Imported textures
    /// keep their sizes. Returns the previous divisor, to restore. A block written for the full
    /// output (`SizeClass::FULL`) thus runs at half resolution under divisor 2 unchanged:
    /// aograph's `resolution = "half"`.
    pub fn set_size_divisor(&mut self, divisor: u32) -> u32 {
        std::mem::replace(&mut self.size_divisor, divisor.max(1)).max(1)
    }
    /// The divisor in effect (1 unless [`GraphBuilder::set_size_divisor`] changed it).
    pub fn size_divisor(&self) -> u32 {
        self.size_divisor.max(1)
    }

    fn add_resource(&mut self, name: &str, kind: ResourceKind, origin: ResourceOrigin) -> u32 {
        self.decl.resources.push(ResourceDecl {
            name: name.to_string(),
            kind,
            origin,
            exported: false,
            writers: Vec::new(),
        });
        (self.decl.resources.len() - 1) as u32
    }

    /// A transient texture owned by the graph; it must be written before it is read.
    pub fn create_texture(&mut self, name: &str, mut desc: TextureDesc) -> TextureHandle {
        desc.size = desc.size.divided(self.size_divisor());
        Handle::new(
            self.add_resource(name, ResourceKind::Texture(desc), ResourceOrigin::Transient),
            0,
        )
    }
    /// A texture provided by the caller at execution (`Executor::import_texture`).
    pub fn import_texture(&mut self, name: &str, desc: TextureDesc) -> TextureHandle {
        Handle::new(
            self.add_resource(name, ResourceKind::Texture(desc), ResourceOrigin::Imported),
            0,
        )
    }
    /// A transient buffer owned by the graph.
    pub fn create_buffer(&mut self, name: &str, desc: BufferDesc) -> BufferHandle {
        Handle::new(
            self.add_resource(name, ResourceKind::Buffer(desc), ResourceOrigin::Transient),
            0,
        )
    }
    /// A buffer provided by the caller at execution.
    pub fn import_buffer(&mut self, name: &str, desc: BufferDesc) -> BufferHandle {
        Handle::new(
            self.add_resource(name, ResourceKind::Buffer(desc), ResourceOrigin::Imported),
            0,
        )
    }
    /// A top-level acceleration structure provided by the caller at execution
    /// (`Executor::import_acceleration_structure`), for passes that trace rays with ray queries
    /// (`PassBuilder::read_acceleration_structure`).
    pub fn import_acceleration_structure(&mut self, name: &str) -> AccelerationStructureHandle {
        Handle::new(
            self.add_resource(
                name,
                ResourceKind::AccelerationStructure,
                ResourceOrigin::Imported,
            ),
            0,
        )
    }
    /// A persistent texture: `previous` holds last frame's value (check
    /// `Executor::history_valid`), `current` must be written this frame and becomes next
    /// frame's `previous`.
    pub fn history_texture(&mut self, name: &str, mut desc: TextureDesc) -> HistoryTexture {
        desc.size = desc.size.divided(self.size_divisor());
        let prev = self.add_resource(
            &format!("{name}.previous"),
            ResourceKind::Texture(desc),
            ResourceOrigin::HistoryPrevious {
                history: name.to_string(),
            },
        );
        let cur = self.add_resource(
            name,
            ResourceKind::Texture(desc),
            ResourceOrigin::HistoryCurrent {
                history: name.to_string(),
            },
        );
        HistoryTexture {
            previous: Handle::new(prev, 0),
            current: Handle::new(cur, 0),
        }
    }
    /// Requests `handle`'s resource as an output: passes that contribute to its final version
    /// are kept, the rest may be culled. Read it back with `Executor::read_texture`.
    pub fn export(&mut self, handle: TextureHandle) {
        if let Some(r) = self.decl.resources.get_mut(handle.id as usize) {
            r.exported = true;
        }
    }
    /// Descriptor of a texture handle of this builder, its size as the current size divisor's
    /// scope names it ([`SizeClass::within`]), so a block that creates a texture the size of
    /// another gets that size under any divisor.
    pub fn texture_desc(&self, handle: TextureHandle) -> Option<TextureDesc> {
        let divisor = self.size_divisor();
        self.decl
            .resources
            .get(handle.id as usize)
            .and_then(|r| r.texture_desc().copied())
            .map(|mut d| {
                d.size = d.size.within(divisor);
                d
            })
    }

    fn add_pass(&mut self, name: &str, kind: PassKind) -> PassBuilder<'_> {
        self.decl.passes.push(PassDecl {
            name: name.to_string(),
            kind,
            textures: Vec::new(),
            buffers: Vec::new(),
            uniforms: Vec::new(),
            side_effect: false,
            loads_per_invocation: None,
            constants: Vec::new(),
            samplers: Vec::new(),
        });
        let id = PassId(self.decl.passes.len() - 1);
        let divisor = self.size_divisor();
        PassBuilder::new(&mut self.decl, id, divisor)
    }
    /// A compute pass running `entry` of the WGSL file `shader` (relative to the shader root).
    pub fn compute_pass(&mut self, name: &str, shader: &str, entry: &str) -> PassBuilder<'_> {
        self.add_pass(
            name,
            PassKind::Compute {
                shader: shader.to_string(),
                entry: entry.to_string(),
                dispatch: None,
            },
        )
    }
    /// A render pass drawing one full-screen triangle into its colour attachments.
    pub fn fullscreen_pass(
        &mut self,
        name: &str,
        shader: &str,
        vertex: &str,
        fragment: &str,
    ) -> PassBuilder<'_> {
        self.add_pass(
            name,
            PassKind::Fullscreen {
                shader: shader.to_string(),
                vertex: vertex.to_string(),
                fragment: fragment.to_string(),
            },
        )
    }
    /// A pass whose commands user code records.
    pub fn custom_pass(&mut self, name: &str, pass: impl CustomPass + 'static) -> PassBuilder<'_> {
        self.add_pass(name, PassKind::Custom(Arc::new(pass)))
    }
    /// Copies `src` into `dst` (same size and format); returns `dst`'s new version.
    pub fn copy_pass(
        &mut self,
        name: &str,
        src: TextureHandle,
        dst: TextureHandle,
    ) -> TextureHandle {
        let mut p = self.add_pass(name, PassKind::Copy);
        p.read_texture(TextureAccess::CopySrc, src);
        p.write_texture(TextureAccess::CopyDst, dst)
    }
    /// Reopens a declared pass to add uses (passes may be declared before their inputs exist).
    /// A `PassId` of another graph is recorded as an error (reported by compile) and gets a
    /// stand-in pass, so misuse never panics.
    pub fn pass(&mut self, id: PassId) -> PassBuilder<'_> {
        if id.0 >= self.decl.passes.len() {
            self.decl.errors.push(GraphError::InvalidPass {
                pass: format!("#{}", id.0),
                message: "this pass id does not belong to this graph".into(),
            });
            return self.add_pass(
                &format!("invalid pass #{}", id.0),
                PassKind::Custom(Arc::new(crate::custom::NoopPass)),
            );
        }
        PassBuilder::new(&mut self.decl, id, self.size_divisor.max(1))
    }

    /// Finishes declaring.
    pub fn build(self) -> GraphDecl {
        self.decl
    }
}
