//! What the g-buffer node (aograph-scene) and the AO techniques (aograph-ao) share, on top of
//! the render graph, without depending on each other: the g-buffer's channels (a technique
//! states which it reads; the g-buffer writes only those), the frame inputs (the per-frame `View`
//! block every pass may bind, the scene's lighting block and ray-tracing BVH a technique
//! declares when it reads them), the compact normal encoding's CPU side ([`normal_oct`]), and the precision of AO
//! intermediates (a shader variant the graph offers generically: see [`intermediate_shader`]).
//!
//! `aograph-graph` knows none of this: it is a render graph, not an AO renderer.

mod channels;
mod lighting;
pub mod normal_oct;
mod precision;
mod scene_bvh;
mod view;

pub use channels::{DepthFormat, GBufferChannel, GBufferChannels, GBufferTextures};
pub use lighting::{LIGHTING_BUFFER, LightingUniforms, SkyColours};
pub use precision::{INTERMEDIATE_ALIAS, intermediate_shader};
pub use scene_bvh::{BVH_INSTANCES_BUFFER, BVH_NODES_BUFFER, BVH_TRIANGLES_BUFFER, SceneBvhInputs};
pub use view::{Mat4Cols, ReadsView, VIEW_BINDING, VIEW_BUFFER, ViewMatrices, ViewUniforms};
