//! Input adapters: graph passes that turn an application's frame into the g-buffer channels a
//! technique reads, declared only for the channels it reads (shaders/embed/):
//!
//! - hardware depth to linear depth (`linear_depth.wgsl`), for every depth convention; linear
//!   depth given as such is read in place;
//! - the application's normals decoded to view space (`normals_decode.wgsl`), or normals rebuilt
//!   from depth where it has none (`normals_from_depth.wgsl`); the compact encoding
//!   (`normals_oct.wgsl`) where the technique reads that;
//! - view-space positions (`positions.wgsl`);
//! - the application's motion vectors to aograph's motion channel (`motion.wgsl`).
//!
//! With a viewport, the application's textures are larger than the output: every pass that
//! reads one reads at its pixel plus the viewport's corner (`VIEWPORT_IMPORT`, a uniform
//! written each frame, so a moving viewport needs no new plan), and linear depth given as such
//! is copied out of its rectangle (`linear_depth_crop.wgsl`). Without one the corner is (0, 0).
//!
//! Invariant: every channel produced has the format and conventions of aograph's own g-buffer
//! (aograph_frame::GBufferChannel), and the output's size, so a technique cannot tell the two
//! apart.

use aograph_frame::{GBufferChannel, GBufferChannels, GBufferTextures, ReadsView};
use aograph_graph::{
    BufferAccess, BufferDesc, BufferHandle, Extent, GraphBuilder, SizeClass, TextureDesc,
    TextureHandle,
};

use crate::inputs::{InputLayout, NormalSpace};

/// Imported resource names: one texture per name, the same in every plan. The application's
/// depth (or linear depth).
pub const DEPTH_IMPORT: &str = "embed.depth";
/// The application's normals.
pub const NORMALS_IMPORT: &str = "embed.normals";
/// The application's motion vectors.
pub const MOTION_IMPORT: &str = "embed.motion";
/// The texture the AO is written to.
pub const OUTPUT_IMPORT: &str = "embed.output";
/// The viewport's top-left corner in the input textures (`vec4<u32>`: x, y, 0, 0), written
/// every frame.
pub const VIEWPORT_IMPORT: &str = "embed.viewport";
/// The bytes of the [`VIEWPORT_IMPORT`] buffer.
pub const VIEWPORT_BYTES: u64 = 16;

/// Channels the adapters can produce from an application's frame.
pub fn producible(c: GBufferChannel) -> bool {
    matches!(
        c,
        GBufferChannel::LinearDepth
            | GBufferChannel::Normals
            | GBufferChannel::NormalsOct
            | GBufferChannel::Positions
            | GBufferChannel::Motion
    )
}

