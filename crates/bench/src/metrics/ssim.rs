//! Structural similarity (SSIM) with the Pyramid HBAO paper's settings, which this project
//! follows so its numbers sit next to the paper's Table 1 (docs/techniques/pyramid-hbao.md §5.2):
//!
//! - window 11x11, **uniform**: the paper "passes a sliding window of size KxK over two images,
//!   compares the windows and returns the average of the obtained values" and names no
//!   Gaussian weighting, so every pixel of the window weighs the same (Wang et al.'s Gaussian
//!   sigma = 1.5 window is available as [`SsimWindow::Gaussian`]);
//! - k1 = 0.001 **as printed in the paper** (standard SSIM, and Wang et al., use 0.01; the spec
//!   flags the difference and we follow the paper), k2 = 0.03, dynamic range L = 1
//!   (accessibility is in [0, 1]): c1 = (k1 L)^2, c2 = (k2 L)^2;
//! - moments are population moments (divided by the window's weight, not weight - 1).
//!
//! Sky: a window is centred on every non-sky pixel, and its moments use only the non-sky
//! pixels inside it (sky is 1 in both images and would inflate the similarity near
//! silhouettes). Windows are clipped at the image border the same way, so small images keep
//! their border pixels. The result is the mean over those windows.
//!
//! The windowed sums are separable convolutions of (m, m x, m y, m x^2, m y^2, m x y), m the
//! mask, in f64: O(window) per pixel, exact for any window shape.

/// Window weighting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SsimWindow {
    /// Every pixel of the window weighs the same (the paper).
    Uniform,
    /// Gaussian weights with this sigma in pixels (Wang et al. 2004: 1.5).
    Gaussian {
        /// Standard deviation of the weights, in pixels.
        sigma: f64,
    },
}

/// SSIM constants and window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsimParams {
    /// Window side in pixels (odd).
    pub window: u32,
    /// Window weighting: uniform (the paper) or Gaussian (Wang et al.).
    pub shape: SsimWindow,
    /// Luminance constant: c1 = (k1 L)^2 (0.001 as printed in the paper; 0.01 in Wang et al.).
    pub k1: f64,
    /// Contrast-structure constant: c2 = (k2 L)^2 (0.03 in both).
    pub k2: f64,
    /// Dynamic range L of the values.
    pub dynamic_range: f64,
}

impl SsimParams {
    /// The Pyramid HBAO paper: 11x11 uniform window, k1 = 0.001 (as printed), k2 = 0.03, L = 1.
    pub const PAPER: Self = Self {
        window: 11,
        shape: SsimWindow::Uniform,
        k1: 0.001,
        k2: 0.03,
        dynamic_range: 1.0,
    };
    /// Wang et al. 2004: 11x11 Gaussian window with sigma 1.5, k1 = 0.01, k2 = 0.03, L = 1.
    pub const WANG: Self = Self {
        window: 11,
        shape: SsimWindow::Gaussian { sigma: 1.5 },
        k1: 0.01,
        k2: 0.03,
        dynamic_range: 1.0,
    };

    /// The luminance stabiliser c1 = (k1 L)^2.
    pub fn c1(&self) -> f64 {
        (self.k1 * self.dynamic_range).powi(2)
    }
    /// The contrast-structure stabiliser c2 = (k2 L)^2.
    pub fn c2(&self) -> f64 {
        (self.k2 * self.dynamic_range).powi(2)
    }
    /// One-dimensional window weights, offsets -r..=r.
    fn kernel(&self) -> Vec<f64> {
        let r = (self.window.max(1) / 2) as i32;
        (-r..=r)
            .map(|d| match self.shape {
                SsimWindow::Uniform => 1.0,
                SsimWindow::Gaussian { sigma } => (-(d * d) as f64 / (2.0 * sigma * sigma)).exp(),
            })
            .collect()
    }
}

impl Default for SsimParams {
    fn default() -> Self {
        Self::PAPER
    }
}

/// SSIM of one window from its moments (Wang et al. Eq. 13; the paper's Eq. 10).
pub fn ssim_from_moments(
    mu_x: f64,
    mu_y: f64,
    var_x: f64,
    var_y: f64,
    cov: f64,
    c1: f64,
    c2: f64,
) -> f64 {
    ((2.0 * mu_x * mu_y + c1) * (2.0 * cov + c2))
        / ((mu_x * mu_x + mu_y * mu_y + c1) * (var_x + var_y + c2))
}

/// Sums of `channels` weighted by `kernel` along one axis; taps outside the image are skipped.
fn convolve(
    channels: &[Vec<f64>],
    kernel: &[f64],
    width: usize,
    height: usize,
    horizontal: bool,
) -> Vec<Vec<f64>> {
    let r = (kernel.len() / 2) as isize;
    channels
        .iter()
        .map(|src| {
            let mut out = vec![0.0; src.len()];
            for y in 0..height {
                for x in 0..width {
                    let mut s = 0.0;
                    for (k, w) in kernel.iter().enumerate() {
                        let d = k as isize - r;
                        let (sx, sy) = if horizontal {
                            (x as isize + d, y as isize)
                        } else {
                            (x as isize, y as isize + d)
                        };
                        if sx >= 0 && sy >= 0 && (sx as usize) < width && (sy as usize) < height {
                            s += w * src[sy as usize * width + sx as usize];
                        }
                    }
                    out[y * width + x] = s;
                }
            }
            out
        })
        .collect()
}

