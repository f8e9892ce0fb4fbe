//! A history-aware spatial denoiser for accumulated Monte Carlo AO (rtao's; any technique
//! whose temporal block runs in [`TemporalMode::Average`](super::temporal::TemporalMode)):
//! the filter is wide where a pixel's history is short and narrows as its mean converges
//! (to about a pixel at rtao's 64-frame cap, to nothing from about 150 frames), so the first
//! frames after a camera cut or a disocclusion are smooth and the converged image keeps its
//! detail. It combines, in our own words:
//! - SVGF (Schied et al. 2017): per-pixel variance from the temporal moments (the history's
//!   running mean of A^2), spatial variance while the history is short, and a-trous
//!   iterations whose AO weight is the difference over the local standard deviation (Eq. 5),
//!   with plane and normal weights keeping the filter on one surface;
//! - NVIDIA's REBLUR (NRD): a blur radius that shrinks with history length N as 1 / (1 + kN)
//!   and with the ray's hit distance, and a history fix for pixels with few frames, a sparse
//!   gather that prefers neighbours with long histories.
//!
//! Passes, in order:
//! 1. `<prefix>.history_fix` (shaders/blocks/history_fix.wgsl): the value after the history
//!    fix, and the guide (variance, radius in pixels, n, nearest hit / R), Rgba16Float;
//! 2. `<prefix>.atrous1..K` (shaders/blocks/atrous_denoise.wgsl): a-trous iterations at tap
//!    spacing 1, 2, 4, ..., each skipped at pixels whose radius is below half its spacing.
//!
//! Invariant: the output is R32Float accessibility in [0, 1], exactly 1 on sky, a convex
//! combination of accumulated values; a pixel whose radius is below half a pixel passes
//! through every iteration unchanged, so with a long enough history (n >= 1 + (2 r0 - 1) / k:
//! 152 frames at the defaults with no close hit, 72 with one) the filter is the identity; at
//! rtao's default 64-frame cap it still averages over about a pixel. The guide is the one four-channel texture the block creates
//! (the variance, radius and history length the iterations share).

use aograph_frame::ReadsView;
use aograph_graph::{GraphBuilder, TextureDesc, TextureHandle};
use bytemuck::{Pod, Zeroable};

use super::{BLOCK_FORMAT, desc_of, invalid};
use crate::error::AoResult;

/// Most a-trous iterations (tap spacing up to 16 pixels: a reach of 31 pixels).
pub const MAX_ITERATIONS: u32 = 5;

/// Parameters of [`history_denoise`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HistoryDenoise {
    /// A-trous iterations, 0 to [`MAX_ITERATIONS`] (0: the history fix alone).
    pub iterations: u32,
    /// The filter's radius in pixels on a pixel with one frame of history and no close hit.
    pub base_radius: f32,
    /// k of the radius' 1 / (1 + k (n - 1)) shrink with history length n (REBLUR's 1/(1+kN)).
    pub shrink: f32,
    /// How many standard deviations of AO difference a tap may have and still weigh e^-1
    /// (SVGF's sigma_l: 4).
    pub sigma_ao: f32,
    /// Plane distance, relative to the distance to the camera, at which a tap weighs e^-1.
    pub plane_tolerance: f32,
    /// Pixels with fewer frames than this get the history fix (SVGF: spatial variance below 4).
    pub fix_frames: u32,
    /// The history fix's tap spacing in pixels (a 5x5 gather: a reach of 2 strides).
    pub fix_stride: u32,
    /// The radius' factor where the nearest hit is at distance 0 (1 at R and beyond).
    pub hit_floor: f32,
}

impl Default for HistoryDenoise {
    fn default() -> Self {
        Self {
            iterations: 3,
            base_radius: 8.0,
            shrink: 0.1,
            sigma_ao: 4.0,
            plane_tolerance: 0.02,
            fix_frames: 4,
            fix_stride: 2,
            hit_floor: 0.5,
        }
    }
}

/// The `params` uniform of both shaders (shaders/common/history_denoise_params.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct HistoryDenoiseUniform {
    base_radius: f32,
    shrink: f32,
    sigma_ao: f32,
    plane_tolerance: f32,
    step: f32,
    fix_frames: f32,
    fix_stride: f32,
    hit_floor: f32,
    has_hits: f32,
    _pad: [f32; 3],
}

