//! The declaration: pure data describing resources and passes, produced by [`GraphBuilder`].
//!
//! A declaration is what compile consumes and what its cache is keyed by. It holds no GPU
//! object; custom passes are trait objects whose identity (name and `cache_key`) enters the hash.
//! Invariant: `ResourceDecl::writers[v]` is the pass that produced version `v + 1`.
//!
//! [`GraphBuilder`]: crate::GraphBuilder

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use crate::custom::CustomPass;
use crate::error::GraphError;
use crate::resource::{BufferDesc, SizeClass, TextureAccess, TextureDesc};
pub use crate::uses::{BufferUse, SamplerUse, TextureUse};

/// Index of a pass in its declaration (declaration order).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PassId(pub(crate) usize);

impl PassId {
    /// The pass's position in `GraphDecl::passes`.
    pub fn index(self) -> usize {
        self.0
    }
}

/// Index of a uniform block in a declaration; its bytes can be rewritten every frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct UniformHandle(pub(crate) usize);

/// Where a resource's contents come from and how long they live.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum ResourceOrigin {
    /// Created and owned by the graph for this frame; may share a physical texture.
    Transient,
    /// Provided by the user (e.g. a g-buffer rendered elsewhere); version 0 is readable.
    Imported,
    /// Last frame's value of history `history`; version 0 is readable.
    HistoryPrevious {
        /// The history's name, as given to `GraphBuilder::history_texture`.
        history: String,
    },
    /// This frame's value of history `history`; must be written.
    HistoryCurrent {
        /// The history's name, as given to `GraphBuilder::history_texture`.
        history: String,
    },
}

/// Texture, buffer or acceleration structure, with its descriptor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ResourceKind {
    /// A 2D texture.
    Texture(TextureDesc),
    /// A GPU buffer.
    Buffer(BufferDesc),
    /// A top-level acceleration structure (imported only: the caller builds and updates it).
    AccelerationStructure,
}

/// One virtual resource and the passes that wrote each of its versions.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ResourceDecl {
    /// Name of the resource, as shown in summaries and errors; imports are bound by it
    /// (`Executor::import_texture`). A history's `previous` half is named `{name}.previous`.
    pub name: String,
    /// Texture or buffer, with its descriptor.
    pub kind: ResourceKind,
    /// Where its contents come from and how long they live.
    pub origin: ResourceOrigin,
    /// Requested as an output: kept alive to the end of the frame and readable afterwards.
    pub exported: bool,
    pub(crate) writers: Vec<PassId>,
}

impl ResourceDecl {
    /// The texture descriptor, if this is a texture.
    pub fn texture_desc(&self) -> Option<&TextureDesc> {
        match &self.kind {
            ResourceKind::Texture(d) => Some(d),
            ResourceKind::Buffer(_) | ResourceKind::AccelerationStructure => None,
        }
    }
    /// The newest version (0 when never written).
    pub fn latest_version(&self) -> u32 {
        self.writers.len() as u32
    }
    /// The pass that produced `version`, `None` for version 0.
    pub fn producer(&self, version: u32) -> Option<PassId> {
        version
            .checked_sub(1)
            .and_then(|v| self.writers.get(v as usize).copied())
    }
    /// True when version 0 holds data before any pass runs.
    pub fn readable_before_write(&self) -> bool {
        matches!(
            self.origin,
            ResourceOrigin::Imported | ResourceOrigin::HistoryPrevious { .. }
        )
    }
}

/// A uniform block owned by a pass: bound to `binding`, contents set per frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UniformDecl {
    /// The pass whose shader binds the block.
    pub pass: PassId,
    /// Name of the WGSL `var<uniform>` global the block is bound to.
    pub binding: String,
    /// The block's bytes as declared (laid out as the WGSL struct expects); its length is
    /// part of the structure hash, its contents are not.
    pub initial: Vec<u8>,
    /// The Rust struct's fields when it was declared typed (`PassBuilder::uniform_struct`):
    /// compile checks them against the WGSL struct's members.
    pub fields: Option<&'static [crate::UniformField]>,
}

