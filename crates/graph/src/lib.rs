//! aograph's render graph: declare resources and passes, compile them into a plan (pure, no
//! GPU: order, culling, lifetimes, reuse, cached by hash), and execute the plan on wgpu with a
//! texture pool, history resources and per-pass timing.
//!
//! ```text
//! GraphBuilder --build--> GraphDecl --GraphCompiler::compile--> CompiledGraph --Executor::execute--> GPU
//! ```

mod attachment;
mod bind;
mod binding_slots;
mod builder;
mod compile;
mod cost;
mod custom;
mod declaration;
mod dot;
mod error;
mod execute;
mod gpu;
mod history;
mod imports;
mod lifetime;
mod nearest_name;
mod pass_builder;
mod pipeline;
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
pub use dot::to_dot;
pub use error::{GraphError, GraphResult};
pub use execute::Executor;
pub use gpu::{GpuContext, test_gpu};
pub use lifetime::{Lifetime, PhysicalTexture, texture_bytes};
pub use nearest_name::{did_you_mean, nearest_name};
pub use pass_builder::PassBuilder;
pub use pool::PoolKey;
pub use readback::{TextureReadback, read_texture};
pub use resource::{
    Buffer, BufferAccess, BufferDesc, BufferHandle, Extent, Handle, SizeClass, Texture,
    TextureAccess, TextureDesc, TextureHandle, centred_step, texel_bytes,
};
pub use sampler::SamplerDesc;
pub use shader::{
    ShaderBinding, ShaderBindingKind, ShaderEntry, ShaderLibrary, ShaderModuleInfo, ShaderOverride,
    storage_precision_variant,
};
pub use summary::summary;
pub use timing::{FrameId, PassTimings, TimingMode, TimingSource};
pub use uses::{BufferUse, SamplerUse, TextureUse};
pub use wgpu;