aograph_graph::uniform_layout!(HistoryDenoiseUniform {
    base_radius,
    shrink,
    sigma_ao,
    plane_tolerance,
    step,
    fix_frames,
    fix_stride,
    hit_floor,
    has_hits,
    _pad
});

/// What the block reads besides the accumulated value.
#[derive(Clone, Copy, Debug)]
pub struct HistoryDenoiseInputs {
    /// The accumulated accessibility (the temporal block's output).
    pub accumulated: TextureHandle,
    /// The temporal block's history as written this frame (x mean, y n, z second moment).
    pub history: TextureHandle,
    /// The g-buffer's linear depth (0 = sky); points are rebuilt from it with `view`.
    pub depth: TextureHandle,
    /// The g-buffer's view-space normals.
    pub normals: TextureHandle,
    /// Where `.g` is a hit's distance over R this frame (rtao's trace writes the nearest of
    /// its rays' hits; in binary mode each ray's is the first hit found, not always its
    /// nearest);
    /// `None`: no hit distance, the radius does not narrow near occluders.
    pub hits: Option<TextureHandle>,
    /// The view block of the size the inputs have.
    pub view: aograph_graph::BufferHandle,
}

impl HistoryDenoise {
    /// Range checks, reported under `owner`.
    pub fn validate(&self, owner: &str) -> AoResult<()> {
        if self.iterations > MAX_ITERATIONS {
            return Err(invalid(
                owner,
                "spatial_iterations",
                self.iterations,
                format!("0 to {MAX_ITERATIONS}"),
            ));
        }
        let positive = |name: &str, v: f32, max: f32| {
            if v.is_finite() && v > 0.0 && v <= max {
                Ok(())
            } else {
                Err(invalid(
                    owner,
                    name,
                    v,
                    format!("greater than 0 and at most {max}"),
                ))
            }
        };
        positive("spatial_radius", self.base_radius, 256.0)?;
        positive("sigma_ao", self.sigma_ao, 1e4)?;
        positive("plane_tolerance", self.plane_tolerance, 1.0)?;
        positive("hit_floor", self.hit_floor, 1.0)?;
        if !(self.shrink.is_finite() && (0.0..=1e3).contains(&self.shrink)) {
            return Err(invalid(owner, "spatial_shrink", self.shrink, "0 to 1000"));
        }
        if !(1..=64).contains(&self.fix_frames) {
            return Err(invalid(
                owner,
                "history_fix_frames",
                self.fix_frames,
                "1 to 64",
            ));
        }
        if !(1..=16).contains(&self.fix_stride) {
            return Err(invalid(
                owner,
                "history_fix_stride",
                self.fix_stride,
                "1 to 16",
            ));
        }
        Ok(())
    }

    /// The history fix's stride for a filter of radius `base_radius`: its 5x5 gather reaches
    /// two strides, about 0.4 of the radius, on each side (2 pixels at the default 8).
    pub fn fix_stride_for(base_radius: f32) -> u32 {
        ((base_radius / 5.0).round() as u32).clamp(1, 16)
    }

    fn uniform(&self, step: u32, has_hits: bool) -> HistoryDenoiseUniform {
        HistoryDenoiseUniform {
            base_radius: self.base_radius,
            shrink: self.shrink,
            sigma_ao: self.sigma_ao,
            plane_tolerance: self.plane_tolerance,
            step: step as f32,
            fix_frames: self.fix_frames as f32,
            fix_stride: self.fix_stride as f32,
            hit_floor: self.hit_floor,
            has_hits: has_hits as u32 as f32,
            _pad: [0.0; 3],
        }
    }
}

/// The radius in pixels the history fix gives a pixel with `n` frames of history whose
/// nearest hit is at `hit` (over R): CPU mirror of shaders/blocks/history_fix.wgsl.
pub fn radius_px(p: &HistoryDenoise, n: f32, hit: f32) -> f32 {
    let hit_scale = p.hit_floor + (1.0 - p.hit_floor) * hit.clamp(0.0, 1.0);
    p.base_radius * hit_scale / (1.0 + p.shrink * (n.max(1.0) - 1.0))
}