/// How many threads a compute pass runs; workgroup counts come from the shader's
/// `@workgroup_size`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dispatch {
    /// One thread per texel of a size class at a mip level.
    Threads {
        /// The size class, resolved against the output size each frame.
        size: SizeClass,
        /// The mip level of that size (0 for the base level).
        mip: u32,
    },
    /// Explicit workgroup counts (x, y, z).
    Workgroups([u32; 3]),
}

/// What a pass records.
#[derive(Clone)]
pub enum PassKind {
    /// A compute shader entry point from a WGSL file.
    Compute {
        /// The WGSL file, relative to the shader root (or an inline name), optionally with a
        /// variant suffix.
        shader: String,
        /// Name of the `@compute` entry point.
        entry: String,
        /// How many threads run; `None` until the builder sets one.
        dispatch: Option<Dispatch>,
    },
    /// A full-screen triangle drawn into the colour attachments.
    Fullscreen {
        /// The WGSL file, relative to the shader root (or an inline name), optionally with a
        /// variant suffix.
        shader: String,
        /// Name of the `@vertex` entry point: it is drawn with 3 vertices and no vertex
        /// buffer, so it must make the full-screen triangle from `vertex_index`.
        vertex: String,
        /// Name of the `@fragment` entry point.
        fragment: String,
    },
    /// A texture-to-texture copy of the pass's `CopySrc` into its `CopyDst`.
    Copy,
    /// User code recording its own commands.
    Custom(Arc<dyn CustomPass>),
}

impl std::fmt::Debug for PassKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PassKind::Compute { shader, entry, .. } => write!(f, "compute {shader}:{entry}"),
            PassKind::Fullscreen {
                shader, fragment, ..
            } => write!(f, "fullscreen {shader}:{fragment}"),
            PassKind::Copy => write!(f, "copy"),
            PassKind::Custom(c) => write!(f, "custom {}", c.kind_name()),
        }
    }
}

impl Hash for PassKind {
    fn hash<H: Hasher>(&self, h: &mut H) {
        match self {
            PassKind::Compute {
                shader,
                entry,
                dispatch,
            } => (0u8, shader, entry, dispatch).hash(h),
            PassKind::Fullscreen {
                shader,
                vertex,
                fragment,
            } => (1u8, shader, vertex, fragment).hash(h),
            PassKind::Copy => 2u8.hash(h),
            PassKind::Custom(c) => (3u8, c.kind_name(), c.cache_key()).hash(h),
        }
    }
}

/// One pass: what it records and what it reads and writes.
#[derive(Clone, Debug)]
pub struct PassDecl {
    /// Name of the pass, as shown in timings, summaries and errors.
    pub name: String,
    /// What the pass records.
    pub kind: PassKind,
    /// Its texture uses, in the order they were declared.
    pub textures: Vec<TextureUse>,
    /// Its buffer uses, in the order they were declared.
    pub buffers: Vec<BufferUse>,
    /// The uniform blocks its shader binds (indices into `GraphDecl::uniforms`).
    pub uniforms: Vec<UniformHandle>,
    /// Kept even when no output needs it (e.g. it writes to the CPU or a swapchain).
    pub side_effect: bool,
    /// Texel loads one invocation (thread or fragment) makes, as the pass's author states them
    /// for its parameters: what a roofline compares the pass's load rate with (`cost.rs`).
    /// Not part of the structure: it changes no plan.
    pub loads_per_invocation: Option<f32>,
    /// Values of the shader's pipeline-overridable constants (`override NAME` in WGSL), sorted
    /// by name: fixed when the pipeline is built, so each distinct set is its own pipeline.
    pub constants: Vec<PipelineConstant>,
    /// The samplers bound to the shader's `sampler` globals, sorted by binding name
    /// (`PassBuilder::sampler`).
    pub samplers: Vec<SamplerUse>,
}

