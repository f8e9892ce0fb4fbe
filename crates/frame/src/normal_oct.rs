//! The CPU side of the compact normal encoding (`GBufferChannel::NormalsOct`), the same f32
//! operations as shaders/common/normal_oct.wgsl: for code that reads the channel back or
//! fills it (tests, tools). Octahedral map, two snorm16 components in one u32 (x low).
//! Invariant: `decode(encode(n))` is a unit vector within 1e-4 rad of a unit `n`; 0 decodes
//! to +z.

/// WGSL `pack2x16snorm`: floor(0.5 + 32767 clamp(v, -1, 1)) per component, x in the low half.
fn pack2x16snorm(v: [f32; 2]) -> u32 {
    let q = |x: f32| ((0.5 + 32767.0 * x.clamp(-1.0, 1.0)).floor() as i16) as u16 as u32;
    q(v[0]) | (q(v[1]) << 16)
}

/// WGSL `unpack2x16snorm`: max(i16 / 32767, -1) per component.
fn unpack2x16snorm(b: u32) -> [f32; 2] {
    let q = |h: u32| ((h as u16 as i16) as f32 / 32767.0).max(-1.0);
    [q(b & 0xffff), q(b >> 16)]
}

/// `normal_oct_encode`: a (unit) normal to its 32-bit code.
pub fn encode(n: [f32; 3]) -> u32 {
    let l1 = (n[0].abs() + n[1].abs() + n[2].abs()).max(1e-30);
    let m = [n[0] / l1, n[1] / l1, n[2] / l1];
    let sign = |v: f32| if v >= 0.0 { 1.0 } else { -1.0 };
    let e = if m[2] >= 0.0 {
        [m[0], m[1]]
    } else {
        [
            (1.0 - m[1].abs()) * sign(m[0]),
            (1.0 - m[0].abs()) * sign(m[1]),
        ]
    };
    pack2x16snorm(e)
}

/// `normal_oct_decode`: the unit normal of a code.
pub fn decode(bits: u32) -> [f32; 3] {
    let e = unpack2x16snorm(bits);
    let z = 1.0 - e[0].abs() - e[1].abs();
    let t = (-z).max(0.0);
    let x = e[0] + if e[0] >= 0.0 { -t } else { t };
    let y = e[1] + if e[1] >= 0.0 { -t } else { t };
    let l = (x * x + y * y + z * z).sqrt();
    [x / l, y / l, z / l]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angle(a: [f32; 3], b: [f32; 3]) -> f64 {
        let d: f64 = (0..3).map(|i| a[i] as f64 * b[i] as f64).sum();
        let c: [f64; 3] = [
            a[1] as f64 * b[2] as f64 - a[2] as f64 * b[1] as f64,
            a[2] as f64 * b[0] as f64 - a[0] as f64 * b[2] as f64,
            a[0] as f64 * b[1] as f64 - a[1] as f64 * b[0] as f64,
        ];
        (c.iter().map(|v| v * v).sum::<f64>().sqrt()).atan2(d)
    }

    #[test]
    fn axes_round_trip_exactly_and_zero_is_plus_z() {
        for n in [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ] {
            assert_eq!(decode(encode(n)), n, "{n:?}");
        }
        assert_eq!(decode(0), [0.0, 0.0, 1.0]);
        // +z is (0, 0) in the square: the code of a cleared target.
        assert_eq!(encode([0.0, 0.0, 1.0]), 0);
    }

    #[test]
    fn every_direction_round_trips_within_1e_4_rad() {
        // A Fibonacci sphere of 20000 directions, both hemispheres and the folded seams.
        let count = 20_000;
        let mut worst = 0.0f64;
        for i in 0..count {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f64 * 2.399_963_229_728_653;
            let n = [(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32];
            let d = decode(encode(n));
            let len = d.iter().map(|v| v * v).sum::<f32>().sqrt();
            assert!((len - 1.0).abs() < 1e-6, "{n:?} decodes to length {len}");
            worst = worst.max(angle(n, d));
        }
        // The square's step is 2 / 32767; the map stretches it by at most about 2.
        assert!(worst < 1e-4, "worst {worst:e} rad");
        assert!(worst > 1e-6, "worst {worst:e} rad: quantisation must show");
    }
}
