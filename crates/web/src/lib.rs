//! aograph's ambient occlusion in a web page, on the browser's WebGPU.
//!
//! The page is an application with its own renderer, as examples/own_renderer is: it draws a
//! procedural scene's triangles into its own reversed-Z depth buffer and world-space normals
//! ([`PageRenderer`]), hands both to `aograph_embed::AmbientOcclusion`, and shades the canvas
//! with the AO. Techniques and their parameters change live; the page's controls are generated
//! from the techniques' parameter descriptions ([`technique_catalogue`]).
//!
//! Everything but the browser glue (`page.rs`, wasm32 only) is target-independent: the native
//! example `native_ao` runs the same frames on a native device, which is how the browser test
//! (scripts/web-test.sh) checks the page's AO against aograph-embed's native result.
//!
//! Invariant: nothing is read from a file system; the WGSL of the page's own passes is
//! compiled in (shaders/web/, [`shader_mount`]) as aograph's is.

#![warn(missing_docs)]

mod ao_page;
mod catalogue;
mod page_renderer;
mod scene_mesh;

#[cfg(target_arch = "wasm32")]
mod page;

pub use ao_page::{AoPage, PageError, ao_mean, ao_values};
pub use catalogue::technique_catalogue;
pub use page_renderer::{OFFSCREEN_FORMAT, PageRenderer, offscreen_target};
pub use scene_mesh::{SceneMesh, Vertex};

/// The page's own WGSL (shaders/web/) as an `aograph_graph::ShaderMount`, so that
/// tests validate it with naga beside aograph's.
pub fn shader_mount() -> aograph_graph::ShaderMount {
    aograph_graph::ShaderMount::new("aograph-web")
        .with_files(aograph_shaders::folder("web").unwrap_or_default())
}

/// The text of `path` (relative to shaders/, "web/prepass.wgsl"), compiled in.
pub(crate) fn shader_source(path: &str) -> &'static str {
    aograph_shaders::folder("web")
        .unwrap_or_default()
        .iter()
        .find(|(p, _)| *p == path)
        .map_or("", |(_, s)| *s)
}