/// Declares the imports and the adapter passes for `wanted`; returns the channels as a
/// g-buffer (those not wanted are `None`).
pub fn declare_inputs(
    b: &mut GraphBuilder,
    layout: &InputLayout,
    wanted: GBufferChannels,
    view: BufferHandle,
) -> GBufferTextures {
    let full = |f| TextureDesc::new(f, SizeClass::FULL);
    // The application's textures: the output's size, or larger around a viewport.
    let given = |f| match layout.inputs_size {
        Some((w, h)) => TextureDesc::new(f, SizeClass::Fixed(Extent::new(w, h))),
        None => full(f),
    };
    let viewport = b.import_buffer(
        VIEWPORT_IMPORT,
        BufferDesc {
            size: VIEWPORT_BYTES,
        },
    );
    let mut g = GBufferTextures::default();
    let depth = b.import_texture(DEPTH_IMPORT, given(layout.depth_format));
    let linear_depth = if layout.linear_depth_given() && layout.inputs_size.is_none() {
        depth
    } else if layout.linear_depth_given() {
        let out = b.create_texture(
            "embed.linear_depth",
            full(GBufferChannel::LinearDepth.format()),
        );
        let mut p = b.compute_pass(
            "embed.linear_depth_crop",
            "embed/linear_depth_crop.wgsl",
            "main",
        );
        p.sample("depth", depth)
            .read_buffer("viewport", BufferAccess::Uniform, viewport);
        let out = p.write_storage("linear_depth", out);
        p.dispatch_over(out);
        out
    } else {
        let out = b.create_texture(
            "embed.linear_depth",
            full(GBufferChannel::LinearDepth.format()),
        );
        let mut p = b.compute_pass("embed.linear_depth", "embed/linear_depth.wgsl", "main");
        p.sample("depth", depth)
            .read_buffer("viewport", BufferAccess::Uniform, viewport);
        p.read_view(view);
        let out = p.write_storage("linear_depth", out);
        p.dispatch_over(out);
        out
    };
    g.linear_depth = Some(linear_depth);

    if wanted.has_normals() {
        let normals = b.create_texture("embed.normals", full(GBufferChannel::Normals.format()));
        let normals = match layout.normals {
            Some((format, space, encoding)) => {
                let given = b.import_texture(NORMALS_IMPORT, given(format));
                let mut p =
                    b.compute_pass("embed.normals_decode", "embed/normals_decode.wgsl", "main");
                p.sample("normals_in", given)
                    .sample("linear_depth", linear_depth)
                    .read_buffer("viewport", BufferAccess::Uniform, viewport);
                p.read_view(view);
                p.constant("ENCODING", encoding.shader_constant());
                p.constant("WORLD_SPACE", (space == NormalSpace::World) as u32 as f64);
                let out = p.write_storage("normals", normals);
                p.dispatch_over(out);
                out
            }
            None => {
                let mut p = b.compute_pass(
                    "embed.normals_from_depth",
                    "embed/normals_from_depth.wgsl",
                    "main",
                );
                p.sample("linear_depth", linear_depth);
                p.read_view(view);
                let out = p.write_storage("normals", normals);
                p.dispatch_over(out);
                out
            }
        };
        if wanted.contains(GBufferChannel::Normals) {
            g.normals = Some(normals);
        }
        if wanted.contains(GBufferChannel::NormalsOct) {
            let oct = b.create_texture(
                "embed.normals_oct",
                full(GBufferChannel::NormalsOct.format()),
            );
            let mut p = b.compute_pass("embed.normals_oct", "embed/normals_oct.wgsl", "main");
            p.sample("normals", normals);
            let out = p.write_storage("normals_oct", oct);
            p.dispatch_over(out);
            g.normals_oct = Some(out);
        }
    }

    if wanted.contains(GBufferChannel::Positions) {
        let out = b.create_texture("embed.positions", full(GBufferChannel::Positions.format()));
        let mut p = b.compute_pass("embed.positions", "embed/positions.wgsl", "main");
        p.sample("linear_depth", linear_depth);
        p.read_view(view);
        let out = p.write_storage("positions", out);
        p.dispatch_over(out);
        g.positions = Some(out);
    }

    // Without the application's motion the channel stays empty: techniques then reproject
    // through the view matrices (a static scene), as with aograph's own g-buffer.
    if let (true, Some((format, scale_bits))) =
        (wanted.contains(GBufferChannel::Motion), layout.motion)
    {
        let given = b.import_texture(MOTION_IMPORT, given(format));
        let out = b.create_texture("embed.motion", full(GBufferChannel::Motion.format()));
        let mut p = b.compute_pass("embed.motion", "embed/motion.wgsl", "main");
        p.sample("motion_in", given)
            .sample("linear_depth", linear_depth)
            .read_buffer("viewport", BufferAccess::Uniform, viewport);
        p.read_view(view);
        let scale = scale_bits.map(f32::from_bits);
        let bytes: Vec<u8> = [scale[0], scale[1], 0.0, 0.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        p.uniform("uv_scale", &bytes);
        let out = p.write_storage("motion", out);
        p.dispatch_over(out);
        g.motion = Some(out);
    }
    g
}

/// Declares the pass writing `accessibility` into the imported output texture of `format`.
pub fn declare_output(
    b: &mut GraphBuilder,
    accessibility: TextureHandle,
    format: wgpu::TextureFormat,
) -> TextureHandle {
    let target = b.import_texture(OUTPUT_IMPORT, TextureDesc::new(format, SizeClass::FULL));
    let mut p = b.fullscreen_pass("embed.output", "embed/output.wgsl", "vs", "fs");
    p.sample("ao", accessibility);
    let out = p.color_target(
        target,
        aograph_graph::ColorTarget::clear([1.0, 0.0, 0.0, 1.0]),
    );
    b.export(out);
    out
}