/// A value for one `override` declaration of a pass's shader (WGSL's pipeline-overridable
/// constants; Vulkan's specialization constants). Unlike a uniform, the driver compiles the
/// value in: a loop bound becomes a constant it can unroll.
#[derive(Clone, Debug)]
pub struct PipelineConstant {
    /// Name of the WGSL `override` declaration.
    pub name: String,
    /// The value, finite, converted to the override's type when the pipeline is built.
    pub value: f64,
}

// Equal and hashed by the value's bits (values are finite: `PassBuilder::constant`), so a
// constant can key a pipeline.
impl PartialEq for PipelineConstant {
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name && self.value.to_bits() == other.value.to_bits()
    }
}
impl Eq for PipelineConstant {}

impl std::hash::Hash for PipelineConstant {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.name.hash(state);
        self.value.to_bits().hash(state);
    }
}

impl PassDecl {
    /// True when the pass records a render pass: a full-screen pass, or any pass with a
    /// colour or depth attachment.
    pub fn is_raster(&self) -> bool {
        matches!(self.kind, PassKind::Fullscreen { .. })
            || self.textures.iter().any(|u| {
                matches!(
                    u.access,
                    TextureAccess::ColorAttachment
                        | TextureAccess::DepthAttachment
                        | TextureAccess::DepthRead
                )
            })
    }
}

/// A whole declaration, ready to compile.
#[derive(Clone, Debug, Default)]
pub struct GraphDecl {
    /// Every virtual resource, indexed by its handles' resource index.
    pub resources: Vec<ResourceDecl>,
    /// Every pass, indexed by [`PassId`], in declaration order.
    pub passes: Vec<PassDecl>,
    /// Every uniform block, indexed by [`UniformHandle`].
    pub uniforms: Vec<UniformDecl>,
    /// Misuse found while declaring (e.g. conflicting writes); compile reports the first.
    pub(crate) errors: Vec<GraphError>,
}

impl GraphDecl {
    /// Hash of the declaration's structure: resources, passes, uses, shaders, pipeline
    /// constants, samplers, attachment operations, and each uniform block's owner, binding and
    /// size, but not its contents. A changed parameter value therefore hits the compile cache
    /// and the executor's pipelines;
    /// the executor writes the new declaration's contents into the plan's uniform buffers
    /// (see `Executor`), and per-frame data goes through `Executor::write_uniform`.
    pub fn structure_hash(&self) -> u64 {
        let mut h = crate::structure_hash::StructureHasher::default();
        self.resources.hash(&mut h);
        for p in &self.passes {
            (
                &p.name,
                &p.kind,
                &p.textures,
                &p.buffers,
                &p.uniforms,
                p.side_effect,
                &p.constants,
                &p.samplers,
            )
                .hash(&mut h);
        }
        for u in &self.uniforms {
            (u.pass, &u.binding, u.initial.len()).hash(&mut h);
        }
        self.errors.len().hash(&mut h);
        h.finish()
    }
    /// The uniform block bound to `binding` in pass `pass` (for per-frame writes with
    /// `Executor::write_uniform` by code that did not keep the handle).
    pub fn uniform(&self, pass: &str, binding: &str) -> Option<UniformHandle> {
        let p = self.pass_by_name(pass)?;
        self.uniforms
            .iter()
            .position(|u| u.pass == p && u.binding == binding)
            .map(UniformHandle)
    }
    /// The first pass named `name`, if any.
    pub fn pass_by_name(&self, name: &str) -> Option<PassId> {
        self.passes.iter().position(|p| p.name == name).map(PassId)
    }
    /// The index in `resources` of the first resource named `name`, if any.
    pub fn resource_by_name(&self, name: &str) -> Option<usize> {
        self.resources.iter().position(|r| r.name == name)
    }
}
