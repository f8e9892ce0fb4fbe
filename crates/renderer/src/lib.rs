//! aograph's own renderer: the frame graph it renders on a scene (the `View` block, the
//! g-buffer with only the channels the technique reads, the AO technique, optionally the
//! shading pass), a [`Renderer`] that renders frames of it on demand and swaps techniques live
//! (one executor, every plan kept), and the ray-traced reference of the same frames
//! ([`frame_reference()`]).
//!
//! Layers: `aograph-graph` (declare, compile, execute), `aograph-frame` (channels, View
//! block), `aograph-ao-passes` (techniques), `aograph-scene` (scenes, g-buffer node, tracers), this
//! crate (a scene's frames), then the `aograph` CLI (config files, commands, bench, viewer) on
//! top. An application with its own renderer wants `aograph-embed` instead, which needs no
//! scene.
//!
//! ```no_run
//! use std::sync::Arc;
//! use aograph_ao_passes::{AoConfig, TechniqueRegistry};
//! use aograph_graph::{Extent, GpuContext};
//! use aograph_renderer::{FrameOutputs, Renderer, shader_library};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let gpu = Arc::new(GpuContext::new()?);
//! let scene = Arc::new(aograph_scene::procedural_scene("columns")?);
//! let registry = TechniqueRegistry::with_builtins();
//! let ao = AoConfig { technique: "gtao".into(), ..AoConfig::default() };
//! let mut renderer = Renderer::new(gpu, shader_library(), &registry, scene, &ao,
//!                                  FrameOutputs::default(), Extent::new(320, 180))?;
//! renderer.render(0.0)?;
//! let accessibility: Vec<f32> = renderer.read_ao()?;   // row-major, 1 = unoccluded
//! # Ok(()) }
//! ```

#![warn(missing_docs)]

mod error;
pub mod frame_graph;
pub mod frame_reference;
pub mod gbuffer;
mod output_size;
pub mod pass_owner;
mod readback;
pub mod renderer;
mod scene_radius;
mod scene_tracing;
mod shader_mount;

pub use error::{RenderError, RenderResult};
pub use frame_graph::{
    FrameGraph, FrameOutputs, build_frame_graph, build_frame_graph_with, build_gbuffer_graph,
};
pub use frame_reference::{FrameView, ReferenceSettings, frame_reference};
pub use output_size::{MAX_SIDE, check_size};
pub use pass_owner::{PassOwner, PassOwners};
pub use renderer::{GraphExtension, Renderer};
pub use scene_radius::{resolve_radius, short};
pub use shader_mount::{renderer_mounts, shader_library, shader_mount};
