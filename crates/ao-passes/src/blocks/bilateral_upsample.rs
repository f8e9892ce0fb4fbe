//! Bilateral upsampling: a low-resolution AO to full resolution, guided by linear depth (and
//! optionally normals) at both resolutions. One pass, `<prefix>.upsample`.
//!
//! For a full-resolution pixel p (depth z_p, normal n_p) the low-resolution position is
//! u = (p + 0.5) / f - 0.5, f = full pixels per low texel (low texel x covers [x f, (x + 1) f)),
//! and the four taps i of the 2x2 bilinear footprint of u are weighted
//!
//! ```text
//! w_i = b_i * exp(-((z_i - z_p) / (depth_sigma * z_p))^2 / 2) * max(0, n_p . n_i)^normal_power
//! out = sum_i w_i ao_i / sum_i w_i                      when sum_i w_i > 1e-4
//! out = ao_j, j = argmin_i |z_i - z_p|                  otherwise (nearest-depth upsampling)
//! ```
//!
//! b_i are the bilinear weights, sky taps (z_i = 0) get weight 0, taps past the border are
//! clamped to it, the normal term is present only when normals are given. On a surface that
//! is continuous across the footprint this is bilinear interpolation; across a depth edge only
//! the taps on p's side count, and when none agrees the nearest-depth tap is copied (no
//! blending across the edge). Sky pixels write 1; a pixel whose four taps are sky writes 1.
//!
//! Sizes: the low and full textures must have relative size classes whose divisors divide
//! (f = low divisor / full divisor), e.g. 1/2 and full, or a factor-K pyramid level over its
//! base; fixed sizes are rejected because the texel mapping would not be exact.
//!
//! Invariant: the output is R32Float at the full-resolution depth's size, a convex combination
//! of low-resolution values (or 1), so finite [0, 1] input gives finite [0, 1] output.

use aograph_graph::{GraphBuilder, SizeClass, TextureDesc, TextureHandle};

use super::{BLOCK_FORMAT, desc_of, invalid};
use crate::error::AoResult;

/// Parameters of the bilateral upsampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BilateralUpsample {
    /// Relative depth tolerance sigma_z of the depth term.
    pub depth_sigma: f32,
    /// Exponent of the normal term (used only with normals; 0 = off).
    pub normal_power: f32,
}

impl Default for BilateralUpsample {
    fn default() -> Self {
        Self {
            depth_sigma: 0.1,
            normal_power: 8.0,
        }
    }
}

/// The textures an upsampling reads.
#[derive(Clone, Copy, Debug)]
pub struct UpsampleInputs {
    /// Low-resolution AO (R32Float).
    pub ao: TextureHandle,
    /// Linear depth at the AO's resolution (0 = sky).
    pub depth_low: TextureHandle,
    /// Linear depth at the target resolution (0 = sky); the output has its size.
    pub depth_full: TextureHandle,
    /// View-space normals (low, full), optional.
    pub normals: Option<(TextureHandle, TextureHandle)>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct UpsampleUniform {
    factor: f32,
    depth_sigma: f32,
    normal_power: f32,
    _pad: f32,
}

aograph_graph::uniform_layout!(UpsampleUniform {
    factor,
    depth_sigma,
    normal_power,
    _pad
});

impl BilateralUpsample {
    /// Range checks; errors are reported under `prefix`.
    pub fn validate(&self, prefix: &str) -> AoResult<()> {
        if !(self.depth_sigma.is_finite() && self.depth_sigma > 0.0 && self.depth_sigma <= 10.0) {
            return Err(invalid(
                prefix,
                "depth_sigma",
                self.depth_sigma,
                "greater than 0 and at most 10 (relative depth)",
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

/// Full-resolution pixels per low-resolution texel, from the two size classes.
pub fn upsample_factor(low: SizeClass, full: SizeClass) -> Option<u32> {
    match (low, full) {
        (SizeClass::Relative { divisor: lo }, SizeClass::Relative { divisor: hi })
            if lo >= hi && lo % hi.max(1) == 0 =>
        {
            Some(lo / hi.max(1))
        }
        _ => None,
    }
}

/// Adds `<prefix>.upsample`; returns the full-resolution AO (R32Float, `depth_full`'s size).
pub fn bilateral_upsample(
    b: &mut GraphBuilder,
    prefix: &str,
    inputs: &UpsampleInputs,
    params: &BilateralUpsample,
) -> AoResult<TextureHandle> {
    params.validate(prefix)?;
    let low = desc_of(b, prefix, "ao", inputs.ao)?.size;
    let depth_low = desc_of(b, prefix, "depth_low", inputs.depth_low)?.size;
    let full = desc_of(b, prefix, "depth_full", inputs.depth_full)?.size;
    if depth_low != low {
        return Err(invalid(
            prefix,
            "depth_low",
            format!("size {depth_low}"),
            format!("the low-resolution AO's size ({low})"),
        ));
    }
    let factor = upsample_factor(low, full).ok_or_else(|| {
        invalid(
            prefix,
            "ao",
            format!("size {low} over {full}"),
            "relative size classes whose divisors divide (e.g. 1/2 over full)",
        )
    })?;
    if let Some((nl, nf)) = inputs.normals {
        let (nl, nf) = (
            desc_of(b, prefix, "normals_low", nl)?.size,
            desc_of(b, prefix, "normals_full", nf)?.size,
        );
        if nl != low || nf != full {
            return Err(invalid(
                prefix,
                "normals",
                format!("sizes {nl}, {nf}"),
                format!("the low and full sizes ({low}, {full})"),
            ));
        }
    }
    let name = format!("{prefix}.upsample");
    let out = b.create_texture(&name, TextureDesc::new(BLOCK_FORMAT, full));
    let shader = if inputs.normals.is_some() {
        "blocks/bilateral_upsample_normals.wgsl"
    } else {
        "blocks/bilateral_upsample.wgsl"
    };
    let mut p = b.compute_pass(&name, shader, "main");
    p.sample("ao", inputs.ao)
        .sample("depth_low", inputs.depth_low)
        .sample("depth_full", inputs.depth_full);
    if let Some((nl, nf)) = inputs.normals {
        p.sample("normals_low", nl).sample("normals_full", nf);
    }
    let u = UpsampleUniform {
        factor: factor as f32,
        depth_sigma: params.depth_sigma,
        normal_power: params.normal_power,
        _pad: 0.0,
    };
    p.uniform_struct("params", &u);
    // The full-resolution centre (depth, normal), then 4 low-resolution taps of AO, depth and
    // normal.
    p.loads_per_invocation(if inputs.normals.is_some() {
        2.0 + 4.0 * 3.0
    } else {
        1.0 + 4.0 * 2.0
    });
    let out = p.write_storage("dst", out);
    p.dispatch_over(out);
    Ok(out)
}
