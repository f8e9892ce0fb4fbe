//! Deterministic low-discrepancy ray directions for the reference: a 2D Sobol (0,2)-sequence,
//! scrambled per pixel, mapped to cosine-weighted directions on the hemisphere.
//!
//! Choices: the first two Sobol dimensions (van der Corput and its companion) form a (0,2)-
//! sequence, so every power-of-two prefix stratifies the unit square; each pixel XOR-scrambles
//! both dimensions with a hash of its index (random digit scrambling). Unlike a Cranley-
//! Patterson rotation, XOR scrambling keeps the net structure, and it still decorrelates
//! neighbouring pixels. Points map to the hemisphere by Malley's method (uniform on the disk,
//! lifted to the hemisphere), which is exactly cosine-weighted, so the AO estimator is a plain
//! mean. Invariants: the same pixel index always gets the same directions (results are
//! reproducible and cacheable), and every direction has a strictly positive component along
//! the normal.

use glam::{Vec2, Vec3};
use std::f32::consts::TAU;

/// Second Sobol dimension (direction numbers of the polynomial x + 1), 32-bit.
fn sobol_second_dimension(mut index: u32) -> u32 {
    let mut result = 0u32;
    let mut v = 1u32 << 31;
    while index != 0 {
        if index & 1 != 0 {
            result ^= v;
        }
        index >>= 1;
        v ^= v >> 1;
    }
    result
}

/// 32-bit integer hash with good avalanche (C. Wellons' "lowbias32").
pub(crate) fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// The per-pixel scramble: two independent 32-bit masks from the pixel index.
pub fn pixel_scramble(pixel: u32) -> [u32; 2] {
    let a = hash_u32(pixel ^ 0x9e37_79b9);
    [a, hash_u32(a ^ 0x85eb_ca6b)]
}

/// Maps 32 random bits to [0, 1) (24 bits of precision, never 1.0).
fn unit_float(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Point `index` of the scrambled 2D Sobol sequence, in [0, 1)^2.
pub fn sobol_2d(index: u32, scramble: [u32; 2]) -> Vec2 {
    Vec2::new(
        unit_float(index.reverse_bits() ^ scramble[0]),
        unit_float(sobol_second_dimension(index) ^ scramble[1]),
    )
}

/// Cosine-weighted direction around +Z for a point of the unit square (Malley's method).
/// The z component is always > 0.
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = TAU * u.y;
    let z = (1.0 - u.x).max(1e-12).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Two unit tangents completing the unit `normal` to a right-handed orthonormal basis
/// (Duff et al. 2017, branchless).
pub fn tangent_frame(normal: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(normal.z);
    let a = -1.0 / (sign + normal.z);
    let b = normal.x * normal.y * a;
    (
        Vec3::new(
            1.0 + sign * normal.x * normal.x * a,
            sign * b,
            -sign * normal.x,
        ),
        Vec3::new(b, sign + normal.y * normal.y * a, -normal.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_prefix_is_stratified_in_both_dimensions() {
        // A (0,2)-sequence puts exactly one of the first 16 points in each 1/16 column and row.
        for scramble in [[0, 0], pixel_scramble(12345)] {
            let mut columns = [0; 16];
            let mut rows = [0; 16];
            for i in 0..16 {
                let p = sobol_2d(i, scramble);
                columns[(p.x * 16.0) as usize] += 1;
                rows[(p.y * 16.0) as usize] += 1;
            }
            assert_eq!(columns, [1; 16]);
            assert_eq!(rows, [1; 16]);
        }
    }

    #[test]
    fn cosine_directions_are_unit_and_above_the_surface() {
        for i in 0..256 {
            let d = cosine_hemisphere(sobol_2d(i, pixel_scramble(7)));
            assert!((d.length() - 1.0).abs() < 1e-5);
            assert!(d.z > 0.0);
        }
        assert!(cosine_hemisphere(Vec2::new(0.999_999_9, 0.3)).z > 0.0);
    }

    #[test]
    fn tangent_frame_is_orthonormal() {
        for n in [
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::X,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
        ] {
            let (t, b) = tangent_frame(n);
            assert!(t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5 && t.dot(b).abs() < 1e-5);
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
        }
    }
}
