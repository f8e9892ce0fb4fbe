//! aograph's ambient occlusion in an application's own wgpu renderer.
//!
//! This crate is the embedding layer: it owns no window, scene or g-buffer. The application
//! hands over its depth buffer (Depth32Float, Depth24Plus, Depth16Unorm, or linear depth) and
//! the projection it rendered with, optionally its normals (view or world space, in one of four
//! encodings) and motion vectors; input adapters (graph passes declared only when needed) turn
//! them into the channels aograph's techniques read, and the chosen technique runs in the
//! application's command encoder. Techniques and parameters change at run time without new
//! pipelines for settings seen before.
//!
//! Layers: `aograph-graph` (the frame graph: declare, compile, execute), `aograph-frame` (the
//! view block and g-buffer channels), `aograph-ao-passes` (the techniques), this crate (the
//! application's frame in, AO out). aograph's own renderer, scenes, reference and tools are in
//! other crates; none of them is a dependency here.
//!
//! ```no_run
//! use aograph_embed::{AmbientOcclusion, AoInputs, DepthInput};
//! # fn frame(adapter: &wgpu::Adapter, device: &wgpu::Device, queue: &wgpu::Queue,
//! #          depth: &wgpu::Texture, projection: glam::Mat4, view: glam::Mat4)
//! #          -> Result<(), aograph_embed::EmbedError> {
//! // Once: a technique by name, with R in the application's world units.
//! let mut ao = AmbientOcclusion::from_toml(adapter, device, queue, r#"
//!     technique = "gtao"
//!     radius = 0.5
//! "#)?;
//! // Every frame, after the depth pre-pass: record AO into the frame's encoder.
//! let mut encoder = device.create_command_encoder(&Default::default());
//! let out = ao.encode(&mut encoder, &AoInputs::new(DepthInput::Hardware(depth), projection, view))?;
//! // ... bind `out.view` in the lighting pass, multiply it into ambient light ...
//! queue.submit([encoder.finish()]);
//! // Any time: another technique (its plan is kept; switching back builds nothing).
//! ao.set_config_toml("technique = \"mssao\"\nradius = 0.5")?;
//! # Ok(()) }
//! ```

#![warn(missing_docs)]

mod adapters;
mod ambient_occlusion;
mod error;
mod inputs;
mod output;
mod projection;
mod settings;
mod shader_mount;

pub use adapters::{
    DEPTH_IMPORT, MOTION_IMPORT, NORMALS_IMPORT, OUTPUT_IMPORT, VIEWPORT_BYTES, VIEWPORT_IMPORT,
    declare_inputs, declare_output, producible,
};
pub use ambient_occlusion::AmbientOcclusion;
pub use error::{EmbedError, EmbedResult};
pub use inputs::{
    AoInputs, DepthInput, HARDWARE_DEPTH_FORMATS, InputLayout, MotionInput, NormalEncoding,
    NormalSpace, NormalsInput, Viewport,
};
pub use output::{AoOutputFormat, AoOutputView, OUTPUT_USAGE};
pub use projection::DepthConvention;
pub use settings::{check_settings_toml, feedable_techniques};
pub use shader_mount::{shader_library, shader_mount};

/// The `[ao]` settings type (technique, radius, per-technique tables), re-exported.
pub use aograph_ao_passes::AoConfig;
