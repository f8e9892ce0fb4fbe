//! SSDO's precomputed sample sets (docs/techniques/ssdo.md §1.3): M = 4x4 = 16 sets of N low-discrepancy
//! offsets `lambda_i * omega_i`, stored as one table in the `params` uniform; every pixel uses
//! the set its 4x4 interleave index names (`interleave_4x4` of shaders/common/noise.wgsl).
//!
//! The paper fixes only the shape (directions uniform in solid angle around n, since each
//! covers dw = 2 pi / N; lengths in [0, r_max]; M x N precomputed low-discrepancy points). The
//! choices, written down here:
//! - Directions: per set a Hammersley set over (u, v) (u stratified by i, v = radical inverse
//!   base 2 of i), cos(theta) = 1 - u, phi = 2 pi v. Set s shifts u by `RI_2(s) / N` (inside
//!   each stratum) and rotates v by `RI_3(s)` (Cranley-Patterson), so each set is stratified on
//!   its own and the 16 sets together fill 16 N strata of cos(theta): the 4x4 blur then
//!   averages one well-spread 16 N-point set.
//! - Lengths: `lambda = r_max * cbrt(w)`, w = fract(RI_3(i + 1) + RI_5(s)) kept >= 1/64: points
//!   uniform in the volume of the hemisphere ("a set of sampling points ... located in a
//!   hemisphere"). A blocker at distance d along omega is then caught with probability
//!   1 - (d / r_max)^3, closer to the reference's "any hit within R" than uniform lengths.
//! - The frame around n is built in the shader (Duff et al. 2017's branchless basis).

use bytemuck::{Pod, Zeroable};

/// Number of interleaved sample sets (4 x 4, Table 1 of the paper).
pub const SETS: usize = 16;
/// Largest N (the paper's Table 1 uses 8 and 16).
pub const MAX_SAMPLES: u32 = 16;

/// The `params` uniform of every SSDO pass (`SsdoParams` in shaders/ao/ssdo/common.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SsdoUniform {
    /// r_max (world units).
    pub r_max: f32,
    /// Fade start (world units).
    pub fade_start: f32,
    /// Depth bias (world units).
    pub bias: f32,
    /// Sender patch area A_s (world units^2).
    pub sender_area: f32,
    /// Distance clamp of the form factor (scene units).
    pub distance_clamp: f32,
    /// Light lobe exponent.
    pub light_lobe: f32,
    /// Sky gradient.
    pub sky_gradient: f32,
    /// Blur plane tolerance (world units).
    pub blur_plane_tolerance: f32,
    /// Sample count N.
    pub sample_count: u32,
    /// Bounce: 0 or 1.
    pub bounce: u32,
    /// Environment: 0 ambient, 1 sky.
    pub sky: u32,
    /// Unused; pads the row to 16 bytes.
    pub _pad0: u32,
    /// `[set * 16 + i]` = (x, y, z, cos theta): offset in units of r_max in the frame (t, b, n).
    pub samples: [[f32; 4]; SETS * MAX_SAMPLES as usize],
}

aograph_graph::uniform_layout!(SsdoUniform {
    r_max,
    fade_start,
    bias,
    sender_area,
    distance_clamp,
    light_lobe,
    sky_gradient,
    blur_plane_tolerance,
    sample_count,
    bounce,
    sky,
    _pad0,
    samples
});

fn radical_inverse(mut i: u32, base: u32) -> f32 {
    let (mut f, mut r) = (1.0 / base as f32, 0.0f32);
    let inv = f;
    while i > 0 {
        r += (i % base) as f32 * f;
        i /= base;
        f *= inv;
    }
    r
}

/// Sample `i` of set `s` for `n` samples per set: (x, y, z, cos theta), |xyz| <= 1, z >= 0.
pub fn sample(s: u32, i: u32, n: u32) -> [f32; 4] {
    let n = n.max(1) as f32;
    let u = ((i as f32 + radical_inverse(s, 2)) / n).clamp(0.0, 1.0);
    let v = (radical_inverse(i, 2) + radical_inverse(s, 3)).fract();
    let w = (radical_inverse(i + 1, 3) + radical_inverse(s, 5))
        .fract()
        .max(1.0 / 64.0);
    let cos_t = (1.0 - u).clamp(0.0, 1.0);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * v;
    let len = w.cbrt();
    [
        sin_t * phi.cos() * len,
        sin_t * phi.sin() * len,
        cos_t * len,
        cos_t,
    ]
}

/// The whole table for `n` samples per set (entries past `n` in a set stay zero).
pub fn sample_table(n: u32) -> [[f32; 4]; SETS * MAX_SAMPLES as usize] {
    let n = n.clamp(1, MAX_SAMPLES);
    let mut t = [[0.0; 4]; SETS * MAX_SAMPLES as usize];
    for s in 0..SETS as u32 {
        for i in 0..n {
            t[(s * MAX_SAMPLES + i) as usize] = sample(s, i, n);
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_lie_in_the_unit_hemisphere_with_their_cosine() {
        for n in [4, 8, 16] {
            for s in 0..SETS as u32 {
                for i in 0..n {
                    let [x, y, z, c] = sample(s, i, n);
                    let len = (x * x + y * y + z * z).sqrt();
                    assert!(
                        len > 0.2 && len <= 1.0 + 1e-6,
                        "set {s} sample {i}: length {len}"
                    );
                    assert!(z >= 0.0 && (0.0..=1.0).contains(&c));
                    assert!((z / len - c).abs() < 1e-5, "cos theta is the direction's z");
                }
            }
        }
    }

    #[test]
    fn each_set_is_stratified_and_the_union_fills_the_strata() {
        let n = 8;
        for s in 0..SETS as u32 {
            let mut strata: Vec<usize> = (0..n)
                .map(|i| ((1.0 - sample(s, i, n)[3]) * n as f32 + 1e-3).floor() as usize)
                .collect();
            strata.sort();
            assert_eq!(
                strata,
                (0..n as usize).collect::<Vec<_>>(),
                "set {s}: one sample per cos stratum"
            );
        }
        let mut fine: Vec<usize> = (0..SETS as u32)
            .flat_map(|s| {
                (0..n).map(move |i| {
                    ((1.0 - sample(s, i, n)[3]) * (SETS as u32 * n) as f32 + 1e-3).floor() as usize
                })
            })
            .collect();
        fine.sort();
        fine.dedup();
        assert_eq!(
            fine.len(),
            SETS * n as usize,
            "the 16 sets fill all 16 N strata"
        );
        // Uniform in solid angle: the mean cosine over the union is 1/2.
        let mean: f32 = (0..SETS as u32)
            .flat_map(|s| (0..n).map(move |i| sample(s, i, n)[3]))
            .sum::<f32>()
            / (SETS as f32 * n as f32);
        assert!((mean - 0.5).abs() < 0.01, "mean cos {mean}");
    }

    #[test]
    fn table_leaves_unused_entries_zero() {
        let t = sample_table(8);
        assert!(t[8] == [0.0; 4] && t[15] == [0.0; 4] && t[16] != [0.0; 4]);
        assert!(t.iter().flatten().all(|v| v.is_finite()));
    }
}
