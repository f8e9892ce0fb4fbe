//! Shared AO building blocks (subgraphs any technique composes): the linear-depth pyramid and
//! XeGTAO's depth prefilter, separable Gaussian and bilateral blurs, XeGTAO's edge-aware
//! denoiser, a history-aware denoiser for accumulated ray-traced AO (`history_denoise`),
//! bilateral upsampling, and temporal reprojection and accumulation (`temporal`,
//! documented in its own module).
//!
//! Each block is one function that adds its passes to a [`GraphBuilder`] and returns the
//! handles it wrote. Pass and texture names are `<prefix>.<pass>` with the caller's prefix
//! (a technique passes its own name, so its plan reads `hbao.blur_x`, `mssao.depth_level2`).
//!
//! Invariants every block keeps:
//! - every single-channel texture a block creates is R32Float ([`BLOCK_FORMAT`]): its shaders
//!   write r32float storage textures, the only single-channel float storage format core wgpu
//!   guarantees (the temporal block's history is Rgba32Float, see its docs). The one exception
//!   is a separable blur's first-axis texture, which a technique may ask for at its
//!   intermediate precision (`gaussian_blur_with_intermediate`,
//!   `bilateral_blur_with_intermediate`: R16Float through the shaders' r16float variants);
//! - sizes are declared as size classes derived from the input's, never computed by hand;
//! - linear depth 0 marks sky; blocks that read depth write accessibility 1 on sky pixels and
//!   treat sky taps as absent; nothing writes NaN or infinity (every division has a non-zero
//!   denominator by construction).

use aograph_frame::intermediate_shader;
use aograph_graph::{Extent, GraphBuilder, SizeClass, TextureDesc, TextureHandle};

use crate::error::{AoError, AoResult};

pub mod bilateral_blur;
pub mod bilateral_upsample;
pub mod depth_prefilter;
pub mod depth_pyramid;
pub mod edge_denoise;
pub mod gaussian_blur;
pub mod half_resolution;
pub mod history_denoise;
pub mod temporal;

#[cfg(test)]
mod tests;

pub use bilateral_blur::{BilateralBlur, bilateral_blur, bilateral_blur_with_intermediate};
pub use bilateral_upsample::{BilateralUpsample, UpsampleInputs, bilateral_upsample};
pub use depth_prefilter::depth_prefilter;
pub use depth_pyramid::{DepthPyramid, DepthReduction, depth_pyramid};
pub use edge_denoise::{EdgeDenoise, edge_denoise};
pub use gaussian_blur::{
    GaussianBlur, gaussian_blur, gaussian_blur_with_intermediate, gaussian_weights,
};
pub use history_denoise::{HistoryDenoise, HistoryDenoiseInputs, HistoryDenoised, history_denoise};

/// Format of every texture a block creates.
pub const BLOCK_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Largest blur radius in taps on one side (taps = 2 * radius + 1 <= 63); the weights live in
/// a uniform array of 32 floats.
pub const MAX_BLUR_RADIUS: u32 = 31;

/// An invalid block parameter, reported under the caller's prefix.
pub(crate) fn invalid(
    prefix: &str,
    name: &str,
    value: impl std::fmt::Display,
    allowed: impl Into<String>,
) -> AoError {
    AoError::InvalidParameter {
        technique: prefix.into(),
        name: name.into(),
        value: value.to_string(),
        allowed: allowed.into(),
    }
}

/// The descriptor of `handle`, or an error naming the block and the argument.
pub(crate) fn desc_of(
    b: &GraphBuilder,
    prefix: &str,
    what: &str,
    handle: TextureHandle,
) -> AoResult<TextureDesc> {
    b.texture_desc(handle).ok_or_else(|| {
        invalid(
            prefix,
            what,
            format!("{handle:?}"),
            "a texture handle of this graph",
        )
    })
}

/// `size` divided by `factor^level` per axis, rounded up: level `level` of a pyramid built on
/// a texture of size class `size`. Relative classes compose exactly (ceil(ceil(w/a)/b) =
/// ceil(w/(a*b))); fixed sizes are divided here.
pub fn scaled_size(size: SizeClass, factor: u32, level: u32) -> SizeClass {
    let f = factor.max(1).saturating_pow(level);
    match size {
        SizeClass::Relative { divisor } => SizeClass::Relative {
            divisor: divisor.max(1).saturating_mul(f),
        },
        SizeClass::Fixed(e) => SizeClass::Fixed(Extent::new(
            e.width.div_ceil(f).max(1),
            e.height.div_ceil(f).max(1),
        )),
        // No built-in scales a centred level (only `centred_size` extends it); such a size is
        // taken as a ceil-divided pyramid over the centred pyramid's base, which differs from
        // the centred level by at most one texel a level.
        SizeClass::Centred {
            base_divisor,
            factor: k,
            level: l,
        } => SizeClass::Relative {
            divisor: base_divisor
                .max(1)
                .saturating_mul(k.max(1).saturating_pow(l))
                .saturating_mul(f),
        },
    }
}

