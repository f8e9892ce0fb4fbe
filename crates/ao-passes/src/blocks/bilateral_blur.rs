//! Depth- and normal-aware separable blur: `<prefix>.bilateral_x`, then `<prefix>.bilateral_y`.
//!
//! For a pixel p and a tap q = p + k * axis, k = -r..r (r = (taps - 1) / 2):
//!
//! ```text
//! w(q)   = G(k) * D(p, q) * N(p, q)
//! G(k)   = exp(-k^2 / (2 sigma^2)) / sum_j exp(-j^2 / (2 sigma^2))       spatial Gaussian
//! D(p,q) = exp(-((z_q - z_p) / (depth_sigma * z_p))^2 / 2)               relative depth term
//! N(p,q) = max(0, n_p . n_q)^normal_power                                normal term (k != 0)
//! out(p) = sum_q w(q) ao(q) / sum_q w(q)
//! ```
//!
//! The depth term is relative to the centre's depth so one tolerance serves near and far
//! surfaces (with depth_sigma = 0.1 a tap 10 % farther keeps e^-0.5 = 61 % of its weight); the
//! normal term stops the blur at creases where depth is continuous. Sky taps and taps past the
//! border are left out; sky pixels write 1. `depth_sigma` = 0 or `normal_power` = 0 turns that
//! term off. Reads linear depth (R32Float, 0 = sky) and view-space normals (xyz, w = 1 on
//! geometry) at the input's size.
//!
//! Invariant: the output is R32Float at the input's size, a convex combination of input values
//! (the centre tap always has weight G(0) > 0), so finite [0, 1] input gives finite [0, 1] output.
//! The horizontal pass's texture is R32Float too, or R16Float with
//! [`bilateral_blur_with_intermediate`].

use aograph_graph::{GraphBuilder, TextureHandle};

use super::{
    BLOCK_FORMAT, BlurUniform, blur_pass, check_blur, check_intermediate, gaussian_weights, invalid,
};
use crate::error::AoResult;

/// Parameters of the bilateral blur.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilateralBlur {
    /// Spatial standard deviation in pixels.
    pub sigma: f32,
    /// Taps per axis, odd, 1 to 63.
    pub taps: u32,
    /// Relative depth tolerance sigma_z (0 = no depth term beyond the sky mask).
    pub depth_sigma: f32,
    /// Exponent of the normal term (0 = no normal term).
    pub normal_power: f32,
}

impl Default for BilateralBlur {
    fn default() -> Self {
        Self {
            sigma: 2.0,
            taps: 9,
            depth_sigma: 0.1,
            normal_power: 8.0,
        }
    }
}

impl BilateralBlur {
    /// Range checks; errors are reported under `prefix`.
    pub fn validate(&self, prefix: &str) -> AoResult<()> {
        check_blur(prefix, self.sigma, self.taps)?;
        if !(self.depth_sigma.is_finite() && (0.0..=10.0).contains(&self.depth_sigma)) {
            return Err(invalid(
                prefix,
                "depth_sigma",
                self.depth_sigma,
                "0 (off) to 10 (relative depth)",
            ));
        }
        if !(self.normal_power.is_finite() && (0.0..=128.0).contains(&self.normal_power)) {
            return Err(invalid(
                prefix,
                "normal_power",
                self.normal_power,
                "0 (off) to 128",
            ));
        }
        Ok(())
    }
}

/// Adds `<prefix>.bilateral_x` and `<prefix>.bilateral_y` blurring `input` guided by `depth` and
/// `normals` (same size); returns `<prefix>.bilateral_y` (R32Float, the input's size).
pub fn bilateral_blur(
    b: &mut GraphBuilder,
    prefix: &str,
    input: TextureHandle,
    depth: TextureHandle,
    normals: TextureHandle,
    params: &BilateralBlur,
) -> AoResult<TextureHandle> {
    bilateral_blur_with_intermediate(b, prefix, input, depth, normals, params, BLOCK_FORMAT)
}

/// [`bilateral_blur`] with the horizontal pass's texture `<prefix>.bilateral_x` in
/// `intermediate` (R32Float or R16Float); the output stays R32Float.
pub fn bilateral_blur_with_intermediate(
    b: &mut GraphBuilder,
    prefix: &str,
    input: TextureHandle,
    depth: TextureHandle,
    normals: TextureHandle,
    params: &BilateralBlur,
    intermediate: wgpu::TextureFormat,
) -> AoResult<TextureHandle> {
    params.validate(prefix)?;
    check_intermediate(prefix, intermediate)?;
    let weights = gaussian_weights(params.sigma, params.taps);
    let extra = [("depth", depth), ("normals", normals)];
    let shader = "blocks/bilateral_blur.wgsl";
    let x = blur_pass(
        b,
        prefix,
        "bilateral_x",
        shader,
        input,
        &extra,
        &BlurUniform::new([1, 0], &weights, params.depth_sigma, params.normal_power),
        intermediate,
    )?;
    blur_pass(
        b,
        prefix,
        "bilateral_y",
        shader,
        x,
        &extra,
        &BlurUniform::new([0, 1], &weights, params.depth_sigma, params.normal_power),
        BLOCK_FORMAT,
    )
}
