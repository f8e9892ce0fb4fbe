//! SSDO's radiance against the radiance reference (issue 19): RMSE and PSNR in linear
//! radiance over the non-sky pixels and all three channels, for the direct term alone and
//! for direct plus the bounce.
//!
//! PSNR's peak is the brightest channel of the reference's full radiance (direct + bounce)
//! over the measured pixels, for both scores, so the two are on one scale: PSNR = 20 log10
//! (peak / RMSE). Invariant: every score is finite or, for an exact match, +inf PSNR.

use aograph_tracing::RadianceImage;
use serde::{Deserialize, Serialize};

use super::nonfinite;

/// The scores of one run.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RadianceScores {
    /// RMSE of the technique's direct radiance against the reference's direct term, in linear
    /// radiance over the R, G and B channels of every measured pixel.
    #[serde(with = "nonfinite")]
    pub direct_rmse: f64,
    /// PSNR in dB of `direct_rmse` against `peak`; +inf for an exact match.
    #[serde(with = "nonfinite")]
    pub direct_psnr: f64,
    /// Direct + indirect against the reference's direct + bounce.
    #[serde(with = "nonfinite")]
    pub full_rmse: f64,
    /// PSNR in dB of `full_rmse` against the same `peak`; +inf for an exact match.
    #[serde(with = "nonfinite")]
    pub full_psnr: f64,
    /// The PSNR peak (brightest reference channel).
    pub peak: f64,
}

/// Scores `direct` and `indirect` (RGBA per pixel, as `Renderer::read_extra` gives them)
/// against `reference` over the pixels where `valid` holds; `None` without such pixels.
pub fn radiance_scores(
    direct: &[f32],
    indirect: &[f32],
    reference: &RadianceImage,
    valid: &[bool],
) -> Option<RadianceScores> {
    let (mut sd, mut sf, mut n, mut peak) = (0.0f64, 0.0f64, 0usize, 0.0f64);
    for (i, _) in valid.iter().enumerate().filter(|(_, v)| **v) {
        let rd = reference.direct[i].to_array();
        let ri = reference.indirect[i].to_array();
        for c in 0..3 {
            let (d, b) = (f64::from(direct[4 * i + c]), f64::from(indirect[4 * i + c]));
            let (rd, ri) = (f64::from(rd[c]), f64::from(ri[c]));
            sd += (d - rd).powi(2);
            sf += (d + b - rd - ri).powi(2);
            peak = peak.max(rd + ri);
            n += 1;
        }
    }
    if n == 0 {
        return None;
    }
    let psnr = |rmse: f64| {
        if rmse == 0.0 {
            f64::INFINITY
        } else {
            20.0 * (peak.max(1e-12) / rmse).log10()
        }
    };
    let (direct_rmse, full_rmse) = ((sd / n as f64).sqrt(), (sf / n as f64).sqrt());
    Some(RadianceScores {
        direct_rmse,
        direct_psnr: psnr(direct_rmse),
        full_rmse,
        full_psnr: psnr(full_rmse),
        peak,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn reference() -> RadianceImage {
        RadianceImage {
            width: 2,
            height: 1,
            direct: vec![Vec3::new(1.0, 0.5, 0.25), Vec3::splat(9.0)],
            indirect: vec![Vec3::new(0.0, 0.5, 0.0), Vec3::ZERO],
        }
    }

    #[test]
    fn an_exact_match_scores_zero_rmse_and_infinite_psnr() {
        let direct = [1.0, 0.5, 0.25, 1.0, 0.0, 0.0, 0.0, 1.0];
        let indirect = [0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let s = radiance_scores(&direct, &indirect, &reference(), &[true, false]).unwrap();
        assert_eq!((s.direct_rmse, s.full_rmse), (0.0, 0.0));
        assert!(s.direct_psnr.is_infinite() && s.full_psnr.is_infinite());
        assert_eq!(s.peak, 1.0, "the sky pixel's 9 is not measured");
    }

    #[test]
    fn a_missing_bounce_shows_in_the_full_score_only() {
        // Direct exact, no indirect: full error 0.5 in one of three channels.
        let direct = [1.0, 0.5, 0.25, 1.0, 0.0, 0.0, 0.0, 1.0];
        let s = radiance_scores(&direct, &[0.0; 8], &reference(), &[true, false]).unwrap();
        assert_eq!(s.direct_rmse, 0.0);
        let rmse = (0.25f64 / 3.0).sqrt();
        assert!((s.full_rmse - rmse).abs() < 1e-12);
        assert!((s.full_psnr - 20.0 * (1.0 / rmse).log10()).abs() < 1e-9);
        assert!(radiance_scores(&direct, &[0.0; 8], &reference(), &[false, false]).is_none());
    }
}
