//! The per-run picture: the technique's accessibility, its signed error map and the
//! reference side by side in one RGB PNG (3 panels of the output size, 2-pixel grey gaps).
//!
//! The error map is technique - reference on a diverging scale: white = 0, blue = too dark
//! (over-occluded), red = too bright (under-occluded), fully saturated at +-[`ERROR_RANGE`]
//! (fixed, so maps of different runs compare); sky (not measured) is mid grey.

use std::path::Path;

use crate::images::write_rgb_png;
use aograph_app_config::error::AppResult;

/// |error| at which the error map saturates.
pub const ERROR_RANGE: f32 = 0.25;
const GAP: u32 = 2;
const SKY: [u8; 3] = [128, 128, 128];
const TOO_DARK: [f32; 3] = [33.0, 102.0, 172.0];
const TOO_BRIGHT: [f32; 3] = [178.0, 24.0, 43.0];

/// The colour of error `e` (technique - reference).
pub fn error_colour(e: f32) -> [u8; 3] {
    let t = if e.is_finite() {
        (e / ERROR_RANGE).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let end = if t < 0.0 { TOO_DARK } else { TOO_BRIGHT };
    let a = t.abs();
    end.map(|c| (255.0 + (c - 255.0) * a).round() as u8)
}

fn gray(v: f32) -> [u8; 3] {
    let g = if v.is_finite() {
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    } else {
        0
    };
    [g; 3]
}

/// RGB pixels of the three panels.
pub fn side_by_side(
    ao: &[f32],
    reference: &[f32],
    valid: &[bool],
    width: u32,
    height: u32,
) -> (u32, Vec<u8>) {
    let (w, h) = (width as usize, height as usize);
    let total_w = 3 * w + 2 * GAP as usize;
    let mut rgb = vec![96u8; total_w * h * 3];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let err = if valid[i] {
                error_colour(ao[i] - reference[i])
            } else {
                SKY
            };
            for (panel, c) in [gray(ao[i]), err, gray(reference[i])]
                .into_iter()
                .enumerate()
            {
                let px = panel * (w + GAP as usize) + x;
                let o = (y * total_w + px) * 3;
                rgb[o..o + 3].copy_from_slice(&c);
            }
        }
    }
    (total_w as u32, rgb)
}

/// Writes the side-by-side PNG.
pub fn write_side_by_side(
    path: &Path,
    ao: &[f32],
    reference: &[f32],
    valid: &[bool],
    width: u32,
    height: u32,
) -> AppResult<()> {
    let (w, rgb) = side_by_side(ao, reference, valid, width, height);
    write_rgb_png(path, w, height, &rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_scale_is_white_at_zero_blue_when_dark_red_when_bright() {
        assert_eq!(error_colour(0.0), [255, 255, 255]);
        assert_eq!(error_colour(-1.0), [33, 102, 172]);
        assert_eq!(error_colour(ERROR_RANGE), [178, 24, 43]);
        let half = error_colour(-ERROR_RANGE / 2.0);
        assert!(half[2] > half[0], "half-dark is light blue: {half:?}");
    }

    #[test]
    fn panels_are_ao_error_reference() {
        let (w, rgb) = side_by_side(&[0.5, 1.0], &[0.75, 1.0], &[true, false], 2, 1);
        assert_eq!(w, 3 * 2 + 2 * GAP);
        assert_eq!(&rgb[0..3], &[128, 128, 128], "ao 0.5");
        let err = (2 + GAP as usize) * 3;
        assert_eq!(&rgb[err..err + 3], &error_colour(-0.25), "too dark by 0.25");
        assert_eq!(&rgb[err + 3..err + 6], &SKY);
        let r = 2 * (2 + GAP as usize) * 3;
        assert_eq!(&rgb[r..r + 3], &[191, 191, 191], "reference 0.75");
    }
}
