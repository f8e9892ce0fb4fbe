//! Property tests on size classes and byte counts.

use aograph_graph::wgpu::TextureFormat;
use aograph_graph::*;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn nested_division_composes(w in 1u32..20_000, h in 1u32..20_000, a in 1u32..64, b in 1u32..64) {
        let direct = SizeClass::Relative { divisor: a * b }.resolve(Extent::new(w, h));
        prop_assert_eq!(direct, Extent::new(w.div_ceil(a).div_ceil(b), h.div_ceil(a).div_ceil(b)));
    }

    #[test]
    fn resolved_sizes_are_at_least_one_and_at_most_the_output(w in 0u32..10_000, h in 0u32..10_000, k in 0u32..40, f in 0u32..8, l in 0u32..12) {
        let out = Extent::new(w, h);
        for s in [SizeClass::FULL, SizeClass::half_pow(k), SizeClass::pyramid_level(f, l)] {
            let e = s.resolve(out);
            prop_assert!(e.width >= 1 && e.height >= 1);
            prop_assert!(e.width <= w.max(1) && e.height <= h.max(1));
        }
    }

    #[test]
    fn pyramid_level_equals_repeated_rounding_up(w in 1u32..5_000, h in 1u32..5_000, f in 2u32..5, l in 0u32..8) {
        let mut e = Extent::new(w, h);
        for _ in 0..l {
            e = Extent::new(e.width.div_ceil(f), e.height.div_ceil(f));
        }
        prop_assert_eq!(SizeClass::pyramid_level(f, l).resolve(Extent::new(w, h)), e);
    }

    #[test]
    fn mipped_bytes_are_the_sum_of_levels(w in 1u32..4_000, h in 1u32..4_000, mips in 1u32..12) {
        let d = TextureDesc::new(TextureFormat::R32Float, SizeClass::FULL).with_mips(mips);
        let expected: u64 = (0..mips).map(|m| Extent::new(w, h).mip(m).pixels() * 4).sum();
        prop_assert_eq!(d.bytes(Extent::new(w, h)), expected);
    }
}
