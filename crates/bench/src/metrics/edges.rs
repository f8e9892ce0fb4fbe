//! The depth-edge band: pixels within a few pixels of a depth discontinuity, where
//! screen-space AO draws its halos (dark rims behind silhouettes, light rims in front).
//!
//! A pixel is an edge pixel when one of its 4-neighbours differs in depth by more than a
//! relative jump `|d_p - d_q| / min(d_p, d_q) > jump` (default 10%), or when exactly one of the
//! two is sky (depth <= 0): a silhouette against the sky is a discontinuity too. Both pixels of
//! such a pair are marked. The band is the set of pixels within `band` pixels (Chebyshev
//! distance, i.e. a square of side 2 band + 1) of an edge pixel; callers intersect it with the
//! non-sky mask before measuring.

/// Half-width of the band in pixels that `aograph bench` uses.
pub const DEFAULT_EDGE_BAND: u32 = 3;
/// Relative depth jump that counts as an edge.
pub const DEFAULT_EDGE_JUMP: f32 = 0.1;

fn is_jump(a: f32, b: f32, jump: f32) -> bool {
    match (a > 0.0, b > 0.0) {
        (true, true) => (a - b).abs() > jump * a.min(b),
        (false, false) => false,
        _ => true,
    }
}

/// Edge pixels of a linear depth image (0 = sky), row-major.
pub fn depth_edges(depth: &[f32], width: u32, height: u32, jump: f32) -> Vec<bool> {
    let (w, h) = (width as usize, height as usize);
    let mut edge = vec![false; w * h];
    if depth.len() < w * h {
        return edge;
    }
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if x + 1 < w && is_jump(depth[i], depth[i + 1], jump) {
                edge[i] = true;
                edge[i + 1] = true;
            }
            if y + 1 < h && is_jump(depth[i], depth[i + w], jump) {
                edge[i] = true;
                edge[i + w] = true;
            }
        }
    }
    edge
}

/// Dilates `edges` by `band` pixels in every direction (a separable square max filter).
pub fn edge_band(edges: &[bool], width: u32, height: u32, band: u32) -> Vec<bool> {
    let (w, h, r) = (width as usize, height as usize, band as usize);
    let mut rows = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let (lo, hi) = (x.saturating_sub(r), (x + r).min(w.saturating_sub(1)));
            rows[y * w + x] = (lo..=hi).any(|sx| edges.get(y * w + sx).copied().unwrap_or(false));
        }
    }
    let mut out = vec![false; w * h];
    for y in 0..h {
        let (lo, hi) = (y.saturating_sub(r), (y + r).min(h.saturating_sub(1)));
        for x in 0..w {
            out[y * w + x] = (lo..=hi).any(|sy| rows[sy * w + x]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::masked_mae;

    /// 20x10 with depth 1 left of x = 10 and 2 from x = 10: the edge pixels are columns 9 and
    /// 10, and a band of 3 covers columns 6..=13.
    fn step() -> Vec<f32> {
        (0..200)
            .map(|i| if i % 20 < 10 { 1.0 } else { 2.0 })
            .collect()
    }

    #[test]
    fn a_depth_step_marks_both_sides_and_the_band_around_them() {
        let e = depth_edges(&step(), 20, 10, DEFAULT_EDGE_JUMP);
        for (i, v) in e.iter().enumerate() {
            assert_eq!(*v, i % 20 == 9 || i % 20 == 10, "pixel {i}");
        }
        let b = edge_band(&e, 20, 10, 3);
        for (i, v) in b.iter().enumerate() {
            assert_eq!(*v, (6..=13).contains(&(i % 20)), "pixel {i}");
        }
        assert_eq!(b.iter().filter(|v| **v).count(), 80);
    }

    #[test]
    fn halo_error_shows_in_the_band_mae() {
        // A technique right everywhere except a dark halo of 0.3 on the two columns behind
        // the step (x = 10, 11): band MAE = 0.3 * 20 / 80 = 0.075.
        let reference = vec![0.8f32; 200];
        let ao: Vec<f32> = (0..200)
            .map(|i| {
                if (10..12).contains(&(i % 20)) {
                    0.5
                } else {
                    0.8
                }
            })
            .collect();
        let band = edge_band(&depth_edges(&step(), 20, 10, DEFAULT_EDGE_JUMP), 20, 10, 3);
        assert!((masked_mae(&ao, &reference, &band).unwrap() - 0.075).abs() < 1e-6);
    }

    #[test]
    fn smooth_slopes_and_small_jumps_are_not_edges() {
        let ramp: Vec<f32> = (0..200).map(|i| 1.0 + 0.05 * (i % 20) as f32).collect();
        assert!(depth_edges(&ramp, 20, 10, 0.1).iter().all(|e| !e));
        let small: Vec<f32> = (0..200)
            .map(|i| if i % 20 < 10 { 1.0 } else { 1.09 })
            .collect();
        assert!(depth_edges(&small, 20, 10, 0.1).iter().all(|e| !e));
    }

    #[test]
    fn silhouettes_against_the_sky_are_edges_and_sky_alone_is_not() {
        let d: Vec<f32> = (0..200)
            .map(|i| if i / 20 < 5 { 0.0 } else { 3.0 })
            .collect();
        let e = depth_edges(&d, 20, 10, 0.1);
        assert!(
            e.iter()
                .enumerate()
                .all(|(i, v)| *v == (i / 20 == 4 || i / 20 == 5))
        );
        assert!(depth_edges(&[0.0; 200], 20, 10, 0.1).iter().all(|e| !e));
    }
}
