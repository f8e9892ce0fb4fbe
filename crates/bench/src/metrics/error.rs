//! Pixel error statistics over a mask: mean absolute error, root mean square error, PSNR with
//! peak 1.0 (accessibility lives in [0, 1]) and the mean signed error (technique - reference,
//! negative = over-darkening). Sums are accumulated in f64 so a 4K image loses no precision.

/// Peak signal value of accessibility images, used by [`psnr`].
pub const PEAK: f64 = 1.0;

/// Error of one image against another over the masked pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorStats {
    /// Pixels measured.
    pub count: usize,
    /// Mean absolute error: mean of |a - b|.
    pub mae: f64,
    /// Root mean square error: sqrt(mean of (a - b)^2).
    pub rmse: f64,
    /// Decibels; `f64::INFINITY` when the images are identical.
    pub psnr: f64,
    /// Mean of a - b.
    pub signed: f64,
}

/// PSNR in dB for an RMSE with peak [`PEAK`]: 20 log10(peak / rmse); infinite at rmse 0,
/// NaN when the RMSE is undefined (no pixels).
pub fn psnr(rmse: f64) -> f64 {
    if rmse.is_nan() {
        f64::NAN
    } else if rmse == 0.0 {
        f64::INFINITY
    } else {
        20.0 * (PEAK / rmse).log10()
    }
}

/// Errors of `a` against `b` over the pixels where `mask` is true. With no such pixel every
/// statistic is NaN and `count` is 0.
pub fn error_stats(a: &[f32], b: &[f32], mask: &[bool]) -> ErrorStats {
    let (mut abs, mut sq, mut signed, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for ((x, y), m) in a.iter().zip(b).zip(mask) {
        if *m {
            let e = *x as f64 - *y as f64;
            abs += e.abs();
            sq += e * e;
            signed += e;
            n += 1;
        }
    }
    if n == 0 {
        return ErrorStats {
            count: 0,
            mae: f64::NAN,
            rmse: f64::NAN,
            psnr: f64::NAN,
            signed: f64::NAN,
        };
    }
    let nf = n as f64;
    let rmse = (sq / nf).sqrt();
    ErrorStats {
        count: n,
        mae: abs / nf,
        rmse,
        psnr: psnr(rmse),
        signed: signed / nf,
    }
}

/// MAE over the masked pixels, `None` when the mask is empty.
pub fn masked_mae(a: &[f32], b: &[f32], mask: &[bool]) -> Option<f64> {
    let s = error_stats(a, b, mask);
    (s.count > 0).then_some(s.mae)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_zero_error_and_infinite_psnr() {
        let a = [0.2f32, 0.5, 0.9, 1.0];
        let s = error_stats(&a, &a, &[true; 4]);
        assert_eq!((s.count, s.mae, s.rmse, s.signed), (4, 0.0, 0.0, 0.0));
        assert_eq!(s.psnr, f64::INFINITY);
    }

    #[test]
    fn a_constant_offset_is_the_mae_the_rmse_and_the_signed_error() {
        let b = [0.25f32, 0.5, 0.75, 0.5];
        let a: Vec<f32> = b.iter().map(|v| v + 0.25).collect();
        let s = error_stats(&a, &b, &[true; 4]);
        assert_eq!((s.mae, s.rmse, s.signed), (0.25, 0.25, 0.25));
        // 20 log10(1 / 0.25) = 12.0412 dB
        assert!((s.psnr - 12.041199826559248).abs() < 1e-12);
        let darker: Vec<f32> = b.iter().map(|v| v - 0.25).collect();
        assert_eq!(error_stats(&darker, &b, &[true; 4]).signed, -0.25);
    }

    #[test]
    fn rmse_weighs_large_errors_more_than_mae() {
        // errors 0, 0, 0, 0.4: MAE 0.1, RMSE sqrt(0.16 / 4) = 0.2, signed 0.1
        let b = [0.5f32; 4];
        let a = [0.5f32, 0.5, 0.5, 0.9];
        let s = error_stats(&a, &b, &[true; 4]);
        assert!(
            (s.mae - 0.1).abs() < 1e-7
                && (s.rmse - 0.2).abs() < 1e-7
                && (s.signed - 0.1).abs() < 1e-7,
            "{s:?}"
        );
    }

    #[test]
    fn masked_pixels_do_not_count() {
        let a = [0.0f32, 1.0, 0.5];
        let b = [0.0f32, 0.0, 0.5];
        let s = error_stats(&a, &b, &[true, false, true]);
        assert_eq!((s.count, s.mae), (2, 0.0));
        assert_eq!(masked_mae(&a, &b, &[false, true, false]), Some(1.0));
        assert_eq!(masked_mae(&a, &b, &[false; 3]), None);
        assert!(error_stats(&a, &b, &[false; 3]).mae.is_nan());
    }
}