/// Mean SSIM of `x` against `y` over windows centred on the pixels where `mask` is true (see
/// the module docs). NaN when no pixel is masked in.
pub fn ssim(
    x: &[f32],
    y: &[f32],
    mask: &[bool],
    width: u32,
    height: u32,
    params: &SsimParams,
) -> f64 {
    let (w, h) = (width as usize, height as usize);
    let n = w * h;
    let mut ch = vec![vec![0.0f64; n]; 6];
    for i in 0..n.min(x.len()).min(y.len()).min(mask.len()) {
        if mask[i] {
            let (a, b) = (x[i] as f64, y[i] as f64);
            ch[0][i] = 1.0;
            ch[1][i] = a;
            ch[2][i] = b;
            ch[3][i] = a * a;
            ch[4][i] = b * b;
            ch[5][i] = a * b;
        }
    }
    let kernel = params.kernel();
    let sums = convolve(&convolve(&ch, &kernel, w, h, true), &kernel, w, h, false);
    let (c1, c2) = (params.c1(), params.c2());
    let (mut total, mut count) = (0.0f64, 0usize);
    for i in 0..n.min(mask.len()) {
        let weight = sums[0][i];
        if !mask[i] || weight <= 0.0 {
            continue;
        }
        let (mx, my) = (sums[1][i] / weight, sums[2][i] / weight);
        let vx = (sums[3][i] / weight - mx * mx).max(0.0);
        let vy = (sums[4][i] / weight - my * my).max(0.0);
        let cov = sums[5][i] / weight - mx * my;
        total += ssim_from_moments(mx, my, vx, vy, cov, c1, c2);
        count += 1;
    }
    if count == 0 {
        f64::NAN
    } else {
        total / count as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_ssim_one() {
        let x: Vec<f32> = (0..64 * 48)
            .map(|i| ((i * 37 % 101) as f32) / 100.0)
            .collect();
        for p in [SsimParams::PAPER, SsimParams::WANG] {
            let s = ssim(&x, &x, &vec![true; x.len()], 64, 48, &p);
            assert!((s - 1.0).abs() < 1e-12, "{p:?}: {s}");
        }
    }

    #[test]
    fn constant_images_compare_by_luminance_only() {
        // sigma = 0 everywhere, so SSIM = (2ab + c1) / (a^2 + b^2 + c1) with a = 0.5, b = 0.25,
        // c1 = 1e-6: (0.25 + 1e-6) / (0.3125 + 1e-6).
        let x = vec![0.5f32; 20 * 20];
        let y = vec![0.25f32; 20 * 20];
        let s = ssim(&x, &y, &vec![true; 400], 20, 20, &SsimParams::PAPER);
        assert!((s - 0.800000639997952).abs() < 1e-12, "{s}");
    }

    /// A 6x1 image is inside every 11-wide window, so each window holds the whole image and
    /// SSIM is the one-window value worked out by hand.
    #[test]
    fn hand_computed_single_window_cases() {
        let p = SsimParams::PAPER;
        let x = [0.0f32, 1.0, 0.0, 1.0, 0.0, 1.0];
        let all = [true; 6];
        // y = 1 - x: mu 0.5 and 0.5, var 0.25 and 0.25, cov -0.25:
        // (0.5 + c1)(-0.5 + c2) / ((0.5 + c1)(0.5 + c2)) = -0.4991 / 0.5009
        let y: Vec<f32> = x.iter().map(|v| 1.0 - v).collect();
        assert!((ssim(&x, &y, &all, 6, 1, &p) - -0.9964064683569573).abs() < 1e-12);
        // y = x / 2: mu 0.5 and 0.25, var 0.25 and 0.0625, cov 0.125:
        // (0.25 + c1)(0.25 + c2) / ((0.3125 + c1)(0.3125 + c2))
        let y: Vec<f32> = x.iter().map(|v| v / 2.0).collect();
        assert!((ssim(&x, &y, &all, 6, 1, &p) - 0.6404599890730255).abs() < 1e-12);
    }

    #[test]
    fn sky_pixels_neither_centre_a_window_nor_enter_one() {
        let (w, h) = (16u32, 16u32);
        let r: Vec<f32> = (0..256).map(|i| 0.3 + 0.002 * i as f32).collect();
        let a: Vec<f32> = r.iter().map(|v| v - 0.05).collect();
        let mask: Vec<bool> = (0..256).map(|i| i % 16 < 10).collect();
        let mut garbage = a.clone();
        for (i, v) in garbage.iter_mut().enumerate() {
            if !mask[i] {
                *v = if i % 2 == 0 { 0.0 } else { 1.0 };
            }
        }
        let clean = ssim(&a, &r, &mask, w, h, &SsimParams::PAPER);
        assert_eq!(clean, ssim(&garbage, &r, &mask, w, h, &SsimParams::PAPER));
        assert!(ssim(&a, &r, &[false; 256], w, h, &SsimParams::PAPER).is_nan());
    }

    #[test]
    fn gaussian_window_weights_follow_sigma() {
        let k = SsimParams::WANG.kernel();
        assert_eq!(k.len(), 11);
        assert_eq!(k[5], 1.0);
        assert!((k[6] - (-1.0f64 / 4.5).exp()).abs() < 1e-15);
        assert!(SsimParams::PAPER.kernel().iter().all(|w| *w == 1.0));
    }
}
