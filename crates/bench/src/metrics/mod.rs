//! Image metrics of a technique's accessibility against the ray-traced reference.
//!
//! Every metric is taken over the non-sky pixels only (linear depth > 0): sky is 1 in both
//! images by convention, and counting it would flatter a technique by the fraction of sky in
//! the frame. Sign convention: error = technique - reference, so a negative mean signed error
//! means the technique over-darkens.
//!
//! - [`error`]: MAE, RMSE, PSNR (peak 1.0), mean signed error, and MAE inside a mask (the
//!   depth-edge band, where halos live).
//! - [`ssim`](mod@ssim): SSIM with the Pyramid HBAO paper's settings (11x11 window, k1 and k2 as printed).
//! - [`edges`]: the band of a few pixels around depth discontinuities.
//! - [`flicker`]: mean absolute frame-to-frame change over a multi-frame run.
//! - [`nonfinite`]: how infinite or undefined values (PSNR of identical images) are serialised.

pub mod edges;
pub mod error;
pub mod flicker;
pub mod nonfinite;
pub mod radiance;
pub mod ssim;

use serde::{Deserialize, Serialize};

pub use edges::{DEFAULT_EDGE_BAND, DEFAULT_EDGE_JUMP, depth_edges, edge_band};
pub use error::{ErrorStats, error_stats, masked_mae, psnr};
pub use flicker::FlickerMeter;
pub use radiance::{RadianceScores, radiance_scores};
pub use ssim::{SsimParams, SsimWindow, ssim};

use aograph_app_config::error::{AppError, AppResult};

/// Knobs of [`compare`]; the defaults are what `aograph bench` reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetricOptions {
    /// Half-width in pixels of the band around depth edges (Chebyshev distance).
    pub edge_band: u32,
    /// Relative depth jump between 4-neighbours that counts as an edge (0.1 = 10%).
    pub edge_jump: f32,
    /// The SSIM window and constants (default: the Pyramid HBAO paper's, [`SsimParams::PAPER`]).
    pub ssim: SsimParams,
}

impl Default for MetricOptions {
    fn default() -> Self {
        Self {
            edge_band: DEFAULT_EDGE_BAND,
            edge_jump: DEFAULT_EDGE_JUMP,
            ssim: SsimParams::default(),
        }
    }
}

/// Every metric of one image against the reference (and, for multi-frame runs, its flicker).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Non-sky pixels measured.
    pub pixels: usize,
    /// Mean absolute error |technique - reference| over the non-sky pixels, in accessibility
    /// units (0..1); NaN with no non-sky pixel.
    #[serde(with = "nonfinite")]
    pub mae: f64,
    /// Root mean square error over the non-sky pixels, 0..1; weighs large errors more than MAE.
    #[serde(with = "nonfinite")]
    pub rmse: f64,
    /// dB with peak 1.0; `inf` for identical images.
    #[serde(with = "nonfinite")]
    pub psnr: f64,
    /// Mean SSIM over windows centred on the non-sky pixels (1 = identical; see
    /// [`ssim`](mod@ssim) for the window and constants); NaN with no non-sky pixel.
    #[serde(with = "nonfinite")]
    pub ssim: f64,
    /// Mean of technique - reference: negative = over-darkening.
    #[serde(with = "nonfinite")]
    pub signed_error: f64,
    /// The signed error over the image's left and right fifths (`None` where a fifth has no
    /// geometry): where a view is (nearly) its own mirror image, their difference is a
    /// left/right bias of the technique (docs/results/output-sizes.md, "At every output size").
    #[serde(default)]
    pub signed_error_left: Option<f64>,
    /// The signed error over the image's right fifth; see `signed_error_left`.
    #[serde(default)]
    pub signed_error_right: Option<f64>,
    /// MAE over the non-sky pixels of the depth-edge band; `None` when the frame has no edge.
    pub edge_mae: Option<f64>,
    /// Non-sky pixels in the edge band.
    pub edge_pixels: usize,
    /// Mean absolute frame-to-frame change; `None` for single-frame runs.
    pub flicker: Option<f64>,
}

