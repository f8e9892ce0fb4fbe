//! XeGTAO's edge-aware denoiser (docs/techniques/gtao.md §6): 1 to 3 passes of a 3x3 filter whose
//! weights come from per-pixel depth-edge weights (left, right, top, bottom) written by the AO
//! pass that precedes it (gtao writes them; any technique can, with
//! shaders/common/edges.wgsl). Passes `<prefix>.denoise<k>`, k = 1..passes; 1 pass is
//! XeGTAO's "sharp" default, 2 "medium" (its auto-tune's choice), 3 "soft".
//!
//! Per pass (shaders/blocks/edge_denoise.wgsl): symmetrised edges, XeGTAO's leak, diagonal
//! weights 0.425 x the edge products along their L-shaped paths, the centre weighted by the
//! blur beta: 1.2 on the last pass and 1.2 / 5 on earlier ones (XeGTAO's DenoiseBlurBeta).
//!
//! Invariant: the output is R32Float at the input's size, a convex combination of input values
//! at every non-sky pixel, clamped to [0, 1] on the last pass (the input may exceed 1: gtao's
//! per-pixel estimate is averaged before it is clamped, spec §12), exactly 1 on sky; a constant
//! stays constant; no weight crosses a pixel whose edge weight towards it is 0 except through
//! the leak, and sky is never a tap. Earlier passes' textures have the caller's intermediate
//! format.

use aograph_frame::intermediate_shader;
use aograph_graph::{GraphBuilder, TextureDesc, TextureHandle};
use bytemuck::{Pod, Zeroable};

use super::{BLOCK_FORMAT, check_intermediate, desc_of, invalid};
use crate::error::AoResult;

/// Most denoise passes (XeGTAO's "soft").
pub const MAX_DENOISE_PASSES: u32 = 3;

/// Parameters of the edge-aware denoiser.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeDenoise {
    /// Passes, 1 to 3.
    pub passes: u32,
    /// Centre weight of the last pass (XeGTAO: 1.2); earlier passes use a fifth of it.
    pub blur_beta: f32,
}

impl Default for EdgeDenoise {
    /// XeGTAO's defaults: 1 pass, blur beta 1.2.
    fn default() -> Self {
        Self {
            passes: 1,
            blur_beta: 1.2,
        }
    }
}

/// The `params` uniform of shaders/blocks/edge_denoise.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct DenoiseUniform {
    /// Blur beta (centre weight).
    beta: f32,
    /// 1.0 on the last pass, 0.0 before.
    last_pass: f32,
    _pad0: f32,
    _pad1: f32,
}

aograph_graph::uniform_layout!(DenoiseUniform {
    beta,
    last_pass,
    _pad0,
    _pad1
});

/// Adds the denoise passes over `ao` (raw accessibility), guided by `edges` (Rgba8Unorm,
/// from the AO pass) and `depth` (linear, 0 = sky); returns the last pass's R32Float output.
/// Earlier passes write `intermediate` (R32Float or R16Float).
pub fn edge_denoise(
    b: &mut GraphBuilder,
    prefix: &str,
    ao: TextureHandle,
    edges: TextureHandle,
    depth: TextureHandle,
    params: &EdgeDenoise,
    intermediate: wgpu::TextureFormat,
) -> AoResult<TextureHandle> {
    if !(1..=MAX_DENOISE_PASSES).contains(&params.passes) {
        return Err(invalid(
            prefix,
            "denoise_passes",
            params.passes,
            format!("1 to {MAX_DENOISE_PASSES}"),
        ));
    }
    if !(params.blur_beta.is_finite() && params.blur_beta > 0.0 && params.blur_beta <= 1e4) {
        return Err(invalid(
            prefix,
            "blur_beta",
            params.blur_beta,
            "greater than 0 and at most 10000",
        ));
    }
    check_intermediate(prefix, intermediate)?;
    let size = desc_of(b, prefix, "input", ao)?.size;
    let mut src = ao;
    for k in 1..=params.passes {
        let last = k == params.passes;
        let format = if last { BLOCK_FORMAT } else { intermediate };
        let name = format!("{prefix}.denoise{k}");
        let out = b.create_texture(&name, TextureDesc::new(format, size));
        let shader = intermediate_shader("blocks/edge_denoise.wgsl", format);
        let beta = if last {
            params.blur_beta
        } else {
            params.blur_beta / 5.0
        };
        let uniform = DenoiseUniform {
            beta,
            last_pass: last as u32 as f32,
            _pad0: 0.0,
            _pad1: 0.0,
        };
        let mut p = b.compute_pass(&name, &shader, "main");
        p.sample("src", src)
            .sample("edges", edges)
            .sample("depth", depth);
        p.uniform_struct("params", &uniform);
        // Centre depth and AO, 5 edge texels, 8 neighbours' depth and AO.
        p.loads_per_invocation(23.0);
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        src = out;
    }
    Ok(src)
}

/// XeGTAO's edge weight of one neighbour (CPU mirror of shaders/common/edges.wgsl, before
/// quantisation): `delta` = z_neighbour - z_centre after slope compensation.
pub fn edge_weight(delta: f32, centre_z: f32) -> f32 {
    (1.25 - delta.abs() / (centre_z * 0.011)).clamp(0.0, 1.0)
}
