//! [`PassBuilder`]: adds one pass's uses to the declaration a [`GraphBuilder`] builds: the
//! textures it samples, stores or renders into, buffers, uniform blocks, samplers, its
//! dispatch size and pipeline constants. Reads return `&mut Self`; writes return the next
//! version's handle.
//!
//! Invariant: every use is recorded on the pass it was called on, in call order, and a misuse
//! (a stale version written, a handle of another graph, a non-finite constant) is recorded as
//! an error for compile to report instead of panicking; the builder never fails.
//!
//! [`GraphBuilder`]: crate::GraphBuilder

use crate::attachment::{AttachmentOps, ColorTarget, DepthTarget, LoadOp};
use crate::declaration::*;
use crate::error::GraphError;
use crate::resource::*;
use crate::sampler::SamplerDesc;

/// An attachment's requested operations, before the load is resolved.
#[derive(Clone, Copy)]
enum Target {
    Color(ColorTarget),
    Depth(DepthTarget),
}

/// Adds uses to one pass. Reads return `&mut Self`; writes return the new version's handle.
pub struct PassBuilder<'a> {
    graph: &'a mut GraphDecl,
    id: PassId,
    /// The graph builder's size divisor when the pass was added ([`PassBuilder::dispatch_size`]).
    size_divisor: u32,
}

impl<'a> PassBuilder<'a> {
    /// The builder of pass `id` of the declaration `graph` (a pass `graph` has), declared
    /// under the size divisor `size_divisor`.
    pub(crate) fn new(graph: &'a mut GraphDecl, id: PassId, size_divisor: u32) -> Self {
        Self {
            graph,
            id,
            size_divisor,
        }
    }
}

