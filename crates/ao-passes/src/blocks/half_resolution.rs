//! Half resolution: the g-buffer and view block a technique reads when it runs at half the
//! output size (`resolution = "half"`, crate::Resolution), built from the full-size ones.
//!
//! Passes, under `<prefix>` (e.g. `gtao.half`):
//! - `<prefix>.view` (shaders/blocks/half_view.wgsl): the frame's view block with `size`
//!   halved and `inv_size` doubled, so half texel p's centre is full pixel corner 2p + 1, the
//!   centre of its 2x2 block, and a projected radius halves in pixels;
//! - `<prefix>.select` (shaders/blocks/half_gbuffer/select.wgsl): per half texel, the 2x2
//!   block's nearest surface, its depth moved to the block's centre along its tangent plane
//!   (a plane stays on itself), its normal, and which sample it was;
//! - `<prefix>.normals_oct`, `<prefix>.motion`, `<prefix>.positions` (gather_*.wgsl): the same
//!   sample's octahedral normal, motion and view-space position, where the g-buffer has them
//!   (a pass nobody reads is culled). The position is the sample's own, on its surface (not
//!   moved to the block's centre): a ray traced from it (`rtao`) starts on the surface even
//!   where the plane move falls back, at a grazing angle near the horizon, and the depth does
//!   not lie on the surface at the centre.
//!
//! Invariant: every half texture has the size class of the full channel divided by 2 (ceil:
//! an odd size's last half texel covers one column or row), which is what
//! [`fn@super::bilateral_upsample`] expects of its low-resolution inputs.

use aograph_frame::{GBufferChannel, GBufferTextures, ReadsView, ViewUniforms};
use aograph_graph::{BufferDesc, BufferHandle, GraphBuilder, SizeClass, TextureDesc};

use crate::error::{AoError, AoResult};

/// The channels a half-resolution g-buffer holds (the rest are not downsampled).
pub const HALF_CHANNELS: [GBufferChannel; 5] = [
    GBufferChannel::LinearDepth,
    GBufferChannel::Normals,
    GBufferChannel::NormalsOct,
    GBufferChannel::Motion,
    GBufferChannel::Positions,
];

/// A half-resolution g-buffer and its view block.
#[derive(Clone, Copy, Debug)]
pub struct HalfGBuffer {
    /// Linear depth, normals, and octahedral normals and motion where the full g-buffer has
    /// them, all at half size.
    pub gbuffer: GBufferTextures,
    /// The view block of the half-size image (a buffer the graph writes).
    pub view: BufferHandle,
    /// The half linear depth (also in `gbuffer`), which every half g-buffer has.
    pub depth: aograph_graph::TextureHandle,
    /// The half view-space normals (also in `gbuffer`), which every half g-buffer has.
    pub normals: aograph_graph::TextureHandle,
}

fn channel(
    gbuffer: &GBufferTextures,
    prefix: &str,
    c: GBufferChannel,
) -> AoResult<aograph_graph::TextureHandle> {
    gbuffer.get(c).ok_or_else(|| AoError::MissingChannel {
        technique: prefix.into(),
        channel: c.name().into(),
    })
}

/// Declares the half-resolution g-buffer of `gbuffer` (linear depth and normals required)
/// and its view block. Call it at the builder's full-size divisor: the textures it creates
/// are half of that.
pub fn half_gbuffer(
    b: &mut GraphBuilder,
    prefix: &str,
    gbuffer: &GBufferTextures,
    view: BufferHandle,
) -> AoResult<HalfGBuffer> {
    let depth = channel(gbuffer, prefix, GBufferChannel::LinearDepth)?;
    let normals = channel(gbuffer, prefix, GBufferChannel::Normals)?;
    let half = SizeClass::half_pow(1);
    let tex = |b: &mut GraphBuilder, name: &str, c: GBufferChannel| {
        b.create_texture(
            &format!("{prefix}.{name}"),
            TextureDesc::new(c.format(), half),
        )
    };

    let half_view = b.create_buffer(
        &format!("{prefix}.view"),
        BufferDesc {
            size: std::mem::size_of::<ViewUniforms>() as u64,
        },
    );
    let mut pass = b.compute_pass(&format!("{prefix}.view"), "blocks/half_view.wgsl", "main");
    pass.read_view(view);
    let half_view = pass.write_buffer("half_view", half_view);
    pass.dispatch_workgroups(1, 1, 1);

    let half_depth = tex(b, "linear_depth", GBufferChannel::LinearDepth);
    let half_normals = tex(b, "normals", GBufferChannel::Normals);
    let choice = b.create_texture(
        &format!("{prefix}.choice"),
        TextureDesc::new(wgpu::TextureFormat::R32Uint, half),
    );
    let mut pass = b.compute_pass(
        &format!("{prefix}.select"),
        "blocks/half_gbuffer/select.wgsl",
        "main",
    );
    pass.read_view(view);
    pass.sample("depth", depth).sample("normals", normals);
    // Four depths, then the kept sample's normal.
    pass.loads_per_invocation(5.0);
    let half_depth = pass.write_storage("half_depth", half_depth);
    let half_normals = pass.write_storage("half_normals", half_normals);
    let choice = pass.write_storage("choice", choice);
    pass.dispatch_over(half_depth);

    let mut out = GBufferTextures {
        linear_depth: Some(half_depth),
        normals: Some(half_normals),
        ..GBufferTextures::default()
    };
    let gathers = [
        (
            GBufferChannel::NormalsOct,
            "normals_oct",
            "blocks/half_gbuffer/gather_oct.wgsl",
        ),
        (
            GBufferChannel::Motion,
            "motion",
            "blocks/half_gbuffer/gather_rgba32f.wgsl",
        ),
        (
            GBufferChannel::Positions,
            "positions",
            "blocks/half_gbuffer/gather_rgba32f.wgsl",
        ),
    ];
    for (c, name, shader) in gathers {
        let Some(src) = gbuffer.get(c) else { continue };
        let dst = tex(b, name, c);
        let mut pass = b.compute_pass(&format!("{prefix}.{name}"), shader, "main");
        pass.sample("src", src).sample("choice", choice);
        pass.loads_per_invocation(2.0);
        let dst = pass.write_storage("dst", dst);
        pass.dispatch_over(dst);
        match c {
            GBufferChannel::NormalsOct => out.normals_oct = Some(dst),
            GBufferChannel::Motion => out.motion = Some(dst),
            _ => out.positions = Some(dst),
        }
    }
    Ok(HalfGBuffer {
        gbuffer: out,
        view: half_view,
        depth: half_depth,
        normals: half_normals,
    })
}
