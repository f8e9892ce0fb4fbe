//! Separable Gaussian blur: a horizontal pass `<prefix>.blur_x`, then a vertical pass
//! `<prefix>.blur_y`, each with the same 1D kernel.
//!
//! Weights (Pyramid HBAO spec §3, the paper's denoiser: sigma 1.5, 5 taps, the default):
//! w\[k\] = exp(-k^2 / (2 sigma^2)) / sum_{j=-r..r} exp(-j^2 / (2 sigma^2)), k = -r..r,
//! r = (taps - 1) / 2; for sigma 1.5 and 5 taps {0.120078, 0.233881, 0.292082, 0.233881,
//! 0.120078}. Each pass renormalises by the weights of the taps it used, so taps past the image
//! border are dropped rather than clamped and a constant image stays constant.
//!
//! Depth: without a depth input the blur is the paper's plain Gaussian. With one, sky pixels
//! (depth 0) write accessibility 1 and sky taps are left out (sky is not a surface and has no
//! AO to average). Depth awareness (a relative depth term, `depth_sigma`, see
//! shaders/common/blur.wgsl) is optional and off by default, as in the paper; a depth- and
//! normal-aware filter is [`fn@super::bilateral_blur`].
//!
//! Invariant: the output is R32Float at the input's size; finite for finite input; a convex
//! combination of input values (sky pixels excepted), so [0, 1] stays [0, 1]. The horizontal
//! pass's texture is R32Float too, or R16Float with [`gaussian_blur_with_intermediate`].

use aograph_graph::{GraphBuilder, TextureHandle};

use super::{BLOCK_FORMAT, BlurUniform, blur_pass, check_blur, check_intermediate, invalid};
use crate::error::AoResult;

/// Parameters of the separable Gaussian.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussianBlur {
    /// Standard deviation in pixels (Pyramid HBAO: 1.5).
    pub sigma: f32,
    /// Taps per axis, odd, 1 to 63 (Pyramid HBAO: 5).
    pub taps: u32,
    /// Relative depth tolerance of the optional depth term; `None` (the default) is the plain
    /// Gaussian. Needs a depth input.
    pub depth_sigma: Option<f32>,
}

impl Default for GaussianBlur {
    /// The Pyramid HBAO denoiser: sigma 1.5, 5 taps, no depth term (spec §3).
    fn default() -> Self {
        Self {
            sigma: 1.5,
            taps: 5,
            depth_sigma: None,
        }
    }
}

impl GaussianBlur {
    /// Range checks; errors are reported under `prefix`.
    pub fn validate(&self, prefix: &str) -> AoResult<()> {
        check_blur(prefix, self.sigma, self.taps)?;
        if let Some(s) = self.depth_sigma {
            if !(s.is_finite() && s > 0.0 && s <= 10.0) {
                return Err(invalid(
                    prefix,
                    "depth_sigma",
                    s,
                    "greater than 0 and at most 10 (relative depth)",
                ));
            }
        }
        Ok(())
    }
}

/// The normalised 1D kernel: `taps` weights for offsets -r..r, summing to 1.
pub fn gaussian_weights(sigma: f32, taps: u32) -> Vec<f32> {
    let r = (taps.max(1) as i32 - 1) / 2;
    let s = sigma.max(1e-6) as f64;
    let raw: Vec<f64> = (-r..=r)
        .map(|k| (-(k * k) as f64 / (2.0 * s * s)).exp())
        .collect();
    let sum: f64 = raw.iter().sum();
    raw.iter().map(|w| (w / sum) as f32).collect()
}

/// Adds `<prefix>.blur_x` and `<prefix>.blur_y` blurring `input`; returns the blurred texture
/// (`<prefix>.blur_y`, R32Float, the input's size). `depth` (linear, 0 = sky, same size) makes
/// sky write 1 and enables `depth_sigma`.
pub fn gaussian_blur(
    b: &mut GraphBuilder,
    prefix: &str,
    input: TextureHandle,
    depth: Option<TextureHandle>,
    params: &GaussianBlur,
) -> AoResult<TextureHandle> {
    gaussian_blur_with_intermediate(b, prefix, input, depth, params, BLOCK_FORMAT)
}

/// [`gaussian_blur`] with the horizontal pass's texture `<prefix>.blur_x` in `intermediate`
/// (a technique's intermediate format, R32Float or R16Float); the output stays R32Float.
pub fn gaussian_blur_with_intermediate(
    b: &mut GraphBuilder,
    prefix: &str,
    input: TextureHandle,
    depth: Option<TextureHandle>,
    params: &GaussianBlur,
    intermediate: wgpu::TextureFormat,
) -> AoResult<TextureHandle> {
    params.validate(prefix)?;
    check_intermediate(prefix, intermediate)?;
    let weights = gaussian_weights(params.sigma, params.taps);
    let depth_sigma = match (params.depth_sigma, depth) {
        (Some(_), None) => {
            return Err(invalid(
                prefix,
                "depth_sigma",
                params.depth_sigma.unwrap_or(0.0),
                "only with a depth input",
            ));
        }
        (s, _) => s.unwrap_or(0.0),
    };
    let (shader, extra): (&str, Vec<(&str, TextureHandle)>) = match depth {
        Some(d) => ("blocks/gaussian_blur_depth.wgsl", vec![("depth", d)]),
        None => ("blocks/gaussian_blur.wgsl", Vec::new()),
    };
    let x = blur_pass(
        b,
        prefix,
        "blur_x",
        shader,
        input,
        &extra,
        &BlurUniform::new([1, 0], &weights, depth_sigma, 0.0),
        intermediate,
    )?;
    blur_pass(
        b,
        prefix,
        "blur_y",
        shader,
        x,
        &extra,
        &BlurUniform::new([0, 1], &weights, depth_sigma, 0.0),
        BLOCK_FORMAT,
    )
}
