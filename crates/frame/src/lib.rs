//! What the g-buffer node (aograph-scene) and the AO techniques (aograph-ao) share, on top of
//! the render graph, without depending on each other: the g-buffer's channels (a technique
//! states which it reads; the g-buffer writes only those), the per-frame `View` uniform block
//! every pass may bind, the compact normal encoding's CPU side ([`normal_oct`]), and the precision of AO intermediates (a shader variant the graph
//! offers generically: see [`intermediate_shader`]).
//!
//! `aograph-graph` knows none of this: it is a render graph, not an AO renderer.

mod channels;
pub mod normal_oct;
mod precision;
mod view;

pub use channels::{DepthFormat, GBufferChannel, GBufferChannels, GBufferTextures};
pub use precision::{INTERMEDIATE_ALIAS, intermediate_shader};
pub use view::{Mat4Cols, ReadsView, VIEW_BINDING, VIEW_BUFFER, ViewUniforms};