/// What [`history_denoise`] wrote.
#[derive(Clone, Copy, Debug)]
pub struct HistoryDenoised {
    /// The filtered accessibility (R32Float).
    pub accessibility: TextureHandle,
    /// The guide (Rgba16Float): variance of the pixel's value, radius in pixels, frames of
    /// history n, nearest hit over R; for inspection and tests.
    pub guide: TextureHandle,
}

/// Adds the history fix and the a-trous iterations.
pub fn history_denoise(
    b: &mut GraphBuilder,
    prefix: &str,
    inputs: &HistoryDenoiseInputs,
    params: &HistoryDenoise,
) -> AoResult<HistoryDenoised> {
    params.validate(prefix)?;
    let size = desc_of(b, prefix, "accumulated", inputs.accumulated)?.size;
    let has_hits = inputs.hits.is_some();

    // Pass 1: the history fix and the guide.
    let name = format!("{prefix}.history_fix");
    let fixed = b.create_texture(&name, TextureDesc::new(BLOCK_FORMAT, size));
    let guide = b.create_texture(
        &format!("{prefix}.guide"),
        TextureDesc::new(wgpu::TextureFormat::Rgba16Float, size),
    );
    let mut p = b.compute_pass(&name, "blocks/history_fix.wgsl", "main");
    p.uniform_struct("params", &params.uniform(1, has_hits));
    p.sample("accumulated", inputs.accumulated)
        .sample("history", inputs.history)
        .sample("depth", inputs.depth)
        .sample("normals", inputs.normals)
        // Without hit distances the shader never reads `hits` (has_hits = 0).
        .sample("hits", inputs.hits.unwrap_or(inputs.accumulated));
    p.read_view(inputs.view);
    // Centre value, history, depth and normal, and the 3x3 neighbours' depth, normal,
    // history and hit distance (4 + 9 x 4); the history fix's 25 taps (depth, normal,
    // history) run only on pixels with a short history.
    p.loads_per_invocation(40.0);
    let mut src = p.write_storage("dst", fixed);
    let guide = p.write_storage("guide", guide);
    p.dispatch_over(src);

    // Passes 2..: a-trous iterations at spacing 1, 2, 4, ...
    for k in 1..=params.iterations {
        let name = format!("{prefix}.atrous{k}");
        let out = b.create_texture(&name, TextureDesc::new(BLOCK_FORMAT, size));
        let mut p = b.compute_pass(&name, "blocks/atrous_denoise.wgsl", "main");
        p.uniform_struct("params", &params.uniform(1 << (k - 1), has_hits));
        p.sample("src", src)
            .sample("guide", guide)
            .sample("depth", inputs.depth)
            .sample("normals", inputs.normals);
        p.read_view(inputs.view);
        // Centre value, guide, depth and normal; 9 taps' depth, normal and value (4 + 9 x 3).
        p.loads_per_invocation(31.0);
        let out = p.write_storage("dst", out);
        p.dispatch_over(out);
        src = out;
    }
    Ok(HistoryDenoised {
        accessibility: src,
        guide,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_radius_shrinks_as_one_over_one_plus_k_n_and_with_close_hits() {
        let p = HistoryDenoise::default();
        assert_eq!(radius_px(&p, 1.0, 1.0), 8.0);
        // 8 / (1 + 0.1 * 9)
        assert!((radius_px(&p, 10.0, 1.0) - 8.0 / 1.9).abs() < 1e-6);
        // A hit at distance 0 halves it (hit_floor 0.5).
        assert_eq!(radius_px(&p, 1.0, 0.0), 4.0);
        // 64 frames: 8 / 7.3, about a pixel: the iterations at spacing 1 and 2 still run,
        // the one at spacing 4 no longer does.
        assert!((radius_px(&p, 64.0, 1.0) - 8.0 / 7.3).abs() < 1e-6);
    }

    #[test]
    fn out_of_range_settings_are_refused_by_name() {
        let bad = HistoryDenoise {
            iterations: 9,
            ..HistoryDenoise::default()
        };
        let e = bad.validate("rtao").unwrap_err().to_string();
        assert!(
            e.contains("spatial_iterations") && e.contains("0 to 5"),
            "{e}"
        );
        let bad = HistoryDenoise {
            base_radius: -1.0,
            ..HistoryDenoise::default()
        };
        assert!(
            bad.validate("rtao")
                .unwrap_err()
                .to_string()
                .contains("spatial_radius")
        );
    }
}
