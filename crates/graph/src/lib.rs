//! aograph's render graph: declare resources and passes, compile them into a plan (pure, no
//! GPU: order, culling, lifetimes, reuse, cached by hash), and execute the plan on wgpu with a
//! texture pool, history resources and per-pass timing.
//!
//! ```text
//! GraphBuilder --build--> GraphDecl --GraphCompiler::compile--> CompiledGraph --Executor::execute--> GPU
//! ```

mod builder;
mod compile;
mod custom;
mod declaration;
mod dot;
mod error;
mod execute;
mod gbuffer_channels;
mod gpu;
mod history;
mod lifetime;
mod pipeline;
mod plugin;
mod pool;
mod readback;
mod resource;
mod shader;
mod shader_check;
mod summary;
mod timing;
mod view;

pub use builder::{GraphBuilder, HistoryTexture, PassBuilder};
pub use compile::{compile, CompileOptions, CompiledGraph, CulledPass, GraphCompiler};
pub use custom::{BoundTexture, CustomPass, NoopPass, PassContext};
pub use declaration::{BufferUse, Dispatch, GraphDecl, PassDecl, PassId, PassKind, ResourceDecl, ResourceKind, ResourceOrigin, TextureUse, UniformDecl, UniformHandle};
pub use dot::to_dot;
pub use error::{GraphError, GraphResult};
pub use execute::Executor;
pub use gbuffer_channels::{DepthFormat, GBufferChannel, GBufferChannels, GBufferTextures};
pub use gpu::{test_gpu, GpuContext};
pub use lifetime::{texture_bytes, Lifetime, PhysicalTexture};
pub use plugin::{check_range, parse_params, GraphConfig, GraphPlugin, OutputConfig, ParamSpec, PluginConfig, PluginIo, PluginRegistry};
pub use pool::PoolKey;
pub use readback::{read_texture, TextureReadback};
pub use resource::{texel_bytes, Buffer, BufferAccess, BufferDesc, BufferHandle, Extent, Handle, SizeClass, Texture, TextureAccess, TextureDesc, TextureHandle};
pub use shader::{intermediate_variant, ShaderBinding, ShaderBindingKind, ShaderEntry, ShaderLibrary, ShaderModuleInfo, INTERMEDIATE_ALIAS};
pub use summary::summary;
pub use timing::{PassTimings, TimingSource};
pub use view::{Mat4Cols, ViewUniforms, VIEW_BUFFER};
pub use wgpu;