/// Compares `ao` with `reference` (both row-major, `width` x `height`) over the pixels where
/// `depth` > 0. `flicker` is left `None`: it needs every frame (see [`FlickerMeter`]).
pub fn compare(
    ao: &[f32],
    reference: &[f32],
    depth: &[f32],
    width: u32,
    height: u32,
    options: &MetricOptions,
) -> AppResult<Metrics> {
    let n = width as usize * height as usize;
    for (what, len) in [
        ("technique image", ao.len()),
        ("reference", reference.len()),
        ("depth", depth.len()),
    ] {
        if len != n {
            return Err(AppError::InvalidArgument {
                name: what.into(),
                value: format!("{len} pixels"),
                allowed: format!("{n} pixels ({width}x{height})"),
            });
        }
    }
    let valid: Vec<bool> = depth.iter().map(|d| *d > 0.0).collect();
    let e = error_stats(ao, reference, &valid);
    let band = edge_band(
        &depth_edges(depth, width, height, options.edge_jump),
        width,
        height,
        options.edge_band,
    );
    let band_valid: Vec<bool> = band.iter().zip(&valid).map(|(b, v)| *b && *v).collect();
    let edge_pixels = band_valid.iter().filter(|b| **b).count();
    let fifth = |left: bool| -> Option<f64> {
        let w = width as usize;
        let cols = (w / 5).max(1);
        let mask: Vec<bool> = (0..n)
            .map(|i| {
                let x = i % w;
                valid[i] && if left { x < cols } else { x >= w - cols }
            })
            .collect();
        let s = error_stats(ao, reference, &mask);
        (s.count > 0).then_some(s.signed)
    };
    Ok(Metrics {
        pixels: e.count,
        mae: e.mae,
        rmse: e.rmse,
        psnr: e.psnr,
        ssim: ssim(ao, reference, &valid, width, height, &options.ssim),
        signed_error: e.signed,
        signed_error_left: fifth(true),
        signed_error_right: fifth(false),
        edge_mae: masked_mae(ao, reference, &band_valid),
        edge_pixels,
        flicker: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 32x32 "reference": a smooth gradient with a darker square, sky in the top rows.
    fn scene() -> (Vec<f32>, Vec<f32>, u32, u32) {
        let (w, h) = (32u32, 32u32);
        let mut ao = Vec::new();
        let mut depth = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let sky = y < 4;
                let square = (10..20).contains(&x) && (12..22).contains(&y);
                depth.push(if sky {
                    0.0
                } else if square {
                    2.0
                } else {
                    5.0
                });
                ao.push(if sky {
                    1.0
                } else {
                    0.4 + 0.5 * x as f32 / w as f32 - if square { 0.2 } else { 0.0 }
                });
            }
        }
        (ao, depth, w, h)
    }

    #[test]
    fn the_signed_error_of_each_outer_fifth_is_its_own() {
        // 32 wide: the fifths are columns 0-5 and 26-31. The left one is 0.1 too bright, the
        // right one 0.05 too dark, the middle 0.3 too bright.
        let (r, d, w, h) = scene();
        let ao: Vec<f32> = r
            .iter()
            .enumerate()
            .map(|(i, v)| match i % 32 {
                0..=5 => v + 0.1,
                26..=31 => v - 0.05,
                _ => v + 0.3,
            })
            .collect();
        let m = compare(&ao, &r, &d, w, h, &MetricOptions::default()).unwrap();
        let (l, rt) = (m.signed_error_left.unwrap(), m.signed_error_right.unwrap());
        assert!(
            (l - 0.1).abs() < 1e-6 && (rt + 0.05).abs() < 1e-6,
            "{l} {rt}"
        );
    }

    #[test]
    fn the_reference_against_itself_is_perfect() {
        let (r, d, w, h) = scene();
        let m = compare(&r, &r, &d, w, h, &MetricOptions::default()).unwrap();
        assert_eq!(m.pixels, 32 * 28);
        assert_eq!((m.mae, m.rmse, m.signed_error), (0.0, 0.0, 0.0));
        assert_eq!(m.psnr, f64::INFINITY);
        assert!((m.ssim - 1.0).abs() < 1e-12, "ssim {}", m.ssim);
        assert_eq!(m.edge_mae, Some(0.0));
        assert!(m.edge_pixels > 0);
        let json = serde_json::to_string(&m).unwrap();
        assert!(json.contains("\"psnr\":\"inf\""), "{json}");
        assert_eq!(serde_json::from_str::<Metrics>(&json).unwrap(), m);
    }

    #[test]
    fn a_biased_image_has_the_known_error() {
        let (r, d, w, h) = scene();
        // Too dark by 0.1 everywhere, and sky left at 1 (sky must not count).
        let biased: Vec<f32> = r
            .iter()
            .zip(&d)
            .map(|(v, z)| if *z > 0.0 { v - 0.1 } else { 1.0 })
            .collect();
        let m = compare(&biased, &r, &d, w, h, &MetricOptions::default()).unwrap();
        assert!((m.mae - 0.1).abs() < 1e-6, "mae {}", m.mae);
        assert!((m.rmse - 0.1).abs() < 1e-6);
        assert!(
            (m.signed_error + 0.1).abs() < 1e-6,
            "over-darkening is negative: {}",
            m.signed_error
        );
        assert!((m.psnr - 20.0).abs() < 1e-4, "psnr {}", m.psnr);
        assert!((m.edge_mae.unwrap() - 0.1).abs() < 1e-6);
        assert!(
            m.ssim < 1.0 && m.ssim > 0.9,
            "a small offset keeps the structure: {}",
            m.ssim
        );
    }

    #[test]
    fn mismatched_sizes_are_an_error_not_a_panic() {
        let (r, d, w, h) = scene();
        assert!(compare(&r[1..], &r, &d, w, h, &MetricOptions::default()).is_err());
    }
}