/// Level `level` of a centred factor-`factor` pyramid over textures of size class `size`
/// (`SizeClass::Centred`: the block grid overhangs both edges alike).
pub fn centred_size(size: SizeClass, factor: u32, level: u32) -> SizeClass {
    match size {
        SizeClass::Relative { divisor } => SizeClass::Centred {
            base_divisor: divisor,
            factor,
            level,
        },
        SizeClass::Centred {
            base_divisor,
            factor: f,
            level: l,
        } if f == factor => SizeClass::Centred {
            base_divisor,
            factor,
            level: l + level,
        },
        SizeClass::Fixed(e) => SizeClass::Fixed(centred_level_extent(e, factor, level)),
        // No built-in nests pyramids of two factors; such a level is taken over its base.
        SizeClass::Centred { base_divisor, .. } => SizeClass::Centred {
            base_divisor,
            factor,
            level,
        },
    }
}

/// Level `level` of a centred factor-`factor` pyramid over an image of size `base`.
pub fn centred_level_extent(base: Extent, factor: u32, level: u32) -> Extent {
    SizeClass::Centred {
        base_divisor: 1,
        factor,
        level,
    }
    .resolve(base)
}

/// Pyramid level `level` of an image of size `base`: ceil(base / factor^level) per axis.
pub fn level_extent(base: Extent, factor: u32, level: u32) -> Extent {
    scaled_size(SizeClass::Fixed(base), factor, level).resolve(base)
}

/// Separable-blur constants shared by the blur shaders (shaders/common/blur.wgsl, `BlurParams`).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BlurUniform {
    /// Tap offset per step: (1, 0) for the horizontal pass, (0, 1) for the vertical one.
    pub axis: [i32; 2],
    pub radius: i32,
    /// Relative depth tolerance sigma_z (0 = no depth term).
    pub depth_sigma: f32,
    /// Exponent of the normal term (0 = no normal term).
    pub normal_power: f32,
    pub _pad: [f32; 3],
    /// One-sided normalised weights w[|k|], k = -radius..radius.
    pub weights: [f32; 32],
}

aograph_graph::uniform_layout!(BlurUniform {
    axis,
    radius,
    depth_sigma,
    normal_power,
    _pad,
    weights
});

impl BlurUniform {
    pub fn new(axis: [i32; 2], weights: &[f32], depth_sigma: f32, normal_power: f32) -> Self {
        let radius = weights.len() / 2;
        let mut w = [0.0f32; 32];
        for (k, slot) in w.iter_mut().enumerate().take(radius + 1) {
            *slot = weights[radius + k];
        }
        Self {
            axis,
            radius: radius as i32,
            depth_sigma,
            normal_power,
            _pad: [0.0; 3],
            weights: w,
        }
    }
}

/// Checks a separable blur's spatial parameters: sigma in (0, 32], taps odd in 1..=63.
pub(crate) fn check_blur(prefix: &str, sigma: f32, taps: u32) -> AoResult<()> {
    if !(sigma.is_finite() && sigma > 0.0 && sigma <= 32.0) {
        return Err(invalid(
            prefix,
            "sigma",
            sigma,
            "greater than 0 and at most 32 (pixels)",
        ));
    }
    if taps == 0 || taps.is_multiple_of(2) || taps > 2 * MAX_BLUR_RADIUS + 1 {
        return Err(invalid(
            prefix,
            "taps",
            taps,
            format!("an odd number from 1 to {}", 2 * MAX_BLUR_RADIUS + 1),
        ));
    }
    Ok(())
}

/// Checks a blur's intermediate format: R32Float or R16Float.
pub(crate) fn check_intermediate(prefix: &str, format: wgpu::TextureFormat) -> AoResult<()> {
    match format {
        wgpu::TextureFormat::R32Float | wgpu::TextureFormat::R16Float => Ok(()),
        f => Err(invalid(
            prefix,
            "intermediate_format",
            format!("{f:?}"),
            "R32Float or R16Float",
        )),
    }
}

/// Adds one pass of a separable blur: `shader` reads `src` (plus `extra` sampled inputs) and
/// writes a new `format` (R32Float or R16Float) texture of `src`'s size named
/// `<prefix>.<pass>`, through the shader's variant for that format.
#[allow(clippy::too_many_arguments)]
pub(crate) fn blur_pass(
    b: &mut GraphBuilder,
    prefix: &str,
    pass: &str,
    shader: &str,
    src: TextureHandle,
    extra: &[(&str, TextureHandle)],
    uniform: &BlurUniform,
    format: wgpu::TextureFormat,
) -> AoResult<TextureHandle> {
    let size = desc_of(b, prefix, "input", src)?.size;
    let name = format!("{prefix}.{pass}");
    let out = b.create_texture(&name, TextureDesc::new(format, size));
    let mut p = b.compute_pass(&name, &intermediate_shader(shader, format), "main");
    p.sample("src", src);
    for (binding, h) in extra {
        p.sample(binding, *h);
    }
    p.uniform_struct("params", uniform);
    // Each tap reads the input and every guide (depth, normals); the centre reads the guides
    // once more.
    let taps = 2 * uniform.radius + 1;
    let guides = extra.len() as f32;
    p.loads_per_invocation(taps as f32 * (1.0 + guides) + guides);
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    Ok(out)
}