impl PassBuilder<'_> {
    /// The pass being built: keep it to reopen the pass later with
    /// [`GraphBuilder::pass`](crate::GraphBuilder::pass).
    pub fn id(&self) -> PassId {
        self.id
    }
    fn decl(&mut self) -> &mut PassDecl {
        &mut self.graph.passes[self.id.0]
    }

    /// Records a use; returns the written version for writing accesses.
    fn use_texture(
        &mut self,
        binding: Option<&str>,
        access: TextureAccess,
        handle: TextureHandle,
        mip: Option<u32>,
    ) -> Option<TextureHandle> {
        let target = match access {
            TextureAccess::ColorAttachment => Some(Target::Color(ColorTarget::default())),
            TextureAccess::DepthAttachment | TextureAccess::DepthRead => {
                Some(Target::Depth(DepthTarget::default()))
            }
            _ => None,
        };
        self.use_texture_as(binding, access, handle, mip, target)
    }

    /// [`Self::use_texture`] with an attachment's requested operations (resolved here: see
    /// `attachment.rs`).
    fn use_texture_as(
        &mut self,
        binding: Option<&str>,
        access: TextureAccess,
        handle: TextureHandle,
        mip: Option<u32>,
        target: Option<Target>,
    ) -> Option<TextureHandle> {
        let pass_name = self.decl().name.clone();
        let Some(res) = self.graph.resources.get_mut(handle.id as usize) else {
            self.graph.errors.push(GraphError::InvalidPass {
                pass: pass_name,
                message: format!("texture handle {handle:?} does not belong to this graph"),
            });
            return None;
        };
        let mips = res.texture_desc().map(|d| d.mip_levels).unwrap_or(1);
        let mut read = access.reads().then_some(handle);
        let mut written = None;
        if access.writes() {
            if handle.version != res.latest_version() {
                let first = res.producer(handle.version + 1).map(|p| p.0).unwrap_or(0);
                let first = self
                    .graph
                    .passes
                    .get(first)
                    .map(|p| p.name.clone())
                    .unwrap_or_default();
                let resource = self.graph.resources[handle.id as usize].name.clone();
                self.graph.errors.push(GraphError::ConflictingWrites {
                    resource,
                    first,
                    second: pass_name,
                });
            }
            let res = &mut self.graph.resources[handle.id as usize];
            // A write that keeps part of the old contents also depends on them.
            let partial =
                mip.is_some() && mips > 1 && (handle.version > 0 || res.readable_before_write());
            if partial {
                read = Some(handle);
            }
            res.writers.push(self.id);
            written = Some(Handle::new(handle.id, res.latest_version()));
        }
        // Attachments: resolve the load (module docs of `attachment.rs`); a load reads the
        // version it keeps.
        let keeps = self
            .graph
            .resources
            .get(handle.id as usize)
            .is_some_and(|r| handle.version > 0 || r.readable_before_write());
        let attachment = target.map(|t| match (t, access) {
            (Target::Color(c), _) => AttachmentOps::Color {
                load: c.load.unwrap_or(if keeps {
                    LoadOp::Load
                } else {
                    LoadOp::Clear([0.0; 4])
                }),
                blend: c.blend,
            },
            (Target::Depth(d), access) => AttachmentOps::Depth {
                load: d.load.unwrap_or(if keeps {
                    LoadOp::Load
                } else {
                    LoadOp::Clear(d.far_value())
                }),
                compare: d.compare,
                read_only: access == TextureAccess::DepthRead,
            },
        });
        if attachment.is_some_and(|a| a.loads()) {
            read = Some(handle);
        }
        self.decl().textures.push(TextureUse {
            binding: binding.map(str::to_string),
            access,
            read,
            written,
            mip,
            attachment,
        });
        written
    }

    fn write(
        &mut self,
        binding: Option<&str>,
        access: TextureAccess,
        handle: TextureHandle,
        mip: Option<u32>,
    ) -> TextureHandle {
        self.use_texture(binding, access, handle, mip)
            .unwrap_or(handle)
    }

    /// Reads `handle` through the WGSL `texture_2d` global `binding` (all mips).
    pub fn sample(&mut self, binding: &str, handle: TextureHandle) -> &mut Self {
        self.use_texture(Some(binding), TextureAccess::Sampled, handle, None);
        self
    }
    /// Reads one mip level of `handle` through `binding`.
    pub fn sample_mip(&mut self, binding: &str, handle: TextureHandle, mip: u32) -> &mut Self {
        self.use_texture(Some(binding), TextureAccess::Sampled, handle, Some(mip));
        self
    }
    /// Reads `handle` through a read-only storage texture global.
    pub fn read_storage(&mut self, binding: &str, handle: TextureHandle) -> &mut Self {
        self.use_texture(Some(binding), TextureAccess::StorageRead, handle, None);
        self
    }
    /// Writes `handle` through a write-only storage texture global.
    pub fn write_storage(&mut self, binding: &str, handle: TextureHandle) -> TextureHandle {
        self.write(Some(binding), TextureAccess::StorageWrite, handle, None)
    }
    /// Writes mip `mip` of `handle` through a write-only storage texture global.
    pub fn write_storage_mip(
        &mut self,
        binding: &str,
        handle: TextureHandle,
        mip: u32,
    ) -> TextureHandle {
        self.write(
            Some(binding),
            TextureAccess::StorageWrite,
            handle,
            Some(mip),
        )
    }
    /// Updates `handle` in place through a read-write storage texture global.
    pub fn read_write_storage(&mut self, binding: &str, handle: TextureHandle) -> TextureHandle {
        self.write(Some(binding), TextureAccess::StorageReadWrite, handle, None)
    }
    /// Renders into `handle` as the next colour attachment: a graph-owned texture is cleared
    /// to 0 on its first write, an imported one keeps its contents, later versions load.
    pub fn color_attachment(&mut self, handle: TextureHandle) -> TextureHandle {
        self.write(None, TextureAccess::ColorAttachment, handle, None)
    }
    /// Renders into `handle` with an explicit load (clear value) and blend state.
    pub fn color_target(&mut self, handle: TextureHandle, target: ColorTarget) -> TextureHandle {
        self.use_texture_as(
            None,
            TextureAccess::ColorAttachment,
            handle,
            None,
            Some(Target::Color(target)),
        )
        .unwrap_or(handle)
    }
    /// Depth-tests (`LessEqual`) and writes `handle`: cleared to 1.0 on a graph-owned
    /// texture's first write, loaded otherwise.
    pub fn depth_attachment(&mut self, handle: TextureHandle) -> TextureHandle {
        self.write(None, TextureAccess::DepthAttachment, handle, None)
    }
    /// Depth-tests and writes `handle` with an explicit test and load, e.g.
    /// [`DepthTarget::reversed_z`] (clears to 0.0, passes `GreaterEqual`).
    pub fn depth_target(&mut self, handle: TextureHandle, target: DepthTarget) -> TextureHandle {
        self.use_texture_as(
            None,
            TextureAccess::DepthAttachment,
            handle,
            None,
            Some(Target::Depth(target)),
        )
        .unwrap_or(handle)
    }
    /// Depth-tests (`LessEqual`) against `handle` without writing it (a read-only attachment,
    /// which the pass may also sample).
    pub fn depth_read(&mut self, handle: TextureHandle) -> &mut Self {
        self.use_texture(None, TextureAccess::DepthRead, handle, None);
        self
    }
    /// Depth-tests against `handle` with `compare`, without writing it.
    pub fn depth_read_with(
        &mut self,
        handle: TextureHandle,
        compare: wgpu::CompareFunction,
    ) -> &mut Self {
        let target = DepthTarget {
            load: Some(LoadOp::Load),
            compare,
        };
        self.use_texture_as(
            None,
            TextureAccess::DepthRead,
            handle,
            None,
            Some(Target::Depth(target)),
        );
        self
    }
    /// Declares a read a custom pass performs in its own way (e.g. a copy source).
    pub fn read_texture(&mut self, access: TextureAccess, handle: TextureHandle) -> &mut Self {
        if access.writes() {
            self.write(None, access, handle, None);
        } else {
            self.use_texture(None, access, handle, None);
        }
        self
    }
    /// Declares a write a custom pass performs in its own way.
    pub fn write_texture(&mut self, access: TextureAccess, handle: TextureHandle) -> TextureHandle {
        self.write(None, access, handle, None)
    }

    fn use_buffer(
        &mut self,
        binding: Option<&str>,
        access: BufferAccess,
        handle: BufferHandle,
    ) -> BufferHandle {
        let pass_name = self.decl().name.clone();
        let Some(res) = self.graph.resources.get_mut(handle.id as usize) else {
            self.graph.errors.push(GraphError::InvalidPass {
                pass: pass_name,
                message: format!("buffer handle {handle:?} does not belong to this graph"),
            });
            return handle;
        };
        let mut written = None;
        if access.writes() {
            if handle.version != res.latest_version() {
                let resource = res.name.clone();
                let first = res
                    .producer(handle.version + 1)
                    .map(|p| self.graph.passes[p.0].name.clone())
                    .unwrap_or_default();
                self.graph.errors.push(GraphError::ConflictingWrites {
                    resource,
                    first,
                    second: pass_name,
                });
            }
            let res = &mut self.graph.resources[handle.id as usize];
            res.writers.push(self.id);
            written = Some(Handle::new(handle.id, res.latest_version()));
        }
        let read = access.reads().then_some(handle);
        self.decl().buffers.push(BufferUse {
            binding: binding.map(str::to_string),
            access,
            read,
            written,
        });
        written.unwrap_or(handle)
    }
    /// Reads a buffer through a uniform or read-only storage global.
    pub fn read_buffer(
        &mut self,
        binding: &str,
        access: BufferAccess,
        handle: BufferHandle,
    ) -> &mut Self {
        self.use_buffer(Some(binding), access, handle);
        self
    }
    /// Binds an imported acceleration structure to the shader's `acceleration_structure`
    /// global `binding` (ray queries only read it).
    pub fn read_acceleration_structure(
        &mut self,
        binding: &str,
        handle: AccelerationStructureHandle,
    ) -> &mut Self {
        // Recorded as a read-only use of the resource, like a buffer's: lifetimes and binding
        // slots treat both alike, and the resource's kind says what is bound.
        self.use_buffer(
            Some(binding),
            BufferAccess::AccelerationStructure,
            Handle::new(handle.id, handle.version),
        );
        self
    }
    /// Writes a buffer through a storage global; returns the new version.
    pub fn write_buffer(&mut self, binding: &str, handle: BufferHandle) -> BufferHandle {
        self.use_buffer(Some(binding), BufferAccess::StorageWrite, handle)
    }

    /// A uniform block bound to `binding` with initial contents; rewrite it per frame with
    /// `Executor::write_uniform`.
    pub fn uniform(&mut self, binding: &str, bytes: &[u8]) -> UniformHandle {
        let id = self.id;
        self.graph.uniforms.push(UniformDecl {
            pass: id,
            binding: binding.to_string(),
            initial: bytes.to_vec(),
            fields: None,
        });
        let handle = UniformHandle(self.graph.uniforms.len() - 1);
        self.decl().uniforms.push(handle);
        handle
    }

    /// [`PassBuilder::uniform`] with a typed block: compile also checks the struct's fields
    /// against the WGSL struct's members, name by name and offset by offset
    /// ([`UniformLayout`](crate::UniformLayout)).
    pub fn uniform_struct<T: crate::UniformLayout>(
        &mut self,
        binding: &str,
        value: &T,
    ) -> UniformHandle {
        let handle = self.uniform(binding, bytemuck::bytes_of(value));
        self.graph.uniforms[handle.0].fields = Some(T::FIELDS);
        handle
    }

    /// Binds a sampler described by `desc` to the shader's `sampler` global `binding`;
    /// declaring it again replaces the description. Compile checks that the shader has that
    /// sampler, and that every sampler of the shader is declared. One wgpu sampler is made per
    /// distinct description, e.g. [`SamplerDesc::LINEAR_CLAMP`].
    pub fn sampler(&mut self, binding: &str, desc: SamplerDesc) -> &mut Self {
        let samplers = &mut self.decl().samplers;
        match samplers.binary_search_by(|s| s.binding.as_str().cmp(binding)) {
            Ok(i) => samplers[i].desc = desc,
            Err(i) => samplers.insert(
                i,
                SamplerUse {
                    binding: binding.to_string(),
                    desc,
                },
            ),
        }
        self
    }

    /// Runs one compute thread per texel of `handle` (at the mip this pass writes, if any).
    pub fn dispatch_over(&mut self, handle: TextureHandle) -> &mut Self {
        let size = self
            .graph
            .resources
            .get(handle.id as usize)
            .and_then(|r| r.texture_desc())
            .map(|d| d.size)
            .unwrap_or(SizeClass::FULL);
        let mip = self
            .decl()
            .textures
            .iter()
            .rev()
            .find(|u| u.resource() == handle.id as usize)
            .and_then(|u| u.mip)
            .unwrap_or(0);
        self.set_dispatch(Dispatch::Threads { size, mip })
    }
    /// Runs one compute thread per texel of a size class.
    pub fn dispatch_size(&mut self, size: SizeClass) -> &mut Self {
        let size = size.divided(self.size_divisor);
        self.set_dispatch(Dispatch::Threads { size, mip: 0 })
    }
    /// Explicit workgroup counts.
    pub fn dispatch_workgroups(&mut self, x: u32, y: u32, z: u32) -> &mut Self {
        self.set_dispatch(Dispatch::Workgroups([x, y, z]))
    }
    fn set_dispatch(&mut self, d: Dispatch) -> &mut Self {
        if let PassKind::Compute { dispatch, .. } = &mut self.decl().kind {
            *dispatch = Some(d);
        }
        self
    }
    /// States the texel loads one invocation of this pass makes (a thread of a compute pass, a
    /// fragment of a full-screen pass), for rooflines (`pass_costs`).
    pub fn loads_per_invocation(&mut self, loads: f32) -> &mut Self {
        self.decl().loads_per_invocation = Some(loads);
        self
    }
    /// Sets the shader's pipeline-overridable constant `name` (`override name: T = ...;` in the
    /// WGSL) for this pass; setting it again replaces the value. The value is compiled into the
    /// pipeline, so a loop bound the driver can unroll goes here rather than in a uniform; each
    /// distinct value is a pipeline of its own (cached). Compile checks that the shader declares
    /// the constant; a non-finite value is an error.
    pub fn constant(&mut self, name: &str, value: f64) -> &mut Self {
        if !value.is_finite() {
            let pass = self.decl().name.clone();
            self.graph.errors.push(GraphError::InvalidPass {
                pass,
                message: format!(
                    "pipeline constant `{name}` = {value}: a constant must be a finite number"
                ),
            });
            return self;
        }
        let constants = &mut self.decl().constants;
        match constants.binary_search_by(|c| c.name.as_str().cmp(name)) {
            Ok(i) => constants[i].value = value,
            Err(i) => constants.insert(
                i,
                PipelineConstant {
                    name: name.to_string(),
                    value,
                },
            ),
        }
        self
    }
    /// Keeps the pass even when no output depends on it.
    pub fn side_effect(&mut self) -> &mut Self {
        self.decl().side_effect = true;
        self
    }
}
