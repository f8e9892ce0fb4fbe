//! aograph's render graph: declare resources and passes, compile them into a plan (pure, no
//! GPU: order, culling, lifetimes, reuse, cached by hash), and execute the plan on wgpu with a
//! texture pool, history resources and per-pass timing.
//!
//! ```text
//! GraphBuilder --build--> GraphDecl --GraphCompiler::compile--> CompiledGraph --Executor::execute--> GPU
//! ```
//!
//! Declaring and compiling need no GPU, so a graph can be checked in a unit test. Here one
//! compute pass fills a half-resolution texture that the graph exports; a second pass whose
//! output nothing needs is culled:
//!
//! ```
//! use aograph_graph::{
//!     CompileOptions, GraphBuilder, ShaderLibrary, SizeClass, TextureDesc, compile, wgpu,
//! };
//!
//! let shaders = ShaderLibrary::inline_only();
//! shaders.add_inline(
//!     "fill.wgsl",
//!     "@group(0) @binding(0) var dst: texture_storage_2d<r32float, write>;
//!      @compute @workgroup_size(8, 8)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          let size = textureDimensions(dst);
//!          if (id.x >= size.x || id.y >= size.y) { return; }
//!          textureStore(dst, vec2<i32>(id.xy), vec4<f32>(1.0));
//!      }",
//! );
//!
//! let mut graph = GraphBuilder::new();
//! let desc = TextureDesc::new(wgpu::TextureFormat::R32Float, SizeClass::half_pow(1));
//! let ao = graph.create_texture("ao", desc);
//! let mut fill = graph.compute_pass("fill", "fill.wgsl", "main");
//! let ao = fill.write_storage("dst", ao);
//! fill.dispatch_over(ao);
//! graph.export(ao);
//!
//! let unused = graph.create_texture("unused", desc);
//! let mut extra = graph.compute_pass("extra", "fill.wgsl", "main");
//! let unused = extra.write_storage("dst", unused);
//! extra.dispatch_over(unused);
//!
//! let plan = compile(graph.build(), &shaders, CompileOptions::default())?;
//! assert_eq!(plan.pass_names(), ["fill"]);
//! assert_eq!(plan.culled_names(), ["extra"]);
//! # Ok::<(), aograph_graph::GraphError>(())
//! ```

#![warn(missing_docs)]

mod attachment;
mod bind;
mod binding_slots;
mod builder;
mod compile;
mod cost;
mod custom;
mod declaration;
mod device_fit;
mod dot;
mod error;
mod execute;
mod gpu;
mod history;
mod history_slots;
mod imports;
mod lifetime;
mod name_lookups;
mod nearest_name;
mod pass_builder;
mod pipeline;
mod plain_texture;
mod plan_state;
mod pool;
mod readback;
mod record;
mod resource;
mod sampler;
mod shader;
mod shader_check;
mod structure_hash;
mod summary;
mod timing;
mod uniform_layout;
mod uses;

pub use attachment::{AttachmentOps, ColorTarget, DepthTarget, LoadOp};
pub use binding_slots::{BindingSlot, BindingSource};
pub use builder::{GraphBuilder, HistoryTexture};
pub use compile::{CompileOptions, CompiledGraph, CulledPass, GraphCompiler, PlanKey, compile};
pub use cost::{PassCost, pass_costs};
pub use custom::{BoundTexture, CustomPass, NoopPass, PassContext};
pub use declaration::{
    Dispatch, GraphDecl, PassDecl, PassId, PassKind, PipelineConstant, ResourceDecl, ResourceKind,
    ResourceOrigin, UniformDecl, UniformHandle,
};
pub use device_fit::{DeviceProfile, check_plan};
pub use dot::to_dot;
pub use error::{GraphError, GraphResult};
pub use execute::Executor;
pub use gpu::{GpuContext, test_gpu};
pub use history_slots::HistorySlot;
pub use lifetime::{Lifetime, PhysicalTexture, texture_bytes};
pub use name_lookups::name_lookup_count;
pub use nearest_name::{did_you_mean, nearest_name};
pub use pass_builder::PassBuilder;
pub use plain_texture::plain_texture;
pub use pool::PoolKey;
pub use readback::{TextureReadback, read_texture};
pub use resource::{
    AccelerationStructure, AccelerationStructureHandle, Buffer, BufferAccess, BufferDesc,
    BufferHandle, Extent, Handle, SizeClass, Texture, TextureAccess, TextureDesc, TextureHandle,
    centred_step, texel_bytes,
};
pub use sampler::SamplerDesc;
pub use shader::{
    IncludeVariant, ShaderBinding, ShaderBindingKind, ShaderEntry, ShaderLibrary, ShaderModuleInfo,
    ShaderMount, ShaderOverride, ShaderRevision, StructMember, shader_variant,
    storage_precision_variant,
};
pub use summary::summary;
pub use timing::{FrameId, PassTimings, TimingMode, TimingSource};
#[doc(hidden)]
pub use uniform_layout::field_size as uniform_field_size;
pub use uniform_layout::{UniformField, UniformLayout, uniform_layout_mismatch};
pub use uses::{BufferUse, SamplerUse, TextureUse};
pub use wgpu;
