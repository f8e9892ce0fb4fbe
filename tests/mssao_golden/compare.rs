//! Comparing GPU read-backs with the CPU mirror, with the tolerances' reasons.

use super::*;

// ---------------------------------------------------------------------------------------------
// Comparison

/// Checks |got - want| <= bound(want) everywhere; returns the largest |got - want|.
pub(crate) fn assert_within(
    got: &[f32],
    want: &[f32],
    bound: impl Fn(f32) -> f32,
    what: &str,
) -> f32 {
    assert_eq!(got.len(), want.len(), "{what}: length");
    let mut worst = 0.0f32;
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let e = (g - w).abs();
        assert!(
            g.is_finite() && e <= bound(*w),
            "{what}: texel {i}: got {g}, want {w}"
        );
        worst = worst.max(e);
    }
    worst
}

/// Checks |got - want| <= TOL |want| + floor everywhere; returns the largest relative error.
pub(crate) fn assert_close(got: &[f32], want: &[f32], floor: f32, what: &str) -> f32 {
    assert_within(got, want, |w| TOL * w.abs() + floor, what);
    got.iter()
        .zip(want)
        .filter(|(_, w)| **w != 0.0)
        .map(|(g, w)| (g - w).abs() / w.abs())
        .fold(0.0, f32::max)
}

/// Relative tolerance of everything compared with [`assert_close`]: each value is a sum or a
/// positively weighted mean of non-negative per-sample terms, so its rounding error is
/// relative. The GPU's sqrt and division are within a few ulp of the CPU's (Vulkan allows 2.5
/// ulp for division and an inversesqrt-based sqrt), so each term differs by < 1e-6 relative,
/// and the normalised values (means, blurred and upsampled tuples, whose weights go through
/// exp2/log2, accurate to a few ulp) by well under 1e-5. The largest relative error seen on
/// lavapipe is 2.5e-6 (printed by each test); every deliberate break moved values by 3e-4
/// relative or more.
pub(crate) const TOL: f32 = 1e-5;
/// Absolute floor for values in [0, 1] made of per-sample terms (means, AO_max,
/// accessibility): a device that fuses the multiply-adds of a dot product (FMA) differs by up
/// to one rounding of a product of unit vectors, 2^-23, per term, also where the cosine
/// cancels to almost 0 (samples nearly in the tangent plane); 8x that.
pub(crate) const FLOOR: f32 = 1e-6;
/// The same for raw sums of up to 64 terms (the tuple's second channel).
pub(crate) const SUM_FLOOR: f32 = 1e-5;

pub(crate) fn channel(v: &[V4], c: usize) -> Vec<f32> {
    v.iter().map(|t| t[c]).collect()
}

pub(crate) fn channel3(v: &[V3], c: usize) -> Vec<f32> {
    v.iter().map(|t| t[c]).collect()
}
